//! The cage a renderer under test runs in. Every line's renderer is started by a supervisor of
//! its own (raycast itself, started with [`SUPERVISE`]): a small single-threaded process that
//! enters the line's namespaces (user, network, IPC, PID) and forks the line's init, which
//! builds the renderer's own root (a mount namespace: the system's folders read-only, its own
//! program, its folders on a size-limited tmpfs, a private /tmp; `root.rs`) and runs the
//! renderer confined as far as the kernel allows (an unprivileged user when check runs as root;
//! Landlock; resource limits; a private HOME and TMPDIR), enforces the line's deadline, and
//! ends everything the renderer started before it reports, setsid, double forks and fork bombs
//! included. check itself only waits for the supervisor's report, with a deadline of its own
//! behind the supervisor's. Where the supervisor can wait (Linux), a line is made ready
//! ([`ready`]) while the line before it runs, and started with the time then left.

mod report;

// One room per system, each with the same interface: `supervise` (a line's supervisor), `Wall`
// (what keeps a renderer from the references, found before any line runs), `SYSTEM` (the
// folders every program may read), `is_root`, `unprivileged_user` and `stage` (a renderer
// never runs as root), and how check starts and stops a supervisor.
#[cfg(target_os = "linux")]
mod linux;
#[cfg(target_os = "linux")]
use linux as system;
#[cfg(all(unix, not(target_os = "linux")))]
mod macos;
#[cfg(all(unix, not(target_os = "linux")))]
use macos as system;
#[cfg(windows)]
mod windows;
#[cfg(windows)]
use windows as system;
#[cfg(not(target_os = "linux"))]
mod same_user;
#[cfg(unix)]
mod unix;

use crate::render::StopFlag;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

pub use system::{SYSTEM, Wall, is_root, stage, supervise, unprivileged_user};
/// A renderer's command and what it may read, made reachable for an unprivileged user.
#[derive(Debug)]
pub struct Staged {
    /// The command, its words that named a copied path renamed into the copy.
    pub command: Vec<String>,
    /// What it may read, copies in place of what the user could not reach.
    pub readable: Vec<PathBuf>,
    /// What was copied, for the report; `None` when nothing needed copying.
    pub note: Option<String>,
}

/// The hidden first word of raycast's command line that makes it a line's supervisor; what
/// follows is the line's request as JSON.
pub const SUPERVISE: &str = "__supervise";

/// The resource limits a renderer runs under (`setrlimit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Address space, in bytes (`--memory`).
    pub memory: u64,
    /// The largest file it may write, in bytes.
    pub file_size: u64,
    /// Processes, when the renderer has a user count of its own (another user, or a user
    /// namespace); otherwise the supervisor ends them all when the line ends.
    pub processes: u64,
    /// Open files.
    pub open_files: u64,
    /// The bytes its own root holds: everything it writes, in every folder (`--disk`).
    pub disk: u64,
    /// The files and folders its own root holds: one for each 64 KiB of `disk` (a course's
    /// scene and picture are larger), at least 256.
    pub files: u64,
}

impl Limits {
    /// The files and folders a line may make in `disk` bytes.
    pub fn files_for(disk: u64) -> u64 {
        (disk / (64 << 10)).max(256)
    }
}

impl Default for Limits {
    /// 4 GiB of memory, files of up to 256 MiB (the largest image check reads), 256 processes,
    /// 256 open files, 1 GiB and 16,384 files written in all (a course's picture is under a
    /// megabyte); no core files.
    fn default() -> Limits {
        Limits {
            memory: 4 << 30,
            file_size: crate::check::MAX_IMAGE_BYTES,
            processes: 256,
            open_files: 256,
            disk: 1 << 30,
            files: Limits::files_for(1 << 30),
        }
    }
}

