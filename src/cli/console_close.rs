//! Closing check's console window on Windows (or logging off, or shutting down) ends the
//! process as soon as its console handler returns, and at the latest when Windows' grace is
//! spent (about 5 s for a closed window). ctrlc's handler returns at once, so check would die
//! before its report was written. This handler sets the stop flag and holds the event until
//! check has ended on its own (its report written: the process's exit ends this thread too).

// Registering a console handler is a system call with a function pointer: the one `unsafe`
// here, sound because the handler is a plain function that lives as long as the program.
#![allow(unsafe_code)]

use std::sync::OnceLock;
use std::time::Duration;

use windows_sys::Win32::Foundation::{FALSE, TRUE};
use windows_sys::Win32::System::Console::{
    CTRL_CLOSE_EVENT, CTRL_LOGOFF_EVENT, CTRL_SHUTDOWN_EVENT, SetConsoleCtrlHandler,
};
use windows_sys::core::BOOL;

use crate::render::StopFlag;

/// Longer than any grace Windows gives (5 s for a closed window, 20 s at shutdown): Windows,
/// or check's own end, ends the wait first.
const HOLD: Duration = Duration::from_secs(30);

static STOP: OnceLock<&'static StopFlag> = OnceLock::new();

/// Sets `stop` when the console closes, and holds Windows' end of the process while check
/// finishes. Call after ctrlc's handler is set: the last handler set is asked first, and this
/// one passes Ctrl-C and Ctrl-Break on to ctrlc's.
pub(super) fn stop_on_close(stop: &'static StopFlag) {
    if STOP.set(stop).is_ok() {
        unsafe { SetConsoleCtrlHandler(Some(on_event), TRUE) };
    }
}

/// Called by Windows on a thread of its own for each console event.
unsafe extern "system" fn on_event(event: u32) -> BOOL {
    match STOP.get() {
        Some(stop) if hold(event, stop, HOLD) => TRUE,
        _ => FALSE,
    }
}

/// Whether `event` ends the process; if so `stop` is set and the event held for `hold`.
fn hold(event: u32, stop: &StopFlag, hold: Duration) -> bool {
    if !matches!(
        event,
        CTRL_CLOSE_EVENT | CTRL_LOGOFF_EVENT | CTRL_SHUTDOWN_EVENT
    ) {
        return false;
    }
    stop.set();
    std::thread::sleep(hold);
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use windows_sys::Win32::System::Console::{CTRL_BREAK_EVENT, CTRL_C_EVENT};

    #[test]
    fn a_closing_console_stops_check_and_ctrl_c_is_left_to_ctrlc() {
        for event in [CTRL_C_EVENT, CTRL_BREAK_EVENT] {
            let stop = StopFlag::leaked();
            assert!(!hold(event, stop, Duration::ZERO));
            assert!(!stop.is_set());
        }
        for event in [CTRL_CLOSE_EVENT, CTRL_LOGOFF_EVENT, CTRL_SHUTDOWN_EVENT] {
            let stop = StopFlag::leaked();
            assert!(hold(event, stop, Duration::ZERO));
            assert!(stop.is_set());
        }
    }
}
