//! Assignments 5 to 7 (the grid, `-stats`, solid textures, samplers and filters) have no staff
//! images. Every one of their command lines in the course's COMMANDS.txt runs here, headless,
//! and writes images of the course's sizes; and what the handouts fix is checked:
//!
//! * every assignment-6 image made with `-grid` is byte for byte the image made without it;
//! * `-stats` prints the course's statistics block line by line in the staff format, with the
//!   same counts on one thread and two;
//! * uniform sampling gives the same image twice, random and jittered sampling the same image
//!   with one seed (on any number of threads) and another with another seed.
//!
//! The course data comes from RAYCAST_LATER_DIR (default ../shared/later-assignments); where
//! the variable is set, missing data fails the tests.

mod common;

use common::{course_lines, later_dir, without};
use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Output};

use rayon::prelude::*;

/// The course's command lines of assignments 5 to 7, as argument lists.
fn lines(dir: &Path) -> Vec<Vec<String>> {
    course_lines(dir, &["scene5_", "scene6_", "scene7_"])
}

/// The image files a line writes, with the size each must have.
fn expected_images(args: &[String]) -> Vec<(usize, (u32, u32))> {
    let at = |flag: &str| args.iter().position(|a| a == flag);
    let size = at("-size").unwrap();
    let (w, h): (u32, u32) = (
        args[size + 1].parse().unwrap(),
        args[size + 2].parse().unwrap(),
    );
    let mut images = Vec::new();
    if let Some(i) = at("-output") {
        images.push((i + 1, (w, h)));
    }
    if let Some(i) = at("-render_samples") {
        let zoom: u32 = args[i + 2].parse().unwrap();
        images.push((i + 1, (w * zoom, h * zoom)));
    }
    if let Some(i) = at("-render_filter") {
        let zoom: u32 = args[i + 2].parse().unwrap();
        images.push((i + 1, (w * zoom + 1, h * zoom + 1)));
    }
    images
}

fn run(folder: &Path, args: &[String]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(args)
        .current_dir(folder)
        .output()
        .unwrap()
}

