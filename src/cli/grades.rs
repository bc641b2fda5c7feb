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
    // Pictures the course leaves free are never failed; they are counted apart as well.
    let informational = graded
        .iter()
        .filter(|g| {
            matches!(
                g.accepted,
                Some(check::choices::Acceptance::Informational(_))
            )
        })
        .count();
    if informational > 0 {
        let _ = writeln!(
            out,
            "{passed} passed ({informational} informational), {failed} failed"
        );
    } else {
        let _ = writeln!(out, "{passed} passed, {failed} failed");
    }
    failed
}

/// Sets `stop` out of time when the run's `deadline` is near: 5% of it (at least 1 s, at most
/// 15 s) is kept for the report and the platforms' files, which are written whole before it.
pub(super) fn stop_at_deadline(
    stop: &'static crate::render::StopFlag,
    deadline: Option<std::time::Duration>,
) {
    use std::time::Duration;
    let Some(deadline) = deadline else {
        return;
    };
    let kept = (deadline / 20).clamp(Duration::from_secs(1), Duration::from_secs(15));
    let work = deadline.saturating_sub(kept);
    std::thread::spawn(move || {
        std::thread::sleep(work);
        stop.set_out_of_time();
    });
}

/// A flag that Ctrl-C, SIGTERM and SIGHUP set (on Windows Ctrl-C, Ctrl-Break and the console's
/// closing): the renderers running end, and what was graded so far is reported, marked partial.
/// A second time, check ends at once: the renderers end with their supervisors, which watch
/// check; the scratch goes here; the report is not written.
pub(super) fn stop_on_signals() -> &'static crate::render::StopFlag {
    let stop = crate::render::StopFlag::leaked();
    let heard = std::sync::atomic::AtomicUsize::new(0);
    let on_signal = move || {
        stop.set();
        if heard.fetch_add(1, std::sync::atomic::Ordering::Relaxed) > 0 {
            crate::check::remove_scratch_now();
            eprintln!("raycast: check: stopped at once; no report written");
            std::process::exit(130);
        }
    };
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        match signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
            Ok(mut signals) => {
                std::thread::spawn(move || {
                    for _ in signals.forever() {
                        on_signal();
                    }
                });
            }
            Err(_) => {
                for signal in [SIGINT, SIGTERM, SIGHUP] {
                    let _ = signal_hook::flag::register(signal, stop.shared());
                }
            }
        }
    }
    #[cfg(not(unix))]
    {
        // ctrlc hears the console's Ctrl-C and Ctrl-Break; its closing is held until check ends.
        let _ = ctrlc::set_handler(on_signal);
        #[cfg(windows)]
        super::console_close::stop_on_close(stop);
    }
    stop
}
