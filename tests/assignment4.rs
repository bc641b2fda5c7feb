//! Assignment 4 (shadows, mirrors, glass, point lights) has no staff images. Every one of its
//! command lines in the course's COMMANDS.txt runs here, and the images are checked for what a
//! correct tracer must show:
//!
//! * shadows only ever take light away: with `-shadows` no channel of any pixel is brighter
//!   than without, and some pixels are darker;
//! * a shadowed point differs from its unshadowed twin by exactly the blocked light's share;
//! * `-bounces 0` is the image of the same scene with every reflective and transparent colour
//!   removed, byte for byte;
//! * in each bounce series, each further bounce changes the image, and by less than the one
//!   before (the traced weights shrink);
//! * the floor under the point light follows c + l·d + q·d² as each scene states it, pixel by
//!   pixel, with d worked out from the camera ray through the pixel;
//! * glass of index 1 with a black surface shows the scene behind it unbent;
//! * a mirror floor shows the objects above it upside down;
//! * one thread and two give the same image;
//! * the normal and depth pictures show the camera ray's own hit, whatever the tracing
//!   options, also at a non-square size.
//!
//! The course data comes from RAYCAST_LATER_DIR (default ../shared/later-assignments); where
//! the variable is set, missing data fails the tests.

mod common;

use common::{course_lines, later_dir, without};
use std::io::Write as _;
use std::path::Path;
use std::process::Command;

use glam::Vec3A;
use raycast::Scene;
use raycast::camera::pixel_to_screen;
use rayon::prelude::*;

/// The course's assignment-4 command lines, as argument lists (without `raytracer`).
fn assignment_4_lines(dir: &Path) -> Vec<Vec<String>> {
    course_lines(dir, &["scene4_"])
}

fn value_of<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    let at = args.iter().position(|a| a == flag)?;
    args.get(at + 1).map(String::as_str)
}

fn with_value(args: &[String], flag: &str, value: &str) -> Vec<String> {
    let mut args = args.to_vec();
    let at = args.iter().position(|a| a == flag).unwrap();
    args[at + 1] = value.to_string();
    args
}

/// Runs raycast on `args` in `folder`, its `-output` sent to a scratch file, and returns the
/// image.
fn render(folder: &Path, args: &[String]) -> image::RgbImage {
    let scratch = tempfile::tempdir().unwrap();
    let output = scratch.path().join("out.tga");
    let args = with_value(args, "-output", output.to_str().unwrap());
    let run = Command::new(env!("CARGO_BIN_EXE_raycast"))
        .args(&args)
        .current_dir(folder)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "raycast {} failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&run.stderr)
    );
    image::open(&output).unwrap().to_rgb8()
}

/// A copy of a course scene with its text edited, placed in a scratch folder; meshes are still
/// found, since raycast looks for them in the working directory (the course's scene folder)
/// after the scene's own.
fn edited_scene(dir: &Path, scene: &str, edit: impl Fn(&str) -> String) -> tempfile::TempDir {
    let text = std::fs::read_to_string(dir.join("scenes").join(scene)).unwrap();
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit of {scene} changed nothing");
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join(scene), edited).unwrap();
    folder
}

fn line_for<'a>(lines: &'a [Vec<String>], output: &str) -> &'a [String] {
    lines
        .iter()
        .find(|l| value_of(l, "-output") == Some(output))
        .unwrap_or_else(|| panic!("no line writes {output}"))
}

