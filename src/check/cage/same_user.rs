//! On macOS and Windows a renderer runs as check's own user (check never switches users there),
//! so nothing has to be made reachable for another user.

use std::path::{Path, PathBuf};

use super::Staged;

/// No other user to run renderers as.
pub fn unprivileged_user(_needed: &[PathBuf]) -> Option<Result<(u32, u32), String>> {
    None
}

/// The command and readable paths as they are: check's own user reaches them.
pub fn stage(command: &[String], readable: &[PathBuf], _area: &Path) -> Result<Staged, String> {
    Ok(Staged {
        command: command.to_vec(),
        readable: readable.to_vec(),
        note: None,
    })
}
