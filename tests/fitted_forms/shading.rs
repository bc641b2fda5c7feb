//! The shading sum: ambient, each light's diffuse and highlight, back faces, attenuation, and
//! the normals they are worked out from.

use crate::*;

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
fn highlights_written_their_own_way_are_named_with_the_form_fitted() {
    if common::later_dir("the fitted forms of assignment 3").is_none() {
        return;
    }
    let lines = [
        "scene3_03_bunny_mesh_200.txt",
        "output3_09.tga",
        "output3_10.tga",
        "output3_12.tga",
    ];
    // pow(max(N.H, 0), q) for every light, in front of the surface or behind it; with bytes
    // rounded.
    assert_eq!(
        later_named(
            "highlight_ungated+rounded",
            &lines,
            "specular_unclamped",
            "highlight where N·L < 0 1)"
        ),
        3
    );
    // pow(fabs(N.H), q) for every light: where q is even (output3_12's) the library's form
    // draws the same.
    assert_eq!(
        later_named("highlight_absolute", &lines, "specular_unclamped", ""),
        3
    );
    // H = (L + V) / 2, bytes rounded; the dark spheres of output3_10 that lose their
    // highlights read as silhouettes moved, and are fitted all the same.
    assert_eq!(
        later_named(
            "half_vector_halved+rounded",
            &lines,
            "half_vector",
            "H not unit 1, H scaled by 0.5)"
        ),
        4
    );
    // Phong's (R.V)^q with V the ray's direction: on output3_10 and output3_12 it puts every
    // highlight out of sight, the very picture of no specular term, whose sentence says so.
    assert_eq!(
        later_named(
            "mirror_against_the_ray",
            &["scene3_03_bunny_mesh_200.txt", "output3_09.tga"],
            "half_vector",
            ""
        ),
        2
    );
    assert_eq!(
        later_named(
            "mirror_against_the_ray",
            &["output3_10.tga", "output3_12.tga"],
            "specular_missing",
            ""
        ),
        2
    );
}

#[test]
fn a_diffuse_term_of_the_absolute_cosine_alone_is_the_shade_back_abs() {
    if conformance_dir().is_none() {
        return;
    }
    // kd * fabs(N.L), the highlight left as the course's (these lines have none).
    assert_eq!(
        conformance_named(
            "diffuse_absolute",
            &["scene2_01_diffuse.txt", "scene2_03_colored_lights.txt"],
            "shade_back_abs",
            ""
        ),
        2
    );
}

#[test]
fn an_ambient_light_added_alone_is_the_ambient_uncoloured() {
    if conformance_dir().is_none() {
        return;
    }
    // `color = ambientLight`, bytes rounded besides: a grey wash over every object (2_03's
    // are white, the same either way).
    assert_eq!(
        conformance_named(
            "ambient_light_alone+rounded",
            &["scene2_02_ambient.txt", "scene2_04_perspective.txt"],
            "ambient_uncoloured",
            ""
        ),
        2
    );
}

#[test]
fn a_diffuse_term_never_clamped_is_the_diffuse_unclamped() {
    if conformance_dir().is_none() {
        return;
    }
    // kd * light * N.L below zero: the far side of each sphere darker than its ambient light
    // alone, the coloured lights taking from each other.
    assert_eq!(
        conformance_named(
            "diffuse_never_clamped",
            &["scene2_02_ambient.txt", "scene2_03_colored_lights.txt"],
            "diffuse_unclamped",
            ""
        ),
        2
    );
    // With the ambient term inside the loop besides: the shading's fit finds both, the
    // ambient weight at the number of lights and N·L taken as it is.
    let failing = failing(
        "ambient_in_loop_never_clamped",
        &["scene2_03_colored_lights.txt"],
    );
    assert_eq!(failing.len(), 1, "{}", failing.join("\n"));
    assert!(
        failing[0].contains("off: diffuse_unclamped+ambient_per_light: "),
        "{}",
        failing[0]
    );
}

