//! A line's supervisor: raycast started as `raycast __supervise REQUEST`. It stays
//! single-threaded (so that it can fork its init, and the renderer's process can be prepared
//! between fork and exec), enters the line's namespaces where the kernel lets it, forks the
//! line's init (the first process of its PID namespace), which builds the renderer's own root,
//! runs the renderer confined and tells the supervisor how it ended; the supervisor reports
//! that on its stdout, as one JSON object, once nothing the renderer started is left.

// Preparing the renderer between fork and exec (`pre_exec`) needs an unsafe block.
#![allow(unsafe_code)]

use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::os::unix::net::UnixStream;
use std::os::unix::process::CommandExt;
use std::process::{Command, ExitCode, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rustix::process::{Pid, Signal, WaitOptions};

use super::super::report::{self, ending_json, ending_of};
use super::confine::Namespaces;
use super::{Confinement, Ending, Request, cgroup, confine, reap, root};

/// The supervisor's whole life: `request` is the JSON check passed. Its report goes to stdout;
/// the renderer's stderr and stdout go to the supervisor's stderr.
pub fn supervise(request: &str) -> ExitCode {
    report::serve(request, run)
}

fn run(request: &Request) -> (Ending, Confinement) {
    let parent = rustix::process::getppid();
    let stop = super::super::unix::stop_when_signalled();
    let mut cage = Confinement {
        user: match request.user {
            Some((uid, _)) => format!("uid {uid}"),
            None => "check's own user".to_string(),
        },
        ..Confinement::default()
    };
    cage.landlock = confine::landlock_state(request);
    // Before the namespaces (a user namespace would hide the groups' files): the supervisor
    // joins the line's groups, and the init and the renderer are born in them.
    // Single-threaded first: the supervisor moves its one thread into the groups.
    until_single_threaded();
    let group = cgroup::LineGroup::join(&request.limits);
    cage.line_group = group.as_ref().map(|_| ()).map_err(Clone::clone);
    let namespaces = confine::enter_namespaces();
    cage.network_namespace = namespaces.network;
    cage.ipc_namespace = namespaces.ipc;
    cage.pid_namespace = namespaces.pid;
    // Where there is no PID namespace, what outlives the init is adopted here, and ended.
    cage.subreaper = rustix::process::set_child_subreaper(Some(rustix::process::getpid())).is_ok();
    let (report, for_init) = match UnixStream::pair() {
        Ok(pair) => pair,
        Err(e) => {
            return (
                Ending::NotStarted(format!("no channel to its init: {e}")),
                cage,
            );
        }
    };
    let start = Instant::now();
    // SAFETY: the supervisor is single-threaded here (the Landlock probe's thread has been
    // joined), so the child is a whole copy of a process in which no other thread held a
    // lock; it may allocate and run ordinary code, and leaves by _exit.
    let init = match unsafe { libc::fork() } {
        -1 => {
            let e = std::io::Error::last_os_error();
            return (
                Ending::NotStarted(format!("its init could not start: {e}")),
                cage,
            );
        }
        0 => {
            drop(report);
            let counted_by_group = group.is_ok();
            let (ending, cage) = init(
                request,
                &namespaces,
                (counted_by_group, &for_init),
                cage,
                &stop,
            );
            let said = serde_json::json!({ "ending": ending_json(&ending), "cage": cage.json() });
            let _ = (&for_init).write_all(said.to_string().as_bytes());
            // SAFETY: _exit ends the init at once, without the supervisor's exit handlers;
            // as the PID namespace's first process, it takes every other one with it.
            unsafe { libc::_exit(0) }
        }
        pid => Pid::from_raw(pid),
    };
    drop(for_init);
    let Some(init) = init else {
        return (
            Ending::NotStarted("its init has no process id".into()),
            cage,
        );
    };
    // A held line: its cage is built while check's word is awaited; without it (check closed
    // stdin, was stopped, or is gone), the init is ended unstarted.
    let started = if request.held {
        word_to_start(&stop, parent)
            .filter(|limit| {
                let millis = limit.as_millis() as u64;
                (&report).write_all(&millis.to_le_bytes()).is_ok()
            })
            .map(|limit| (Instant::now(), limit))
    } else {
        Some((start, request.limit))
    };
    let ended_here = match started {
        Some((start, limit)) => wait_for_init(init, (start, limit), &stop, parent),
        None => {
            end_init(init);
            Some(Ending::Interrupted)
        }
    };
    reap::end_descendants();
    if let Ok(group) = group {
        cage.memory_ran_out = group.ran_out_of_memory();
        group.leave();
    }
    let mut said = String::new();
    let _ = report.set_nonblocking(true);
    let _ = (&report).take(64 * 1024).read_to_string(&mut said);
    let told: Option<serde_json::Value> = serde_json::from_str(&said).ok();
    match (ended_here, told) {
        (Some(ending), _) => (ending, cage),
        (None, Some(told)) => (
            ending_of(&told["ending"]),
            Confinement::from_json(&told["cage"])
                .map(|told| Confinement {
                    memory_ran_out: cage.memory_ran_out,
                    ..told
                })
                .unwrap_or(cage),
        ),
        (None, None) => (
            Ending::NotStarted("its init ended without a word (killed by the renderer?)".into()),
            cage,
        ),
    }
}

/// Waits for the line's init, which keeps the line's deadline (`limit` from `start`); this
/// one, a little later, holds if the init cannot. `Some` where the supervisor ended the init
/// (stopped, orphaned, or past the backstop): how the line ended.
fn wait_for_init(
    init: Pid,
    (start, limit): (Instant, Duration),
    stop: &AtomicBool,
    parent: Option<Pid>,
) -> Option<Ending> {
    let backstop = limit + INIT_GRACE;
    let init_end = reap::ChildEnd::of(Some(init));
    loop {
        match rustix::process::waitpid(Some(init), WaitOptions::NOHANG) {
            Ok(Some(_)) | Err(_) => return None,
            Ok(None) => {}
        }
        let why = if stop.load(Ordering::Relaxed) || rustix::process::getppid() != parent {
            Some(Ending::Interrupted)
        } else if start.elapsed() >= backstop {
            Some(Ending::TimedOut(limit))
        } else {
            None
        };
        if why.is_some() {
            end_init(init);
            return why;
        }
        init_end.wait(LOOK_EVERY.min(backstop.saturating_sub(start.elapsed())));
    }
}

/// Kills the line's init and reaps it: with it goes its PID namespace, every process in it.
fn end_init(init: Pid) {
    let _ = rustix::process::kill_process(init, Signal::KILL);
    let _ = rustix::process::waitpid(Some(init), WaitOptions::empty());
}

/// check's word to start a held line: the time it may run, in milliseconds, on a line of the
/// supervisor's stdin. `None` where stdin closes or says something else, where the supervisor
/// is asked to stop, or where check is gone.
fn word_to_start(stop: &AtomicBool, parent: Option<Pid>) -> Option<Duration> {
    use rustix::event::{PollFd, PollFlags, Timespec};
    let stdin = std::io::stdin();
    let wait = Timespec {
        tv_sec: 0,
        tv_nsec: LOOK_EVERY.as_nanos() as i64,
    };
    let mut heard = Vec::new();
    loop {
        if stop.load(Ordering::Relaxed) || rustix::process::getppid() != parent {
            return None;
        }
        let mut ready = [PollFd::new(&stdin, PollFlags::IN)];
        if rustix::event::poll(&mut ready, Some(&wait)).unwrap_or(0) == 0 {
            continue;
        }
        let mut byte = [0u8; 64];
        let n = rustix::io::read(&stdin, &mut byte).ok()?;
        if n == 0 {
            return None;
        }
        heard.extend_from_slice(&byte[..n]);
        if let Some(end) = heard.iter().position(|&b| b == b'\n') {
            let millis: u64 = std::str::from_utf8(&heard[..end])
                .ok()?
                .trim()
                .parse()
                .ok()?;
            return Some(Duration::from_millis(millis));
        }
        if heard.len() > 32 {
            return None;
        }
    }
}

/// The init's word to start from its supervisor, on the channel between them: the time the
/// renderer may run. `None` where the channel closes first.
fn started_by_supervisor(channel: &UnixStream) -> Option<Duration> {
    let mut millis = [0u8; 8];
    let mut channel = channel;
    channel.read_exact(&mut millis).ok()?;
    Some(Duration::from_millis(u64::from_le_bytes(millis)))
}

/// Waits, at most 100 ms, until this process is single-threaded again: a joined thread (the
/// Landlock probe's) may still be leaving the kernel's thread group, and the kernel refuses a
/// user namespace to a process of more than one thread (seen once in CI: the line then ran
/// without its own root).
fn until_single_threaded() {
    let deadline = Instant::now() + Duration::from_millis(100);
    while Instant::now() < deadline {
        let threads = std::fs::read_dir("/proc/self/task").map_or(1, |tasks| tasks.count());
        if threads <= 1 {
            return;
        }
        std::thread::sleep(Duration::from_micros(200));
    }
}

/// How often the supervisor and the init look up from waiting for their child: whether they
/// were told to stop, the supervisor's parent is gone, or a deadline has passed (a signal, and
/// the child's end, wake them at once).
const LOOK_EVERY: Duration = Duration::from_millis(10);

/// How long past the line's deadline the supervisor waits for the line's init, which keeps the
/// deadline itself and then gives back the pictures.
const INIT_GRACE: Duration = Duration::from_millis(1500);

/// The line's init: the first process of the line's PID namespace (where the kernel gives
/// one), in a mount namespace of its own. It moves into the renderer's own root, runs the
/// renderer, enforces the deadline, ends every other process of the line, and gives back the
/// pictures.
fn init(
    request: &Request,
    namespaces: &Namespaces,
    (counted_by_group, supervisor): (bool, &UnixStream),
    mut cage: Confinement,
    stop: &AtomicBool,
) -> (Ending, Confinement) {
    // With the supervisor gone, the init (and so its namespace) goes.
    let _ = rustix::process::set_parent_process_death_signal(Some(Signal::KILL));
    // A session of its own: no controlling terminal, so /dev/tty is never the teacher's
    // terminal, to write escapes to past check.
    let _ = rustix::process::setsid();
    let root = own_root(request, namespaces.pid);
    cage.own_root = root.as_ref().map(|_| ()).map_err(Clone::clone);
    // A held line starts when its supervisor says, with the time then left.
    let held;
    let request = if request.held {
        let Some(limit) = started_by_supervisor(supervisor) else {
            return (Ending::Interrupted, cage);
        };
        held = Request {
            limit,
            ..request.clone()
        };
        &held
    } else {
        request
    };
    let Some((program, own)) = request.command.split_first() else {
        return (Ending::NotStarted("no renderer given".into()), cage);
    };
    let said = match std::io::stderr().as_fd().try_clone_to_owned() {
        Ok(fd) => Stdio::from(fd),
        Err(_) => Stdio::null(),
    };
    let mut command = Command::new(program);
    command
        .args(own)
        .current_dir(&request.work)
        .env_clear()
        .envs(confine::environment(request))
        .stdin(Stdio::null())
        .stdout(said)
        .stderr(Stdio::inherit());
    if let Some((uid, gid)) = request.user {
        command.uid(uid).gid(gid);
    }
    // The renderer's own process count: another user's, or a user namespace's; none where the
    // line's group counts them (every line of every check as `nobody` would share one count).
    let counted = (request.user.is_some() || namespaces.user) && !counted_by_group;
    let prepare = confine::in_child(request, counted, root.is_ok());
    // SAFETY: the closure runs in the forked child before exec. The init is single-threaded
    // (signal-hook's handlers need no thread), so no lock is held by another thread at the
    // fork, and what the closure does (prctl, setrlimit, Landlock's system calls and its small
    // allocations) is safe there.
    unsafe {
        command.pre_exec(prepare);
    }
    let start = Instant::now();
    let child = match command.spawn() {
        Ok(child) => child,
        Err(e) => {
            return (Ending::NotStarted(format!("{program}: {e}")), cage);
        }
    };
    let renderer = Pid::from_raw(child.id() as i32);
    // The renderer's status is taken below with wait() (waitpid(-1): any child, whatever its
    // process group; rustix's waitpid(None) is waitpid(0), the caller's group only, which
    // missed setsid orphans), which also reaps the orphans the init adopts; `child` is never
    // waited on.
    drop(child);
    let renderer_end = reap::ChildEnd::of(renderer);
    let ending = loop {
        match rustix::process::wait(WaitOptions::NOHANG) {
            Ok(Some((pid, status))) if Some(pid) == renderer => {
                break Ending::of_exit(status.exit_status(), status.terminating_signal());
            }
            Ok(Some(_)) => continue,
            Ok(None) => {}
            Err(e) => break Ending::NotStarted(format!("its init lost it: {e}")),
        }
        if stop.load(Ordering::Relaxed) {
            break Ending::Interrupted;
        }
        if start.elapsed() >= request.limit {
            break Ending::TimedOut(request.limit);
        }
        // Woken by the renderer's end; between, the orphans the init adopts are reaped.
        renderer_end.wait(LOOK_EVERY.min(request.limit.saturating_sub(start.elapsed())));
    };
    if let Some(renderer) = renderer {
        let _ = rustix::process::kill_process(renderer, Signal::KILL);
    }
    if namespaces.pid {
        reap::end_namespace();
    } else {
        reap::end_descendants();
    }
    if let (Ok(root), false) = (&root, request.work_kept) {
        root.give_back_pictures(&request.outputs, request.limits.file_size);
    }
    (ending, cage)
}

/// A mount namespace for the init, and the renderer's own root in it.
fn own_root(request: &Request, fresh_proc: bool) -> Result<root::Root, String> {
    use rustix::thread::UnshareFlags;
    // SAFETY: NEWNS does not unshare the file descriptor table; the init is single-threaded.
    unsafe { rustix::thread::unshare_unsafe(UnshareFlags::NEWNS) }
        .map_err(|e| format!("no mount namespace: {e}"))?;
    root::enter(request, fresh_proc)
}
