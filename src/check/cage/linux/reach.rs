//! A renderer never runs as root. When check runs as root, the renderer runs as an
//! unprivileged user, who must be able to reach its program and what it reads; what that user
//! cannot reach (a renderer under /root, a home folder of mode 750 under `sudo`) is copied into
//! check's scratch, open to every user, and the renderer runs from the copy. What cannot be
//! copied is refused before any line runs, naming the path and the fix.

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use super::Staged;

/// The most a renderer's folder may hold to be copied whole: a project's sources and build.
const FOLDER_BYTES: u64 = 256 << 20;
/// And the most files.
const FOLDER_FILES: usize = 20_000;

/// Makes `command` (its program first) and `readable` reachable by other users, copying into
/// `area` (a folder other users may pass through) each readable path they cannot reach. The
/// program's folder is copied whole when it is small enough, else the program alone.
pub fn stage(command: &[String], readable: &[PathBuf], area: &Path) -> Result<Staged, String> {
    let program = PathBuf::from(&command[0]);
    let mut staged = Staged {
        command: command.to_vec(),
        readable: Vec::new(),
        note: None,
    };
    let mut copied = Vec::new();
    for (k, path) in readable.iter().enumerate() {
        let Err(why) = super::reachable_by_others(path) else {
            staged.readable.push(path.clone());
            continue;
        };
        let copy = area.join(format!("{k}"));
        let holds_program = program.starts_with(path);
        let target = if path.is_dir() {
            copy.clone()
        } else {
            copy.join(file_name(path))
        };
        let (from, to) = match copy_open(path, &target, &mut Budget::default()) {
            Ok(()) => (path.clone(), target),
            // A program's folder too big to copy (a build folder): the program alone.
            Err(_) if holds_program => {
                let _ = std::fs::remove_dir_all(&copy);
                let alone = copy.join(file_name(&program));
                copy_open(&program, &alone, &mut Budget::default())
                    .map_err(|e| refusal(path, &why, &e))?;
                (program.clone(), alone)
            }
            Err(e) => return Err(refusal(path, &why, &e)),
        };
        open_path_to(area)?;
        for word in staged.command.iter_mut() {
            if let Ok(rest) = Path::new(word.as_str()).strip_prefix(&from) {
                let renamed = if rest.as_os_str().is_empty() {
                    to.clone()
                } else {
                    to.join(rest)
                };
                *word = renamed.display().to_string();
            }
        }
        staged.readable.push(if to.is_dir() {
            to.clone()
        } else {
            to.parent().unwrap_or(&to).to_path_buf()
        });
        copied.push(format!("{} ({why})", from.display()));
    }
    if !copied.is_empty() {
        staged.note = Some(format!(
            "check ran as root, so the renderer ran as an unprivileged user, from copies of what \
             that user could not reach: {}",
            copied.join("; ")
        ));
    }
    Ok(staged)
}

/// Why check will not run the renderer, and what to do.
fn refusal(path: &Path, why: &str, copy: &str) -> String {
    format!(
        "check runs as root, and never runs a renderer as root; the user it runs renderers as \
         cannot reach {} ({why}), and it could not be copied where that user can ({copy}). \
         Run check as an ordinary user, or open the path to other users (chmod o+rx on it and \
         on each folder above it)",
        path.display()
    )
}

fn file_name(path: &Path) -> PathBuf {
    PathBuf::from(path.file_name().unwrap_or(path.as_os_str()))
}

/// What a copy has used of the folder's allowance.
#[derive(Default)]
struct Budget {
    bytes: u64,
    files: usize,
}