#[test]
fn normals_never_turned_toward_the_ray_are_the_back_faces_mistake_of_each_line() {
    if conformance_dir().is_none() {
        return;
    }
    // With -shade_back, the back faces shaded from the wrong side: shade_back_ignored's form 1;
    // without it, shaded at all: back_faces_lit's form 1, which draws there as the ambient term
    // alone (the lights stand outside the sphere, behind its inside's outward normal), so the
    // line cannot tell it from ambient_on_back_faces, the likelier, named first.
    let failing = failing("normals_never_turned", &["scene2_05_inside_sphere.txt"]);
    assert_eq!(failing.len(), 2, "{}", failing.join("\n"));
    assert!(
        failing[0].contains("output2_05,")
            && failing[0].contains("off: shade_back_ignored: raycast's render")
            && failing[0].contains("form 1)"),
        "{}",
        failing[0]
    );
    assert!(
        failing[1].contains("output2_05_no_back")
            && failing[1].contains("off: ambient_on_back_faces, back_faces_lit: raycast's render"),
        "{}",
        failing[1]
    );
    // Glass seen from inside, bytes rounded: every failing picture shade_back_ignored's form 1.
    assert_eq!(
        later_named(
            "normals_never_turned+rounded",
            &[
                "scene4_05_transparent_bar.txt",
                "scene4_06_transparent_bars.txt"
            ],
            "shade_back_ignored",
            "form 1)"
        ),
        5
    );
}

#[test]
fn a_loop_over_the_lights_that_stops_early_is_the_lights_skipped() {
    if common::later_dir("the fitted forms of assignments 2 to 4").is_none() {
        return;
    }
    // for (i = 0; i < n - 1; i++): with one light, none shades.
    assert_eq!(
        conformance_named(
            "light_loop_short+rounded",
            &["scene2_01_diffuse.txt", "scene2_03_colored_lights.txt"],
            "lights_skipped",
            "form 0)"
        ),
        2
    );
    // A return inside the loop: the first light alone (with two, the same as all but the
    // last; with three, form 1).
    assert_eq!(
        later_named(
            "first_light_only",
            &["output4_02.tga", "output3_11.tga"],
            "lights_skipped",
            ""
        ),
        2
    );
}

#[test]
fn a_shading_that_leaves_out_the_lights_colour_is_the_light_colour_ignored() {
    // The course's coloured lights, and its weird lighting of assignment 3 (diffuse and
    // specular), shine white.
    assert_eq!(
        conformance_named(
            "light_colour_left_out",
            &["scene2_03_colored_lights.txt"],
            "light_colour_ignored",
            ""
        ),
        1
    );
    if common::later_dir("the fitted forms of assignment 3").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "light_colour_left_out+rounded",
            &[
                "scene3_11_weird_lighting_diffuse.txt",
                "scene3_12_weird_lighting_specular.txt"
            ],
            "light_colour_ignored",
            ""
        ),
        2
    );
}

#[test]
fn a_light_taken_as_one_brightness_is_the_light_colour_ignored_with_its_form() {
    // scene2_03's lights are 0.8 of one primary each: greys of 0.8, not white.
    assert_eq!(
        conformance_named(
            "light_as_brightest_channel+rounded",
            &["scene2_03_colored_lights.txt"],
            "light_colour_ignored",
            "form 1)"
        ),
        1
    );
    if common::later_dir("the fitted forms of assignment 3").is_none() {
        return;
    }
    // The weird lighting's lights are white already at their brightest: a grey of 1 is white.
    assert_eq!(
        later_named(
            "light_as_brightest_channel",
            &[
                "scene3_11_weird_lighting_diffuse.txt",
                "scene3_12_weird_lighting_specular.txt"
            ],
            "light_colour_ignored",
            ""
        ),
        2
    );
}

#[test]
fn an_ambient_light_the_reader_never_stores_is_the_ambient_missing() {
    assert_eq!(
        conformance_named(
            "ambient_never_stored+rounded",
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
}

#[test]
fn a_highlight_worked_out_with_the_diffuse_cosine_in_it_is_the_specular_fix() {
    if common::later_dir("the fitted forms of assignment 3").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "highlight_times_cosine+rounded",
            &["output3_09.tga", "output3_12.tga"],
            "specular_fix",
            ""
        ),
        2
    );
}