/// What a line's supervisor is asked to run, and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// The renderer's executable (resolved) and its own arguments, then the line's.
    pub command: Vec<String>,
    /// The folder it runs in, holding its copies of the line's scene files: writable.
    pub work: PathBuf,
    /// The folder its pictures go to: writable.
    pub outputs: PathBuf,
    /// Folders and files it may read beyond the system's: its own submission.
    pub readable: Vec<PathBuf>,
    /// Folders it must never see, even inside a readable one: the suite.
    pub hidden: Vec<PathBuf>,
    /// An empty folder for its own root to be mounted on (see `root.rs`); `None`: it runs
    /// among the machine's files, confined by the rest of the cage.
    pub root: Option<PathBuf>,
    /// Whether its work folder is bound in place, its writes kept (a build writes its program
    /// into the submission), rather than copied into its own root, its writes dropped.
    pub work_kept: bool,
    /// Its wall-clock time.
    pub limit: Duration,
    /// Its resource limits.
    pub limits: Limits,
    /// The user and group it runs as, when check runs as root.
    pub user: Option<(u32, u32)>,
    /// Whether the supervisor builds the line's cage and then waits for check's word (the time
    /// left, on its stdin) before it starts the renderer: a line made ready while another runs
    /// ([`ready`]).
    pub held: bool,
}

impl Request {
    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "command": self.command,
            "work": self.work,
            "outputs": self.outputs,
            "readable": self.readable,
            "hidden": self.hidden,
            "root": self.root,
            "work_kept": self.work_kept,
            "limit_ms": self.limit.as_millis() as u64,
            "memory": self.limits.memory,
            "file_size": self.limits.file_size,
            "processes": self.limits.processes,
            "open_files": self.limits.open_files,
            "disk": self.limits.disk,
            "files": self.limits.files,
            "user": self.user.map(|(u, g)| [u, g]),
            "held": self.held,
        })
    }

    fn from_json(text: &str) -> Result<Request, String> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| format!("a request that is not JSON: {e}"))?;
        let strings = |key: &str| -> Result<Vec<String>, String> {
            value[key]
                .as_array()
                .ok_or(format!("no '{key}' in the request"))?
                .iter()
                .map(|v| {
                    v.as_str()
                        .map(String::from)
                        .ok_or(format!("'{key}' not text"))
                })
                .collect()
        };
        let number = |key: &str| {
            value[key]
                .as_u64()
                .ok_or(format!("no '{key}' in the request"))
        };
        let user = match &value["user"] {
            serde_json::Value::Array(pair) => match (&pair[..], pair.len()) {
                ([u, g], 2) => Some((
                    u.as_u64().ok_or("a user that is not a number")? as u32,
                    g.as_u64().ok_or("a group that is not a number")? as u32,
                )),
                _ => return Err("'user' is not [uid, gid]".into()),
            },
            _ => None,
        };
        Ok(Request {
            command: strings("command")?,
            work: value["work"]
                .as_str()
                .map(PathBuf::from)
                .ok_or("no 'work' in the request")?,
            outputs: value["outputs"]
                .as_str()
                .map(PathBuf::from)
                .ok_or("no 'outputs' in the request")?,
            readable: strings("readable")?
                .into_iter()
                .map(PathBuf::from)
                .collect(),
            hidden: strings("hidden")?.into_iter().map(PathBuf::from).collect(),
            root: value["root"].as_str().map(PathBuf::from),
            work_kept: value["work_kept"].as_bool().unwrap_or(false),
            held: value["held"].as_bool().unwrap_or(false),
            limit: Duration::from_millis(number("limit_ms")?),
            limits: Limits {
                memory: number("memory")?,
                file_size: number("file_size")?,
                processes: number("processes")?,
                open_files: number("open_files")?,
                disk: number("disk")?,
                files: number("files")?,
            },
            user,
        })
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ending {
    /// It exited with status 0.
    Success,
    /// It exited with another status.
    Failed {
        /// The exit status.
        status: i32,
    },
    /// A signal ended it.
    Signaled {
        /// The signal's number.
        signal: i32,
    },
    /// It outlasted the time limit and was killed.
    TimedOut(Duration),
    /// check was interrupted (Ctrl-C, SIGTERM, SIGHUP) while it ran, and ended it.
    Interrupted,
    /// check's whole run was out of time (`--deadline`) before this line ran or while it ran.
    DeadlineCame,
    /// It was not run: the renderer's time budget (`--budget`) was spent before its turn.
    OverBudget(Duration),
    /// The renderer's time budget (`--budget`) ran out while it ran, after `after`.
    BudgetRanOut {
        /// The whole budget.
        budget: Duration,
        /// How long the line had run.
        after: Duration,
    },
    /// It could not be started at all.
    NotStarted(String),
}

