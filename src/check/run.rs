//! Preparing a line's run: the renderer's program checked once, and each line's own folders (a
//! work folder with copies of the files the line reads, an output folder), owned by the user
//! the renderer runs as.

use std::path::{Path, PathBuf};

use super::suite::Line;

/// The files `line` reads, relative to the suite's scenes folder: its `-input` scene and the
/// meshes the scene names; every file of the folder where the scene cannot be read.
pub fn line_files(line: &Line, scenes: &Path) -> Vec<PathBuf> {
    let everything = || -> Vec<PathBuf> {
        std::fs::read_dir(scenes)
            .map(|entries| {
                entries
                    .filter_map(Result::ok)
                    .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
                    .map(|e| PathBuf::from(e.file_name()))
                    .collect()
            })
            .unwrap_or_default()
    };
    let Some(input) = line
        .args
        .iter()
        .position(|a| a == "-input")
        .and_then(|at| line.args.get(at + 1))
        .map(PathBuf::from)
        .filter(|p| inside(p))
    else {
        return everything();
    };
    let Ok(description) = crate::parse::read_scene(&scenes.join(&input)) else {
        return everything();
    };
    let beside = input.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut files = vec![input];
    for object in &description.objects {
        if let crate::parse::description::Shape::Mesh { file } = &object.shape {
            // Looked for beside the scene first, then in the working folder, as raycast does.
            for candidate in [beside.join(file), PathBuf::from(file)] {
                if inside(&candidate) && scenes.join(&candidate).is_file() {
                    files.push(candidate);
                }
            }
        }
    }
    files.sort();
    files.dedup();
    files
}

/// Whether a relative `path` stays inside the folder it is relative to.
pub(super) fn inside(path: &Path) -> bool {
    path.components().all(|c| {
        matches!(
            c,
            std::path::Component::Normal(_) | std::path::Component::CurDir
        )
    })
}

/// A line's folders: `work`, holding read-only copies of `files` from `scenes` and a private
/// home and temporary folder, `out` and `root`, empty; the first two owned by `user` where one is given (the
/// line's own folder above them can be passed through, not listed).
pub fn prepare(
    scenes: &Path,
    files: &[PathBuf],
    folder: &Path,
    user: Option<(u32, u32)>,
) -> Result<(PathBuf, PathBuf), String> {
    use super::modes;
    let failed = |path: &Path, e: std::io::Error| format!("{}: {e}", path.display());
    let work = folder.join("work");
    let out = folder.join("out");
    // The mount point of the renderer's own root (the cage's), empty.
    let root = folder.join("root");
    for made in [
        folder,
        &work,
        &out,
        &root,
        &work.join(".home"),
        &work.join(".tmp"),
    ] {
        std::fs::create_dir_all(made).map_err(|e| failed(made, e))?;
    }
    modes::set_mode(folder, 0o711).map_err(|e| failed(folder, e))?;
    for file in files {
        let target = work.join(file);
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(|e| failed(parent, e))?;
        }
        std::fs::copy(scenes.join(file), &target).map_err(|e| failed(&scenes.join(file), e))?;
        modes::set_mode(&target, 0o444).map_err(|e| failed(&target, e))?;
    }
    if let Some((uid, gid)) = user {
        for owned in [&work, &out, &work.join(".home"), &work.join(".tmp")] {
            modes::give(owned, (uid, gid)).map_err(|e| failed(owned, e))?;
        }
    }
    Ok((work, out))
}

/// Whether the renderer's program can run at all: found (on `PATH` for a bare name), a file,
/// executable. Asked once before any line, so that a wrong path is one clear error, not a
/// crash on every line.
pub fn check_program(program: &[String]) -> Result<PathBuf, String> {
    let Some(executable) = program.first() else {
        return Err("--renderer is empty: which program should be graded?".into());
    };
    // A path (`./raytracer`, `x64\Release\raytracer.exe` on Windows), or a name for the PATH.
    let path = if Path::new(executable).components().count() > 1 {
        with_program_extension(resolve(executable))
    } else {
        let on_path = std::env::var_os("PATH")
            .map(|p| {
                std::env::split_paths(&p)
                    .map(|d| with_program_extension(d.join(executable)))
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default();
        match on_path.into_iter().find(|p| p.is_file()) {
            Some(found) => found,
            None => {
                return Err(format!(
                    "--renderer: '{executable}' is not a program on PATH (give its path, such \
                     as ./{executable})"
                ));
            }
        }
    };
    let metadata = std::fs::metadata(&path)
        .map_err(|e| format!("--renderer: '{}' cannot be run: {e}", path.display()))?;
    if !metadata.is_file() {
        return Err(format!("--renderer: '{}' is not a file", path.display()));
    }
    if !super::modes::is_executable(&metadata) {
        return Err(format!(
            "--renderer: '{}' is not executable (chmod +x it, or name its interpreter: \
             --renderer \"python3 {}\")",
            path.display(),
            executable
        ));
    }
    Ok(path)
}

/// On Windows a program named without its extension (`raytracer`, as the course's command lines
/// name it) is found as the system finds it: `raytracer.exe`. Elsewhere, and where the name
/// is a file already, `path` itself.
fn with_program_extension(path: PathBuf) -> PathBuf {
    if cfg!(windows) && path.extension().is_none() && !path.is_file() {
        let exe = path.with_extension("exe");
        if exe.is_file() {
            return exe;
        }
    }
    path
}

/// A renderer named by a relative path (`./raytracer`) runs from its work folder, so it is made
/// absolute first; a bare name stays as it is, for the PATH.
fn resolve(executable: &str) -> PathBuf {
    let path = Path::new(executable);
    if path.components().count() > 1 && path.is_relative() {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    } else {
        path.to_path_buf()
    }
}
