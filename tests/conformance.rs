//! The course's own acceptance tests: every command of COMMANDS.txt, run as the handout gives
//! it, each image compared with the staff's reference.
//!
//! The data comes from RAYCAST_CONFORMANCE_DIR (default: ../shared/conformance beside the
//! project). Where the variable is set, missing data fails the test; where it is not and the
//! default folder is absent, the test says so loudly and passes without checking anything.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A pixel differs when a channel is off by more than this many levels...
const LEVELS: i16 = 2;
/// ...and an image passes when at most this fraction of its pixels differ.
const MAX_DIFFERING: f64 = 0.001;

fn conformance_dir() -> Option<PathBuf> {
    match std::env::var_os("RAYCAST_CONFORMANCE_DIR") {
        Some(dir) => {
            let dir = PathBuf::from(dir);
            assert!(
                dir.join("COMMANDS.txt").is_file(),
                "RAYCAST_CONFORMANCE_DIR is {} but there is no COMMANDS.txt there",
                dir.display()
            );
            Some(dir)
        }
        None => {
            let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/conformance");
            if dir.join("COMMANDS.txt").is_file() {
                Some(dir)
            } else {
                let _ = writeln!(
                    std::io::stderr(),
                    "\n*** CONFORMANCE TESTS SKIPPED: no course data at {} and \
                     RAYCAST_CONFORMANCE_DIR is not set ***\n",
                    dir.display()
                );
                None
            }
        }
    }
}

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

#[test]
fn course_reference_images_are_reproduced() {
    let Some(dir) = conformance_dir() else { return };
    let commands = std::fs::read_to_string(dir.join("COMMANDS.txt")).unwrap();
    let out_dir = tempfile::tempdir().unwrap();
    let failures_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/conformance-failures");
    let mut passed = 0;
    let mut failures = Vec::new();
    let mut checked = 0;
    for line in commands.lines().filter(|l| l.starts_with("raytracer ")) {
        let mut args: Vec<String> = line.split_whitespace().skip(1).map(String::from).collect();
        // Output names become paths in a scratch folder; remember which is which.
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
                let path = out_dir.path().join(&name);
                args[at] = path.to_str().unwrap().to_string();
                outputs.push((name, path));
            }
        }
        let run = Command::new(env!("CARGO_BIN_EXE_raycast"))
            .args(&args)
            .current_dir(dir.join("scenes"))
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "`{line}` failed: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        for (name, path) in outputs {
            checked += 1;
            let stem = name.trim_end_matches(".tga");
            let actual = image::open(&path).unwrap().to_rgb8();
            let reference = image::open(dir.join("reference").join(format!("{stem}.png")))
                .unwrap()
                .to_rgb8();
            match compare(&actual, &reference) {
                Some(c) if (c.differing as f64) <= MAX_DIFFERING * c.total as f64 => passed += 1,
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
                                ", differences in red {} ({} of {} pixels off by more than {LEVELS} levels)",
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
    }
    // Straight to stderr, past the test harness's capture: CI logs show the count.
    let _ = writeln!(
        std::io::stderr(),
        "conformance: {passed} of {checked} course images match their references"
    );
    assert!(
        failures.is_empty(),
        "images that differ:\n{}",
        failures.join("\n")
    );
    assert_eq!(checked, 44, "COMMANDS.txt should name 44 images");
}
