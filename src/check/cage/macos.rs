//! The cage on macOS (and other Unix systems without Linux's namespaces): a line's supervisor
//! (raycast started as `raycast __supervise REQUEST`) starts the renderer in a process group
//! of its own, under resource limits (file size, open files, no core files), with a private
//! HOME and TMPDIR, and through the system's sandbox where it has one (`sandbox-exec`, with a
//! profile that denies the network, every write outside the line's folders, and every read of
//! the suite). At the line's end, or its deadline, the whole group is killed.
//!
//! Why `sandbox-exec`: it is the only way an ordinary program on macOS confines another's
//! files and network without an entitlement or an administrator; Apple calls it deprecated,
//! yet every release to date ships it and its own services use the same profiles. Where it is
//! missing or refuses, the renderer runs without it, the report says so, and a class of other
//! people's programs is refused without `--no-cage`.
//!
//! What it does not do: a renderer that leaves its process group (`setsid`) outlives the line,
//! and memory is bounded per process only where the system enforces `RLIMIT_AS`.

// Preparing the renderer between fork and exec (`pre_exec`) needs an unsafe block.
#![allow(unsafe_code)]

use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

use super::{Confinement, Ending, Limits, Request, report};

pub use super::same_user::{stage, unprivileged_user};
pub use super::unix::is_root;
pub(super) use super::unix::{ask_to_stop, detach};

/// The folders every program may read.
pub const SYSTEM: &[&str] = &[
    "/bin",
    "/sbin",
    "/usr",
    "/System",
    "/Library",
    "/etc",
    "/private/etc",
    "/opt",
    "/dev",
    "/Applications",
];

/// The system's sandbox program.
const SANDBOX_EXEC: &str = "/usr/bin/sandbox-exec";

/// What keeps a renderer from the references here: the sandbox, where it works.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Wall {
    /// Whether `sandbox-exec` confines a program on this machine, or why not.
    pub sandbox: Result<(), String>,
}

impl Wall {
    /// The wall on this machine (the same for every suite: the sandbox's profile names it).
    pub fn find(_suite: &Path, _root: bool) -> Wall {
        Wall {
            sandbox: sandbox_works(),
        }
    }

    /// `Ok` where the sandbox holds, or for one's own renderer; for other people's programs
    /// without a sandbox, why not and what to do.
    pub fn holds(&self, others: bool) -> Result<(), String> {
        match &self.sandbox {
            Ok(()) => Ok(()),
            Err(_) if !others => Ok(()),
            Err(why) => Err(format!(
                "nothing here keeps a renderer from the suite's references and from writing \
                 outside its folders (the system's sandbox: {why}): grade other people's \
                 programs on a machine whose sandbox works, or give --no-cage to grade them \
                 here anyway"
            )),
        }
    }
}

