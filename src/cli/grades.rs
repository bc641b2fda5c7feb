//! What `raycast check` and a class's run share on the terminal: the grades of one renderer,
//! and the flag that Ctrl-C, SIGTERM and SIGHUP set. Its own file so that `check` (which hands
//! a class to `class`) and `class` depend on it, not on each other.

use std::io::Write;

use crate::check::{self, Status};

/// Prints the verdict (what to fix first, for all the lines at once), a line per picture and
/// the count; returns how many failed.
pub(super) fn print_grades(
    out: &mut impl Write,
    groups: &[check::Group],
    graded: &[check::Graded],
) -> usize {
    // What a renderer printed reaches these lines: shown, never obeyed, one line each.
    for line in check::verdict_lines(groups) {
        let _ = writeln!(out, "{}", check::visible(&line));
    }
    for g in graded {
        let _ = writeln!(out, "{}", check::visible(&check::verdict(g)));
    }
    let passed = graded.iter().filter(|g| g.status == Status::Pass).count();
    let failed = graded.len() - passed;
    let _ = writeln!(out, "{passed} passed, {failed} failed");
    failed
}

/// A flag that Ctrl-C, SIGTERM and SIGHUP set: the renderers running end, and what was graded
/// so far is reported, marked partial.
pub(super) fn stop_on_signals() -> &'static crate::render::StopFlag {
    let stop = crate::render::StopFlag::leaked();
    for signal in [
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGHUP,
    ] {
        let _ = signal_hook::flag::register(signal, stop.shared());
    }
    stop
}
