//! [`Hooks`]: what a job tells its front end while it runs (progress,
//! warnings, notes), so that the library prints nothing and every front
//! end shows the same messages its own way: the command line as bars and
//! `warning:` lines, Python as `UserWarning`s.

use std::sync::Mutex;

/// How far a job has come.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress<'a> {
    /// What the job starts next, for a one-line status (`"reading
    /// park.exr"`, `"projecting park.exr (2048x1024, lmax 8)"`).
    Step(&'a str),
    /// `done` of `total` units of `stage` are finished (`"rendering"`, 120
    /// of 256 rows). Reported from worker threads, so a front end may see
    /// the counts of one stage out of order; a new `stage` ends the last.
    Count {
        /// The stage, as a front end labels its bar.
        stage: &'a str,
        /// Units finished.
        done: usize,
        /// Units in the stage.
        total: usize,
    },
}

/// What a job calls as it goes. Every method has a default that drops
/// what it is given, so a front end implements only what it shows.
///
/// Jobs call these from worker threads: implementations must be [`Sync`].
pub trait Hooks: Sync {
    /// Progress of the job ([`Progress`]).
    fn progress(&self, progress: Progress<'_>) {
        let _ = progress;
    }

    /// A warning for the user as it arises (a stretched map, negative
    /// texels, values replaced), naming the input.
    fn warn(&self, message: &str) {
        let _ = message;
    }

    /// Something the user should know that is not a problem (what was
    /// baked and how fast, which albedo was used, a limit applied).
    fn note(&self, message: &str) {
        let _ = message;
    }
}

/// Hooks that drop everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Hooks for Silent {}

/// Hooks that keep the warnings and notes, in the order they came, and
/// drop progress: for callers that hand them on afterwards (the Python
/// package turns warnings into `UserWarning`s once the GIL is back).
#[derive(Debug, Default)]
pub struct Collected {
    warnings: Mutex<Vec<String>>,
    notes: Mutex<Vec<String>>,
}

impl Collected {
    /// No messages yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The warnings so far, in order.
    #[must_use]
    pub fn warnings(&self) -> Vec<String> {
        self.warnings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The notes so far, in order.
    #[must_use]
    pub fn notes(&self) -> Vec<String> {
        self.notes.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// The warnings, taken out.
    #[must_use]
    pub fn into_warnings(self) -> Vec<String> {
        self.warnings
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
    }
}

impl Hooks for Collected {
    fn warn(&self, message: &str) {
        self.warnings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(message.to_string());
    }

    fn note(&self, message: &str) {
        self.notes
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(message.to_string());
    }
}

/// Counts units of a stage finished on any thread and reports the count
/// after each: for steps whose loops tick once per unit (a row rendered,
/// a face's rows prefiltered) without knowing how many are done.
pub struct StageCounter<'a> {
    hooks: &'a dyn Hooks,
    stage: &'a str,
    total: usize,
    done: std::sync::atomic::AtomicUsize,
}

impl<'a> StageCounter<'a> {
    /// Nothing done yet of `total` units of `stage`; reports that.
    #[must_use]
    pub fn new(hooks: &'a dyn Hooks, stage: &'a str, total: usize) -> Self {
        hooks.progress(Progress::Count {
            stage,
            done: 0,
            total,
        });
        Self {
            hooks,
            stage,
            total,
            done: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// `n` more units are finished.
    pub fn add(&self, n: usize) {
        let done = self.done.fetch_add(n, std::sync::atomic::Ordering::Relaxed) + n;
        self.hooks.progress(Progress::Count {
            stage: self.stage,
            done,
            total: self.total,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collected_hooks_keep_messages_in_order() {
        let c = Collected::new();
        let hooks: &dyn Hooks = &c;
        hooks.warn("first");
        hooks.note("a note");
        hooks.warn("second");
        hooks.progress(Progress::Step("dropped"));
        assert_eq!(c.notes(), ["a note"]);
        assert_eq!(c.into_warnings(), ["first", "second"]);
    }

    #[test]
    fn a_stage_counter_reports_every_unit() {
        struct Last(Mutex<Vec<(String, usize, usize)>>);
        impl Hooks for Last {
            fn progress(&self, p: Progress<'_>) {
                if let Progress::Count { stage, done, total } = p {
                    self.0.lock().unwrap().push((stage.into(), done, total));
                }
            }
        }
        let last = Last(Mutex::new(Vec::new()));
        let counter = StageCounter::new(&last, "rows", 3);
        counter.add(1);
        counter.add(2);
        let seen = last.0.into_inner().unwrap();
        let counts: Vec<usize> = seen.iter().map(|s| s.1).collect();
        assert_eq!(counts, [0, 1, 3]);
        assert!(seen.iter().all(|s| s.0 == "rows" && s.2 == 3));
    }
}
