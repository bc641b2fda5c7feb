//! The cage on Windows: a line's supervisor (raycast started as `raycast __supervise REQUEST`)
//! makes a job object and joins it before it starts the renderer, so every process the renderer
//! starts is in the job too, with no window of time in which one is not. The job:
//! - ends every process in it when the supervisor's handle closes (kill on job close), so
//!   nothing outlives the line, however the supervisor ends;
//! - holds the memory of all its processes together to `--memory` and their number to the
//!   line's process limit (the supervisor counts as one);
//! - dies on an unhandled exception instead of waiting on the "stopped working" dialog;
//! - has no desktop, clipboard, global atoms, display settings or log-off (UI restrictions).
//!
//! Every process is started without a console window of its own (no window flashes per line),
//! with a private HOME, TEMP and TMP in its work folder.
//!
//! Its writes are kept to its folders by a low integrity level (`integrity.rs`): the line's
//! folders are labelled low and the supervisor lowers its own level before it starts the
//! renderer, which inherits it; no administrator's rights are needed. Where Windows refuses
//! either step, the renderer runs at the user's level and the report says why.
//!
//! What it does not do: keep the renderer's reads to its folders. That needs a restricted
//! token or an AppContainer whose every readable folder is granted by access list, which
//! changes the rights of the student's own files. The report says so (`sandbox: not
//! confined`), the terminal says so in one line, and a class (other people's programs) is
//! refused without `--no-cage`: a student grading their own renderer needs no more.

// The job object's calls are the system's C interface.
#![allow(unsafe_code)]

mod integrity;

