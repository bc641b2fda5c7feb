//! What confines a renderer: user, network, IPC and PID namespaces (entered by its supervisor),
//! and, between fork and exec, resource limits, death with its init, no new privileges, and
//! Landlock's rules (the system's files and its own submission readable; its work, output and
//! private temporary folders writable; no TCP; no signals out of its domain).

// The one system call here with no safe wrapper, `unshare`, needs an unsafe block.
#![allow(unsafe_code)]

use std::path::PathBuf;

use landlock::{
    ABI, Access, AccessFs, AccessNet, Ruleset, RulesetAttr, RulesetCreated, RulesetCreatedAttr,
    RulesetError, RulesetStatus, Scope, path_beneath_rules,
};
use rustix::process::{Resource, Rlimit, Signal};

use super::Request;

/// The folders of the system a program needs to run (its libraries, interpreters, settings,
/// devices and the kernel's views): readable, never writable.
pub const SYSTEM: &[&str] = &[
    "/bin", "/sbin", "/usr", "/lib", "/lib32", "/lib64", "/libx32", "/etc", "/opt", "/proc",
    "/sys", "/dev",
];

/// Files of the system a program may write to.
const SYSTEM_SINKS: &[&str] = &["/dev/null", "/dev/zero", "/dev/full"];

/// Which namespaces the supervisor entered.
pub struct Namespaces {
    /// A user namespace (taken without root, to make the others), mapping check's user to itself.
    pub user: bool,
    /// A network namespace: no interface but a loopback that is down (and no abstract UNIX
    /// sockets of the machine's).
    pub network: bool,
    /// An IPC namespace: System V shared memory, semaphores, message queues and POSIX message
    /// queues private to the line, and gone with it.
    pub ipc: bool,
    /// A PID namespace: the supervisor's next child is its first process, and every process in
    /// it ends when that one does.
    pub pid: bool,
}

/// Puts the supervisor in new namespaces, as far as the kernel allows: without root, in a user
/// namespace of its own first (check's user mapped to itself, so the renderer's files are its
/// own and its program keeps no capability), which lets it make the others. The PID namespace
/// takes effect for the supervisor's children: its first child, the line's init, is process 1
/// there; the renderer is that init's child, so a renderer's abort() is still its own.
pub fn enter_namespaces() -> Namespaces {
    use rustix::thread::UnshareFlags;
    // SAFETY: none of these flags unshares the file descriptor table, the one case in which
    // `unshare` affects memory safety; the supervisor is single-threaded here.
    let enter = |flags| unsafe { rustix::thread::unshare_unsafe(flags) }.is_ok();
    let (uid, gid) = (rustix::process::getuid(), rustix::process::getgid());
    let user = !uid.is_root() && enter(UnshareFlags::NEWUSER) && map_to_itself(uid, gid);
    Namespaces {
        user,
        network: enter(UnshareFlags::NEWNET),
        ipc: enter(UnshareFlags::NEWIPC),
        pid: enter(UnshareFlags::NEWPID),
    }
}

/// Maps the user and group outside to themselves in the new user namespace (without a map,
/// nothing it made could own a file).
fn map_to_itself(uid: rustix::process::Uid, gid: rustix::process::Gid) -> bool {
    let write = |file: &str, text: String| std::fs::write(format!("/proc/self/{file}"), text);
    let (uid, gid) = (uid.as_raw(), gid.as_raw());
    write("setgroups", "deny".into()).is_ok()
        && write("uid_map", format!("{uid} {uid} 1")).is_ok()
        && write("gid_map", format!("{gid} {gid} 1")).is_ok()
}

/// The renderer's environment: the PATH, a private HOME and TMPDIR in its work folder, and a
/// plain locale; nothing else of check's.
pub fn environment(request: &Request) -> Vec<(String, String)> {
    let path = std::env::var("PATH").unwrap_or_else(|_| "/usr/local/bin:/usr/bin:/bin".into());
    vec![
        ("PATH".into(), path),
        (
            "HOME".into(),
            request.work.join(".home").display().to_string(),
        ),
        (
            "TMPDIR".into(),
            request.work.join(".tmp").display().to_string(),
        ),
        ("LANG".into(), "C.UTF-8".into()),
    ]
}

