//! Mistakes written in forms of their own (the example `student_forms`, not the fault library's
//! code): check fits the camera, the depth range and the shading to the student's pictures and
//! names the fault from where the fit lands, on every picture the mistake changes.

// The renderers here are shell scripts around the example.
#![cfg(unix)]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

fn conformance_dir() -> Option<PathBuf> {
    common::data_dir(
        "the fitted forms",
        "RAYCAST_CONFORMANCE_DIR",
        "../shared/conformance",
        "COMMANDS.txt",
    )
}

/// check's report of the example's `form` on the conformance lines of `scenes`: each failing
/// picture's line of the terminal's table.
fn failing(form: &str, scenes: &[&str]) -> Vec<String> {
    failing_in(
        &conformance_dir().expect("the conformance suite"),
        form,
        scenes,
    )
}

/// [`failing`] on the lines of the suite in `conformance` that name any of `scenes` (a scene
/// file, or an output's file name).
fn failing_in(conformance: &Path, form: &str, scenes: &[&str]) -> Vec<String> {
    let out = checked_in(conformance, form, scenes);
    let failing: Vec<String> = out
        .lines()
        .filter(|l| l.starts_with("FAIL"))
        .map(String::from)
        .collect();
    assert!(!failing.is_empty(), "{form}: nothing failed\n{out}");
    failing
}

