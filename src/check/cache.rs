//! raycast's own renders of a suite's lines, kept between runs: the shards of a class on other
//! machines, or the next run over the same suite, read them instead of rendering again. A
//! render is found by a key made of raycast's own program (its bytes: a rebuilt raycast renders
//! anew), the command line, the bytes of every file the line reads, and the answers the suite
//! pins its open questions to (a pinned answer's render is the reference).
//!
//! The renders of the faults check simulates are kept the same way, keyed by the fault as
//! planted (its parameters with it) instead of the pinned answers; and so are a line's
//! diagnoses, keyed by the student's pictures themselves (see [`KeptDiagnosis`]).
//!
//! The folder: `RAYCAST_CACHE_DIR`, or `$XDG_CACHE_HOME/raycast`, or `~/.cache/raycast`; set
//! `RAYCAST_CACHE_DIR=off` to keep nothing. After each run it is trimmed to
//! `RAYCAST_CACHE_SIZE` (1 GiB by default), the least recently used pictures first;
//! `raycast check cache clear` empties it.

use std::hash::{DefaultHasher, Hasher};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::rule::Rule;
use super::run::line_files;
use super::suite::{Line, Pin};
use crate::image_io::{self, ImageFormat};
use crate::shade::Image;

/// The size the folder is trimmed to when `RAYCAST_CACHE_SIZE` does not say.
const DEFAULT_LIMIT: u64 = 1 << 30;

/// Where renders are kept, if anywhere.
pub fn folder() -> Option<PathBuf> {
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
        let mut hasher = DefaultHasher::new();
        let bytes = std::env::current_exe()
            .and_then(std::fs::read)
            .unwrap_or_default();
        hasher.write(&bytes);
        hasher.finish()
    })
}

/// The renders of one line kept: raycast's own (the reference where the suite has none) and
/// each fault's, the line's files read once.
pub struct LineRenders {
    folder: Option<PathBuf>,
    /// Raycast's program, the command line and the bytes of every file the line reads.
    line: DefaultHasher,
    images: usize,
}

impl LineRenders {
    /// The kept renders of `line`, whose files are in `scenes`.
    pub fn of(line: &Line, scenes: &Path) -> LineRenders {
        let folder = folder();
        let mut hasher = DefaultHasher::new();
        hasher.write_u64(program());
        hasher.write(line.command.as_bytes());
        for file in line_files(line, scenes) {
            hasher.write(file.to_string_lossy().as_bytes());
            hasher.write(&std::fs::read(scenes.join(&file)).unwrap_or_default());
        }
        LineRenders {
            folder,
            line: hasher,
            images: line.outputs.len(),
        }
    }

    /// The key of raycast's render with the answers `pinned`, or of a fault's, as planted.
    fn key(&self, pinned: &[Pin], planted: Option<&str>) -> String {
        let mut hasher = self.line.clone();
        write_pins(&mut hasher, pinned);
        if let Some(planted) = planted {
            hasher.write(b"planted");
            hasher.write(planted.as_bytes());
        }
        format!("{}-{:016x}", env!("CARGO_PKG_VERSION"), hasher.finish())
    }

    /// The line's pictures as raycast renders them with the answers `pinned`: kept, or rendered
    /// by `render` and kept.
    pub fn course<E>(
        &self,
        pinned: &[Pin],
        render: impl FnOnce() -> Result<Vec<Image>, E>,
    ) -> Result<Vec<Image>, E> {
        self.kept_or(&self.key(pinned, None), render)
    }

    /// The line's pictures as a student's renderer with the fault `planted` (its `Debug` form,
    /// parameters and all) renders them: kept, or rendered by `render` and kept. A fault's
    /// render depends on the line and the fault alone, not on the student: a class renders it
    /// once for all its students, and a student's next run not at all.
    pub fn fault<E>(
        &self,
        planted: &str,
        render: impl FnOnce() -> Result<Vec<Image>, E>,
    ) -> Result<Vec<Image>, E> {
        self.kept_or(&self.key(&[], Some(planted)), render)
    }

    /// Whether the fault `planted`'s render is kept.
    pub fn has_fault(&self, planted: &str) -> bool {
        let key = self.key(&[], Some(planted));
        self.folder
            .as_ref()
            .is_some_and(|folder| (0..self.images).all(|k| file(folder, &key, k).is_file()))
    }

