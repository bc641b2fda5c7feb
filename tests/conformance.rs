//! The course's own acceptance tests: every command line that has a staff image, run as the
//! handout gives it, each image compared with the staff's reference.
//!
//! Two suites: assignments 1 and 2 (`conformance/`, 44 images) and assignment 3
//! (`later-assignments/reference/a3`, 15 images). The data comes from RAYCAST_CONFORMANCE_DIR
//! and RAYCAST_LATER_DIR (defaults: ../shared/conformance and ../shared/later-assignments beside
//! the project). Where a variable is set, missing data fails the test; where it is not and the
//! default folder is absent, the test says so loudly and passes without checking anything.

mod common;

use common::data_dir;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use rayon::prelude::*;

/// A pixel differs when a channel is off by more than this many levels...
const LEVELS: i16 = 2;
/// ...and an image passes when at most this fraction of its pixels differ.
const MAX_DIFFERING: f64 = 0.001;

struct Comparison {
    differing: usize,
    total: usize,
    diff: image::RgbImage,
}

fn compare(actual: &image::RgbImage, reference: &image::RgbImage) -> Option<Comparison> {
    if actual.dimensions() != reference.dimensions() {
        return None;
    }
    let mut diff = image::RgbImage::new(actual.width(), actual.height());
    let mut differing = 0;
    for ((a, r), d) in actual
        .pixels()
        .zip(reference.pixels())
        .zip(diff.pixels_mut())
    {
        let worst = (0..3)
            .map(|c| (a[c] as i16 - r[c] as i16).abs())
            .max()
            .unwrap_or(0);
        if worst > LEVELS {
            differing += 1;
            *d = image::Rgb([255, 0, 0]);
        } else {
            // The matching image, dimmed, so the red differences stand out in context.
            *d = image::Rgb(r.0.map(|v| v / 3));
        }
    }
    Some(Comparison {
        differing,
        total: actual.pixels().len(),
        diff,
    })
}

/// A suite: command lines (`raytracer ARGS`), the folder they run in, and the folder of the
/// reference images (`NAME.png` for an output `NAME.tga`).
struct Suite<'a> {
    name: &'a str,
    commands: PathBuf,
    scenes: PathBuf,
    references: PathBuf,
}

/// Runs every line of the suite (in parallel), compares each image with its reference, and
/// returns (images matched, images checked, one message per failure).
fn run_suite(suite: &Suite) -> (usize, usize, Vec<String>) {
    let commands = std::fs::read_to_string(&suite.commands).unwrap();
    let out_dir = tempfile::tempdir().unwrap();
    let failures_dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/conformance-failures")
        .join(suite.name.replace(' ', "-"));
    let lines: Vec<&str> = commands
        .lines()
        .filter(|l| l.starts_with("raytracer "))
        .collect();
    let results: Vec<(usize, usize, Vec<String>)> = lines
        .par_iter()
        .enumerate()
        .map(|(number, line)| {
            let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
            // Output names become paths in a scratch folder of the line's own (two lines may
            // write the same name); remember which is which.
            let line_dir = out_dir.path().join(number.to_string());
            std::fs::create_dir(&line_dir).unwrap();
            let mut outputs = Vec::new();
            for i in 0..args.len() {
                // -depth TMIN TMAX FILE: the file is its third value.
                let value = match args[i].as_str() {
                    "-output" | "-normals" => 1,
                    "-depth" => 3,
                    _ => 0,
                };
                if value > 0 {
                    let at = i + value;
                    let name = args[at].clone();
                    let path = line_dir.join(&name);
                    args[at] = path.to_str().unwrap().to_string();
                    outputs.push((name, path));
                }
            }
            let run = Command::new(env!("CARGO_BIN_EXE_raycast"))
                .args(&args)
                .current_dir(&suite.scenes)
                .output()
                .unwrap();
            assert!(
                run.status.success(),
                "`{line}` failed: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            let (mut passed, mut checked, mut failures) = (0, 0, Vec::new());
            for (name, path) in outputs {
                checked += 1;
                let stem = name.trim_end_matches(".tga");
                let actual = image::open(&path).unwrap().to_rgb8();
                let reference = image::open(suite.references.join(format!("{stem}.png")))
                    .unwrap()
                    .to_rgb8();
                match compare(&actual, &reference) {
                    Some(c) if (c.differing as f64) <= MAX_DIFFERING * c.total as f64 => {
                        passed += 1
                    }
                    comparison => {
                        std::fs::create_dir_all(&failures_dir).unwrap();
                        let actual_path = failures_dir.join(format!("{stem}-actual.png"));
                        actual.save(&actual_path).unwrap();
                        let mut message = format!("{stem}: actual image {}", actual_path.display());
                        match comparison {
                            Some(c) => {
                                let diff_path = failures_dir.join(format!("{stem}-diff.png"));
                                c.diff.save(&diff_path).unwrap();
                                message += &format!(
                                    ", differences in red {} ({} of {} pixels off by more \
                                     than {LEVELS} levels)",
                                    diff_path.display(),
                                    c.differing,
                                    c.total
                                );
                            }
                            None => message += ": size differs from the reference",
                        }
                        failures.push(message);
                    }
                }
            }
            (passed, checked, failures)
        })
        .collect();
    results.into_iter().fold(
        (0, 0, Vec::new()),
        |(passed, checked, mut failures), (p, c, f)| {
            failures.extend(f);
            (passed + p, checked + c, failures)
        },
    )
}

/// Runs a suite, prints its one summary line past the test harness's capture (so CI logs show
/// it), and fails on any mismatch or a count other than `expected`.
fn check_suite(suite: &Suite, expected: usize) {
    let (passed, checked, failures) = run_suite(suite);
    let _ = writeln!(
        std::io::stderr(),
        "{}: {passed}/{checked} course images match their references",
        suite.name
    );
    assert!(
        failures.is_empty(),
        "images that differ:\n{}",
        failures.join("\n")
    );
    assert_eq!(
        checked,
        expected,
        "{} should name {expected} images",
        suite.commands.display()
    );
}

#[test]
fn assignments_1_and_2_staff_images_are_reproduced() {
    let Some(dir) = data_dir(
        "the staff images of assignments 1 and 2",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    ) else {
        return;
    };
    let suite = Suite {
        name: "a1-a2 staff images",
        commands: dir.join("COMMANDS.txt"),
        scenes: dir.join("scenes"),
        references: dir.join("reference"),
    };
    check_suite(&suite, 44);
}

#[test]
fn assignment_3_staff_images_are_reproduced() {
    let Some(dir) = data_dir(
        "the staff images of assignment 3",
        "RAYCAST_LATER_DIR",
        "../shared/later-assignments",
        "reference/a3/COMMANDS.txt",
    ) else {
        return;
    };
    let suite = Suite {
        name: "a3 staff images",
        commands: dir.join("reference/a3/COMMANDS.txt"),
        scenes: dir.join("scenes"),
        references: dir.join("reference/a3"),
    };
    check_suite(&suite, 15);
}
