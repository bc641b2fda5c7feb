//! What a renderer may read by default: its own project. A program reads what was built beside
//! it (data in `../data`, libraries through CMake's `$ORIGIN/../lib`, a virtual environment's
//! `lib/`), and the cage is there to keep it from the suite, from other students and from the
//! rest of the machine, not from itself. So each program a renderer's command names (its
//! executable, a script it is given, the interpreter a script's `#!` line names) brings the
//! folder it is in, the prefix above a `bin/` folder, and the nearest folder above that is
//! plainly a project's root; never a home folder itself, a system folder, or a folder that
//! holds the suite.

use std::path::{Path, PathBuf};

/// What marks a project's root: a repository, a build's description, an environment's.
const PROJECT_MARKS: &[&str] = &[
    ".git",
    "CMakeLists.txt",
    "Makefile",
    "makefile",
    "GNUmakefile",
    "Cargo.toml",
    "pyproject.toml",
    "setup.py",
    "pyvenv.cfg",
    "conda-meta",
];

/// The suffixes of Visual Studio's and Xcode's project files, which also mark a root.
const PROJECT_SUFFIXES: &[&str] = &[".sln", ".vcxproj", ".xcodeproj"];

/// How far above a program's folder its project's root is looked for: `build/bin/raytracer`
/// under the root is the deepest common layout.
const LEVELS_UP: usize = 3;

/// The folders `program` brings for the renderer to read, the first being the one it is in.
/// `suite`: the suite's folder, made absolute.
pub fn own_folders(program: &Path, suite: &Path) -> Vec<PathBuf> {
    let mut folders = Vec::new();
    // As named (a virtual environment's `bin/python` is a link out of it) and as resolved.
    let mut named = vec![program.to_path_buf()];
    if let Ok(resolved) = std::fs::canonicalize(program) {
        named.push(resolved);
    }
    for path in named {
        if path.is_dir() {
            push(&mut folders, path, suite);
            continue;
        }
        let Some(folder) = path.parent() else {
            continue;
        };
        push(&mut folders, folder.to_path_buf(), suite);
        if folder.file_name().is_some_and(|n| n == "bin")
            && let Some(prefix) = folder.parent()
        {
            push(&mut folders, prefix.to_path_buf(), suite);
        }
        if let Some(root) = folder
            .ancestors()
            .take(LEVELS_UP + 1)
            .find(|f| is_project_root(f))
        {
            push(&mut folders, root.to_path_buf(), suite);
        }
    }
    folders
}

/// The interpreter a script's `#!` line names (through `/usr/bin/env NAME`, found on PATH), if
/// `program` is a script.
pub fn interpreter(program: &Path) -> Option<PathBuf> {
    use std::io::Read;
    let mut head = [0u8; 256];
    let n = std::fs::File::open(program).ok()?.read(&mut head).ok()?;
    let first = head[..n].split(|&b| b == b'\n').next()?;
    let line = std::str::from_utf8(first.strip_prefix(b"#!")?).ok()?;
    let mut words = line.split_whitespace();
    let named = PathBuf::from(words.next()?);
    if named.file_name().is_some_and(|n| n == "env") {
        let name = words.find(|w| !w.starts_with('-'))?;
        let path = std::env::var_os("PATH")?;
        return std::env::split_paths(&path)
            .map(|folder| folder.join(name))
            .find(|candidate| candidate.is_file());
    }
    Some(named)
}

/// Adds `folder` unless it is already there or must not be read: `/`, a home folder itself
/// (`/home/ana`, `/root`: the user's everything), a system folder (readable already), or one
/// that holds the suite.
fn push(folders: &mut Vec<PathBuf>, folder: PathBuf, suite: &Path) {
    let depth = folder.components().count();
    let home = std::env::var_os("HOME").map(PathBuf::from);
    let too_wide = depth <= 2
        || home.as_deref() == Some(folder.as_path())
        || folder.parent() == Some(Path::new("/home"))
        || suite.starts_with(&folder);
    if !too_wide && !folders.contains(&folder) {
        folders.push(folder);
    }
}

/// Whether `folder` is plainly a project's root.
fn is_project_root(folder: &Path) -> bool {
    if PROJECT_MARKS.iter().any(|mark| folder.join(mark).exists()) {
        return true;
    }
    std::fs::read_dir(folder).is_ok_and(|entries| {
        entries.flatten().any(|entry| {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            PROJECT_SUFFIXES.iter().any(|suffix| name.ends_with(suffix))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(path: &Path) {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, "").unwrap();
    }

    #[test]
    fn a_program_brings_its_project_and_no_more() {
        let dir = tempfile::tempdir().unwrap();
        let base = std::fs::canonicalize(dir.path()).unwrap();
        let project = base.join("tracer");
        let suite = base.join("suite");
        std::fs::create_dir_all(&suite).unwrap();
        // CMake's layout: the program in build/bin, its libraries in build/lib, data beside
        // the sources.
        touch(&project.join("CMakeLists.txt"));
        let program = project.join("build/bin/raytracer");
        touch(&program);
        assert_eq!(
            own_folders(&program, &suite),
            vec![
                project.join("build/bin"),
                project.join("build"),
                project.clone()
            ]
        );
        // No mark within three levels: the program's folder alone.
        let lone = base.join("a/b/c/d/e/raytracer");
        touch(&lone);
        assert_eq!(own_folders(&lone, &suite), vec![base.join("a/b/c/d/e")]);
        // A project that holds the suite is not readable; its program's folder still is.
        touch(&suite.join("Makefile"));
        let inside = suite.join("tools/raytracer");
        touch(&inside);
        assert_eq!(own_folders(&inside, &suite), vec![suite.join("tools")]);
        // A Visual Studio solution marks a root too.
        touch(&base.join("vs/tracer.sln"));
        let built = base.join("vs/x64/Release/raytracer");
        touch(&built);
        assert_eq!(
            own_folders(&built, &suite),
            vec![base.join("vs/x64/Release"), base.join("vs")]
        );
    }

    #[test]
    #[cfg(unix)]
    fn a_virtual_environment_is_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let base = std::fs::canonicalize(dir.path()).unwrap();
        let venv = base.join("venv");
        touch(&venv.join("pyvenv.cfg"));
        touch(&venv.join("lib/python3.11/site-packages/numpy/__init__.py"));
        std::fs::create_dir_all(venv.join("bin")).unwrap();
        std::os::unix::fs::symlink("/usr/bin/python3", venv.join("bin/python")).unwrap();
        let folders = own_folders(&venv.join("bin/python"), &base.join("suite"));
        assert_eq!(folders[..2], [venv.join("bin"), venv.clone()]);
        let script = base.join("tracer.py");
        std::fs::write(
            &script,
            format!("#!{}/bin/python\nprint(1)\n", venv.display()),
        )
        .unwrap();
        assert_eq!(interpreter(&script), Some(venv.join("bin/python")));
        std::fs::write(&script, "#!/usr/bin/env -S sh\n").unwrap();
        assert!(interpreter(&script).is_some_and(|p| p.ends_with("sh")));
        std::fs::write(&script, "print(1)\n").unwrap();
        assert_eq!(interpreter(&script), None);
    }
}