use std::io::{Read, Write};
use std::os::windows::io::{AsHandle, AsRawHandle, FromRawHandle, OwnedHandle};
use std::os::windows::process::CommandExt;
use std::path::Path;
use std::process::{Child, Command, ExitCode, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use windows_sys::Win32::Foundation::{HANDLE, HANDLE_FLAG_INHERIT, SetHandleInformation};
use windows_sys::Win32::System::Console::{GetStdHandle, STD_INPUT_HANDLE, STD_OUTPUT_HANDLE};
use windows_sys::Win32::System::Diagnostics::Debug::{
    SEM_FAILCRITICALERRORS, SEM_NOGPFAULTERRORBOX, SetErrorMode,
};
use windows_sys::Win32::System::JobObjects::{
    AssignProcessToJobObject, CreateJobObjectW, JOB_OBJECT_LIMIT_ACTIVE_PROCESS,
    JOB_OBJECT_LIMIT_DIE_ON_UNHANDLED_EXCEPTION, JOB_OBJECT_LIMIT_JOB_MEMORY,
    JOB_OBJECT_LIMIT_KILL_ON_JOB_CLOSE, JOB_OBJECT_UILIMIT_DESKTOP,
    JOB_OBJECT_UILIMIT_DISPLAYSETTINGS, JOB_OBJECT_UILIMIT_EXITWINDOWS,
    JOB_OBJECT_UILIMIT_GLOBALATOMS, JOB_OBJECT_UILIMIT_HANDLES, JOB_OBJECT_UILIMIT_READCLIPBOARD,
    JOB_OBJECT_UILIMIT_SYSTEMPARAMETERS, JOB_OBJECT_UILIMIT_WRITECLIPBOARD,
    JOBOBJECT_BASIC_UI_RESTRICTIONS, JOBOBJECT_EXTENDED_LIMIT_INFORMATION,
    JobObjectBasicUIRestrictions, JobObjectExtendedLimitInformation, SetInformationJobObject,
    TerminateJobObject,
};
use windows_sys::Win32::System::Threading::{CREATE_NO_WINDOW, GetCurrentProcess};

use super::{Confinement, Ending, Limits, Request, report};

pub use super::same_user::{stage, unprivileged_user};

/// The folders every program may read. The cage keeps no reads here; the list only tells
/// check which paths in a renderer's error are the system's own.
pub const SYSTEM: &[&str] = &[
    "C:\\Windows",
    "C:\\Program Files",
    "C:\\Program Files (x86)",
    "C:\\ProgramData",
];

/// A renderer never runs as another user on Windows.
pub fn is_root() -> bool {
    false
}

/// A supervisor gets no console window of its own (a check from a terminal flashes none per
/// line).
pub(super) fn detach(supervisor: &mut Command) {
    supervisor.creation_flags(CREATE_NO_WINDOW);
}

/// Asks a supervisor to end its line: its stdin closes, which it watches (Windows has no signal
/// for one process to ask another to stop).
pub(super) fn ask_to_stop(supervisor: &mut Child) {
    drop(supervisor.stdin.take());
}

/// What keeps a renderer from the references on Windows: nothing but the job (see the module's
/// documentation), so a class of other people's programs needs `--no-cage` said aloud.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Wall;

impl Wall {
    /// The wall here: the same for every suite.
    pub fn find(_suite: &Path, _root: bool) -> Wall {
        Wall
    }

    /// `Ok` for one's own renderer; for other people's programs, why not and what to do.
    pub fn holds(&self, others: bool) -> Result<(), String> {
        if !others {
            return Ok(());
        }
        Err(NOT_CONFINED_FOR_OTHERS.to_string())
    }
}

const NOT_CONFINED_FOR_OTHERS: &str = "on Windows the cage ends every process of a line, \
    bounds its memory and processes (a job object) and keeps its writes to its folders (a low \
    integrity level), but it does not keep a renderer from reading the suite's references: \
    grade other people's programs on Linux, or give --no-cage to grade them here anyway";

/// The supervisor's whole life: `request` is the JSON check passed. Its report goes to stdout
/// once the renderer has ended; then the job ends whatever is left, the supervisor with it.
pub fn supervise(request: &str) -> ExitCode {
    let (ending, cage, job) = match Request::from_json(request) {
        Ok(request) => run(&request),
        Err(why) => (Ending::NotStarted(why), confinement(), None),
    };
    report::write(&ending, &cage);
    let _ = std::io::stdout().flush();
    if let Some(job) = job {
        // SAFETY: `job` is the job object this process made and is in; ending it ends this
        // process too, after the report above.
        unsafe { TerminateJobObject(job.as_raw_handle() as HANDLE, 0) };
    }
    ExitCode::SUCCESS
}

/// The cage as Windows has it, before the job is made.
fn confinement() -> Confinement {
    Confinement {
        user: "check's own user".to_string(),
        landlock: "not on Windows".to_string(),
        own_root: Err("not on Windows".to_string()),
        system: "windows".to_string(),
        sandbox: Err("reads are not confined on Windows".to_string()),
        low_integrity: Err("not tried".to_string()),
        ..Confinement::default()
    }
}

fn run(request: &Request) -> (Ending, Confinement, Option<OwnedHandle>) {
    let mut cage = confinement();
    // The renderer must not inherit the report's pipe (to forge a report) or the stop pipe.
    for std in [STD_OUTPUT_HANDLE, STD_INPUT_HANDLE] {
        // SAFETY: plain calls on this process's own standard handles.
        unsafe { SetHandleInformation(GetStdHandle(std), HANDLE_FLAG_INHERIT, 0) };
    }
    // No "stopped working" or "insert a disk" dialog for the renderer (the mode is inherited):
    // a crash ends the line at once.
    // SAFETY: sets this process's error mode, nothing else.
    unsafe { SetErrorMode(SEM_FAILCRITICALERRORS | SEM_NOGPFAULTERRORBOX) };
    let job = match make_job(&request.limits) {
        Ok(job) => job,
        Err(why) => {
            cage.job = Err(why);
            return (
                Ending::NotStarted("no job object for the line".into()),
                cage,
                None,
            );
        }
    };
    cage.job = Ok(());
    cage.subreaper = true;
    let stop = Arc::new(AtomicBool::new(false));
    watch_stdin(stop.clone());
    let Some((program, own)) = request.command.split_first() else {
        return (
            Ending::NotStarted("no renderer given".into()),
            cage,
            Some(job),
        );
    };
    let said = match std::io::stderr().as_handle().try_clone_to_owned() {
        Ok(handle) => Stdio::from(handle),
        Err(_) => Stdio::null(),
    };
    // Its writes kept to its folders: they are labelled low, then this process (and so the
    // renderer, which inherits its level) is lowered. Never lowered where the folders could
    // not be labelled: the renderer could not write its picture.
    cage.low_integrity = integrity::open_to_low(&[&request.work, &request.outputs])
        .and_then(|()| integrity::lower_own_level());
    let mut command = Command::new(program);
    command
        .args(own)
        .current_dir(&request.work)
        .env_clear()
        .envs(environment(request))
        .stdin(Stdio::null())
        .stdout(said)
        .stderr(Stdio::inherit())
        .creation_flags(CREATE_NO_WINDOW);
    let start = Instant::now();
    let mut child = match command.spawn() {
        Ok(child) => child,
        Err(e) => {
            return (
                Ending::NotStarted(format!("{program}: {e}")),
                cage,
                Some(job),
            );
        }
    };
    let ending = super::wait_for(&mut child, start, request.limit, &stop, |status| {
        ending_of(status.code().unwrap_or(-1))
    });
    (ending, cage, Some(job))
}

/// The line's job object, with this process in it.
fn make_job(limits: &Limits) -> Result<OwnedHandle, String> {
    let last_error = |what: &str| format!("{what}: {}", std::io::Error::last_os_error());
    // SAFETY: an unnamed job with default security; the handle is owned below.
    let raw = unsafe { CreateJobObjectW(std::ptr::null(), std::ptr::null()) };
    if raw.is_null() {
        return Err(last_error("CreateJobObject"));
    }
    // SAFETY: `raw` is a fresh handle that nothing else owns.
    let job = unsafe { OwnedHandle::from_raw_handle(raw as _) };
    // SAFETY: a zeroed limit structure is valid (no limits); the fields set are plain numbers.
    let mut limit: JOBOBJECT_EXTENDED_LIMIT_INFORMATION = unsafe { std::mem::zeroed() };
    limit.BasicLimitInformation.LimitFlags = JOB_OBJECT_LIMIT_KILL_ON_JOB_CLOSE
        | JOB_OBJECT_LIMIT_DIE_ON_UNHANDLED_EXCEPTION
        | JOB_OBJECT_LIMIT_ACTIVE_PROCESS
        | JOB_OBJECT_LIMIT_JOB_MEMORY;
    // The supervisor is one of the job's processes.
    limit.BasicLimitInformation.ActiveProcessLimit =
        (limits.processes + 1).min(u32::MAX as u64) as u32;
    limit.JobMemoryLimit = limits.memory.min(usize::MAX as u64) as usize;
    let ui = JOBOBJECT_BASIC_UI_RESTRICTIONS {
        UIRestrictionsClass: JOB_OBJECT_UILIMIT_DESKTOP
            | JOB_OBJECT_UILIMIT_DISPLAYSETTINGS
            | JOB_OBJECT_UILIMIT_EXITWINDOWS
            | JOB_OBJECT_UILIMIT_GLOBALATOMS
            | JOB_OBJECT_UILIMIT_HANDLES
            | JOB_OBJECT_UILIMIT_READCLIPBOARD
            | JOB_OBJECT_UILIMIT_SYSTEMPARAMETERS
            | JOB_OBJECT_UILIMIT_WRITECLIPBOARD,
    };
    let handle = job.as_raw_handle() as HANDLE;
    // SAFETY: the structures are the sizes given, and live across the calls.
    unsafe {
        if SetInformationJobObject(
            handle,
            JobObjectExtendedLimitInformation,
            (&raw const limit).cast(),
            std::mem::size_of_val(&limit) as u32,
        ) == 0
        {
            return Err(last_error("the job's limits"));
        }
        // Some systems (Wine among them) keep no UI restrictions: the limits above still hold.
        SetInformationJobObject(
            handle,
            JobObjectBasicUIRestrictions,
            (&raw const ui).cast(),
            std::mem::size_of_val(&ui) as u32,
        );
        if AssignProcessToJobObject(handle, GetCurrentProcess()) == 0 {
            return Err(last_error("joining the job"));
        }
    }
    Ok(job)
}

/// Sets `stop` when the supervisor's stdin ends: check closed it (or ended).
fn watch_stdin(stop: Arc<AtomicBool>) {
    std::thread::spawn(move || {
        let mut sink = [0u8; 64];
        let mut stdin = std::io::stdin();
        while matches!(stdin.read(&mut sink), Ok(n) if n > 0) {}
        stop.store(true, Ordering::Relaxed);
    });
}

/// The renderer's environment: the system's own variables a program needs to start, the PATH,
/// and a private home and temporary folder.
fn environment(request: &Request) -> Vec<(String, String)> {
    let mut kept: Vec<(String, String)> = [
        "SystemRoot",
        "SystemDrive",
        "windir",
        "ComSpec",
        "PATH",
        "PATHEXT",
        "NUMBER_OF_PROCESSORS",
        "PROCESSOR_ARCHITECTURE",
        "OS",
    ]
    .iter()
    .filter_map(|name| Some((name.to_string(), std::env::var(name).ok()?)))
    .collect();
    let home = request.work.join(".home").display().to_string();
    let temporary = request.work.join(".tmp").display().to_string();
    kept.extend([
        ("USERPROFILE".into(), home.clone()),
        ("HOME".into(), home),
        ("TEMP".into(), temporary.clone()),
        ("TMP".into(), temporary),
    ]);
    kept
}

/// How a renderer's exit code reads: Windows reports a crash as an exception code where Unix
/// has a signal, so the common ones are named as the signals a student knows (the report
/// explains each); an MSVC `abort()` exits with 3.
fn ending_of(code: i32) -> Ending {
    let signal = match code as u32 {
        0xC000_0005 | 0xC000_00FD | 0xC000_0006 => Some(11), // access violation, stack overflow, in-page error
        0xC000_0409 | 0x4000_0015 => Some(6),                // fail-fast (abort, a failed check)
        0xC000_0094 | 0xC000_008E | 0xC000_0091 => Some(8),  // division by zero, float traps
        0xC000_001D | 0xC000_0096 => Some(4),                // illegal or privileged instruction
        _ => None,
    };
    match signal {
        Some(_) => Ending::of_exit(None, signal),
        None => Ending::of_exit(Some(code), None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exception_codes_read_as_the_signals_students_know() {
        assert_eq!(ending_of(0), Ending::Success);
        assert_eq!(ending_of(3), Ending::Failed { status: 3 });
        assert_eq!(
            ending_of(0xC000_0005_u32 as i32),
            Ending::Signaled { signal: 11 }
        );
        assert_eq!(
            ending_of(0xC000_0409_u32 as i32),
            Ending::Signaled { signal: 6 }
        );
    }

    #[test]
    fn a_class_needs_no_cage_said_aloud_and_ones_own_renderer_does_not() {
        let wall = Wall::find(Path::new("C:\\suite"), false);
        assert_eq!(wall.holds(false), Ok(()));
        assert!(wall.holds(true).unwrap_err().contains("--no-cage"));
    }
}