/// A run: how it ended, the end of what the renderer said (stderr, then stdout), how long it
/// took, and the cage it ran in.
#[derive(Debug, Clone, PartialEq)]
pub struct Ran {
    /// How it ended.
    pub ending: Ending,
    /// The last 64 KiB of what it wrote to stderr and stdout.
    pub stderr: String,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// What confined it, as its supervisor found the kernel.
    pub confinement: Option<Confinement>,
}

/// Which of the cage's mechanisms were in force for a run, as its supervisor found the kernel
/// (where one is missing the renderer runs anyway, and the report says so).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Confinement {
    /// Who the renderer ran as.
    pub user: String,
    /// Landlock's state: "fully enforced", "partially enforced" or why not.
    pub landlock: String,
    /// Whether it had a network namespace of its own (no network).
    pub network_namespace: bool,
    /// Whether its supervisor adopted its orphans (PR_SET_CHILD_SUBREAPER) to end them.
    pub subreaper: bool,
    /// Whether it had an IPC namespace of its own (System V and POSIX IPC private to it).
    pub ipc_namespace: bool,
    /// Whether its line had a PID namespace (every process of the line ends with it).
    pub pid_namespace: bool,
    /// Whether it ran in a root of its own (the system's folders, its own and nothing else;
    /// its writes bounded), or, if not, why not.
    pub own_root: Result<(), String>,
    /// Whether its line had control groups of its own (memory and processes counted over all
    /// the line's processes), or why not (Linux).
    pub line_group: Result<(), String>,
    /// Whether the kernel killed a process of the line for the line's memory.
    pub memory_ran_out: bool,
    /// Whether the kernel's keyrings, which no namespace separates, were closed to it (a
    /// seccomp filter), or why not (Linux).
    pub keyrings: Result<(), String>,
    /// The system it ran on: "linux", "macos" or "windows" (the fields above are Linux's).
    pub system: String,
    /// Windows: whether its line ran in a job object (every process ended with the line, their
    /// memory and number bounded together, no UI), or why not.
    pub job: Result<(), String>,
    /// macOS: whether the system's sandbox (`sandbox-exec`) kept it from the network and its
    /// writes in its folders, the suite out of its reach; on Windows why nothing does.
    pub sandbox: Result<(), String>,
    /// Windows: whether it ran at a low integrity level, its line's folders labelled low (its
    /// writes kept to them), or why not.
    pub low_integrity: Result<(), String>,
}

impl Default for Confinement {
    fn default() -> Confinement {
        Confinement {
            user: String::new(),
            landlock: String::new(),
            network_namespace: false,
            subreaper: false,
            ipc_namespace: false,
            pid_namespace: false,
            own_root: Err("not tried".into()),
            line_group: Err("not tried".into()),
            memory_ran_out: false,
            keyrings: Err(format!("not on {}", std::env::consts::OS)),
            system: std::env::consts::OS.to_string(),
            job: Err(format!("not on {}", std::env::consts::OS)),
            sandbox: Err(format!("not on {}", std::env::consts::OS)),
            low_integrity: Err(format!("not on {}", std::env::consts::OS)),
        }
    }
}

impl Confinement {
    /// As the report writes it.
    pub fn json(&self) -> serde_json::Value {
        let held = |mechanism: &Result<(), String>| match mechanism {
            Ok(()) => serde_json::Value::Bool(true),
            Err(why) => serde_json::Value::String(why.clone()),
        };
        serde_json::json!({
            "system": self.system,
            "job": held(&self.job),
            "sandbox": held(&self.sandbox),
            "low_integrity": held(&self.low_integrity),
            "user": self.user,
            "landlock": self.landlock,
            "network_namespace": self.network_namespace,
            "subreaper": self.subreaper,
            "ipc_namespace": self.ipc_namespace,
            "pid_namespace": self.pid_namespace,
            "own_root": held(&self.own_root),
            "line_group": held(&self.line_group),
            "memory_ran_out": self.memory_ran_out,
            "keyrings_closed": held(&self.keyrings),
        })
    }

