//! check's scratch folders, known by name while they live, so that a second Ctrl-C (check
//! leaves at once, without its report) still removes them; and their removal, however a
//! renderer left them.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The scratch folders alive now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A scratch folder of check's: removed when dropped, or by [`remove_all_now`].
pub struct Scratch {
    path: PathBuf,
    /// Taken when it is removed by hand.
    dir: Option<tempfile::TempDir>,
}

impl Scratch {
    /// A new, empty scratch folder in the system's temporary folder.
    pub fn new() -> Result<Scratch, String> {
        let dir = tempfile::tempdir().map_err(|e| format!("cannot make a scratch folder: {e}"))?;
        Ok(Scratch::live(dir))
    }

    /// A new, empty scratch folder for the lines' folders (each line's copies of its scene
    /// files and the pictures it gave back): in memory where the machine has a shared one with
    /// room (see docs/check.md), in the system's temporary folder otherwise.
    pub fn for_lines() -> Result<Scratch, String> {
        let home = line_scratch_home(std::env::var_os("TMPDIR").is_some());
        let dir = tempfile::Builder::new()
            .tempdir_in(&home)
            .map_err(|e| format!("cannot make a scratch folder in {}: {e}", home.display()))?;
        Ok(Scratch::live(dir))
    }

    /// `dir`, known by name while it lives.
    fn live(dir: tempfile::TempDir) -> Scratch {
        if let Ok(mut live) = LIVE.lock() {
            live.push(dir.path().to_path_buf());
        }
        Scratch {
            path: dir.path().to_path_buf(),
            dir: Some(dir),
        }
    }

    /// Where it is.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Removes it, first giving back the rights a renderer may have taken from the folders it
    /// made; `Err` names what could not be removed, for a warning: a failed clean-up is never
    /// silent.
    pub fn remove(mut self) -> Result<(), String> {
        forget(&self.path);
        // Removed here, not again when dropped.
        self.dir.take().map(tempfile::TempDir::keep);
        remove(&self.path)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        forget(&self.path);
    }
}

/// Where the lines' folders go. Each line makes a handful of folders and files and check
/// removes them all: on a disk's file system that costs an inode allocation each (on ext4
/// without a journal, one that steps over every inode freed in the last seconds), half of a
/// warm class's own time; on a tmpfs it costs nothing. So, where no `TMPDIR` was given
/// (`tmpdir_given`), Linux's shared-memory folder, when it is a tmpfs anyone may write to with
/// at least [`LINE_SCRATCH_ROOM`] free (a container's 64 MiB one is not); the system's
/// temporary folder otherwise. A line's folder is removed as soon as it is graded, so what
/// it holds at once is a line per job, each bounded by the cage's limits.
fn line_scratch_home(tmpdir_given: bool) -> PathBuf {
    #[cfg(target_os = "linux")]
    if !tmpdir_given && let Some(memory) = shared_memory_with_room(Path::new("/dev/shm")) {
        return memory;
    }
    let _ = tmpdir_given;
    std::env::temp_dir()
}

/// The free bytes a shared-memory folder must have to hold the lines' folders.
#[cfg(target_os = "linux")]
pub const LINE_SCRATCH_ROOM: u64 = 2 << 30;

/// `folder`, when it is a tmpfs that anyone may write to (sticky, as /tmp) with at least
/// [`LINE_SCRATCH_ROOM`] bytes free.
#[cfg(target_os = "linux")]
fn shared_memory_with_room(folder: &Path) -> Option<PathBuf> {
    use std::os::unix::fs::PermissionsExt;
    const TMPFS_MAGIC: i64 = 0x0102_1994;
    let mode = std::fs::metadata(folder).ok()?.permissions().mode();
    #[allow(clippy::unnecessary_cast)]
    let tmpfs = rustix::fs::statfs(folder).ok()?.f_type as i64 == TMPFS_MAGIC;
    let room = rustix::fs::statvfs(folder).ok()?;
    let free = room.f_bavail.saturating_mul(room.f_frsize);
    (tmpfs && mode & 0o1777 == 0o1777 && free >= LINE_SCRATCH_ROOM).then(|| folder.to_path_buf())
}

/// Removes one folder inside a scratch folder (a line's, once graded), however its renderer
/// left it.
pub fn remove_inside(folder: &Path) -> Result<(), String> {
    remove(folder)
}

fn forget(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|p| p != path);
    }
}

/// Removes every scratch folder alive, as check leaves at once.
pub fn remove_all_now() {
    let live = LIVE.lock().map(|l| l.clone()).unwrap_or_default();
    for path in live {
        let _ = remove(&path);
    }
}

/// Removes a scratch folder, first giving back the rights a renderer may have taken from the
/// folders it made (one of mode 000 could not be emptied otherwise) and, on Windows, from its
/// files (a read-only file cannot be deleted there).
fn remove(path: &Path) -> Result<(), String> {
    fn open_up(path: &Path) {
        let metadata = std::fs::symlink_metadata(path);
        if cfg!(windows) && metadata.as_ref().is_ok_and(|m| m.is_file()) {
            let _ = super::modes::set_mode(path, 0o600);
        }
        if metadata.is_ok_and(|m| m.is_dir()) {
            let _ = super::modes::set_mode(path, 0o700);
            for entry in std::fs::read_dir(path).into_iter().flatten().flatten() {
                open_up(&entry.path());
            }
        }
    }
    open_up(path);
    std::fs::remove_dir_all(path).map_err(|e| {
        format!(
            "the scratch folder {} could not be removed ({e}): remove it by hand",
            path.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_tmpdir_holds_the_lines_folders() {
        assert_eq!(line_scratch_home(true), std::env::temp_dir());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn shared_memory_holds_the_lines_folders_only_when_open_to_everyone() {
        use std::os::unix::fs::PermissionsExt;
        let shm = Path::new("/dev/shm");
        let Ok(folder) = tempfile::tempdir_in(shm) else {
            return;
        };
        let set = |mode| {
            std::fs::set_permissions(folder.path(), std::fs::Permissions::from_mode(mode)).unwrap()
        };
        set(0o700);
        assert_eq!(shared_memory_with_room(folder.path()), None);
        set(0o1777);
        let free = rustix::fs::statvfs(folder.path()).unwrap();
        let room = free.f_bavail * free.f_frsize >= LINE_SCRATCH_ROOM;
        assert_eq!(
            shared_memory_with_room(folder.path()),
            room.then(|| folder.path().to_path_buf())
        );
    }
}
