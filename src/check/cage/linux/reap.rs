//! Ending everything a renderer left behind: its supervisor is the subreaper of the renderer's
//! tree, so every orphan (setsid, double forks) becomes the supervisor's child, and killing its
//! children until it has none ends the whole tree.

use std::time::{Duration, Instant};

use rustix::process::{Pid, Signal, WaitOptions};

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