/// check's terminal report of the example's `form` on the lines of the suite in `conformance`
/// that name any of `scenes`.
fn checked_in(conformance: &Path, form: &str, scenes: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let suite = dir.path().join("suite");
    std::fs::create_dir_all(&suite).unwrap();
    for folder in ["scenes", "reference"] {
        std::os::unix::fs::symlink(conformance.join(folder), suite.join(folder)).unwrap();
    }
    let commands = std::fs::read_to_string(conformance.join("COMMANDS.txt")).unwrap();
    let lines: Vec<&str> = commands
        .lines()
        .filter(|line| line.starts_with("raytracer "))
        .filter(|line| scenes.iter().any(|s| line.contains(&format!(" {s}"))))
        .collect();
    std::fs::write(suite.join("COMMANDS.txt"), lines.join("\n") + "\n").unwrap();
    let example = common::open_example("student_forms");
    let renderer = dir.path().join(form);
    std::fs::write(
        &renderer,
        format!("#!/bin/sh\nexec {example} {form} \"$@\"\n"),
    )
    .unwrap();
    std::fs::set_permissions(&renderer, std::fs::Permissions::from_mode(0o755)).unwrap();
    let output = Command::new(RAYCAST)
        .args(["check", suite.to_str().unwrap(), "--renderer"])
        .arg(&renderer)
        .args([
            "--allow-read",
            Path::new(&example).parent().unwrap().to_str().unwrap(),
        ])
        .env("RAYCAST_CACHE_DIR", dir.path().join("cache"))
        .output()
        .unwrap();
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Every failing picture names `fault` first, alone.
fn all_named(form: &str, scenes: &[&str], fault: &str) -> Vec<String> {
    named_in(&failing(form, scenes), form, fault)
}

/// Every line of `failing` names `fault` first, alone.
fn named_in(failing: &[String], form: &str, fault: &str) -> Vec<String> {
    let failing = failing.to_vec();
    for line in &failing {
        assert!(
            // Graded against the staff's image, or raycast's render where there is none, or
            // the spread of its renders where the picture is drawn by chance.
            [
                "% of pixels off",
                "against raycast's render",
                "with several seeds"
            ]
            .iter()
            .any(|graded| line
                .contains(&format!("{graded}: {fault}: raycast's render"))
                || line.contains(&format!("{graded}: {fault}, "))),
            "{form}: {line}\n{}",
            failing.join("\n")
        );
    }
    failing
}

#[test]
fn perspective_rays_by_a_tangent_per_axis_are_equal_angle_rays() {
    if conformance_dir().is_none() {
        return;
    }
    all_named(
        "tangent_per_axis",
        &["scene2_04_perspective.txt", "scene2_08_cube.txt"],
        "equal_angle_rays",
    );
}

#[test]
fn an_up_vector_made_orthogonal_and_never_normalised_is_the_camera_basis() {
    if conformance_dir().is_none() {
        return;
    }
    let failing = all_named(
        "up_orthogonal_not_normalised",
        &[
            "scene1_03.txt",
            "scene1_04.txt",
            "scene1_05.txt",
            "scene2_08_cube.txt",
        ],
        "camera_basis",
    );
    // Pictures only the fit explains: the depth of a frame whose up is shortened.
    assert_eq!(failing.len(), 7, "{}", failing.join("\n"));
    assert!(
        failing
            .iter()
            .any(|l| l.contains("depth1_05") && l.contains("scale_x 1, scale_y 0.8165")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_horizontal_vector_never_normalised_is_the_camera_basis_with_its_length() {
    if conformance_dir().is_none() {
        return;
    }
    let failing = all_named(
        "horizontal_not_normalised",
        &["scene1_03.txt", "scene1_04.txt"],
        "camera_basis",
    );
    // |direction × up| of scene1_03's up (0.5, 1, 0): √1.25.
    assert!(
        failing
            .iter()
            .any(|l| l.contains("output1_03") && l.contains("scale_x 1.118")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_screen_built_from_the_unnormalised_direction_is_a_view_of_another_size() {
    if conformance_dir().is_none() {
        return;
    }
    // scene2_08's direction (-0.5, -0.5, -1) is √1.5 long: the view is 1/√1.5 as wide, which
    // the picture cannot tell from a narrower angle; both are named.
    let failing = all_named("raw_direction", &["scene2_08_cube.txt"], "field_of_view");
    assert!(
        failing[0].contains("field_of_view, camera_basis:"),
        "{}",
        failing[0]
    );
}

#[test]
fn half_a_pixel_added_to_the_row_alone_is_a_ray_through_a_pixel_edge() {
    if conformance_dir().is_none() {
        return;
    }
    let failing = all_named(
        "left_edge",
        &[
            "scene1_01.txt",
            "scene1_05.txt",
            "scene2_04_perspective.txt",
            "scene2_14_axes_cube.txt",
        ],
        "pixel_corner",
    );
    assert!(
        failing.iter().all(|l| l.contains("offset_x -0.5")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_depth_counted_from_the_pictures_nearest_hit_is_the_depth_range_with_its_distances() {
    if conformance_dir().is_none() {
        return;
    }
    let failing = all_named(
        "depth_from_nearest",
        &[
            "scene1_02.txt",
            "scene2_06_plane.txt",
            "scene2_16_t_scale.txt",
        ],
        "depth_range",
    );
    assert_eq!(failing.len(), 3, "{}", failing.join("\n"));
    // scene1_02's nearest hit is 8.25 away: the student's range is 8.25 to 12.25.
    assert!(
        failing
            .iter()
            .any(|l| l.contains("depth1_02") && l.contains("near 8.25") && l.contains("far 12.2")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_normal_normalised_as_a_four_vector_is_a_normal_of_another_length_with_its_numbers() {
    if conformance_dir().is_none() {
        return;
    }
    // Only the objects moved by a Transform's translation change: scene2_11 to 2_13's spheres
    // are scaled and turned at the origin, and pass.
    let failing = all_named(
        "normal_four_vector",
        &[
            "scene2_11_squashed_sphere.txt",
            "scene2_14_axes_cube.txt",
            "scene2_15_crazy_transforms.txt",
            "scene2_16_t_scale.txt",
        ],
        "normal_length",
    );
    assert_eq!(failing.len(), 3, "{}", failing.join("\n"));
    // 1/|n|² = 1 + (t·n)²: the fourth component is the translation along the normal.
    assert!(
        failing
            .iter()
            .all(|l| l.contains("normal's 1/|n|²: constant 1, times |Aᵀn|² 0, times (t·n)² 1")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn two_mistakes_of_the_shading_sum_written_their_own_way_are_both_named() {
    if conformance_dir().is_none() {
        return;
    }
    let failing = failing(
        "ambient_in_loop_cosine_squared",
        &["scene2_01_diffuse.txt", "scene2_03_colored_lights.txt"],
    );
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    // One light: the ambient term once either way.
    assert!(failing[0].contains("output2_01") && failing[0].contains("off: cosine_twice: "));
    assert!(
        failing[1].contains("output2_03")
            && failing[1].contains("off: ambient_per_light+cosine_twice: "),
        "{}",
        failing[1]
    );
}

#[test]
fn rays_started_a_tiny_offset_along_the_normal_are_shadow_acne_with_the_offset() {
    let Some(later) = common::later_dir("the fitted forms of assignment 4") else {
        return;
    };
    let failing = failing_in(
        &later,
        "tiny_normal_offset",
        &["scene4_01_sphere_shadow.txt", "output4_04b.tga"],
    );
    let failing = named_in(&failing, "tiny_normal_offset", "shadow_acne");
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    // 1e-7, or a little more where the student's 1e-7 / |d·n| grows past raycast's bound at
    // grazing angles.
    for line in &failing {
        let offset: f64 = line
            .split("offset along the normal ")
            .nth(1)
            .and_then(|rest| rest.split(')').next())
            .and_then(|number| number.parse().ok())
            .unwrap_or_else(|| panic!("no offset: {line}"));
        assert!((1e-7..=1.5e-7).contains(&offset), "{line}");
    }
}

#[test]
fn a_filter_half_a_pixel_wider_is_the_filter_radius_with_its_scale() {
    let Some(later) = common::later_dir("the fitted forms of assignment 7") else {
        return;
    };
    let failing = failing_in(
        &later,
        "filter_half_pixel_wider",
        &["output7_01e_low_res.tga", "output7_01f_low_res.tga"],
    );
    let failing = named_in(&failing, "filter_half_pixel_wider", "filter_radius");
    // A tent of 1.5 reaching 2: 4/3 as far; a Gaussian's sigma of 1 made 1.5.
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    assert!(failing[0].contains("scale 1.3333"), "{}", failing[0]);
    assert!(failing[1].contains("scale 1.5)"), "{}", failing[1]);
}

#[test]
fn marble_in_turns_per_unit_is_the_noise_constants_with_a_frequency_of_two_pi() {
    let Some(later) = common::later_dir("the fitted forms of assignment 6") else {
        return;
    };
    let failing = failing_in(
        &later,
        "marble_in_turns",
        &["scene6_15_marble_cubes.txt", "output6_17a.tga"],
    );
    let failing = named_in(&failing, "marble_in_turns", "noise_constants");
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    assert!(
        failing.iter().all(|l| l.contains("frequency 6.2832)")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_point_light_dimmed_by_the_square_of_its_distance_is_the_attenuation_with_its_divisor() {
    let Some(later) = common::later_dir("the fitted forms of assignment 4") else {
        return;
    };
    let failing = failing_in(
        &later,
        "inverse_square_light",
        &[
            "scene4_12_point_light_circle_d_attenuation.txt",
            "scene4_13_point_light_circle_d2_attenuation.txt",
        ],
    );
    let failing = named_in(&failing, "inverse_square_light", "attenuation");
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    assert!(
        failing
            .iter()
            .all(|l| l.contains("divisor: constant 0, times d 0, times d² 1")),
        "{}",
        failing.join("\n")
    );
}

#[test]
fn a_correct_tracer_in_double_precision_passes_the_checkerboards_edges() {
    let Some(later) = common::later_dir("the fitted forms of assignments 6 and 7") else {
        return;
    };
    // Its refracted rays land on the checkerboard's other side of an edge in 0.1% of the
    // pixels, and its uniform samples on the checkerboard's edges in 0.6%: more than the rule
    // allows, each where raycast's own rays turn on their last digits.
    let out = checked_in(
        &later,
        "double_precision",
        &["output6_14.tga", "output7_05a.tga", "output7_02e.tga"],
    );
    for name in ["output6_14", "output7_05a", "output7_02e"] {
        let line = out
            .lines()
            .find(|l| l.contains(&format!(" {name},")))
            .unwrap_or_else(|| panic!("no line for {name}\n{out}"));
        assert!(line.starts_with("pass"), "{line}");
        assert!(
            line.ends_with(
                "allowed: your picture differs from raycast's only where a ray's colour turns \
                 on the last digits of its arithmetic (double against float, another order of \
                 operations)"
            ),
            "{line}"
        );
    }
    assert!(out.contains("3 passed, 0 failed"), "{out}");
}

#[test]
fn snells_law_in_heckberts_form_with_a_sign_or_a_side_wrong_is_the_refraction_formula() {
    let Some(later) = common::later_dir("the fitted forms of assignment 4") else {
        return;
    };
    // The outward normal changes only the rays leaving the glass; the cosine's sign every one.
    for (form, number) in [("heckbert_outward_normal", 0), ("heckbert_cosine_sign", 2)] {
        let failing = failing_in(
            &later,
            form,
            &["output4_08.tga", "output4_14c.tga", "output6_14.tga"],
        );
        let failing = named_in(&failing, form, "refraction_formula");
        assert_eq!(failing.len(), 3, "{}", failing.join("\n"));
        assert!(
            failing
                .iter()
                .all(|l| l.contains(&format!("form {number})"))),
            "{form}: {}",
            failing.join("\n")
        );
    }
}

#[test]
fn a_unit_shadow_ray_tested_up_to_one_is_the_shadow_reach_of_one_unit() {
    let Some(later) = common::later_dir("the fitted forms of assignment 4") else {
        return;
    };
    let failing = failing_in(
        &later,
        "shadow_to_one_minus_epsilon",
        &["output4_10.tga", "output4_11.tga"],
    );
    let failing = named_in(&failing, "shadow_to_one_minus_epsilon", "shadow_reach");
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    assert!(
        failing.iter().all(|l| l.contains("form 0)")),
        "{}",
        failing.join("\n")
    );
}

/// Each failing picture of `form` on the later assignments' lines that name any of `scenes`
/// names `fault` first, alone, with `numbers` (a part of its line); returns how many failed.
fn later_named(form: &str, scenes: &[&str], fault: &str, numbers: &str) -> usize {
    let later =
        common::later_dir("the fitted forms of assignments 4 to 7").expect("the later assignments");
    let failing = failing_in(&later, form, scenes);
    let failing = named_in(&failing, form, fault);
    assert!(
        failing.iter().all(|l| l.contains(numbers)),
        "{form}: {}",
        failing.join("\n")
    );
    failing.len()
}

#[test]
fn mirror_directions_written_otherwise_are_the_reflection_direction() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    let lines = [
        "scene4_03_mirrored_floor.txt",
        "scene4_04_reflective_sphere.txt",
    ];
    // 2 (N·V) N − V with V the ray's own direction: the mirror direction reversed, which the
    // pictures cannot tell from d + 2 (d·n) n.
    assert_eq!(
        later_named("reflect_view_vector", &lines, "reflection_direction", ""),
        4
    );
    // d − (d·n) n: the factor fitted.
    assert_eq!(
        later_named(
            "reflect_without_two",
            &lines,
            "reflection_direction",
            "factor of (d·n) n -1)"
        ),
        4
    );
}

#[test]
fn a_mirror_colour_weighed_twice_is_the_secondary_colour_with_its_power() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "mirror_colour_twice",
            &["scene4_03_mirrored_floor.txt", "output4_04b.tga"],
            "secondary_colour",
            "power of the reflective colour 2)"
        ),
        2
    );
}

#[test]
fn snells_ratio_the_same_on_both_sides_is_the_refraction_index() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    let lines = [
        "scene4_05_transparent_bar.txt",
        "output4_08.tga",
        "output6_14.tga",
    ];
    for (form, number) in [("ratio_never_flipped", 1), ("ratio_index_both_ways", 2)] {
        let named = later_named(form, &lines, "refraction_index", &format!("form {number})"));
        assert_eq!(named, 3, "{form}");
    }
}

#[test]
fn a_refracted_ray_past_the_critical_angle_of_nans_or_mirrored_is_total_internal_reflection() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    let lines = ["output4_06e.tga", "output4_06f.tga", "output4_14c.tga"];
    for (form, number) in [("total_internal_nan", 3), ("total_internal_mirror", 4)] {
        let named = later_named(
            form,
            &lines,
            "total_internal_reflection",
            &format!("form {number})"),
        );
        assert_eq!(named, 3, "{form}");
    }
}

#[test]
fn a_checkerboard_wrong_for_negative_coordinates_is_the_checker_truncation() {
    if common::later_dir("the fitted forms of assignment 6").is_none() {
        return;
    }
    let lines = ["scene6_13_checkerboard.txt", "output6_14.tga"];
    // fmod(x, 2) < 1: a form of the library's own; floor(|x|) draws as int(x) does.
    assert_eq!(
        later_named("checker_fmod", &lines, "checker_truncation", "form 1)"),
        2
    );
    assert_eq!(
        later_named("checker_absolute", &lines, "checker_truncation", "form 0)"),
        2
    );
}

#[test]
fn uniform_samples_from_edge_to_edge_are_a_grid_spread_by_s_over_s_minus_one() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "uniform_edge_to_edge",
            &["output7_01d_low_res.tga", "output7_01e_low_res.tga"],
            "uniform_corners",
            "spread 1.5)"
        ),
        2
    );
    assert_eq!(
        later_named(
            "uniform_edge_to_edge",
            &["output7_02d.tga"],
            "uniform_corners",
            "spread 1.3333)"
        ),
        1
    );
}

#[test]
fn an_attenuation_read_in_the_other_order_is_the_attenuation() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // scene4_12's 0 1 0 reads the same either way and passes.
    assert_eq!(
        later_named(
            "attenuation_reversed",
            &[
                "scene4_12_point_light_circle_d_attenuation.txt",
                "scene4_13_point_light_circle_d2_attenuation.txt",
                "output4_14a.tga"
            ],
            "attenuation",
            ""
        ),
        2
    );
}

#[test]
fn a_fixed_epsilon_along_the_ray_is_shadow_acne_with_its_least_t() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "absolute_epsilon_along_ray",
            &[
                "scene4_01_sphere_shadow.txt",
                "scene4_03_mirrored_floor.txt"
            ],
            "shadow_acne",
            "least t 1e-6)"
        ),
        2
    );
}

#[test]
fn a_gaussian_whose_sigma_is_taken_as_its_variance_is_the_filter_radius_with_its_scale() {
    let Some(later) = common::later_dir("the fitted forms of assignment 7") else {
        return;
    };
    // σ' = √σ: √0.5 / 0.5, √1.7 / 1.7 and √2.3 / 2.3 times the reach; σ = 1 passes.
    let failing = failing_in(
        &later,
        "gaussian_variance_as_sigma",
        &[
            "filter7_01c.tga",
            "filter7_01f.tga",
            "filter7_01i.tga",
            "output7_01c_low_res.tga",
        ],
    );
    let failing = named_in(&failing, "gaussian_variance_as_sigma", "filter_radius");
    assert_eq!(failing.len(), 3, "{}", failing.join("\n"));
    for (line, sigma) in failing.iter().zip([0.5f64, 1.7, 2.3]) {
        let scale: f64 = line
            .split("scale ")
            .nth(1)
            .and_then(|rest| rest.split(')').next())
            .and_then(|number| number.parse().ok())
            .unwrap_or_else(|| panic!("no scale: {line}"));
        let expected = sigma.sqrt() / sigma;
        assert!((scale / expected - 1.0).abs() < 0.01, "{line}");
    }
}

/// Each failing picture of `form` on the conformance lines that name any of `scenes` names
/// `fault` first (alone, or with those the line cannot tell from it), with `numbers` (a part
/// of its line); returns how many failed.
fn conformance_named(form: &str, scenes: &[&str], fault: &str, numbers: &str) -> usize {
    let failing = named_in(&failing(form, scenes), form, fault);
    assert!(
        failing.iter().all(|l| l.contains(numbers)),
        "{form}: {}",
        failing.join("\n")
    );
    failing.len()
}

#[test]
fn flips_written_in_the_frame_or_the_rows_with_bytes_rounded_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    // Each student's bytes rounded to the nearest, not truncated: a level off in half the
    // pixels, which the rule allows, beside the mistake.
    let lines = ["scene1_03.txt", "scene2_04_perspective.txt"];
    assert_eq!(
        conformance_named("rows_from_the_top+rounded", &lines, "flip_vertical", ""),
        4
    );
    assert_eq!(
        conformance_named("horizontal_reversed+rounded", &lines, "flip_horizontal", ""),
        4
    );
}

#[test]
fn columns_alone_spread_over_width_minus_one_are_the_pixel_span_with_its_axis() {
    if conformance_dir().is_none() {
        return;
    }
    // 200 / 199 across, 1 up.
    assert_eq!(
        conformance_named(
            "columns_over_width_minus_one",
            &["scene1_03.txt", "scene2_04_perspective.txt"],
            "pixel_span_minus_one",
            "scale_x 1.005"
        ),
        4
    );
}

#[test]
fn rays_through_the_far_corner_are_a_ray_through_a_pixel_corner() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "far_corner",
            &["scene1_03.txt", "scene2_04_perspective.txt"],
            "pixel_corner",
            "corner 3"
        ),
        4
    );
}

#[test]
fn a_screen_as_wide_as_the_angle_is_the_field_of_view_with_the_angle_it_amounts_to() {
    if conformance_dir().is_none() {
        return;
    }
    // A screen π/6 wide at distance 1: 2 atan(π/12) = 29.34°.
    assert_eq!(
        conformance_named(
            "screen_as_wide_as_the_angle",
            &["scene2_04_perspective.txt", "scene2_08_cube.txt"],
            "field_of_view",
            "angle 29.33"
        ),
        3
    );
}

#[test]
fn a_depth_counted_to_the_farthest_hit_is_the_depth_range() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "depth_to_farthest",
            &["scene1_02.txt", "scene2_06_plane.txt"],
            "depth_range",
            ""
        ),
        2
    );
}