#[test]
fn every_line_renders_and_shadows_only_darken() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let scenes = dir.join("scenes");
    let lines = assignment_4_lines(&dir);
    assert_eq!(
        lines.len(),
        27,
        "COMMANDS.txt should hold 27 assignment-4 lines"
    );
    let problems: Vec<String> = lines
        .par_iter()
        .filter_map(|args| {
            let name = value_of(args, "-output").unwrap();
            let size: Vec<u32> = args
                .iter()
                .skip_while(|a| *a != "-size")
                .skip(1)
                .take(2)
                .map(|s| s.parse().unwrap())
                .collect();
            let image = render(&scenes, args);
            if image.dimensions() != (size[0], size[1]) {
                return Some(format!("{name}: {:?}, not {size:?}", image.dimensions()));
            }
            if !args.iter().any(|a| a == "-shadows") {
                return Some(format!("{name}: every assignment-4 line asks for -shadows"));
            }
            let unshadowed = render(&scenes, &without(args, "-shadows", 0));
            let brighter = image
                .pixels()
                .zip(unshadowed.pixels())
                .filter(|(s, u)| (0..3).any(|c| s[c] > u[c]))
                .count();
            let darker = image
                .pixels()
                .zip(unshadowed.pixels())
                .filter(|(s, u)| s != u)
                .count();
            if brighter > 0 {
                return Some(format!("{name}: {brighter} pixels brighter with -shadows"));
            }
            if darker == 0 {
                return Some(format!("{name}: -shadows changed nothing"));
            }
            None
        })
        .collect();
    let _ = writeln!(
        std::io::stderr(),
        "a4 command lines: {}/{} rendered with their properties",
        lines.len() - problems.len(),
        lines.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_shadowed_point_loses_exactly_the_blocked_lights_share() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let args = line_for(&lines, "output4_01.tga");
    let scenes = dir.join("scenes");
    let shadowed = render(&scenes, args);
    let lit = render(&scenes, &without(args, "-shadows", 0));
    // scene4_01: a red sphere over a green floor (normal 0.01 1 0.01, diffuse 0 1 0), ambient
    // 0.2, one light straight down of colour 0.8. On the floor, N·L = 1/|(0.01, 1, 0.01)|, so
    // the sphere's shadow takes 0.8·N·L of green away and leaves the ambient 0.2.
    let n_dot_l = 1.0 / Vec3A::new(0.01, 1.0, 0.01).length();
    let byte = |x: f32| ((x * 255.0) as i32).clamp(0, 255) as u8;
    let floor_lit = [0, byte(0.2 + 0.8 * n_dot_l), 0];
    let floor_shadowed = [0, byte(0.2), 0];
    assert_eq!(floor_lit, [0, 254, 0]);
    let mut in_shadow = 0;
    for (s, l) in shadowed.pixels().zip(lit.pixels()) {
        if s != l {
            assert_eq!((s.0, l.0), (floor_shadowed, floor_lit));
            in_shadow += 1;
        }
    }
    // The shadow is a visible patch, not a few pixels.
    assert!(in_shadow > 500, "{in_shadow} pixels in shadow");
}

#[test]
fn bounces_zero_is_the_scene_without_mirrors_or_glass() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    for output in ["output4_04a.tga", "output4_06a.tga", "output4_14a.tga"] {
        let args = line_for(&lines, output);
        assert_eq!(value_of(args, "-bounces"), Some("0"));
        let scene = value_of(args, "-input").unwrap();
        let plain = edited_scene(&dir, scene, |text| {
            text.lines()
                .filter(|l| !l.contains("reflectiveColor") && !l.contains("transparentColor"))
                .collect::<Vec<_>>()
                .join("\n")
        });
        let plain_scene = plain.path().join(scene);
        let plain_args = with_value(args, "-input", plain_scene.to_str().unwrap());
        assert!(
            render(&scenes, args) == render(&scenes, &plain_args),
            "{output} differs from its scene without reflective and transparent colours"
        );
    }
}

#[test]
fn each_bounce_changes_the_image_less_than_the_one_before() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    for (series, last) in [
        ("output4_04", 'd'),
        ("output4_06", 'f'),
        ("output4_14", 'f'),
    ] {
        let images: Vec<image::RgbImage> = ('a'..=last)
            .map(|letter| render(&scenes, line_for(&lines, &format!("{series}{letter}.tga"))))
            .collect();
        let change = |a: &image::RgbImage, b: &image::RgbImage| -> u64 {
            a.as_raw()
                .iter()
                .zip(b.as_raw())
                .map(|(&x, &y)| u64::from(x.abs_diff(y)))
                .sum()
        };
        let changes: Vec<u64> = images.windows(2).map(|w| change(&w[0], &w[1])).collect();
        assert!(
            changes.iter().all(|&c| c > 0) && changes.windows(2).all(|w| w[1] < w[0]),
            "{series}: change from each bounce to the next {changes:?}"
        );
    }
}

