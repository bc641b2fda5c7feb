//! When the cage, not the renderer, is why a line failed: the renderer's own words name a file
//! it could not open that lies outside what the cage let it read, or a shared library it could
//! not load. A student told to "run the same command line by hand" would find it works; the
//! true cause is the cage, and the fix is an `--allow-read`.

use std::path::{Path, PathBuf};

use super::cage::SYSTEM;

/// What the renderer could read, as the cage was told.
pub struct Reach<'a> {
    /// Its readable folders and files beyond the system's.
    pub readable: &'a [PathBuf],
    /// What it must never read (the suite): never advised.
    pub hidden: &'a [PathBuf],
    /// The line's own folder (its work and output folders).
    pub line: &'a Path,
    /// The renderer's program.
    pub program: &'a Path,
}

/// What programs say when a file will not open.
const CANNOT_OPEN: &[&str] = &[
    "no such file",
    "permission denied",
    "cannot open",
    "can't open",
    "could not open",
    "couldn't open",
    "failed to open",
    "unable to open",
    "not found",
    "cannot stat",
    "cannot access",
    "errno 2",
    "errno 13",
];

/// The dynamic loader's words for a library it could not find.
const LIBRARY_MISSING: &str = "error while loading shared libraries: ";

/// Why the cage is the likely cause of what `said` shows, and the `--allow-read` that fixes
/// it; `None` where nothing it said points at the cage.
pub fn cage_refused(said: &str, reach: &Reach) -> Option<String> {
    // Only Linux's cage keeps reads to a list; on Windows and macOS a renderer reads what its
    // user may (but the suite, which nothing needs).
    if !cfg!(target_os = "linux") {
        return None;
    }
    for line in said.lines() {
        let lower = line.to_lowercase();
        if let Some(at) = line.find(LIBRARY_MISSING) {
            let library = line[at + LIBRARY_MISSING.len()..].split(':').next()?.trim();
            return Some(library_advice(library, reach));
        }
        if !CANNOT_OPEN.iter().any(|words| lower.contains(words)) {
            continue;
        }
        for path in absolute_paths(line) {
            if reach.hidden.iter().any(|h| path.starts_with(h)) {
                // A renderer after the suite: nothing to advise.
                return None;
            }
            let readable = reach.readable.iter().any(|r| path.starts_with(r))
                || SYSTEM.iter().any(|s| path.starts_with(s))
                || path.starts_with(reach.line);
            if !readable && std::fs::symlink_metadata(&path).is_ok() {
                let allow = if path.is_dir() {
                    path.clone()
                } else {
                    path.parent().map_or(path.clone(), Path::to_path_buf)
                };
                return Some(format!(
                    "The cage kept the renderer from {}, which lies outside what it may read \
                     (the system's folders, its own project's folders and --allow-read paths): \
                     by hand it can read it, under check it cannot. If it needs it, give check \
                     --allow-read {}.",
                    path.display(),
                    allow.display()
                ));
            }
        }
    }
    None
}

/// The advice for a shared library the loader did not find: the folder that holds it where it
/// lies near the program (CMake's `$ORIGIN/../lib`), else where to look.
fn library_advice(library: &str, reach: &Reach) -> String {
    let near = reach.program.parent().into_iter().flat_map(|folder| {
        folder.ancestors().take(4).flat_map(|above| {
            ["", "lib", "lib64", "build/lib"].map(|sub| above.join(sub).join(library))
        })
    });
    let found = near
        .filter(|candidate| candidate.is_file())
        .find_map(|candidate| candidate.parent().map(Path::to_path_buf))
        .filter(|folder| !reach.readable.iter().any(|r| folder.starts_with(r)));
    match found {
        Some(folder) => format!(
            "The cage kept the renderer from its shared library {library}, in {}, outside what \
             it may read (the system's folders, its own project's folders and --allow-read \
             paths). Give check --allow-read {}.",
            folder.display(),
            folder.display()
        ),
        None => format!(
            "The loader could not find the shared library {library}: where it lies outside the \
             system's folders and the renderer's own project (a library beside the build, \
             found through $ORIGIN or LD_LIBRARY_PATH, which check does not pass on), the cage \
             keeps it out; give check --allow-read with the folder that holds it."
        ),
    }
}

/// The absolute paths in `line`: words that start with `/`, without the quotes, brackets and
/// punctuation around them.
fn absolute_paths(line: &str) -> Vec<PathBuf> {
    line.split(|c: char| c.is_whitespace() || "'\"`()[]{}<>,;=".contains(c))
        .map(|word| word.trim_end_matches([':', '.']))
        .filter(|word| word.starts_with('/') && word.len() > 1)
        .map(PathBuf::from)
        .collect()
}

// Only Linux's cage keeps reads to a list (see cage_refused).
#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn the_cage_is_named_where_the_renderer_was_kept_from_its_own_files() {
        let dir = tempfile::tempdir().unwrap();
        let base = std::fs::canonicalize(dir.path()).unwrap();
        let (data, program, suite) = (base.join("data"), base.join("bin"), base.join("suite"));
        for folder in [&data, &program, &suite.join("reference")] {
            std::fs::create_dir_all(folder).unwrap();
        }
        std::fs::write(data.join("sky.ppm"), "P3").unwrap();
        std::fs::write(base.join("libshade.so"), "").unwrap();
        let readable = [program.clone()];
        let hidden = [suite.clone()];
        let raytracer = program.join("raytracer");
        let reach = Reach {
            readable: &readable,
            hidden: &hidden,
            line: Path::new("/tmp/line0"),
            program: &raytracer,
        };
        let sky = data.join("sky.ppm");
        for said in [
            format!("error: cannot open '{}'", sky.display()),
            format!(
                "FileNotFoundError: [Errno 2] No such file or directory: '{}'",
                sky.display()
            ),
            format!("{}: Permission denied", sky.display()),
        ] {
            let advice = cage_refused(&said, &reach).unwrap_or_else(|| panic!("{said}"));
            assert!(
                advice.starts_with(&format!(
                    "The cage kept the renderer from {}",
                    sky.display()
                )),
                "{advice}"
            );
            assert!(
                advice.ends_with(&format!("--allow-read {}.", data.display())),
                "{advice}"
            );
        }
        let loader = "./raytracer: error while loading shared libraries: libshade.so: cannot \
                      open shared object file: No such file or directory";
        let advice = cage_refused(loader, &reach).unwrap();
        assert!(
            advice.contains(&format!("libshade.so, in {}", base.display())),
            "{advice}"
        );
        let unknown = cage_refused(&loader.replace("libshade", "libnone"), &reach).unwrap();
        assert!(unknown.starts_with("The loader could not find the shared library libnone.so"));
        // Readable, system, the line's own, missing everywhere, or the suite: not the cage.
        for said in [
            format!("cannot open {}", program.join("x").display()),
            "cannot open /usr/share/missing".to_string(),
            "cannot open /tmp/line0/work/scene.txt".to_string(),
            format!("cannot open {}", base.join("nothing").display()),
            format!(
                "cp: cannot stat '{}': No such file",
                suite.join("reference").display()
            ),
            format!("{} was read", sky.display()),
        ] {
            assert_eq!(cage_refused(&said, &reach), None, "{said}");
        }
    }
}