#[test]
fn normals_stored_as_a_normal_map_are_the_signed_normals_with_their_mapping() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "normals_half_plus_half",
            &["scene2_04_perspective.txt", "scene2_06_plane.txt"],
            "normals_signed",
            "mapping 1"
        ),
        2
    );
}

#[test]
fn a_light_dimmed_by_the_cosine_where_it_arrives_is_the_cosine_twice() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "light_scaled_by_cosine",
            &[
                "scene2_01_diffuse.txt",
                "scene2_03_colored_lights.txt",
                "scene2_04_perspective.txt"
            ],
            "cosine_twice",
            ""
        ),
        3
    );
}

#[test]
fn a_recursion_counted_from_one_with_bytes_rounded_is_a_bounce_too_few() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "depth_counted_from_one+rounded",
            &[
                "scene4_03_mirrored_floor.txt",
                "scene4_04_reflective_sphere.txt",
                "output4_08.tga"
            ],
            "bounces_off_by_one",
            "bounces -1)"
        ),
        5
    );
}

#[test]
fn octaves_summed_from_the_second_are_the_noise_constants_with_the_first_octaves_frequency() {
    if common::later_dir("the fitted forms of assignment 6").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "noise_from_second_octave",
            &["scene6_15_marble_cubes.txt", "output6_17a.tga"],
            "noise_constants",
            "first octave's frequency 2)"
        ),
        2
    );
}