    pub(crate) fn from_json(value: &serde_json::Value) -> Option<Confinement> {
        let held = |value: &serde_json::Value| match value {
            serde_json::Value::Bool(true) => Ok(()),
            serde_json::Value::String(why) => Err(why.clone()),
            _ => Err("not recorded".into()),
        };
        Some(Confinement {
            user: value["user"].as_str()?.to_string(),
            landlock: value["landlock"].as_str()?.to_string(),
            network_namespace: value["network_namespace"].as_bool()?,
            subreaper: value["subreaper"].as_bool()?,
            // Reports written before these were kept did not have them.
            ipc_namespace: value["ipc_namespace"].as_bool().unwrap_or(false),
            pid_namespace: value["pid_namespace"].as_bool().unwrap_or(false),
            own_root: held(&value["own_root"]),
            line_group: held(&value["line_group"]),
            memory_ran_out: value["memory_ran_out"].as_bool().unwrap_or(false),
            keyrings: held(&value["keyrings_closed"]),
            // Reports written before other systems were caged were Linux's.
            system: value["system"].as_str().unwrap_or("linux").to_string(),
            job: held(&value["job"]),
            sandbox: held(&value["sandbox"]),
            low_integrity: held(&value["low_integrity"]),
        })
    }

    /// Whether every mechanism of its system held: on Linux Landlock in full, no network,
    /// private IPC, every process ended with the line, a root of its own; on macOS the sandbox
    /// and the line's process group; on Windows the job object and (never yet) a sandbox.
    pub fn is_whole(&self) -> bool {
        match self.system.as_str() {
            "windows" => return self.job.is_ok() && self.sandbox.is_ok(),
            "linux" => {}
            _ => return self.sandbox.is_ok() && self.subreaper,
        }
        self.landlock == "fully enforced"
            && self.network_namespace
            && self.ipc_namespace
            && (self.pid_namespace || self.subreaper)
            && self.own_root.is_ok()
            && self.keyrings.is_ok()
    }

    /// One line for the terminal: what held the renderer, and what was missing.
    pub fn summary(&self) -> String {
        let or_why = |held: &Result<(), String>, what: &str| match held {
            Ok(()) => what.to_string(),
            Err(why) => format!("no {what} ({why})"),
        };
        match self.system.as_str() {
            "windows" => {
                return format!(
                    "renderer caged as {}; {} (every process ended with its line, memory and \
                     processes bounded together, no UI); {}; {}",
                    self.user,
                    or_why(&self.job, "job object"),
                    or_why(
                        &self.low_integrity,
                        "low integrity level (writes in its folders only)"
                    ),
                    or_why(&self.sandbox, "sandbox"),
                );
            }
            "linux" => {}
            _ => {
                return format!(
                    "renderer caged as {}; {}; {}",
                    self.user,
                    or_why(
                        &self.sandbox,
                        "sandbox (no network, writes in its folders only)"
                    ),
                    if self.subreaper {
                        "its process group ended with its line"
                    } else {
                        "no process group of its own"
                    },
                );
            }
        }
        let yes_no = |on: bool, what: &str| {
            if on {
                what.to_string()
            } else {
                format!("no {what}")
            }
        };
        let root = match &self.own_root {
            Ok(()) => "a root of its own".to_string(),
            Err(why) => format!("the machine's files (no root of its own: {why})"),
        };
        let group = match &self.line_group {
            Ok(()) => "memory and processes counted over the line".to_string(),
            Err(why) => format!("memory and processes counted per process ({why})"),
        };
        let keyrings = match &self.keyrings {
            Ok(()) => "the keyrings closed".to_string(),
            Err(why) => format!("the keyrings open ({why})"),
        };
        format!(
            "renderer caged as {}; Landlock {}; {}; {}; {}; {}; {group}; {keyrings}",
            self.user,
            self.landlock,
            yes_no(self.network_namespace, "network namespace"),
            yes_no(self.ipc_namespace, "IPC namespace"),
            if self.pid_namespace {
                "PID namespace".to_string()
            } else {
                yes_no(self.subreaper, "subreaper")
            },
            root,
        )
    }
}