/// Landlock's rules for `request`.
fn ruleset(request: &Request, own_root: bool) -> Result<RulesetCreated, RulesetError> {
    // The rights of Landlock's sixth version (Linux 6.12); an older kernel enforces those it
    // has (best effort), and the report says "partially".
    let abi = ABI::V6;
    let mut writable: Vec<PathBuf> = vec![request.work.clone(), request.outputs.clone()];
    if own_root {
        // Its own root's /tmp and /dev/shm, on the line's tmpfs: nobody else's.
        writable.extend(PRIVATE_TEMPORARY.iter().map(PathBuf::from));
    }
    Ruleset::default()
        .handle_access(AccessFs::from_all(abi))?
        .handle_access(AccessNet::from_all(abi))?
        .scope(Scope::from_all(abi))?
        .create()?
        .add_rules(path_beneath_rules(SYSTEM, AccessFs::from_read(abi)))?
        .add_rules(path_beneath_rules(SYSTEM_SINKS, AccessFs::from_file(abi)))?
        .add_rules(path_beneath_rules(
            &request.readable,
            AccessFs::from_read(abi),
        ))?
        .add_rules(path_beneath_rules(&writable, AccessFs::from_all(abi)))
}

/// The temporary folders of a renderer's own root (see `root.rs`): private to its line.
pub(super) const PRIVATE_TEMPORARY: &[&str] = &["/tmp", "/dev/shm"];

/// Whether Landlock will hold the renderer, in words for the report: the rules are tried on a
/// thread that ends at once (Landlock binds the thread that asks, and what it starts).
pub fn landlock_state(request: &Request) -> String {
    let request = request.clone();
    let tried = std::thread::Builder::new().spawn(move || {
        match ruleset(&request, false).and_then(|r| r.restrict_self()) {
            Ok(status) => match status.ruleset {
                RulesetStatus::FullyEnforced => "fully enforced".to_string(),
                RulesetStatus::PartiallyEnforced => "partially enforced (an older kernel)".into(),
                RulesetStatus::NotEnforced => "not available on this kernel".into(),
            },
            Err(e) => format!("not used ({e})"),
        }
    });
    match tried.map(|thread| thread.join()) {
        Ok(Ok(state)) => state,
        _ => "not tried (no thread could be started)".to_string(),
    }
}

/// What the renderer's process does to itself between fork and exec: it dies with its
/// supervisor, takes its limits (`count_processes` where its process count is its own), and
/// binds itself by Landlock's rules and the seccomp filter that closes the keyrings.
pub fn in_child(
    request: &Request,
    count_processes: bool,
    own_root: bool,
) -> impl FnMut() -> std::io::Result<()> + Send + Sync + 'static {
    let request = request.clone();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    // CPU seconds: the wall-clock limit on every core, and one more.
    let cpu = (request.limit.as_secs() + 1) * cores + 1;
    let keyrings_closed = super::seccomp::program();
    move || {
        rustix::process::set_parent_process_death_signal(Some(Signal::KILL))?;
        // No set-user-ID program may give the renderer more than it has, Landlock or not.
        rustix::thread::set_no_new_privs(true)?;
        let limits = request.limits;
        lower(Resource::As, limits.memory)?;
        lower(Resource::Fsize, limits.file_size)?;
        lower(Resource::Nofile, limits.open_files)?;
        lower(Resource::Core, 0)?;
        lower(Resource::Cpu, cpu)?;
        if count_processes {
            lower(Resource::Nproc, limits.processes)?;
        }
        // Where Landlock is missing the renderer runs without it (the report says so).
        if let Ok(ruleset) = ruleset(&request, own_root) {
            let _ = ruleset.restrict_self();
        }
        // Where seccomp is missing, likewise (the report's `keyrings_closed` says so).
        let _ = super::seccomp::bind(&keyrings_closed);
        Ok(())
    }
}

/// Sets a limit to `value`, or to the hard limit already there where that is lower.
fn lower(resource: Resource, value: u64) -> std::io::Result<()> {
    let hard = rustix::process::getrlimit(resource).maximum;
    let value = hard.map_or(value, |hard| hard.min(value));
    rustix::process::setrlimit(
        resource,
        Rlimit {
            current: Some(value),
            maximum: Some(value),
        },
    )?;
    Ok(())
}