#[test]
fn picture_mistakes_written_their_own_way_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    // Each with bytes rounded to the nearest beside it.
    assert_eq!(
        conformance_named(
            "blue_green_red+rounded",
            &["scene2_03_colored_lights.txt", "scene1_03.txt"],
            "channel_swap",
            ""
        ),
        3
    );
    assert_eq!(
        conformance_named(
            "normals_clamped_at_zero+rounded",
            &["scene2_04_perspective.txt", "scene2_06_plane.txt"],
            "normals_signed",
            "mapping 0)"
        ),
        2
    );
    assert_eq!(
        conformance_named(
            "misses_in_background+rounded",
            &[
                "scene1_02.txt",
                "scene1_03.txt",
                "scene2_04_perspective.txt"
            ],
            "picture_background",
            ""
        ),
        3
    );
}

#[test]
fn back_faces_written_their_own_way_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    let lines = [
        "scene2_05_inside_sphere.txt",
        "scene2_07_sphere_triangles.txt",
    ];
    for (form, fault) in [
        ("back_faces_always_black", "shade_back_ignored"),
        ("back_faces_always_shaded", "back_faces_lit"),
        ("back_faces_ambient", "ambient_on_back_faces"),
    ] {
        assert_eq!(conformance_named(form, &lines, fault, ""), 2, "{form}");
    }
}

