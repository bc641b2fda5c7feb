//! Textures (assignment 6) and the film's samples and filters (assignment 7).

use crate::*;

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
fn marble_along_another_axis_is_the_noise_constants_with_its_axis() {
    if common::later_dir("the fitted forms of assignments 6 and 7").is_none() {
        return;
    }
    // sin(frequency * y + amplitude * N): fitted where each pixel is one ray (the vase's lines
    // of many samples a pixel fail too, and no fit reads them).
    assert_eq!(
        later_named(
            "marble_along_y",
            &[
                "scene6_15_marble_cubes.txt",
                "output6_17a.tga",
                "output7_03a.tga"
            ],
            "noise_constants",
            "axis 1)"
        ),
        3
    );
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
        "jitter_whole_pixel: raycast's renders with this fault planted and several seeds draw it (0.000% of pixels outside their spread)",
    );
    assert_eq!(failing, 3);
}

#[test]
fn jittered_samples_moved_by_half_a_pixel_about_each_cell_are_the_jitter_whole_pixel() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    // (a + 0.5) / s + rand() - 0.5: a whole pixel's spread about each cell's centre, from the
    // student's own generator.
    let failing = later_named(
        "jitter_around_cells",
        &[
            "output7_01h_low_res.tga",
            "output7_02h.tga",
            "output7_02i.tga",
        ],
        "jitter_whole_pixel",
        "jitter_whole_pixel: raycast's renders with this fault planted and several seeds draw it",
    );
    assert_eq!(failing, 3);
}

#[test]
fn filters_of_another_distance_written_their_own_way_are_the_filter_shape() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    let tents = ["output7_01e_low_res.tga", "output7_02e.tga"];
    // 1 - (|dx| + |dy|) / r, tested d < r.
    assert_eq!(
        later_named("tent_manhattan", &tents, "filter_shape", "form 1)"),
        2
    );
    // max(0, 1 - max(|dx|, |dy|) / r).
    assert_eq!(
        later_named("tent_chebyshev", &tents, "filter_shape", "form 2)"),
        2
    );
    // dx² + dy² <= r²: the round box, its edge in (uniform samples of 16 a pixel reach past
    // the disc; 9 do not).
    assert_eq!(
        later_named(
            "box_disc",
            &["output7_01d_low_res.tga", "output7_02d.tga"],
            "filter_shape",
            "form 0)"
        ),
        1
    );
}

#[test]
fn octaves_summed_unweighed_are_the_noise_constants_with_the_octaves_weight() {
    if common::later_dir("the fitted forms of assignment 6").is_none() {
        return;
    }
    // noise(2^i p) summed for i = 0 to octaves - 1, without the 1 / 2^i: fitted as each
    // octave's weight over the last's, 1 where the course's is 1/2.
    assert_eq!(
        later_named(
            "noise_octaves_unweighed",
            &["output6_15.tga", "output6_17a.tga"],
            "noise_constants",
            "each octave's weight over the last's 1)"
        ),
        2
    );
}

#[test]
fn filters_that_gather_the_wrong_pixels_samples_are_the_filter_neighbours() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    // A weight of nothing for every sample outside the pixel's own square.
    assert_eq!(
        later_named(
            "filter_own_pixel",
            &["output7_01e_low_res.tga", "output7_01f_low_res.tga"],
            "filter_neighbours",
            "form 0)"
        ),
        2
    );
    // The neighbours' loop stopping one short: the last neighbour's samples weigh nothing.
    assert_eq!(
        later_named(
            "neighbours_loop_short",
            &["output7_01e_low_res.tga", "output7_01f_low_res.tga"],
            "filter_neighbours",
            "form 1)"
        ),
        2
    );
}

#[test]
fn a_filter_centred_on_a_pixel_corner_is_the_filter_centre() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    // The filter's distance from the pixel's corner, not its centre: the picture shifted by
    // half a pixel, and blurred to one side.
    let low_res = ["output7_01c_low_res.tga", "output7_01f_low_res.tga"];
    assert_eq!(
        later_named("filter_from_corner", &low_res, "filter_centre", "form 0)"),
        2
    );
    assert_eq!(
        later_named(
            "filter_from_top_corner",
            &low_res,
            "filter_centre",
            "form 1)"
        ),
        2
    );
}

#[test]
fn a_gaussian_written_otherwise_is_the_filter_shape() {
    if common::later_dir("the fitted forms of assignment 7").is_none() {
        return;
    }
    // e^(-d²/σ²): the 2 left out, the cut at 2σ kept (not a filter reaching less far).
    assert_eq!(
        later_named(
            "gaussian_without_two",
            &["output7_01f_low_res.tga", "output7_02f.tga"],
            "filter_shape",
            "form 0)"
        ),
        2
    );
    // e^(-d²/2σ): σ not squared (where σ is 1 the two agree, so a line of another σ).
    assert_eq!(
        later_named(
            "gaussian_sigma_unsquared",
            &["output7_02f.tga"],
            "filter_shape",
            "form 1)"
        ),
        1
    );
}

#[test]
fn an_ambient_term_that_asks_a_texture_for_one_colour_is_the_texture_ambient() {
    if common::later_dir("the fitted forms of assignments 6 and 7").is_none() {
        return;
    }
    // A texture's colour without the point is its first material's: the checkerboards and
    // the marble cubes lit ambiently in one colour.
    assert_eq!(
        later_named(
            "texture_ambient_first_material",
            &["scene6_13", "scene6_15", "output7_02.tga"],
            "texture_ambient",
            "form 1)"
        ),
        3
    );
    // Black: where every object is textured, the same picture as the ambient term left out;
    // the glass sphere's line, whose sphere is not textured and keeps its ambient light, says
    // which it is, and the verdict puts texture_ambient first on both.
    assert_eq!(
        later_named(
            "texture_ambient_black",
            &["scene6_13", "scene6_14"],
            "texture_ambient",
            "form 0)"
        ),
        2
    );
}

#[test]
fn noise_interpolated_the_other_way_round_is_the_blend_swapped() {
    if common::later_dir("the fitted forms of assignment 6").is_none() {
        return;
    }
    // N·first + (1 − N)·second, written out with the sine: the marble cubes and the vase.
    assert_eq!(
        later_named(
            "noise_blended_the_other_way",
            &["output6_15.tga", "output6_17a.tga"],
            "texture_blend_swapped",
            ""
        ),
        2
    );
}