/// The last this many bytes of a renderer's stderr and stdout are kept: its error message
/// comes last.
const SAID_TAIL: usize = 64 * 1024;

/// How long check waits past a line's deadline for its supervisor, which enforces the
/// deadline itself, before it kills the supervisor.
const SUPERVISOR_GRACE: Duration = Duration::from_secs(3);

/// How often check looks at a running supervisor (whether it was asked to stop, or is past
/// its deadline); its report wakes the wait at once.
const SUPERVISOR_POLL: Duration = Duration::from_millis(20);

/// How often check looks for the end of a supervisor whose report has come.
const EXITING_POLL: Duration = Duration::from_micros(200);

/// Whether this system's supervisor can be started ahead and hold the line until check's word.
const SUPERVISOR_HOLDS: bool = cfg!(target_os = "linux");

/// Runs `request` under a supervisor and waits for its report. `stop` asks for the run to end
/// early (check was interrupted): the supervisor is told, and ends the renderer's tree.
pub fn run(request: &Request, stop: &StopFlag) -> Ran {
    Readied {
        request: Request {
            held: false,
            ..request.clone()
        },
        waiting: None,
    }
    .start(request.limit)
    .wait(stop)
}

/// A line made ready while another runs: its supervisor started, its cage built, the renderer
/// not yet (where the system's supervisor can wait: elsewhere it is started by `start`).
/// Dropped unstarted, the supervisor hears its stdin close and ends the line unrun.
pub struct Readied {
    request: Request,
    waiting: Option<Result<Supervisor, String>>,
}

/// A supervisor check started, with the ends of its pipes.
struct Supervisor {
    child: std::process::Child,
    said: Option<std::sync::mpsc::Receiver<Vec<u8>>>,
    report: Option<std::sync::mpsc::Receiver<Vec<u8>>>,
}

/// A line whose renderer has been started: `wait` for how it ran.
pub struct Running {
    supervisor: Result<Supervisor, String>,
    start: Instant,
    limit: Duration,
}

/// Makes `request`'s line ready to start: the supervisor builds its cage (its namespaces, its
/// own root) while the line before it still runs, so that what is left when the line's turn
/// comes is the renderer itself.
pub fn ready(request: &Request) -> Readied {
    let request = Request {
        held: SUPERVISOR_HOLDS,
        ..request.clone()
    };
    let waiting = SUPERVISOR_HOLDS.then(|| spawn_supervisor(&request));
    Readied { request, waiting }
}

impl Readied {
    /// Starts the renderer, which may run for `limit` (the time left when its turn came).
    pub fn start(self, limit: Duration) -> Running {
        let start = Instant::now();
        let supervisor = match self.waiting {
            Some(Ok(mut supervisor)) => {
                // A supervisor that cannot hear the word has ended, and says why in its report.
                if let Some(stdin) = supervisor.child.stdin.as_mut() {
                    let _ = writeln!(stdin, "{}", limit.as_millis());
                }
                Ok(supervisor)
            }
            Some(Err(why)) => Err(why),
            None => spawn_supervisor(&Request {
                limit,
                ..self.request
            }),
        };
        Running {
            supervisor,
            start,
            limit,
        }
    }

    /// Gives the line up unstarted (check was stopped, or its budget spent): the supervisor
    /// hears its stdin close, takes the cage down and ends.
    pub fn cancel(self) {
        if let Some(Ok(mut supervisor)) = self.waiting {
            drop(supervisor.child.stdin.take());
            let deadline = Instant::now() + SUPERVISOR_GRACE;
            while Instant::now() < deadline {
                if !matches!(supervisor.child.try_wait(), Ok(None)) {
                    return;
                }
                std::thread::sleep(EXITING_POLL);
            }
            let _ = supervisor.child.kill();
            let _ = supervisor.child.wait();
        }
    }
}

