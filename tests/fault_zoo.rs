//! The fault zoo: for every fault of check's library, raycast renders the course's lines with
//! that fault planted (`-fault NAME`) and is graded by `raycast check` as a student's renderer;
//! check must name that fault first for every picture the fault changes, and in the renderer's
//! verdict. The same for pairs of faults. Because the zoo plants faults with the library's own
//! code, it proves the plumbing; tests/check.rs holds renderers written without it.
//!
//! The suites: every line of assignments 1 and 2 (with the staff's images), and every fourth
//! line of assignments 3 to 7 at a quarter of the size (graded against raycast's own renders).
//! Prints a table of what each fault changed and how often it was named.

// The renderers these tests grade are shell scripts and the cage they test is Unix's; on Windows
// check is run by CI's Wine job (.ci/windows), over raycast.exe itself.
#![cfg(unix)]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::data_dir;
use raycast::check::faults::FAULTS;

fn conformance_dir() -> Option<PathBuf> {
    data_dir(
        "the fault zoo on the course's images",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

fn later_dir() -> Option<PathBuf> {
    common::later_dir("the fault zoo on assignments 3 to 7")
}

/// A suite of every `step`-th line of `dir`'s COMMANDS.txt, with its scenes; at `shrink` 1 with
/// its references, otherwise each picture `shrink` times smaller and graded against raycast's
/// own render (which the zoo's time allows for the later assignments' heavier lines).
fn suite_of(dir: &Path, step: usize, shrink: u32, into: &Path) -> PathBuf {
    let suite = into.join(format!(
        "suite-{}",
        dir.file_name().unwrap().to_string_lossy()
    ));
    std::fs::create_dir_all(&suite).unwrap();
    let lines: Vec<String> = std::fs::read_to_string(dir.join("COMMANDS.txt"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("raytracer "))
        .step_by(step)
        .map(|line| shrunk(line, shrink))
        .chain(
            if shrink == 1 { &[][..] } else { EXTRA_LINES }
                .iter()
                .map(|l| l.to_string()),
        )
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    std::os::unix::fs::symlink(dir.join("scenes"), suite.join("scenes")).unwrap();
    if shrink == 1 {
        std::os::unix::fs::symlink(dir.join("reference"), suite.join("reference")).unwrap();
    }
    suite
}

/// Lines of our own beside the course's, for faults that its lines cannot show: the course's
/// `-weight 0.01` cuts off only rays too faint to move a pixel by 2 levels.
const EXTRA_LINES: &[&str] = &[
    "raytracer -input scene4_04_reflective_sphere.txt -size 50 50 -output weight4_04.tga -shadows -bounces 3 -weight 0.99",
];

/// `line` with its `-size` divided by `shrink`.
fn shrunk(line: &str, shrink: u32) -> String {
    let mut words: Vec<String> = line.split_whitespace().map(String::from).collect();
    if let Some(at) = words.iter().position(|w| w == "-size") {
        for k in at + 1..=at + 2 {
            if let Some(n) = words.get(k).and_then(|w| w.parse::<u32>().ok()) {
                words[k] = (n / shrink).max(8).to_string();
            }
        }
    }
    words.join(" ")
}

/// A renderer: raycast with `fault` planted.
fn planted(dir: &Path, fault: &str) -> String {
    let path = dir.join(format!("{}.sh", fault.replace(',', "-")));
    std::fs::write(
        &path,
        format!(
            "#!/usr/bin/env bash\nexec {} \"$@\" -fault {fault}\n",
            common::open_raycast()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_str().unwrap().to_string()
}

/// What check said of a renderer: its failing pictures' lines and its first verdict line.
struct Graded {
    failing: Vec<String>,
    verdict: String,
}

fn check(suite: &Path, renderer: &str) -> Graded {
    let output = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(["check", suite.to_str().unwrap(), "--renderer", renderer])
        // The planted renderers are scripts that run raycast: its folder is theirs to read.
        .args(["--allow-read", common::open_raycast_folder()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&output.stdout).into_owned();
    Graded {
        failing: out
            .lines()
            .filter(|l| l.starts_with("FAIL") || l.starts_with("ERROR"))
            .map(String::from)
            .collect(),
        verdict: out
            .lines()
            .find(|l| l.starts_with("verdict:"))
            .unwrap_or("")
            .to_string(),
    }
}

/// The codes a picture's line names first: "FAIL   name, 1.2% of pixels off: a, b: ...".
fn first_code(line: &str) -> &str {
    line.split(": ")
        .nth(1)
        .unwrap_or("")
        .split(", ")
        .next()
        .unwrap_or("")
}

/// Whether a picture's line names `fault` first, or among the faults it says this line cannot
/// tell apart.
fn names_first(line: &str, fault: &str) -> bool {
    let among_equals = line.contains("this line alone cannot tell the faults named apart")
        && line
            .split(": ")
            .nth(1)
            .is_some_and(|codes| codes.split(", ").any(|c| c == fault));
    first_code(line) == fault || among_equals
}

/// Whether the verdict's first line names `fault`: as the group's, or among the faults its
/// pictures cannot tell from it ("... by a (or, as well, by b or c: ...)").
fn verdict_names(verdict: &str, fault: &str) -> bool {
    verdict.contains(&format!(" by {fault}:"))
        || verdict.contains(&format!(" by {fault} ("))
        || verdict.split(['(', ')']).nth(1).is_some_and(|equals| {
            equals
                .trim_start_matches("or, as well, by ")
                .split(':')
                .next()
                .is_some_and(|names| names.split(" or ").any(|n| n == fault))
        })
}

#[test]
#[ignore = "the full tier (minutes): cargo test --profile ci -- --include-ignored"]
fn every_fault_is_named_for_every_picture_it_changes() {
    let (Some(conformance), Some(later)) = (conformance_dir(), later_dir()) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suites = [
        suite_of(&conformance, 1, 1, dir.path()),
        suite_of(&later, 4, 4, dir.path()),
    ];
    let mut table = vec!["fault | pictures changed | named first".to_string()];
    let mut wrong = Vec::new();
    // RAYCAST_ZOO_FAULTS=a,b limits a developer's run to those faults.
    let only = std::env::var("RAYCAST_ZOO_FAULTS").ok();
    let wanted = |name: &str| {
        only.as_ref()
            .is_none_or(|o| o.split(',').any(|f| f == name))
    };
    for fault in FAULTS.iter().filter(|f| wanted(f.name)) {
        let renderer = planted(dir.path(), fault.name);
        let (mut changed, mut named) = (0, 0);
        for suite in &suites {
            let graded = check(suite, &renderer);
            for line in &graded.failing {
                changed += 1;
                if names_first(line, fault.name) {
                    named += 1;
                } else {
                    wrong.push(format!("{}: {line}", fault.name));
                }
            }
            if !graded.failing.is_empty() && !verdict_names(&graded.verdict, fault.name) {
                wrong.push(format!("{}: verdict {}", fault.name, graded.verdict));
            }
        }
        assert!(
            changed > 0,
            "{} changes no picture of the suites",
            fault.name
        );
        table.push(format!("{} | {changed} | {named}", fault.name));
    }
    println!("{}", table.join("\n"));
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
#[ignore = "the full tier (minutes): cargo test --profile ci -- --include-ignored"]
fn pairs_of_faults_are_named_together() {
    let Some(conformance) = conformance_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let suite = suite_of(&conformance, 1, 1, dir.path());
    let pairs = [
        ("pixel_corner", "ambient_missing"),
        ("pixel_corner", "channel_swap"),
        ("flip_vertical", "ambient_per_light"),
        ("flip_horizontal", "cosine_twice"),
        ("pixel_span_minus_one", "ambient_missing"),
        ("field_of_view", "ambient_missing"),
        ("t_limit", "channel_swap"),
        ("shade_back_abs", "pixel_corner"),
        ("cosine_twice", "channel_swap"),
        ("camera_basis", "ambient_missing"),
        ("picture_background", "pixel_corner"),
        ("normals_signed", "flip_vertical"),
    ];
    let mut wrong = Vec::new();
    for (a, b) in pairs {
        let graded = check(&suite, &planted(dir.path(), &format!("{a},{b}")));
        assert!(!graded.failing.is_empty(), "{a},{b} changes nothing");
        for line in &graded.failing {
            // A picture only one of the two changes names that one; one both change names the
            // pair; either among equals (faults that draw the same picture, such as the
            // ambient term once per light and none at all in a scene without lights).
            let codes = line.split(": ").nth(1).unwrap_or("");
            let named = codes
                .split(", ")
                .any(|c| [a, b].contains(&c) || c == format!("{a}+{b}") || c == format!("{b}+{a}"));
            if !named {
                wrong.push(format!("{a},{b}: {line}"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