    /// The line's identity: raycast's program, the command line and the bytes of its files.
    pub fn identity(&self) -> u64 {
        self.line.finish()
    }

    /// Whether renders are kept at all (`RAYCAST_CACHE_DIR` is not `off`).
    pub fn keeps(&self) -> bool {
        self.folder.is_some()
    }

    /// The faults (as planted) whose render of the line's image `image` is alike to
    /// `planted`'s, itself among them, where a search has found them.
    pub fn same_pictures(&self, planted: &str, image: usize) -> Option<Vec<String>> {
        let folder = self.folder.as_ref()?;
        let path = folder.join(format!("{}-{image}.same", self.key(&[], Some(planted))));
        let text = std::fs::read_to_string(&path).ok()?;
        used(&path);
        Some(text.lines().map(String::from).collect())
    }

    /// Keeps which faults' renders of the line's image `image` are alike to `planted`'s.
    pub fn keep_same_pictures(&self, planted: &str, image: usize, same: &[String]) {
        let Some(folder) = &self.folder else {
            return;
        };
        let key = format!("{}-{image}", self.key(&[], Some(planted)));
        let aside = folder.join(format!(".{key}.same.{}", std::process::id()));
        if std::fs::create_dir_all(folder).is_ok()
            && std::fs::write(&aside, same.join("\n")).is_ok()
        {
            let _ = std::fs::rename(&aside, folder.join(format!("{key}.same")));
        }
    }

    /// The diagnosis `asked` (which question: the faults, the allowed answers with the suite's
    /// `pinned` ones) of the student's `pictures` of the line (each image's index among the
    /// line's outputs, the student's picture and its reference) under `rule`, kept or to keep.
    /// It depends on raycast's program, the line and those pictures alone, so it is found again
    /// by their bytes.
    pub fn diagnosis(
        &self,
        asked: &str,
        pinned: &[Pin],
        pictures: &[(usize, &Image, Option<&Image>)],
        rule: Rule,
    ) -> KeptDiagnosis {
        let mut hasher = self.line.clone();
        hasher.write(b"diagnosis");
        hasher.write(asked.as_bytes());
        write_pins(&mut hasher, pinned);
        hasher.write_u8(rule.tolerance);
        hasher.write_u64(rule.max_bad.to_bits());
        for &(image, actual, reference) in pictures {
            hasher.write_usize(image);
            for picture in std::iter::once(Some(actual)).chain([reference]) {
                match picture {
                    Some(picture) => {
                        hasher.write_u32(picture.width);
                        hasher.write_u32(picture.height);
                        hasher.write(picture.pixels.as_flattened());
                    }
                    None => hasher.write_u8(0),
                }
            }
        }
        let key = format!("{}-{:016x}", env!("CARGO_PKG_VERSION"), hasher.finish());
        KeptDiagnosis {
            place: self.folder.clone().map(|folder| (folder, key)),
        }
    }

    fn kept_or<E>(
        &self,
        key: &str,
        render: impl FnOnce() -> Result<Vec<Image>, E>,
    ) -> Result<Vec<Image>, E> {
        let Some(folder) = &self.folder else {
            return render();
        };
        let kept: Option<Vec<Image>> = (0..self.images)
            .map(|k| {
                let path = file(folder, key, k);
                let image = super::read_image(&path).ok()?;
                used(&path);
                Some(image)
            })
            .collect();
        if let Some(kept) = kept {
            return Ok(kept);
        }
        let pictures = render()?;
        if std::fs::create_dir_all(folder).is_ok() {
            for (k, picture) in pictures.iter().enumerate() {
                // Written aside and renamed: a run beside this one reads a whole picture or
                // none.
                let aside = folder.join(format!(".{key}-{k}.{}.png", std::process::id()));
                if std::fs::write(&aside, image_io::encode(picture, ImageFormat::Png)).is_ok() {
                    let _ = std::fs::rename(&aside, file(folder, key, k));
                }
            }
        }
        Ok(pictures)
    }
}

/// The answers the suite pins its open questions to, into a key.
fn write_pins(hasher: &mut DefaultHasher, pinned: &[Pin]) {
    for pin in pinned {
        hasher.write(pin.choice.name.as_bytes());
        hasher.write(pin.answer.map_or("raycast", |a| a.name).as_bytes());
    }
}

