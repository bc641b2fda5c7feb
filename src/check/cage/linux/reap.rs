//! Ending everything a renderer left behind: its supervisor is the subreaper of the renderer's
//! tree, so every orphan (setsid, double forks) becomes the supervisor's child, and killing its
//! children until it has none ends the whole tree.

use std::os::fd::OwnedFd;
use std::time::{Duration, Instant};

use rustix::event::{PollFd, PollFlags, Timespec};
use rustix::process::{Pid, PidfdFlags, Signal, WaitOptions};

/// How long the supervisor keeps killing: a tree that still forks faster than it is killed
/// after this long is left to the PID namespace (where there is one) and reported by check's
/// own deadline.
const AT_MOST: Duration = Duration::from_secs(5);

/// Kills the calling process's children and reaps them, again and again as orphans arrive,
/// until it has none.
pub fn end_descendants() {
    let me = rustix::process::getpid();
    let start = Instant::now();
    loop {
        // Any child, whatever its process group (a setsid orphan's is its own).
        loop {
            match rustix::process::wait(WaitOptions::NOHANG) {
                Ok(Some(_)) => continue,
                Ok(None) => break,
                // ECHILD: no child is left.
                Err(_) => return,
            }
        }
        for child in children_of(me) {
            let _ = rustix::process::kill_process(child, Signal::KILL);
        }
        if start.elapsed() > AT_MOST {
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The processes whose parent is `parent`, from /proc/*/stat.
fn children_of(parent: Pid) -> Vec<Pid> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    let parent = parent.as_raw_nonzero().get();
    entries
        .filter_map(|entry| {
            let pid: i32 = entry.ok()?.file_name().to_str()?.parse().ok()?;
            let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
            // "PID (COMMAND) STATE PPID ...": the command may hold spaces and parentheses.
            let after = &stat[stat.rfind(')')? + 1..];
            let ppid: i32 = after.split_whitespace().nth(1)?.parse().ok()?;
            (ppid == parent).then(|| Pid::from_raw(pid)).flatten()
        })
        .collect()
}

/// Ends every other process of the init's PID namespace: kill(-1) from its first process
/// reaches all of them, a re-forking bomb's newest too; then reaps them. Whatever is left when
/// the init exits, the kernel ends with the namespace.
#[allow(unsafe_code)]
pub fn end_namespace() {
    // kill(-1) from any other process would reach every process its user may signal.
    if rustix::process::getpid().as_raw_nonzero().get() != 1 {
        return end_descendants();
    }
    let start = Instant::now();
    loop {
        // SAFETY: kill has no memory effects; rustix has no wrapper for pid -1.
        unsafe { libc::kill(-1, libc::SIGKILL) };
        match rustix::process::wait(WaitOptions::NOHANG) {
            Ok(Some(_)) => continue,
            Err(_) => return,
            Ok(None) if start.elapsed() > AT_MOST => return,
            Ok(None) => std::thread::sleep(Duration::from_millis(1)),
        }
    }
}

/// A child's end to wait for: woken the moment it ends (a pidfd, where the kernel gives one:
/// Linux 5.3 on), or by short sleeps where it does not.
pub struct ChildEnd(Option<OwnedFd>);

/// The sleep between looks where there is no pidfd.
const WITHOUT_PIDFD: Duration = Duration::from_millis(2);

impl ChildEnd {
    pub fn of(child: Option<Pid>) -> ChildEnd {
        ChildEnd(
            child.and_then(|child| rustix::process::pidfd_open(child, PidfdFlags::empty()).ok()),
        )
    }

    /// Returns when the child has ended, a signal arrives, or `most` has passed.
    pub fn wait(&self, most: Duration) {
        let Some(pidfd) = &self.0 else {
            return std::thread::sleep(WITHOUT_PIDFD.min(most));
        };
        let timeout = Timespec {
            tv_sec: most.as_secs() as _,
            tv_nsec: most.subsec_nanos() as _,
        };
        let mut fds = [PollFd::new(pidfd, PollFlags::IN)];
        // An error (EINTR: a signal) ends the wait early, as a signal should.
        let _ = rustix::event::poll(&mut fds, Some(&timeout));
    }
}
