//! The suite's fingerprint, taken before any renderer runs and again after: a renderer runs
//! with the user's rights and could change the suite's files (its references, its scenes) for
//! itself or for the next student; a change voids the grade and says which files changed.

use std::collections::hash_map::DefaultHasher;
use std::hash::Hasher;
use std::path::{Path, PathBuf};

/// The most files a suite's fingerprint reads (a suite of the course has a few hundred).
const MOST_FILES: usize = 100_000;

/// Every file of a suite (followed through links, as check reads them), with its length and a
/// hash of its bytes, in a fixed order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fingerprint(Vec<(PathBuf, u64, u64)>);

impl Fingerprint {
    /// Reads every file under `root`.
    pub fn of(root: &Path) -> Result<Fingerprint, String> {
        let mut files = Vec::new();
        walk(root, root, &mut files)?;
        files.sort();
        Ok(Fingerprint(files))
    }

    /// The files that differ between `self` and `later`: changed, added or gone.
    pub fn changed(&self, later: &Fingerprint) -> Vec<PathBuf> {
        let mut changed: Vec<PathBuf> = self
            .0
            .iter()
            .filter(|entry| !later.0.contains(entry))
            .chain(later.0.iter().filter(|entry| !self.0.contains(entry)))
            .map(|(path, _, _)| path.clone())
            .collect();
        changed.sort();
        changed.dedup();
        changed
    }
}

fn walk(root: &Path, dir: &Path, files: &mut Vec<(PathBuf, u64, u64)>) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
        let metadata = std::fs::metadata(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        if metadata.is_dir() {
            walk(root, &path, files)?;
        } else if metadata.is_file() {
            if files.len() >= MOST_FILES {
                return Err(format!(
                    "{}: more than {MOST_FILES} files in the suite",
                    root.display()
                ));
            }
            let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let mut hasher = DefaultHasher::new();
            hasher.write(&bytes);
            let relative = path.strip_prefix(root).unwrap_or(&path).to_path_buf();
            files.push((relative, bytes.len() as u64, hasher.finish()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_added_or_removed_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("reference/a3")).unwrap();
        std::fs::write(dir.path().join("COMMANDS.txt"), "raytracer\n").unwrap();
        std::fs::write(dir.path().join("reference/a3/x.png"), "x").unwrap();
        let before = Fingerprint::of(dir.path()).unwrap();
        assert!(
            before
                .changed(&Fingerprint::of(dir.path()).unwrap())
                .is_empty()
        );
        std::fs::write(dir.path().join("reference/a3/x.png"), "y").unwrap();
        std::fs::write(dir.path().join("new.txt"), "").unwrap();
        std::fs::remove_file(dir.path().join("COMMANDS.txt")).unwrap();
        let after = Fingerprint::of(dir.path()).unwrap();
        assert_eq!(
            before.changed(&after),
            [
                PathBuf::from("COMMANDS.txt"),
                PathBuf::from("new.txt"),
                PathBuf::from("reference/a3/x.png")
            ]
        );
    }
}