#[test]
fn the_shading_sums_mistakes_written_their_own_way_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    // The ambient term only in a scene without lights: none where there are lights.
    assert_eq!(
        conformance_named(
            "ambient_only_without_lights",
            &[
                "scene2_02_ambient.txt",
                "scene2_06_plane.txt",
                "scene2_08_cube.txt"
            ],
            "ambient_missing",
            ""
        ),
        3
    );
    assert_eq!(
        conformance_named(
            "ambient_times_lights",
            &["scene2_03_colored_lights.txt"],
            "ambient_per_light",
            ""
        ),
        1
    );
    // Each light's terms with the normal turned to the light: |N·L|.
    assert_eq!(
        conformance_named(
            "normal_turned_to_the_light",
            &["scene2_01_diffuse.txt", "scene2_03_colored_lights.txt"],
            "shade_back_abs",
            ""
        ),
        2
    );
}

#[test]
fn the_first_hits_mistakes_written_their_own_way_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "hits_behind_the_eye",
            &["scene2_06_plane.txt"],
            "t_min_ignored",
            ""
        ),
        3
    );
    assert_eq!(
        conformance_named(
            "normal_by_object_matrix",
            &[
                "scene2_11_squashed_sphere.txt",
                "scene2_15_crazy_transforms.txt"
            ],
            "normal_transform",
            ""
        ),
        3
    );
    // A search from t = 50: not one of the listed limits, fitted.
    assert_eq!(
        conformance_named(
            "farthest_fifty",
            &["scene2_06_plane.txt"],
            "t_limit",
            "limit 50)"
        ),
        2
    );
}