/// Starts `request`'s supervisor, its stdout (the report) and stderr (the renderer's words)
/// read on threads of their own.
fn spawn_supervisor(request: &Request) -> Result<Supervisor, String> {
    let program =
        std::env::current_exe().map_err(|e| format!("raycast cannot find its own program: {e}"))?;
    let mut supervisor = Command::new(program);
    supervisor
        .arg(SUPERVISE)
        .arg(request.json().to_string())
        // Kept open while the line runs: a supervisor whose stdin closes was told to stop
        // (where no signal can tell it), and a held one hears on it when to start.
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    system::detach(&mut supervisor);
    let mut child = supervisor
        .spawn()
        .map_err(|e| format!("its supervisor could not start: {e}"))?;
    let said = child.stderr.take().map(|pipe| read_tail(pipe, SAID_TAIL));
    let report = child.stdout.take().map(|pipe| read_tail(pipe, SAID_TAIL));
    Ok(Supervisor {
        child,
        said,
        report,
    })
}

impl Running {
    /// Waits for the line's end: how it ran, its time counted from its start.
    pub fn wait(self, stop: &StopFlag) -> Ran {
        let Running {
            supervisor,
            start,
            limit,
        } = self;
        let not_started = |why: String| Ran {
            ending: Ending::NotStarted(why),
            stderr: String::new(),
            seconds: start.elapsed().as_secs_f64(),
            confinement: None,
        };
        let Supervisor {
            mut child,
            said,
            report,
        } = match supervisor {
            Ok(supervisor) => supervisor,
            Err(why) => return not_started(why),
        };
        let backstop = limit + SUPERVISOR_GRACE;
        let mut told = false;
        // The report, once its pipe has closed: the supervisor's last act, so the wait for its
        // end is woken by it rather than by the next of a round of polls.
        let mut reported: Option<Vec<u8>> = None;
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if start.elapsed() >= backstop => break None,
                Ok(None) => {
                    if stop.is_set() && !told {
                        system::ask_to_stop(&mut child);
                        told = true;
                    }
                    match (&report, &reported) {
                        (Some(pipe), None) => match pipe.recv_timeout(SUPERVISOR_POLL) {
                            Ok(bytes) => reported = Some(bytes),
                            Err(RecvTimeoutError::Timeout) => {}
                            Err(RecvTimeoutError::Disconnected) => {
                                reported = Some(Vec::new());
                            }
                        },
                        _ => std::thread::sleep(EXITING_POLL),
                    }
                }
                Err(e) => return not_started(e.to_string()),
            }
        };
        if status.is_none() {
            // A supervisor past its own deadline was stopped by the renderer (where neither another
            // user nor Landlock's signal scope kept it out): killed, and the renderer dies with it
            // (PR_SET_PDEATHSIG).
            let _ = child.kill();
            let _ = child.wait();
        }
        // Whatever the renderer started ended with its supervisor; the pipes close at once, but
        // are not waited on past the deadline either way.
        let left = backstop
            .saturating_sub(start.elapsed())
            .max(Duration::from_millis(100));
        let report = reported
            .or_else(|| report.and_then(|r| r.recv_timeout(left).ok()))
            .unwrap_or_default();
        let stderr = said
            .and_then(|s| s.recv_timeout(Duration::from_millis(100)).ok())
            .unwrap_or_default();
        let seconds = start.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&stderr).into_owned();
        let Some(status) = status else {
            return Ran {
                ending: Ending::TimedOut(limit),
                stderr,
                seconds,
                confinement: None,
            };
        };
        let report: Option<serde_json::Value> = serde_json::from_slice(&report).ok();
        let Some(report) = report else {
            return Ran {
                ending: Ending::NotStarted(format!(
                    "its supervisor ended ({status}) without a report"
                )),
                stderr,
                seconds,
                confinement: None,
            };
        };
        let ending = match report::ending_of(&report["ending"]) {
            // The supervisor knows only that it was told to stop; check knows why.
            Ending::Interrupted => Ending::stopped(stop),
            ending => ending,
        };
        Ran {
            ending,
            stderr,
            seconds,
            confinement: Confinement::from_json(&report["cage"]).map(with_keyrings),
        }
    }
}