#[test]
fn point_light_attenuation_follows_each_scenes_terms() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    // All three: a white floor (y = -1, normal up), ambient 0.2, one point light of colour 0.8
    // at (0, 2.5, 0); they differ only in the attenuation terms.
    for (output, [c, l, q]) in [
        ("output4_11.tga", [1.0f32, 0.0, 0.0]),
        ("output4_12.tga", [0.0, 0.2, 0.0]),
        ("output4_13.tga", [0.0, 0.0, 0.05]),
    ] {
        let args = line_for(&lines, output);
        let image = render(&scenes, args);
        let scene_path = scenes.join(value_of(args, "-input").unwrap());
        let scene = Scene::load(&scene_path).unwrap();
        let (width, height) = image.dimensions();
        let byte = |x: f32| ((x * 255.0) as i32).clamp(0, 255);
        let (mut lit, mut checked) = (0, 0);
        for row in 0..height {
            for column in 0..width {
                let (u, v) = pixel_to_screen(column, height - 1 - row, width, height);
                let ray = scene.camera.ray(u, v);
                let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) else {
                    continue;
                };
                let point = ray.at(hit.t);
                if hit.normal != Vec3A::Y || (point.y + 1.0).abs() > 1e-4 {
                    continue; // not the floor
                }
                let d = (Vec3A::new(0.0, 2.5, 0.0) - point).length();
                let n_dot_l = 3.5 / d;
                let expected = byte(0.2 + n_dot_l * 0.8 / (c + l * d + q * d * d));
                let actual = i32::from(image.get_pixel(column, row)[0]);
                checked += 1;
                if actual == byte(0.2) {
                    continue; // in a shadow
                }
                lit += 1;
                assert!(
                    (actual - expected).abs() <= 1,
                    "{output} pixel ({column}, {row}): floor at distance {d} from the light \
                     is {actual}, expected {expected}"
                );
            }
        }
        assert!(
            lit > checked / 2 && checked > 10_000,
            "{output}: {lit} lit of {checked} floor pixels"
        );
    }
}

#[test]
fn glass_of_index_one_shows_the_scene_behind_it_unbent() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    let args = line_for(&lines, "output4_07.tga");
    let scene = value_of(args, "-input").unwrap();
    // The sphere made clear glass with nothing of its own (black, no highlight, no mirror), and
    // its twin with the sphere taken out of view. Without -shadows, since glass casts opaque
    // shadows.
    let glass_material = |text: &str| {
        text.replace("diffuseColor 0.1 0.1 0.1", "diffuseColor 0 0 0")
            .replace("specularColor 1 1 1", "")
            .replace("transparentColor 0.7 0.7 0.7", "transparentColor 1 1 1")
            .replace("reflectiveColor 0.3 0.3 0.3", "")
    };
    let clear = edited_scene(&dir, scene, glass_material);
    let gone = edited_scene(&dir, scene, |text| {
        glass_material(text).replace("center 0 2 0", "center 0 -1000 0")
    });
    // The control: the same glass of index 1.5 bends the view.
    let bending = edited_scene(&dir, scene, |text| {
        glass_material(text).replace("indexOfRefraction 1.0", "indexOfRefraction 1.5")
    });
    let args = without(args, "-shadows", 0);
    let image = |folder: &tempfile::TempDir| {
        let path = folder.path().join(scene);
        render(
            &scenes,
            &with_value(&args, "-input", path.to_str().unwrap()),
        )
    };
    let differing = |a: &image::RgbImage, b: &image::RgbImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 2))
            .count()
    };
    let without_glass = image(&gone);
    assert_eq!(
        differing(&image(&clear), &without_glass),
        0,
        "pixels that differ through glass of index 1"
    );
    assert!(differing(&image(&bending), &without_glass) > 1000);
}

