//! What several test programs share: finding the course's data, and editing argument lists.

// Each test program uses what it needs of this.
#![allow(dead_code)]

use std::collections::HashSet;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The course's data folder named by `variable`, or `default` beside the project (`marker` is a
/// file it must hold). Where the variable is set, missing data fails the test; where it is not
/// and the default is missing, `None`, after one line saying which suite is skipped and how to
/// run it (once per suite and test program, past the harness's capture).
pub fn data_dir(suite: &str, variable: &str, default: &str, marker: &str) -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os(variable) {
        let dir = PathBuf::from(dir);
        assert!(
            dir.join(marker).is_file(),
            "{variable} is {} but there is no {marker} there",
            dir.display()
        );
        // Absolute, so that links made to it from a scratch folder (and children run elsewhere)
        // find it: the README's command names it relative to the project.
        return Some(dir.canonicalize().unwrap());
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(default);
    if dir.join(marker).is_file() {
        return Some(dir.canonicalize().unwrap());
    }
    static SAID: Mutex<Option<HashSet<String>>> = Mutex::new(None);
    let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
    if said
        .get_or_insert_with(HashSet::new)
        .insert(suite.to_string())
    {
        let _ = writeln!(
            std::io::stderr(),
            "skipped: {suite} (no course data at {}; put it there or set {variable} to run them)",
            dir.display()
        );
    }
    None
}

/// The course data of assignments 3 to 7 (RAYCAST_LATER_DIR).
pub fn later_dir(suite: &str) -> Option<PathBuf> {
    data_dir(
        suite,
        "RAYCAST_LATER_DIR",
        "../shared/later-assignments",
        "COMMANDS.txt",
    )
}

/// The command lines of the course's `COMMANDS.txt` in `dir` whose scene names start with one of
/// `prefixes`, as argument lists without `raytracer` (and without the file's remarks: `-> ...`
/// and `(preview only)`).
pub fn course_lines(dir: &Path, prefixes: &[&str]) -> Vec<Vec<String>> {
    let commands = std::fs::read_to_string(dir.join("COMMANDS.txt")).unwrap();
    commands
        .lines()
        .filter(|l| {
            prefixes
                .iter()
                .any(|s| l.starts_with(&format!("raytracer -input {s}")))
        })
        .map(|l| {
            let command = l.split("->").next().unwrap();
            let command = command.split("(preview only)").next().unwrap();
            command
                .split_whitespace()
                .skip(1)
                .map(String::from)
                .collect()
        })
        .collect()
}

/// `args` with `flag` (and the `values` words after it) taken out.
pub fn without(args: &[String], flag: &str, values: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut skip = 0;
    for a in args {
        if skip > 0 {
            skip -= 1;
        } else if a == flag {
            skip = values;
        } else {
            out.push(a.clone());
        }
    }
    out
}

/// The program under test.
const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// raycast, copied where every user may run it (once a build, kept in the system's temporary
/// folder): the renderers run as nobody when the tests run as root, and no test may depend on
/// where the checkout sits (a folder closed to other users, such as /root, holds the build).
pub fn open_raycast() -> &'static str {
    static COPY: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    COPY.get_or_init(|| open_copy(Path::new(RAYCAST)))
}

/// The example program `name` of this build (`cargo test` builds the examples beside the
/// program), copied as [`open_raycast`] is.
pub fn open_example(name: &str) -> String {
    let built = Path::new(RAYCAST)
        .parent()
        .unwrap()
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        built.is_file(),
        "no example {} (build it: cargo build --examples, or run all the tests with cargo test)",
        built.display()
    );
    open_copy(&built)
}

/// `built`, copied into a folder of its own in the system's temporary folder that every user
/// may enter (once per build of it).
fn open_copy(built: &Path) -> String {
    let metadata = std::fs::metadata(built).unwrap();
    let stamp = metadata
        .modified()
        .unwrap()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos();
    let name = built.file_name().unwrap().to_str().unwrap();
    let dir = std::env::temp_dir().join(format!("{name}-open-{}-{stamp}", metadata.len()));
    let copy = dir.join(name);
    if !copy.is_file() {
        std::fs::create_dir_all(&dir).unwrap();
        // Each copy its own partial file: tests in threads may copy the same program at once.
        static COPIES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let copy_number = COPIES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let partial = dir.join(format!("{name}.{}.{copy_number}", std::process::id()));
        std::fs::copy(built, &partial).unwrap();
        #[cfg(unix)]
        std::fs::set_permissions(
            &partial,
            <std::fs::Permissions as std::os::unix::fs::PermissionsExt>::from_mode(0o755),
        )
        .unwrap();
        std::fs::rename(&partial, &copy).unwrap();
    }
    #[cfg(unix)]
    std::fs::set_permissions(
        &dir,
        <std::fs::Permissions as std::os::unix::fs::PermissionsExt>::from_mode(0o755),
    )
    .unwrap();
    copy.display().to_string()
}

/// The folder of [`open_raycast`], for `--allow-read`.
pub fn open_raycast_folder() -> &'static str {
    Path::new(open_raycast())
        .parent()
        .unwrap()
        .to_str()
        .unwrap()
}

/// The `summary.json` of a report of `raycast check`.
pub fn summary_of(report: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(report.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The command lines of the processes that carry `token`.
pub fn left_running(token: &str) -> Vec<String> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let cmdline = String::from_utf8_lossy(&cmdline).replace('\0', " ");
        if cmdline.contains(token) {
            found.push(cmdline);
        }
    }
    found
}

/// Whether a memory control group can be made beside this process's own, as check's supervisor
/// makes one for each line (cgroup v1's memory hierarchy, or v2).
pub fn line_groups_can_be_made() -> bool {
    let own = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    let group = own.lines().find_map(|line| {
        let mut fields = line.splitn(3, ':');
        let (_, controllers, path) = (fields.next()?, fields.next()?, fields.next()?);
        let path = path.trim_start_matches('/');
        if controllers.split(',').any(|c| c == "memory") {
            Some(Path::new("/sys/fs/cgroup/memory").join(path))
        } else if controllers.is_empty() {
            Some(Path::new("/sys/fs/cgroup").join(path))
        } else {
            None
        }
    });
    let Some(probe) = group.map(|g| g.join(format!("raycast-probe-{}", std::process::id()))) else {
        return false;
    };
    let made = std::fs::create_dir(&probe).is_ok();
    let _ = std::fs::remove_dir(&probe);
    made
}

/// How many files `dir` holds, in its folders too (none where it does not exist).
pub fn files_in(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |entries| {
        entries
            .flatten()
            .map(|e| {
                if e.path().is_dir() {
                    files_in(&e.path())
                } else {
                    1
                }
            })
            .sum()
    })
}