#[test]
fn a_specular_term_never_added_is_the_specular_missing() {
    if common::later_dir("the fitted forms of assignments 3 and 4").is_none() {
        return;
    }
    // On most of these lines a highlight vector that points away from the eye puts the
    // highlight nowhere too (half_vector's form 0, named beside it); on scene3_09 and scene3_10
    // it shows one at grazing angles, so the student's pictures tell the two apart, and the
    // missing term is named first on every line.
    let lines = [
        "scene3_03",
        "scene3_09",
        "scene3_10",
        "scene3_12",
        "scene4_04",
        "scene4_07",
        "scene4_08",
        "scene4_09",
    ];
    assert_eq!(
        later_named("specular_left_out", &lines, "specular_missing", ""),
        11
    );
}

#[test]
fn a_highlight_of_another_colour_is_the_specular_colour() {
    if common::later_dir("the fitted forms of assignments 3 and 4").is_none() {
        return;
    }
    let lines = ["scene3_", "scene4_0", "scene4_1"];
    // The diffuse colour where the specular one belongs, bytes rounded: on every line with a
    // highlight whose material's two colours differ.
    assert_eq!(
        later_named(
            "highlight_of_the_diffuse_colour+rounded",
            &lines,
            "specular_colour",
            "form 0)"
        ),
        11
    );
    // specularColor never multiplied in: every highlight white, where one was not.
    assert_eq!(
        later_named("highlight_left_white", &lines, "specular_colour", "form 1)"),
        9
    );
    // ks (N·H)^q added as it is, the light's colour left out (the student's own Blinn term):
    // under grey, coloured and point lights.
    assert_eq!(
        later_named(
            "highlight_without_light_colour",
            &[
                "scene3_09",
                "scene3_12",
                "scene4_07",
                "scene6_12",
                "scene6_14"
            ],
            "specular_colour",
            "form 2)"
        ),
        6
    );
}

#[test]
fn a_highlight_worked_out_for_one_light_outside_the_loop_is_the_highlight_one_light() {
    if common::later_dir("the fitted forms of assignments 3 and 4").is_none() {
        return;
    }
    // scene3_12's two lights, and the faceted gem's three point lights (six lines).
    let lines = [
        "scene3_12_weird_lighting_specular.txt",
        "scene4_14_faceted_gem.txt",
    ];
    assert_eq!(
        later_named(
            "highlight_first_light_only+rounded",
            &lines,
            "highlight_one_light",
            "form 0)"
        ),
        7
    );
    assert_eq!(
        later_named(
            "highlight_after_the_loop",
            &lines,
            "highlight_one_light",
            "form 1)"
        ),
        7
    );
}

#[test]
fn a_directional_lights_direction_taken_toward_the_light_is_the_light_direction() {
    // Where the light shines only on what the eye cannot see, lights_skipped draws the same,
    // and is named beside it.
    assert_eq!(
        conformance_named(
            "directional_not_negated",
            &[
                "scene2_01_diffuse.txt",
                "scene2_03_colored_lights.txt",
                "scene2_08_cube.txt"
            ],
            "light_direction",
            ""
        ),
        3
    );
    if common::later_dir("the fitted forms of assignments 3 and 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "direction_read_reversed+rounded",
            &[
                "scene3_09_exponent_variations.txt",
                "scene4_01_sphere_shadow.txt",
                "scene4_02_colored_shadows.txt"
            ],
            "light_direction",
            ""
        ),
        3
    );
}

#[test]
fn a_vector_toward_a_point_light_left_unnormalised_is_the_light_vector() {
    let Some(later) = common::later_dir("the fitted forms of assignment 4") else {
        return;
    };
    let lines = [
        "scene4_10_point_light_distance.txt",
        "scene4_11_point_light_circle.txt",
        "scene4_12_point_light_circle_d_attenuation.txt",
        "scene4_14_faceted_gem.txt",
    ];
    // The shadow ray along it tested to t < 1: at the light.
    assert_eq!(
        later_named(
            "point_direction_unnormalised+rounded",
            &lines,
            "light_vector",
            ""
        ),
        9
    );
    // Tested to the light's distance along it instead: past the light too, which shows where
    // something lies beyond the light (scene4_10), named as the pair.
    assert_eq!(
        later_named("point_vector_to_distance", &lines[1..], "light_vector", ""),
        8
    );
    let failing = failing_in(&later, "point_vector_to_distance", &lines[..1]);
    assert!(
        failing.len() == 1 && failing[0].contains(": light_vector+shadow_past_light: "),
        "{}",
        failing.join("\n")
    );
}
