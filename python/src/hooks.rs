//! [`PyHooks`]: a job's hooks for Python: warnings and notes kept until the
//! GIL is back (then `UserWarning`s), progress as one line on stderr when
//! the caller asks for it.

use std::io::Write;
use std::sync::Mutex;

use shlight_pipeline::{Collected, Hooks, Progress};

/// Warnings and notes kept; counted progress drawn on stderr if `show`.
#[derive(Default)]
pub struct PyHooks {
    kept: Collected,
    show: bool,
    shown: Mutex<usize>,
}

impl PyHooks {
    /// Messages kept, progress drawn only if `show`.
    pub fn new(show: bool) -> Self {
        Self {
            show,
            ..Self::default()
        }
    }

    /// The warnings so far, in order.
    pub fn warnings(&self) -> Vec<String> {
        self.kept.warnings()
    }

    /// The notes so far, in order.
    pub fn notes(&self) -> Vec<String> {
        self.kept.notes()
    }
}

impl Hooks for PyHooks {
    fn progress(&self, progress: Progress<'_>) {
        let Progress::Count { stage, done, total } = progress else {
            return;
        };
        if !self.show {
            return;
        }
        let mut shown = self.shown.lock().unwrap_or_else(|e| e.into_inner());
        if done < *shown {
            return;
        }
        *shown = done;
        let end = if done == total { "\n" } else { "" };
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r{stage}: {done}/{total}{end}");
        let _ = err.flush();
    }

    fn warn(&self, message: &str) {
        self.kept.warn(message);
    }

    fn note(&self, message: &str) {
        self.kept.note(message);
    }
}
