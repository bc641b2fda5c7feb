//! What check keeps between runs, and what it says while it runs: a fault's render of a line is
//! kept beside raycast's references and read, not rendered, the next time (a student's next
//! run, a class's next student), and so is the diagnosis of each picture, told again without a
//! search wherever the same picture comes back; the folder is bounded, least recently used first, and
//! `raycast check cache` shows and clears it; a run without a terminal says how far it has come
//! every few seconds.

// The renderers here are shell scripts.
#![cfg(unix)]

mod common;

use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, SystemTime};

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// The course's conformance suite, where the tests may read it.
fn conformance() -> Option<PathBuf> {
    common::data_dir(
        "the kept renders' tests",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

/// A suite of one line of the course's second assignment, without references: its picture is
/// graded against raycast's own render.
fn suite(dir: &Path, conformance: &Path) -> PathBuf {
    let suite = dir.join("suite");
    std::fs::create_dir_all(suite.join("scenes")).unwrap();
    std::fs::copy(
        conformance.join("scenes/scene2_01_diffuse.txt"),
        suite.join("scenes/scene2_01_diffuse.txt"),
    )
    .unwrap();
    std::fs::write(
        suite.join("COMMANDS.txt"),
        "raytracer -input scene2_01_diffuse.txt -size 60 60 -output a.tga\n",
    )
    .unwrap();
    suite
}

/// A renderer: raycast, after `body` (a line of shell).
fn renderer(dir: &Path, name: &str, body: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(
        &path,
        format!(
            "#!/bin/sh\n{body}\nexec {} \"$@\"{}\n",
            common::open_raycast(),
            if name.starts_with("fault-") {
                format!(" -fault {}", &name[6..name.len() - 3])
            } else {
                String::new()
            }
        ),
    )
    .unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

fn check(suite: &Path, renderer: &Path, cache: &Path, size: Option<&str>) -> Output {
    let mut command = Command::new(RAYCAST);
    command
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(renderer)
        .args(["--allow-read", common::open_raycast_folder()])
        .env("RAYCAST_CACHE_DIR", cache);
    if let Some(size) = size {
        command.env("RAYCAST_CACHE_SIZE", size);
    }
    command.output().unwrap()
}

fn cache_command(cache: &Path, args: &[&str]) -> Output {
    Command::new(RAYCAST)
        .args(["check", "cache"])
        .args(args)
        .env("RAYCAST_CACHE_DIR", cache)
        .output()
        .unwrap()
}

fn text(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr)
}

/// The kept pictures: each with its inode and modification time.
fn kept(cache: &Path) -> Vec<(PathBuf, u64, SystemTime)> {
    let Ok(entries) = std::fs::read_dir(cache.join("references")) else {
        return Vec::new();
    };
    let mut kept: Vec<_> = entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".png"))
        .map(|e| {
            let metadata = e.metadata().unwrap();
            (e.path(), metadata.ino(), metadata.modified().unwrap())
        })
        .collect();
    kept.sort();
    kept
}

#[test]
fn a_faults_render_is_kept_and_read_the_next_time() {
    let Some(conformance) = conformance() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance);
    let cache = dir.path().join("cache");
    let renderer = renderer(dir.path(), "fault-pixel_corner.sh", "");
    let first = check(&suite, &renderer, &cache, None);
    assert!(
        text(&first).contains("FAIL   a, ") && text(&first).contains(": pixel_corner"),
        "{}",
        text(&first)
    );
    // raycast's reference and the renders of the faults that might match.
    let before = kept(&cache);
    assert!(before.len() >= 2, "{before:?}");
    // And which faults draw a picture alike to the one that matched exactly: the next picture
    // it matches exactly is named without a search.
    let records = std::fs::read_dir(cache.join("references"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".same"))
        .count();
    assert!(records >= 1, "no record of the faults alike");
    // Older than now, so that a read shows in the time.
    let long_ago = SystemTime::now() - Duration::from_secs(3600);
    for (path, _, _) in &before {
        let file = std::fs::File::options().append(true).open(path).unwrap();
        file.set_modified(long_ago).unwrap();
    }
    // The diagnosis of this very picture forgotten (as for a class's next student whose
    // picture differs), the search runs again, on the kept renders.
    for record in diagnoses(&cache) {
        std::fs::remove_file(record).unwrap();
    }
    let second = check(&suite, &renderer, &cache, None);
    assert_eq!(
        String::from_utf8_lossy(&first.stdout),
        String::from_utf8_lossy(&second.stdout)
    );
    let after = kept(&cache);
    assert_eq!(after.len(), before.len(), "nothing new rendered: {after:?}");
    for ((path, inode, _), (_, inode_after, modified)) in before.iter().zip(&after) {
        // The same file (a render kept anew would be another, renamed into place), read.
        assert_eq!(inode, inode_after, "{path:?} was written again");
        assert!(*modified > long_ago, "{path:?} was not read");
    }
}