#[test]
fn the_later_stages_mistakes_written_their_own_way_are_named() {
    if common::later_dir("the fitted forms of assignments 4 and 7").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "bytes_wrap",
            &["output4_05.tga", "output4_12.tga"],
            "no_clamp",
            ""
        ),
        2
    );
    assert_eq!(
        later_named(
            "shadow_to_infinity+rounded",
            &["scene4_10_point_light_distance.txt"],
            "shadow_past_light",
            ""
        ),
        1
    );
    // The uniform lines' pictures and the random lines' alike (those graded against the
    // spread of raycast's renders with several seeds).
    assert_eq!(
        later_named(
            "weights_over_count",
            &["output7_01c_low_res.tga", "output7_01f_low_res.tga"],
            "filter_weights",
            "form 0)"
        ),
        2
    );
    assert_eq!(
        later_named(
            "texture_matrix_ignored+rounded",
            &["scene6_13_checkerboard.txt"],
            "texture_transform",
            ""
        ),
        1
    );
}

#[test]
fn the_depth_pictures_mistakes_written_their_own_way_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    // The camera rays started at the depth's near end: the plane nearer than 8 cut away.
    assert_eq!(
        conformance_named(
            "depth_near_as_start",
            &["scene2_06_plane.txt"],
            "depth_tmin",
            "t_min 8)"
        ),
        3
    );
    assert_eq!(
        conformance_named("depth_wraps", &["scene2_06_plane.txt"], "depth_clamp", ""),
        1
    );
}