/// Copies `from` (a file or a folder, links kept as links) to `to`, every folder searchable and
/// every file readable by other users, within the allowance.
fn copy_open(from: &Path, to: &Path, budget: &mut Budget) -> Result<(), String> {
    let failed = |path: &Path, e: std::io::Error| format!("{}: {e}", path.display());
    let metadata = std::fs::symlink_metadata(from).map_err(|e| failed(from, e))?;
    budget.files += 1;
    if budget.files > FOLDER_FILES {
        return Err(format!("more than {FOLDER_FILES} files"));
    }
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent).map_err(|e| failed(parent, e))?;
    }
    if metadata.is_symlink() {
        let link = std::fs::read_link(from).map_err(|e| failed(from, e))?;
        return std::os::unix::fs::symlink(link, to).map_err(|e| failed(to, e));
    }
    if metadata.is_dir() {
        std::fs::create_dir_all(to).map_err(|e| failed(to, e))?;
        std::fs::set_permissions(to, std::fs::Permissions::from_mode(0o755))
            .map_err(|e| failed(to, e))?;
        for entry in std::fs::read_dir(from).map_err(|e| failed(from, e))? {
            let entry = entry.map_err(|e| failed(from, e))?;
            copy_open(&entry.path(), &to.join(entry.file_name()), budget)?;
        }
        return Ok(());
    }
    if !metadata.is_file() {
        // A socket, a FIFO or a device is no part of a renderer.
        return Ok(());
    }
    budget.bytes += metadata.len();
    if budget.bytes > FOLDER_BYTES {
        return Err(format!("more than {} MiB", FOLDER_BYTES >> 20));
    }
    std::fs::copy(from, to).map_err(|e| failed(from, e))?;
    // Readable by all; executable by all where its owner may run it; never set-user-ID.
    let mode = metadata.permissions().mode() & 0o777;
    let open = 0o444 | if mode & 0o100 != 0 { 0o111 } else { 0 } | (mode & 0o200);
    std::fs::set_permissions(to, std::fs::Permissions::from_mode(open)).map_err(|e| failed(to, e))
}

/// Lets other users pass through `area` (never list it).
fn open_path_to(area: &Path) -> Result<(), String> {
    std::fs::set_permissions(area, std::fs::Permissions::from_mode(0o711))
        .map_err(|e| format!("{}: {e}", area.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_folder_is_copied_open_and_the_command_renamed_into_it() {
        let dir = tempfile::tempdir().unwrap();
        let closed = dir.path().join("home/student");
        std::fs::create_dir_all(closed.join("data")).unwrap();
        std::fs::write(closed.join("raytracer"), "#!/bin/sh\n").unwrap();
        std::fs::write(closed.join("data/table.txt"), "1 2 3\n").unwrap();
        std::fs::set_permissions(
            closed.join("raytracer"),
            std::fs::Permissions::from_mode(0o4700),
        )
        .unwrap();
        std::fs::set_permissions(&closed, std::fs::Permissions::from_mode(0o700)).unwrap();
        let area = dir.path().join("area");
        std::fs::create_dir_all(&area).unwrap();
        let program = closed.join("raytracer").display().to_string();
        let staged = stage(
            &[
                program,
                "-x".into(),
                closed.join("data").display().to_string(),
            ],
            std::slice::from_ref(&closed),
            &area,
        )
        .unwrap();
        let copy = area.join("0");
        assert_eq!(
            staged.command[0],
            copy.join("raytracer").display().to_string()
        );
        assert_eq!(staged.command[1], "-x");
        assert_eq!(staged.command[2], copy.join("data").display().to_string());
        assert_eq!(staged.readable, vec![copy.clone()]);
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o7777;
        // Readable and runnable by all, and never set-user-ID.
        assert_eq!(mode(&copy.join("raytracer")), 0o755);
        assert_eq!(mode(&copy.join("data")), 0o755);
        assert_eq!(mode(&copy.join("data/table.txt")) & 0o444, 0o444);
        assert!(staged.note.unwrap().contains("closed to other users"));
    }

    #[test]
    fn a_program_in_a_folder_too_big_to_copy_is_copied_alone() {
        let dir = tempfile::tempdir().unwrap();
        let build = dir.path().join("target");
        std::fs::create_dir_all(&build).unwrap();
        std::fs::write(build.join("raytracer"), "#!/bin/sh\n").unwrap();
        for k in 0..=FOLDER_FILES {
            std::fs::write(build.join(format!("object{k}.o")), "").unwrap();
        }
        std::fs::set_permissions(&build, std::fs::Permissions::from_mode(0o700)).unwrap();
        let area = dir.path().join("area");
        std::fs::create_dir_all(&area).unwrap();
        let program = build.join("raytracer").display().to_string();
        let staged = stage(
            std::slice::from_ref(&program),
            std::slice::from_ref(&build),
            &area,
        )
        .unwrap();
        assert_eq!(
            staged.command,
            [area.join("0/raytracer").display().to_string()]
        );
        assert_eq!(staged.readable, vec![area.join("0")]);
        assert_eq!(std::fs::read_dir(area.join("0")).unwrap().count(), 1);
    }
}
