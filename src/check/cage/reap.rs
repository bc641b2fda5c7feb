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