#[test]
fn more_of_the_later_stages_mistakes_written_their_own_way_are_named() {
    if common::later_dir("the fitted forms of assignments 3 to 7").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "specular_always_faded+rounded",
            &["output3_09.tga", "output3_12.tga"],
            "specular_fix",
            ""
        ),
        2
    );
    assert_eq!(
        later_named(
            "one_bounce_more",
            &["scene4_04_reflective_sphere.txt"],
            "bounces_off_by_one",
            "bounces 1)"
        ),
        3
    );
    // (a + 1) / s: the grid moved half a cell up and right.
    assert_eq!(
        later_named(
            "uniform_upper_corners",
            &["output7_01d_low_res.tga", "output7_02d.tga"],
            "uniform_corners",
            "offset 0.5)"
        ),
        2
    );
    assert_eq!(
        later_named(
            "weights_over_pixel_samples",
            &["output7_01b_low_res.tga", "output7_01e_low_res.tga"],
            "filter_weights",
            "form 1)"
        ),
        2
    );
    assert_eq!(
        later_named(
            "texture_matrix_inverted",
            &["scene6_13_checkerboard.txt"],
            "texture_transform",
            "form 1)"
        ),
        1
    );
    // light - point unnormalised, tested to the distance: as far as the distance squared,
    // which in scene4_10 (every light further than a unit) draws as a ray past the light does:
    // both named, the line cannot tell them apart.
    assert_eq!(
        later_named(
            "shadow_to_distance_squared",
            &["scene4_10_point_light_distance.txt"],
            "shadow_past_light",
            "shadow_past_light, shadow_reach: "
        ),
        1
    );
}

