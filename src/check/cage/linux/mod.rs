//! The cage on Linux: a supervisor per line that enters the line's namespaces (user, network,
//! IPC, PID) and forks the line's init, which builds the renderer's own root (`root.rs`) and
//! runs it under Landlock and resource limits (`confine.rs`), as an unprivileged user when
//! check runs as root (`reach.rs`), and ends every process it started (`reap.rs`). Before any
//! line runs, `wall.rs` finds out whether the suite's references are out of the renderer's
//! reach.

mod cgroup;
mod confine;
mod reach;
mod reap;
mod root;
mod seccomp;
mod supervisor;
mod wall;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use super::{Confinement, Ending, Limits, Request, Staged, run};

pub use super::unix::is_root;
pub(super) use super::unix::{ask_to_stop, detach};
pub use confine::SYSTEM;
pub use reach::stage;
pub use seccomp::keyrings_state;
pub use supervisor::supervise;
pub use wall::Wall;

/// The user a renderer runs as when check runs as root: `nobody` (its ids from /etc/passwd,
/// 65534 where it is not listed), provided it can reach every path the renderer needs;
/// `Err` says why not (check's own user is kept, and the report says so).
pub fn unprivileged_user(needed: &[PathBuf]) -> Option<Result<(u32, u32), String>> {
    if !rustix::process::geteuid().is_root() {
        return None;
    }
    let (uid, gid) = std::fs::read_to_string("/etc/passwd")
        .ok()
        .and_then(|passwd| {
            passwd.lines().find_map(|l| {
                let fields: Vec<&str> = l.split(':').collect();
                (fields.len() > 3 && fields[0] == "nobody")
                    .then(|| Some((fields[2].parse().ok()?, fields[3].parse().ok()?)))
                    .flatten()
            })
        })
        .unwrap_or((65534, 65534));
    for path in needed {
        if let Err(why) = reachable_by_others(path) {
            return Some(Err(why));
        }
    }
    Some(Ok((uid, gid)))
}

/// Whether any user may reach `path`: every folder above it searchable by others, and the file
/// itself readable by others (and, for a folder, searchable).
pub(super) fn reachable_by_others(path: &Path) -> Result<(), String> {
    let path = std::fs::canonicalize(path).map_err(|e| format!("{}: {e}", path.display()))?;
    for folder in path.ancestors().skip(1) {
        let mode = std::fs::metadata(folder)
            .map_err(|e| format!("{}: {e}", folder.display()))?
            .permissions()
            .mode();
        if mode & 0o001 == 0 {
            return Err(format!(
                "{} (mode {:o}) is closed to other users",
                folder.display(),
                mode & 0o777
            ));
        }
    }
    let metadata = std::fs::metadata(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let needs = if metadata.is_dir() { 0o005 } else { 0o004 };
    let mode = metadata.permissions().mode();
    if mode & needs != needs {
        return Err(format!(
            "{} (mode {:o}) is closed to other users",
            path.display(),
            mode & 0o777
        ));
    }
    Ok(())
}