/// A line's diagnosis of a student's pictures, kept in the folder (or nowhere, with
/// `RAYCAST_CACHE_DIR=off`) as the text its asker wrote.
pub struct KeptDiagnosis {
    place: Option<(PathBuf, String)>,
}

impl KeptDiagnosis {
    /// The text kept, where a run before this one kept it.
    pub fn read(&self) -> Option<String> {
        let (folder, key) = self.place.as_ref()?;
        let path = folder.join(format!("{key}.diagnosis"));
        let text = std::fs::read_to_string(&path).ok()?;
        used(&path);
        Some(text)
    }

    /// Keeps `text`: written aside and renamed, so that a run beside this one reads all of it
    /// or none.
    pub fn keep(&self, text: &str) {
        let Some((folder, key)) = &self.place else {
            return;
        };
        let aside = folder.join(format!(".{key}.diagnosis.{}", std::process::id()));
        if std::fs::create_dir_all(folder).is_ok() && std::fs::write(&aside, text).is_ok() {
            let _ = std::fs::rename(&aside, folder.join(format!("{key}.diagnosis")));
        }
    }
}

/// Picture `k` of the render `key`.
fn file(folder: &Path, key: &str, k: usize) -> PathBuf {
    folder.join(format!("{key}-{k}.png"))
}

/// Marks a kept picture as used now: the least recently used go first when the folder is
/// trimmed (a file's access time is not kept on many systems; its modification time is).
fn used(path: &Path) {
    if let Ok(file) = std::fs::File::options().append(true).open(path) {
        let _ = file.set_modified(std::time::SystemTime::now());
    }
}

/// The most the folder may hold: `RAYCAST_CACHE_SIZE` (bytes, or with K, M or G), or 1 GiB.
pub fn limit() -> Result<u64, String> {
    match std::env::var("RAYCAST_CACHE_SIZE") {
        Err(_) => Ok(DEFAULT_LIMIT),
        Ok(text) => parse_size(&text).ok_or_else(|| {
            format!(
                "RAYCAST_CACHE_SIZE: expected a size in bytes, or with K, M or G after it (as 512M), found '{text}'"
            )
        }),
    }
}

/// Bytes, or a number with K, M or G (powers of 1024) after it.
fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let split = text
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let number: u64 = number.parse().ok()?;
    let shift = match unit {
        "" => 0,
        "K" | "k" => 10,
        "M" | "m" => 20,
        "G" | "g" => 30,
        _ => return None,
    };
    number.checked_mul(1 << shift)
}

/// The kept pictures: how many, and their bytes.
pub fn usage() -> (usize, u64) {
    let entries = pictures_kept();
    let pictures = entries
        .iter()
        .filter(|e| e.0.extension().is_some_and(|x| x == "png"))
        .count();
    (pictures, entries.iter().map(|e| e.1).sum())
}

/// Every kept file (pictures, records of renders alike, diagnoses): its path, bytes and last
/// use.
fn pictures_kept() -> Vec<(PathBuf, u64, std::time::SystemTime)> {
    let Some(folder) = folder() else {
        return Vec::new();
    };
    let Ok(entries) = std::fs::read_dir(folder) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|entry| {
            let name = entry.file_name().to_string_lossy().into_owned();
            !name.starts_with('.')
                && [".png", ".same", ".diagnosis"]
                    .iter()
                    .any(|kind| name.ends_with(kind))
        })
        .filter_map(|entry| {
            let metadata = entry.metadata().ok()?;
            let modified = metadata.modified().ok()?;
            metadata
                .is_file()
                .then(|| (entry.path(), metadata.len(), modified))
        })
        .collect()
}

/// Removes the least recently used pictures until the folder holds at most `limit` bytes.
/// Returns how many were removed.
pub fn trim(limit: u64) -> usize {
    let mut kept = pictures_kept();
    let mut total: u64 = kept.iter().map(|e| e.1).sum();
    kept.sort_by_key(|e| e.2);
    let mut removed = 0;
    for (path, bytes, _) in kept {
        if total <= limit {
            break;
        }
        if std::fs::remove_file(&path).is_ok() {
            total -= bytes;
            removed += 1;
        }
    }
    removed
}