/// Whether `sandbox-exec` runs a program under a profile here.
fn sandbox_works() -> Result<(), String> {
    if !Path::new(SANDBOX_EXEC).is_file() {
        return Err(format!("{SANDBOX_EXEC} is not on this system"));
    }
    let ran = Command::new(SANDBOX_EXEC)
        .args([
            "-p",
            "(version 1)(allow default)(deny network*)",
            "/usr/bin/true",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    match ran {
        Ok(status) if status.success() => Ok(()),
        Ok(status) => Err(format!("{SANDBOX_EXEC} refused a profile ({status})")),
        Err(e) => Err(format!("{SANDBOX_EXEC} cannot run: {e}")),
    }
}

/// The sandbox's profile: everything allowed but the network, writes outside the line's
/// folders (the parameters WORK and OUT), and reads of the suite (HIDDEN0, HIDDEN1, ...).
/// Paths come in as parameters (`-D`), never spliced into the profile's text.
fn profile(hidden: usize) -> String {
    let mut profile = String::from(
        "(version 1)\n(allow default)\n(deny network*)\n(deny file-write*)\n\
         (allow file-write* (subpath (param \"WORK\")) (subpath (param \"OUT\")) \
         (literal \"/dev/null\") (literal \"/dev/zero\"))\n",
    );
    for k in 0..hidden {
        profile.push_str(&format!(
            "(deny file-read* (subpath (param \"HIDDEN{k}\")))\n"
        ));
    }
    profile
}

/// The supervisor's whole life: `request` is the JSON check passed. Its report goes to stdout;
/// the renderer's stderr and stdout go to the supervisor's stderr.
pub fn supervise(request: &str) -> ExitCode {
    report::serve(request, run)
}

fn run(request: &Request) -> (Ending, Confinement) {
    let stop = super::unix::stop_when_signalled();
    let mut cage = Confinement {
        user: "check's own user".to_string(),
        landlock: "not on this system".to_string(),
        own_root: Err("not on this system".to_string()),
        sandbox: sandbox_works(),
        subreaper: true,
        ..Confinement::default()
    };
    let Some((program, own)) = request.command.split_first() else {
        return (Ending::NotStarted("no renderer given".into()), cage);
    };
    // The sandbox names real paths (/var is /private/var here).
    let real = |path: &Path| std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let mut command = match &cage.sandbox {
        Ok(()) => {
            let mut command = Command::new(SANDBOX_EXEC);
            command
                .arg("-D")
                .arg(format!("WORK={}", real(&request.work).display()))
                .arg("-D")
                .arg(format!("OUT={}", real(&request.outputs).display()));
            for (k, hidden) in request.hidden.iter().enumerate() {
                command
                    .arg("-D")
                    .arg(format!("HIDDEN{k}={}", real(hidden).display()));
            }
            command
                .arg("-p")
                .arg(profile(request.hidden.len()))
                .arg(program);
            command
        }
        Err(_) => Command::new(program),
    };
    let said = {
        use std::os::fd::AsFd;
        match std::io::stderr().as_fd().try_clone_to_owned() {
            Ok(fd) => Stdio::from(fd),
            Err(_) => Stdio::null(),
        }
    };
    command
        .args(own)
        .current_dir(&request.work)
        .env_clear()
        .envs(environment(request))
        .stdin(Stdio::null())
        .stdout(said)
        .stderr(Stdio::inherit())
        .process_group(0);
    let limits = request.limits;
    // SAFETY: the closure runs in the forked child before exec and only calls setrlimit, which
    // is async-signal-safe.
    unsafe {
        command.pre_exec(move || {
            set_limits(&limits);
            Ok(())
        });
    }
    let start = Instant::now();
    let mut child = match command.spawn() {
        Ok(child) => child,
        Err(e) => {
            cage.subreaper = false;
            return (Ending::NotStarted(format!("{program}: {e}")), cage);
        }
    };
    let group = child.id() as i32;
    let ending = super::wait_for(&mut child, start, request.limit, &stop, |status| {
        Ending::of_exit(status.code(), status.signal())
    });
    // The renderer's whole group, whatever it left running.
    // SAFETY: killpg on the group this supervisor made for the renderer.
    unsafe { libc::killpg(group, libc::SIGKILL) };
    let _ = child.wait();
    (ending, cage)
}

/// The renderer's resource limits (in the child, before exec).
fn set_limits(limits: &Limits) {
    let set = |resource, value: u64| {
        let limit = libc::rlimit {
            rlim_cur: value as libc::rlim_t,
            rlim_max: value as libc::rlim_t,
        };
        // SAFETY: a plain system call on this (child) process.
        unsafe { libc::setrlimit(resource, &limit) };
    };
    set(libc::RLIMIT_AS, limits.memory);
    set(libc::RLIMIT_FSIZE, limits.file_size);
    set(libc::RLIMIT_NOFILE, limits.open_files);
    set(libc::RLIMIT_CORE, 0);
}

/// The renderer's environment: the PATH, a private home and temporary folder, a locale.
fn environment(request: &Request) -> Vec<(String, PathBuf)> {
    let path = std::env::var("PATH").unwrap_or_else(|_| "/usr/bin:/bin:/usr/sbin:/sbin".into());
    vec![
        ("PATH".into(), PathBuf::from(path)),
        ("HOME".into(), request.work.join(".home")),
        ("TMPDIR".into(), request.work.join(".tmp")),
        ("LANG".into(), PathBuf::from("en_US.UTF-8")),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_names_every_hidden_folder_by_parameter() {
        let profile = profile(2);
        assert!(profile.contains("(deny network*)"));
        assert!(profile.contains("(param \"HIDDEN0\")"));
        assert!(profile.contains("(param \"HIDDEN1\")"));
        assert!(!profile.contains("HIDDEN2"));
    }

    #[test]
    fn a_class_without_a_sandbox_needs_no_cage_said_aloud() {
        let wall = Wall {
            sandbox: Err("not here".into()),
        };
        assert_eq!(wall.holds(false), Ok(()));
        assert!(wall.holds(true).unwrap_err().contains("--no-cage"));
        assert_eq!(Wall { sandbox: Ok(()) }.holds(true), Ok(()));
    }
}