/// The kept diagnoses of the line (the faults, the allowed answers).
fn diagnoses(cache: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(cache.join("references"))
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.path())
                .filter(|path| path.extension().is_some_and(|x| x == "diagnosis"))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn a_pictures_diagnosis_is_kept_and_told_again_without_a_search() {
    let Some(conformance) = conformance() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance);
    let cache = dir.path().join("cache");
    let corner = renderer(dir.path(), "fault-pixel_corner.sh", "");
    let first = check(&suite, &corner, &cache, None);
    assert!(text(&first).contains(": pixel_corner"), "{}", text(&first));
    let records = diagnoses(&cache);
    let named: Vec<&PathBuf> = records
        .iter()
        .filter(|path| {
            std::fs::read_to_string(path)
                .unwrap()
                .contains("\"pixel_corner\"")
        })
        .collect();
    assert_eq!(named.len(), 1, "{records:?}");
    // What the next run over the same picture tells is the kept diagnosis, not a new search:
    // a record changed by hand is told as it reads.
    let kept = std::fs::read_to_string(named[0]).unwrap();
    std::fs::write(
        named[0],
        kept.replace("\"pixel_corner\"", "\"shadow_acne\""),
    )
    .unwrap();
    let second = check(&suite, &corner, &cache, None);
    assert!(
        text(&second).contains("FAIL   a, ") && text(&second).contains(": shadow_acne"),
        "{}",
        text(&second)
    );
    // A record that does not read back as a diagnosis is searched again and replaced.
    for record in &records {
        std::fs::write(record, "[[{\"faults\": [\"no_such_fault\"").unwrap();
    }
    let third = check(&suite, &corner, &cache, None);
    assert_eq!(
        String::from_utf8_lossy(&first.stdout),
        String::from_utf8_lossy(&third.stdout)
    );
    assert_eq!(std::fs::read_to_string(named[0]).unwrap(), kept);
    // Another picture of the same line is another diagnosis.
    let other = renderer(dir.path(), "fault-pixel_corner:2.sh", "");
    let fourth = check(&suite, &other, &cache, None);
    assert!(
        text(&fourth).contains(": pixel_corner"),
        "{}",
        text(&fourth)
    );
    assert!(diagnoses(&cache).len() > records.len());
}

#[test]
fn the_folder_is_trimmed_to_its_size_the_least_recently_used_first() {
    let Some(conformance) = conformance() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance);
    let cache = dir.path().join("cache");
    let folder = cache.join("references");
    std::fs::create_dir_all(&folder).unwrap();
    // Ten pictures of 1 MiB from other runs, the first the least recently used.
    for k in 0..10_u64 {
        let path = folder.join(format!("old-{k}.png"));
        std::fs::write(&path, vec![0_u8; 1 << 20]).unwrap();
        let file = std::fs::File::options().append(true).open(&path).unwrap();
        file.set_modified(SystemTime::now() - Duration::from_secs(10_000 - k * 100))
            .unwrap();
    }
    let renderer = renderer(dir.path(), "plain.sh", "");
    let output = check(&suite, &renderer, &cache, Some("4M"));
    assert!(text(&output).contains("pass   a"), "{}", text(&output));
    let left: Vec<String> = kept(&cache)
        .into_iter()
        .map(|(path, _, _)| path.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    let total: u64 = kept(&cache)
        .iter()
        .map(|(path, _, _)| path.metadata().unwrap().len())
        .sum();
    assert!(total <= 4 << 20, "{total} bytes left: {left:?}");
    // The run's own reference, and the most recently used of the others.
    assert!(
        left.iter().any(|name| !name.starts_with("old-")),
        "{left:?}"
    );
    assert!(left.contains(&"old-9.png".to_string()), "{left:?}");
    assert!(!left.contains(&"old-0.png".to_string()), "{left:?}");
    let bad = check(&suite, &renderer, &cache, Some("lots"));
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr).trim_end(),
        "raycast: check: RAYCAST_CACHE_SIZE: expected a size in bytes, or with K, M or G after \
         it (as 512M), found 'lots'"
    );
}

#[test]
fn check_cache_says_what_is_kept_and_clears_it() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let folder = cache.join("references");
    std::fs::create_dir_all(&folder).unwrap();
    for k in 0..3 {
        std::fs::write(folder.join(format!("{k}.png")), vec![0_u8; 1 << 19]).unwrap();
    }
    let said = cache_command(&cache, &[]);
    assert!(said.status.success());
    assert_eq!(
        String::from_utf8_lossy(&said.stdout).trim_end(),
        format!(
            "3 pictures kept in {}: 1.5 MiB of at most 1024.0 MiB (RAYCAST_CACHE_SIZE)",
            folder.display()
        )
    );
    let cleared = cache_command(&cache, &["clear"]);
    assert!(cleared.status.success());
    assert_eq!(
        String::from_utf8_lossy(&cleared.stdout).trim_end(),
        format!("removed 3 pictures (1.5 MiB) from {}", folder.display())
    );
    assert!(kept(&cache).is_empty());
    let wrong = cache_command(&cache, &["empty"]);
    assert_eq!(wrong.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&wrong.stderr).contains("check cache takes nothing, or 'clear'"),
        "{}",
        text(&wrong)
    );
    let off = cache_command(Path::new("off"), &[]);
    assert_eq!(
        String::from_utf8_lossy(&off.stdout).trim_end(),
        "RAYCAST_CACHE_DIR=off: no render is kept between runs"
    );
}

#[test]
fn a_long_run_without_a_terminal_says_how_far_it_has_come() {
    let Some(conformance) = conformance() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite(dir.path(), &conformance);
    // Longer than the few seconds between two lines of progress, however idle the machine.
    let renderer = renderer(dir.path(), "slow.sh", "sleep 7");
    let output = check(&suite, &renderer, &dir.path().join("cache"), None);
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(
        said.lines()
            .any(|line| line.starts_with("raycast: check: 0/1 lines graded, ")),
        "{said}"
    );
    assert!(String::from_utf8_lossy(&output.stdout).contains("pass   a"));
}