/// The supervisor's account of the cage, with the keyrings' state: probed here, in check, not
/// in the supervisor, where a probe's thread still ending when it asked for a user namespace
/// made the kernel refuse it (one needs a single-threaded caller).
#[cfg(target_os = "linux")]
fn with_keyrings(cage: Confinement) -> Confinement {
    Confinement {
        keyrings: linux::keyrings_state(),
        ..cage
    }
}

/// Elsewhere the supervisor's account stands.
#[cfg(not(target_os = "linux"))]
fn with_keyrings(cage: Confinement) -> Confinement {
    cage
}

impl Ending {
    /// How a process ended, from its exit code or the signal that ended it.
    pub(crate) fn of_exit(code: Option<i32>, signal: Option<i32>) -> Ending {
        match (code, signal) {
            (Some(0), _) => Ending::Success,
            (Some(code), _) => Ending::Failed { status: code },
            (None, Some(signal)) => Ending::Signaled { signal },
            (None, None) => Ending::Failed { status: -1 },
        }
    }

    /// How a run ends that check stopped: interrupted by a person, or out of time
    /// (`--deadline`).
    pub fn stopped(stop: &StopFlag) -> Ending {
        if stop.is_out_of_time() {
            Ending::DeadlineCame
        } else {
            Ending::Interrupted
        }
    }
}

/// Waits for a renderer started at `start` until it ends (its status read by `ended`), `stop`
/// is set, or `limit` has passed; the caller ends what is left.
#[cfg(not(target_os = "linux"))]
fn wait_for(
    child: &mut std::process::Child,
    start: Instant,
    limit: Duration,
    stop: &std::sync::atomic::AtomicBool,
    ended: impl Fn(std::process::ExitStatus) -> Ending,
) -> Ending {
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return ended(status),
            Ok(None) => {}
            Err(e) => return Ending::NotStarted(format!("the supervisor lost it: {e}")),
        }
        if stop.load(std::sync::atomic::Ordering::Relaxed) {
            return Ending::Interrupted;
        }
        if start.elapsed() >= limit {
            return Ending::TimedOut(limit);
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// Reads `pipe` to its end on a thread of its own, keeping its last `keep` bytes (so a chatty
/// renderer never blocks on a full pipe); the bytes arrive on the channel at the end.
fn read_tail(
    mut pipe: impl Read + Send + 'static,
    keep: usize,
) -> std::sync::mpsc::Receiver<Vec<u8>> {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut tail = Vec::new();
        let mut chunk = [0u8; 8192];
        while let Ok(n) = pipe.read(&mut chunk) {
            if n == 0 {
                break;
            }
            tail.extend_from_slice(&chunk[..n]);
            if tail.len() > 2 * keep {
                tail.drain(..tail.len() - keep);
            }
        }
        let start = tail.len().saturating_sub(keep);
        let _ = send.send(tail.split_off(start));
    });
    receive
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_reads_back_as_it_was_written() {
        let request = Request {
            command: vec!["/bin/echo".into(), "-input".into(), "a b.txt".into()],
            work: "/tmp/x/work".into(),
            outputs: "/tmp/x/out".into(),
            readable: vec!["/home/s".into()],
            hidden: vec!["/home/suite".into()],
            root: Some("/tmp/x/root".into()),
            work_kept: false,
            limit: Duration::from_millis(2500),
            limits: Limits::default(),
            user: Some((65534, 65533)),
            held: true,
        };
        let text = request.json().to_string();
        assert_eq!(Request::from_json(&text), Ok(request));
        assert!(Request::from_json("{}").is_err());
    }
}
