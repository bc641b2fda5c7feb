//! raycast's own renders of a suite's lines, kept between runs: the shards of a class on other
//! machines, or the next run over the same suite, read them instead of rendering again. A
//! render is found by a key made of raycast's own program (its bytes: a rebuilt raycast renders
//! anew), the command line, the bytes of every file the line reads, and the answers the suite
//! pins its open questions to (a pinned answer's render is the reference).
//!
//! The folder: `RAYCAST_CACHE_DIR`, or `$XDG_CACHE_HOME/raycast`, or `~/.cache/raycast`; set
//! `RAYCAST_CACHE_DIR=off` to keep nothing.

use std::hash::Hasher;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::run::line_files;
use super::suite::{Line, Pin};
use crate::image_io::{self, ImageFormat};
use crate::shade::Image;

/// Where renders are kept, if anywhere.
fn folder() -> Option<PathBuf> {
    let base = match std::env::var_os("RAYCAST_CACHE_DIR") {
        Some(dir) if dir == "off" => return None,
        Some(dir) => PathBuf::from(dir),
        None => std::env::var_os("XDG_CACHE_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?
            .join("raycast"),
    };
    Some(base.join("references"))
}

/// A hash of raycast's own program, read once.
fn program() -> u64 {
    static PROGRAM: OnceLock<u64> = OnceLock::new();
    *PROGRAM.get_or_init(|| {
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        let bytes = std::env::current_exe()
            .and_then(std::fs::read)
            .unwrap_or_default();
        hasher.write(&bytes);
        hasher.finish()
    })
}

/// The key of `line`'s renders.
fn key(line: &Line, scenes: &Path, pinned: &[Pin]) -> String {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    hasher.write_u64(program());
    hasher.write(line.command.as_bytes());
    for pin in pinned {
        hasher.write(pin.choice.name.as_bytes());
        hasher.write(pin.answer.map_or("raycast", |a| a.name).as_bytes());
    }
    for file in line_files(line, scenes) {
        hasher.write(file.to_string_lossy().as_bytes());
        hasher.write(&std::fs::read(scenes.join(&file)).unwrap_or_default());
    }
    format!("{}-{:016x}", env!("CARGO_PKG_VERSION"), hasher.finish())
}

/// `line`'s pictures as raycast renders them: from the cache, or rendered by `render` and kept.
pub fn pictures(
    line: &Line,
    scenes: &Path,
    pinned: &[Pin],
    render: impl FnOnce() -> Result<Vec<Image>, String>,
) -> Result<Vec<Image>, String> {
    let Some(folder) = folder() else {
        return render();
    };
    let key = key(line, scenes, pinned);
    let path = |k: usize| folder.join(format!("{key}-{k}.png"));
    let kept: Option<Vec<Image>> = (0..line.outputs.len())
        .map(|k| super::read_image(&path(k)).ok())
        .collect();
    if let Some(kept) = kept {
        return Ok(kept);
    }
    let pictures = render()?;
    if std::fs::create_dir_all(&folder).is_ok() {
        for (k, picture) in pictures.iter().enumerate() {
            // Written aside and renamed: a run beside this one reads a whole picture or none.
            let aside = folder.join(format!(".{key}-{k}.{}.png", std::process::id()));
            if std::fs::write(&aside, image_io::encode(picture, ImageFormat::Png)).is_ok() {
                let _ = std::fs::rename(&aside, path(k));
            }
        }
    }
    Ok(pictures)
}