/// Runs `args` with its images sent to a scratch folder; returns them (in `expected_images`
/// order) and stdout.
fn render(folder: &Path, args: &[String]) -> (Vec<image::RgbImage>, String) {
    let scratch = tempfile::tempdir().unwrap();
    let mut args = args.to_vec();
    let images = expected_images(&args);
    for (k, &(at, _)) in images.iter().enumerate() {
        args[at] = scratch
            .path()
            .join(format!("{k}.tga"))
            .to_str()
            .unwrap()
            .into();
    }
    let output = run(folder, &args);
    assert!(
        output.status.success(),
        "raycast {} failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    let decoded = (0..images.len())
        .map(|k| {
            image::open(scratch.path().join(format!("{k}.tga")))
                .unwrap()
                .to_rgb8()
        })
        .collect();
    (decoded, String::from_utf8(output.stdout).unwrap())
}

#[test]
fn every_line_runs_and_writes_images_of_the_courses_sizes() {
    let Some(dir) = later_dir("the assignment 5 to 7 tests") else {
        return;
    };
    let scenes = dir.join("scenes");
    let lines = lines(&dir);
    assert_eq!(
        lines.len(),
        126,
        "COMMANDS.txt should hold 126 lines of assignments 5 to 7"
    );
    let problems: Vec<String> = lines
        .par_iter()
        .filter_map(|args| {
            let expected = expected_images(args);
            let (images, _) = render(&scenes, args);
            for ((_, size), image) in expected.iter().zip(&images) {
                if image.dimensions() != *size {
                    return Some(format!(
                        "{}: {:?}, not {size:?}",
                        args.join(" "),
                        image.dimensions()
                    ));
                }
            }
            None
        })
        .collect();
    let _ = writeln!(
        std::io::stderr(),
        "a5-a7 command lines: {}/{} ran and wrote images of the course's sizes",
        lines.len() - problems.len(),
        lines.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_grid_never_changes_the_image() {
    let Some(dir) = later_dir("the assignment 5 to 7 tests") else {
        return;
    };
    let scenes = dir.join("scenes");
    let with_grid: Vec<Vec<String>> = lines(&dir)
        .into_iter()
        .filter(|a| {
            a[1].starts_with("scene6_")
                && a.contains(&"-grid".to_string())
                && a.contains(&"-output".to_string())
                && !a.contains(&"-visualize_grid".to_string())
        })
        .collect();
    assert!(
        with_grid.len() >= 15,
        "{} lines with -grid",
        with_grid.len()
    );
    let differing: Vec<String> = with_grid
        .par_iter()
        .filter_map(|args| {
            let (grid, _) = render(&scenes, args);
            let (plain, _) = render(&scenes, &without(args, "-grid", 3));
            (grid[0] != plain[0]).then(|| args.join(" "))
        })
        .collect();
    let _ = writeln!(
        std::io::stderr(),
        "a6 grid pairs: {}/{} identical with and without -grid",
        with_grid.len() - differing.len(),
        with_grid.len()
    );
    assert!(
        differing.is_empty(),
        "-grid changes:\n{}",
        differing.join("\n")
    );
}

#[test]
fn stats_print_the_courses_block_with_exact_counts() {
    let Some(dir) = later_dir("the assignment 5 to 7 tests") else {
        return;
    };
    let scenes = dir.join("scenes");
    let args: Vec<String> = "-input scene6_02_sphere_triangles.txt -output o.tga -size 200 200 \
                             -grid 10 10 10 -stats -shadows"
        .split_whitespace()
        .map(String::from)
        .collect();
    let on = |threads: &str| {
        let mut a = args.clone();
        a.extend(["-threads".to_string(), threads.to_string()]);
        render(&scenes, &a).1
    };
    let one = on("1");
    let lines: Vec<&str> = one.lines().collect();
    let stars = "*".repeat(44);
    assert_eq!(lines.len(), 15, "{one}");
    assert_eq!(lines[0], stars);
    assert_eq!(lines[1], "RAY TRACING STATISTICS");
    let field = |k: usize, label: &str| -> String {
        let line = lines[k];
        let prefix = format!("  {label:<27}");
        assert!(line.starts_with(&prefix), "line {k}: {line:?}");
        line[prefix.len()..].to_string()
    };
    let time = field(2, "total time");
    assert!(
        time.split(':').map(str::len).collect::<Vec<_>>() == [1, 2, 2],
        "{time}"
    );
    assert_eq!(field(3, "num pixels"), "40000 (200x200)");
    assert_eq!(
        field(4, "scene bounds"),
        "-3.000000 -1.000000 -3.000000  -> 3.000000 1.000000 3.000000"
    );
    assert_eq!(field(5, "num grid cells"), "1000 (10x10x10)");
    let count = |k: usize, label: &str| field(k, label).parse::<u64>().unwrap();
    let non_shadow = count(6, "num non-shadow rays");
    let shadow = count(7, "num shadow rays");
    let intersections = count(8, "total intersections");
    let cells = count(9, "total cells traversed");
    // No bounces: one camera ray a pixel.
    assert_eq!(non_shadow, 40_000);
    assert!(shadow > 0 && intersections > 0 && cells > 0);
    let rate = |k: usize, label: &str| field(k, label);
    let per = |a: u64, b: u64| format!("{:.1}", a as f32 / b as f32);
    assert!(rate(10, "rays per second").ends_with(|c: char| c.is_ascii_digit()));
    assert_eq!(rate(11, "rays per pixel"), per(non_shadow + shadow, 40_000));
    assert_eq!(
        rate(12, "intersections per ray"),
        per(intersections, non_shadow + shadow)
    );
    assert_eq!(
        rate(13, "cells traversed per ray"),
        per(cells, non_shadow + shadow)
    );
    assert_eq!(lines[14], stars);
    // The counts are exact: two threads count the same.
    let two = on("2");
    let counts = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| {
                l.contains("num ")
                    || l.contains("total intersections")
                    || l.contains("cells traversed  ")
            })
            .map(String::from)
            .collect()
    };
    assert_eq!(counts(&one), counts(&two));

    // Without a grid: no cells, and NULL for the grid.
    let (_, plain) = render(&scenes, &without(&args, "-grid", 3));
    assert!(
        plain.contains("  num grid cells             NULL\n"),
        "{plain}"
    );
    assert!(
        plain.contains("  total cells traversed      0\n"),
        "{plain}"
    );
}

#[test]
fn sampling_is_reproducible_and_seeded() {
    let Some(dir) = later_dir("the assignment 5 to 7 tests") else {
        return;
    };
    let scenes = dir.join("scenes");
    let base: Vec<String> = "-input scene7_01_sphere_triangle.txt -size 24 24 -output o.tga"
        .split_whitespace()
        .map(String::from)
        .collect();
    let image = |extra: &str| {
        let mut a = base.clone();
        a.extend(extra.split_whitespace().map(String::from));
        render(&scenes, &a).0.remove(0)
    };
    let uniform = image("-uniform_samples 9 -tent_filter 1.5");
    assert!(uniform == image("-uniform_samples 9 -tent_filter 1.5 -threads 1"));
    for sampler in ["-random_samples 9", "-jittered_samples 9"] {
        let a = image(&format!("{sampler} -gaussian_filter 0.6"));
        assert!(a == image(&format!("{sampler} -gaussian_filter 0.6 -threads 1")));
        assert!(a == image(&format!("{sampler} -gaussian_filter 0.6 -seed 6837")));
        assert!(a != image(&format!("{sampler} -gaussian_filter 0.6 -seed 1")));
        assert!(a != uniform);
    }
    // No sampler, no filter: one centred sample, as in assignments 1 to 6; and the same with
    // the uniform sampler of one sample and the box of half a pixel, said out loud.
    assert!(image("") == image("-uniform_samples 1 -box_filter 0.5"));
}

#[test]
fn a_grid_over_a_flat_or_empty_scene() {
    let dir = tempfile::tempdir().unwrap();
    let camera = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 4 }
        Lights { numLights 1 DirectionalLight { direction 0.2 -0.3 -1 color 0.8 0.8 0.8 } }
        Materials { numMaterials 1 Material { diffuseColor 1 0.5 0 } }";
    std::fs::write(
        dir.path().join("flat.txt"),
        format!(
            "{camera}\nGroup {{ numObjects 2 MaterialIndex 0
                Triangle {{ vertex0 -1 -1 0 vertex1 1 -1 0 vertex2 0 1 0 }}
                Triangle {{ vertex0 -1.5 -1.5 0 vertex1 -0.5 -1.5 0 vertex2 -1 -0.5 0 }} }}"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("planes.txt"),
        format!(
            "{camera}\nGroup {{ numObjects 1 MaterialIndex 0 Plane {{ normal 0 0.1 1 offset 0 }} }}"
        ),
    )
    .unwrap();
    let args = |scene: &str, extra: &str| -> Vec<String> {
        format!("-input {scene} -size 40 40 -output o.tga {extra}")
            .split_whitespace()
            .map(String::from)
            .collect()
    };
    for scene in ["flat.txt", "planes.txt"] {
        let (plain, _) = render(dir.path(), &args(scene, ""));
        let (grid, stats) = render(dir.path(), &args(scene, "-grid 5 5 5 -stats"));
        assert!(plain[0] == grid[0], "{scene}: -grid changes the image");
        assert!(
            stats.contains("num grid cells             125 (5x5x5)"),
            "{stats}"
        );
        let (cells, _) = render(dir.path(), &args(scene, "-grid 5 5 5 -visualize_grid"));
        let drawn = cells[0].pixels().filter(|p| p.0 != [127, 127, 127]).count();
        if scene == "planes.txt" {
            // No box, no cells: only the background (the course's default grey).
            assert_eq!(drawn, 0);
            assert!(stats.contains("scene bounds               NULL"), "{stats}");
        } else {
            assert!(drawn > 100, "{drawn} pixels of cells");
        }
    }
}
