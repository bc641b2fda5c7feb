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
        if let Ok(mut live) = LIVE.lock() {
            live.push(dir.path().to_path_buf());
        }
        Ok(Scratch {
            path: dir.path().to_path_buf(),
            dir: Some(dir),
        })
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