#[test]
fn jittered_samples_anywhere_from_a_generator_of_the_students_own_are_the_jitter_whole_pixel() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    // Its pictures are drawn by chance as no render of raycast's is: they lie within the
    // spread of raycast's renders with the fault planted and several seeds, and outside that
    // of its jittered renders; and no fault whose render is one more draw as far from them as
    // raycast's own is named beside it.
    let failing = later_named(
        "jitter_anywhere",
        &[
            "output7_01h_low_res.tga",
            "output7_02h.tga",
            "output7_02i.tga",
        ],
        "jitter_whole_pixel",
        "several seeds: jitter_whole_pixel: raycast's render",
    );
    assert_eq!(failing, 3);
}

#[test]
fn second_forms_of_the_camera_and_the_first_hits_are_named() {
    if conformance_dir().is_none() {
        return;
    }
    // Tilted, then turned: the other order of the library's two turns, fitted.
    assert_eq!(
        conformance_named(
            "spherical_rays",
            &["scene2_04_perspective.txt"],
            "equal_angle_rays",
            "form_turned_up_first 1)"
        ),
        2
    );
    let lines = ["scene1_03.txt", "scene2_04_perspective.txt"];
    assert_eq!(
        conformance_named("v_from_the_top", &lines, "flip_vertical", ""),
        4
    );
    assert_eq!(
        conformance_named("u_mirrored", &lines, "flip_horizontal", ""),
        4
    );
    assert_eq!(
        conformance_named(
            "orthographic_from_zero",
            &["scene1_07.txt"],
            "t_min_ignored",
            "t_min 0)"
        ),
        2
    );
    assert_eq!(
        conformance_named(
            "normal_not_renormalised",
            &[
                "scene2_11_squashed_sphere.txt",
                "scene2_13_rotated_squashed_sphere.txt"
            ],
            "normal_length",
            ""
        ),
        4
    );
}

#[test]
fn a_glass_rays_colour_added_whole_is_the_secondary_colour() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "glass_colour_ignored",
            &["scene4_05_transparent_bar.txt", "output4_07.tga"],
            "secondary_colour",
            "form 1)"
        ),
        2
    );
}
