//! A check's progress while it runs: on a terminal, a bar redrawn as lines are graded and
//! diagnosed; in a log (CI, a platform's autograder), a line every few seconds, so that a long
//! run is never silent (a short one says nothing).

use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::check::Progress;

/// How often the bar is redrawn.
const REDRAW: Duration = Duration::from_millis(200);
/// How often a log hears how far check has come (and not before the run has lasted as long).
const LOG_EVERY: Duration = Duration::from_secs(5);

/// Shows `progress` on stderr until [`Watcher::finish`].
pub(super) struct Watcher {
    done: mpsc::Sender<()>,
    thread: Option<JoinHandle<()>>,
}

impl Watcher {
    /// Starts showing `progress`.
    pub(super) fn start(progress: Arc<Progress>) -> Watcher {
        let (done, finished) = mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            if std::io::stderr().is_terminal() {
                show_bar(&progress, &finished);
            } else {
                log_lines(&progress, &finished);
            }
        });
        Watcher {
            done,
            thread: Some(thread),
        }
    }

    /// Stops showing it; the bar is cleared.
    pub(super) fn finish(mut self) {
        let _ = self.done.send(());
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn show_bar(progress: &Progress, finished: &mpsc::Receiver<()>) {
    let bar = indicatif::ProgressBar::new(0);
    if let Ok(style) = indicatif::ProgressStyle::with_template("checking {wide_bar} {msg}") {
        bar.set_style(style);
    }
    loop {
        let now = progress.snapshot();
        bar.set_length((now.lines + now.to_diagnose) as u64);
        bar.set_position((now.graded + now.diagnosed) as u64);
        bar.set_message(crate::check::visible(&now.said()));
        match finished.recv_timeout(REDRAW) {
            Err(RecvTimeoutError::Timeout) => continue,
            _ => break,
        }
    }
    bar.finish_and_clear();
}

fn log_lines(progress: &Progress, finished: &mpsc::Receiver<()>) {
    while let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(LOG_EVERY) {
        // A student's name reaches the log as text, never as a control.
        let said = crate::check::visible(&progress.snapshot().said());
        eprintln!("raycast: check: {said}");
    }
}
