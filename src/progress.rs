//! What the command line says on stderr besides errors: progress bars and
//! warnings.
//!
//! Progress bars are drawn only when stderr is a terminal and `--quiet` is
//! not given; a pipe or a log file never sees them. `--quiet` also silences
//! warnings and notes; errors are always printed (by `main`). Everything goes
//! through one [`indicatif::MultiProgress`], so a warning printed while a bar
//! is drawn appears above the bar instead of tearing it.

use std::fmt::Display;
use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use shlight_pipeline::{Hooks, Progress};

/// The stderr side of one run of the command line.
#[derive(Clone, Debug)]
pub struct Ui {
    quiet: bool,
    multi: MultiProgress,
}

impl Ui {
    /// Progress on a terminal unless `quiet`; warnings unless `quiet`.
    pub fn new(quiet: bool) -> Self {
        let draw = !quiet && std::io::stderr().is_terminal();
        let target = if draw {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        Self {
            quiet,
            multi: MultiProgress::with_draw_target(target),
        }
    }

    /// A bar of `len` steps labelled `what` (hidden unless drawn; see the
    /// module docs). Finish it with [`ProgressBar::finish_and_clear`].
    pub fn bar(&self, len: u64, what: &str) -> ProgressBar {
        let style = ProgressStyle::with_template(
            "{msg:>12} [{bar:32}] {pos}/{len} {elapsed_precise} (eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> ");
        let bar = ProgressBar::new(len)
            .with_style(style)
            .with_message(what.to_string());
        self.add(bar)
    }

    /// A spinner for work whose length is unknown, with a message that the
    /// caller updates stage by stage.
    pub fn spinner(&self, what: &str) -> ProgressBar {
        let style =
            ProgressStyle::with_template("{spinner} {msg} {elapsed}").expect("valid template");
        let bar = ProgressBar::new_spinner()
            .with_style(style)
            .with_message(what.to_string());
        let bar = self.add(bar);
        if !bar.is_hidden() {
            bar.enable_steady_tick(Duration::from_millis(120));
        }
        bar
    }

    fn add(&self, bar: ProgressBar) -> ProgressBar {
        if self.multi.is_hidden() {
            // Never drawn: skip the bookkeeping (and any terminal query).
            bar.set_draw_target(ProgressDrawTarget::hidden());
            bar
        } else {
            self.multi.add(bar)
        }
    }

    /// Prints `warning: MSG` unless quiet.
    pub fn warn(&self, msg: impl Display) {
        if !self.quiet {
            self.multi.suspend(|| eprintln!("warning: {msg}"));
        }
    }

    /// Prints `note: MSG` unless quiet: something the user should know
    /// that is not a problem.
    pub fn note(&self, msg: impl Display) {
        if !self.quiet {
            self.multi.suspend(|| eprintln!("note: {msg}"));
        }
    }

    /// Prints `error: MSG` (even when quiet): for errors that do not end
    /// the run at once, such as one failed input of several.
    pub fn error(&self, msg: impl Display) {
        self.multi.suspend(|| eprintln!("error: {msg}"));
    }
}

/// A job's [`Hooks`] on the terminal: [`Progress::Step`] as a spinner's
/// line, each stage of [`Progress::Count`] as a bar of its own (replaced
/// when the stage changes, showing the furthest count), warnings and notes
/// as [`Ui::warn`] and [`Ui::note`] print them. Bars are cleared when it is
/// dropped.
pub struct Reporter<'a> {
    ui: &'a Ui,
    spinner: std::sync::OnceLock<ProgressBar>,
    stage: std::sync::Mutex<Option<(String, ProgressBar, u64)>>,
}

impl<'a> Reporter<'a> {
    /// Nothing drawn until the job reports.
    pub fn new(ui: &'a Ui) -> Self {
        Self {
            ui,
            spinner: std::sync::OnceLock::new(),
            stage: std::sync::Mutex::new(None),
        }
    }

    /// Clears every bar (before printing results on stdout).
    pub fn finish(&self) {
        if let Some(bar) = self.spinner.get() {
            bar.finish_and_clear();
        }
        if let Some((_, bar, _)) = self.stage.lock().expect("no panics while held").take() {
            bar.finish_and_clear();
        }
    }
}

impl Hooks for Reporter<'_> {
    fn progress(&self, progress: Progress<'_>) {
        match progress {
            Progress::Step(what) => self
                .spinner
                .get_or_init(|| self.ui.spinner(what))
                .set_message(what.to_string()),
            Progress::Count { stage, done, total } => {
                let mut current = self.stage.lock().expect("no panics while held");
                if current.as_ref().is_none_or(|(s, _, _)| s != stage) {
                    if let Some((_, bar, _)) = current.take() {
                        bar.finish_and_clear();
                    }
                    *current = Some((stage.to_string(), self.ui.bar(total as u64, stage), 0));
                }
                if let Some((_, bar, furthest)) = current.as_mut() {
                    *furthest = (*furthest).max(done as u64);
                    bar.set_position(*furthest);
                }
            }
        }
    }

    fn warn(&self, message: &str) {
        self.ui.warn(message);
    }

    fn note(&self, message: &str) {
        self.ui.note(message);
    }
}

impl Drop for Reporter<'_> {
    fn drop(&mut self) {
        self.finish();
    }
}