#[test]
fn a_mirror_floor_shows_the_objects_above_it_upside_down() {
    // Red above blue in front of the camera; the floor mirror halves what it reflects. No
    // lights: the course's white ambient light shows every colour flat.
    let text = "
        PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 40 }
        Background { color 0 0 0 }
        Materials { numMaterials 3
            Material { diffuseColor 0 0 0 reflectiveColor 0.5 0.5 0.5 }
            Material { diffuseColor 1 0 0 }
            Material { diffuseColor 0 0 1 } }
        Group { numObjects 3
            MaterialIndex 0 Plane { normal 0 1 0 offset -1 }
            MaterialIndex 1 Sphere { center 0 1.2 0 radius 0.5 }
            MaterialIndex 2 Sphere { center 0 0.2 0 radius 0.5 } }";
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join("mirror.txt"), text).unwrap();
    let args: Vec<String> = "-input mirror.txt -size 101 101 -output x.tga -bounces 1"
        .split(' ')
        .map(String::from)
        .collect();
    let image = render(folder.path(), &args);
    // Down the middle column, top to bottom: each run of one colour, once.
    let mut runs: Vec<[u8; 3]> = Vec::new();
    for row in 0..101 {
        let pixel = image.get_pixel(50, row).0;
        if pixel != [0, 0, 0] && runs.last() != Some(&pixel) {
            runs.push(pixel);
        }
    }
    assert_eq!(
        runs,
        [[255, 0, 0], [0, 0, 255], [0, 0, 127], [127, 0, 0]],
        "red over blue, then their reflection: blue over red at half strength"
    );
    // With no bounce, the mirror is black.
    let image = render(folder.path(), &without(&args, "-bounces", 1));
    assert!((60..101).all(|row| image.get_pixel(50, row).0 == [0, 0, 0]));
}

#[test]
fn one_thread_and_two_give_the_same_image() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    for output in ["output4_06f.tga", "output4_09.tga", "output4_14f.tga"] {
        let args = line_for(&lines, output).to_vec();
        let on = |threads: &str| {
            let mut args = args.clone();
            args.extend(["-threads".to_string(), threads.to_string()]);
            render(&scenes, &args)
        };
        assert!(on("1") == on("2"), "{output}: 1 and 2 threads differ");
    }
}

#[test]
fn normals_and_depth_do_not_depend_on_tracing_options() {
    let Some(dir) = later_dir("the assignment 4 tests") else {
        return;
    };
    let lines = assignment_4_lines(&dir);
    let scenes = dir.join("scenes");
    let args = line_for(&lines, "output4_14f.tga");
    let scratch = tempfile::tempdir().unwrap();
    let pictures = |args: &[String], tag: &str| {
        let normals = scratch.path().join(format!("normals-{tag}.png"));
        let depth = scratch.path().join(format!("depth-{tag}.png"));
        let mut args = with_value(args, "-size", "300");
        let at = args.iter().position(|a| a == "-size").unwrap();
        args[at + 2] = "150".into();
        args.extend(
            ["-normals", normals.to_str().unwrap(), "-depth", "10", "30"].map(String::from),
        );
        args.push(depth.to_str().unwrap().to_string());
        let colour = render(&scenes, &args);
        assert_eq!(colour.dimensions(), (300, 150));
        (
            image::open(&normals).unwrap().to_rgb8(),
            image::open(&depth).unwrap().to_rgb8(),
        )
    };
    let traced = pictures(args, "traced");
    let plain_args = with_value(&without(args, "-shadows", 0), "-bounces", "0");
    let plain = pictures(&plain_args, "plain");
    assert!(
        traced == plain,
        "normals or depth change with -bounces or -shadows"
    );
    // A picture that is not all background: the gem is there.
    assert!(traced.0.pixels().any(|p| p.0 != [0, 0, 0]));
}
