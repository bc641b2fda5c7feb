//! What Linux's and macOS' cages do alike: check starts each supervisor in a process group of
//! its own and asks it to stop with SIGTERM; a supervisor hears SIGTERM, SIGINT and SIGHUP as
//! that request.

use std::process::{Child, Command};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Whether check runs as root.
pub fn is_root() -> bool {
    rustix::process::geteuid().is_root()
}

/// A supervisor gets a process group of its own: a Ctrl-C at the terminal reaches check,
/// which tells each supervisor.
pub(crate) fn detach(supervisor: &mut Command) {
    use std::os::unix::process::CommandExt;
    supervisor.process_group(0);
}

/// Asks a supervisor to end its line (check was interrupted): it ends the renderer's tree and
/// reports.
pub(crate) fn ask_to_stop(supervisor: &mut Child) {
    if let Some(pid) = rustix::process::Pid::from_raw(supervisor.id() as i32) {
        let _ = rustix::process::kill_process(pid, rustix::process::Signal::TERM);
    }
}

/// A flag that a supervisor's SIGTERM, SIGINT or SIGHUP sets: asked to stop (check
/// interrupted) or hung up on, the renderer's tree ends first.
pub(super) fn stop_when_signalled() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGHUP,
    ] {
        let _ = signal_hook::flag::register(signal, stop.clone());
    }
    stop
}
