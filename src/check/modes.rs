//! File modes and owners, where the system has them. On Linux and macOS check gives a line's
//! folders to the user its renderer runs as and opens or closes them by mode; Windows keeps
//! rights in access lists instead, and there a renderer always runs as check's own user, so
//! the modes asked for here have nothing to say (the cage's job object and the folders it is
//! given do the work).

use std::path::Path;

/// Sets `path`'s mode (the permission bits of `chmod`); on Windows, whether it is read-only
/// (a mode with no write bit).
pub fn set_mode(path: &Path, mode: u32) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode))
    }
    #[cfg(not(unix))]
    {
        let mut permissions = std::fs::metadata(path)?.permissions();
        permissions.set_readonly(mode & 0o222 == 0);
        std::fs::set_permissions(path, permissions)
    }
}

/// Whether a file may be run as a program: an execute bit where there are modes; on Windows
/// any file (the system decides by its kind when it is started).
pub fn is_executable(metadata: &std::fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        metadata.permissions().mode() & 0o111 != 0
    }
    #[cfg(not(unix))]
    {
        metadata.is_file()
    }
}

/// Gives `path` (not following a link) to user `uid` and group `gid`.
pub fn give(path: &Path, (uid, gid): (u32, u32)) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::lchown(path, Some(uid), Some(gid))
    }
    #[cfg(not(unix))]
    {
        let _ = (path, uid, gid);
        Ok(())
    }
}

/// Makes `target` a link to `link`; where links need rights a user lacks (Windows), a copy of
/// what it points to.
pub fn copy_link(link: &Path, beside: &Path, target: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        let _ = beside;
        std::os::unix::fs::symlink(link, target)
    }
    #[cfg(not(unix))]
    {
        let _ = link;
        std::fs::copy(beside, target).map(|_| ())
    }
}

/// Copies the folder `from` to `to`: files, folders and links as they are (a link is read by
/// no one but the caged renderer, which Landlock keeps inside).
pub fn copy_tree(from: &Path, to: &Path) -> Result<(), String> {
    let failed = |path: &Path, e: std::io::Error| format!("{}: {e}", path.display());
    std::fs::create_dir_all(to).map_err(|e| failed(to, e))?;
    for entry in std::fs::read_dir(from).map_err(|e| failed(from, e))? {
        let entry = entry.map_err(|e| failed(from, e))?;
        let path = entry.path();
        let kind = entry.file_type().map_err(|e| failed(&path, e))?;
        let target = to.join(entry.file_name());
        if kind.is_dir() {
            copy_tree(&path, &target)?;
        } else if kind.is_symlink() {
            let link = std::fs::read_link(&path).map_err(|e| failed(&path, e))?;
            copy_link(&link, &path, &target).map_err(|e| failed(&target, e))?;
        } else if kind.is_file() {
            std::fs::copy(&path, &target).map_err(|e| failed(&path, e))?;
        }
    }
    Ok(())
}
