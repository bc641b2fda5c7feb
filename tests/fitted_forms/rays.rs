//! The rays after the first (assignment 4 on): shadows, mirrors, glass, their offsets and the
//! recursion that carries their colours.

use crate::*;

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

#[test]
fn shadows_never_cast_however_they_are_lost_are_the_shadows_missing() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // `-shadows` never read, and a shadow ray whose tmax is left at 0: no light is ever
    // blocked. On a line where only glass casts shadows the picture is also a glass that
    // lets the light through whole, and the line says it cannot tell them apart.
    let lines = [
        "output4_01.tga",
        "output4_04a.tga",
        "output4_08.tga",
        "output4_06b.tga",
    ];
    for form in ["shadows_flag_unread", "shadow_ray_of_no_length"] {
        assert_eq!(
            later_named(form, &lines, "shadows_missing", "(0.000% of pixels off)"),
            4,
            "{form}"
        );
    }
}

#[test]
fn mirror_and_glass_rays_never_traced_are_the_secondary_rays_missing() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // `-bounces` never read: no mirror or glass ray at all. Where one bounce is asked for,
    // that is also one bounce fewer, and the line says it cannot tell them apart.
    let lines = ["output4_03.tga", "output4_06b.tga", "output4_07.tga"];
    assert_eq!(
        later_named("bounces_unread", &lines, "secondary_rays_missing", "0.000%"),
        3
    );
    // The refracted ray never traced: the glass shows its surface alone, as a glass whose
    // inside is black (back faces not shaded) does, and the line says so.
    let later = common::later_dir("the fitted forms of assignment 4").unwrap();
    let glass = ["output4_06c.tga", "output4_14c.tga"];
    let failing = failing_in(&later, "glass_never_traced", &glass);
    assert_eq!(failing.len(), 2, "{failing:?}");
    for line in &failing {
        let (said, _) = line.split_once(": raycast's render").unwrap();
        let named: Vec<&str> = said.rsplit(": ").next().unwrap().split(", ").collect();
        assert!(
            named.contains(&"secondary_rays_missing")
                && named.contains(&"shade_back_ignored")
                && line.contains("this line alone cannot tell the faults named apart"),
            "{line}"
        );
    }
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
fn a_mirror_or_glass_weighed_by_the_specular_colour_is_the_secondary_colour() {
    if common::later_dir("the fitted forms of assignments 4 and 6").is_none() {
        return;
    }
    // The glass bar's and the gems' mirrors, whose specular colours differ from their
    // reflective ones (a mirror with no highlight, the floors', reflects nothing at all: the
    // same picture as a mirror ray never traced).
    assert_eq!(
        later_named(
            "mirror_of_the_specular_colour",
            &["scene4_05", "scene4_14", "scene6_12"],
            "secondary_colour",
            "form 2)"
        ),
        8
    );
    // Their glass likewise (where the specular colour is white, the glass's ray added whole
    // draws the same, and is named as form 1).
    assert_eq!(
        later_named(
            "glass_of_the_specular_colour",
            &["scene4_05", "scene4_06", "scene4_14", "scene6_12"],
            "secondary_colour",
            "form 3)"
        ),
        12
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

#[test]
fn a_rays_weight_made_of_other_numbers_than_the_colours_magnitude_is_the_weight_cutoff() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // output4_06f alone of the course's lines cuts rays off where the weight's form shows: each
    // is named with the cut-off that draws it, as the course's weight would be cut there.
    for form in ["weight_by_greatest_channel", "weight_by_mean_channel"] {
        assert_eq!(
            later_named(form, &["output4_06f.tga"], "weight_cutoff", "weight 0.1"),
            1
        );
    }
}

#[test]
fn a_mirror_or_glass_ray_that_misses_bringing_black_is_the_secondary_background() {
    if common::later_dir("the fitted forms of assignments 4 and 6").is_none() {
        return;
    }
    // The recursion's own test for a miss adds nothing: a mirror sphere and glass spheres
    // before a coloured background show black where they show the background.
    assert_eq!(
        later_named(
            "misses_add_nothing",
            &["output4_04b.tga", "scene4_07", "scene6_14"],
            "secondary_background",
            "form 0)"
        ),
        3
    );
    // The mirror's miss alone, where glass rays still see the background (with two bounces
    // or fewer, the bars' glass rays never miss: both forms draw the same, and form 0 is named).
    assert_eq!(
        later_named(
            "mirror_miss_adds_nothing",
            &["scene4_05", "output4_06d.tga", "scene6_14"],
            "secondary_background",
            "form 1)"
        ),
        3
    );
}

#[test]
fn shadow_or_secondary_rays_alone_from_the_surface_are_the_shadow_acne_of_those_rays() {
    if common::later_dir("the fitted forms of assignments 4 and 6").is_none() {
        return;
    }
    // The recursion passes 0 where the shadow test passes an offset: the mirror floor and
    // sphere, and the glass bars, see themselves in speckles, their shadows clean.
    assert_eq!(
        later_named(
            "secondary_from_zero",
            &["scene4_03", "output4_04b.tga", "output4_06c.tga"],
            "shadow_acne",
            "form 2)"
        ),
        3
    );
    // The other way round.
    assert_eq!(
        later_named(
            "shadows_from_zero",
            &["scene4_03", "output4_06c.tga"],
            "shadow_acne",
            "form 1)"
        ),
        2
    );
    // Where a line traces no mirror or glass ray, every ray it casts starts on the surface:
    // form 0.
    assert_eq!(
        later_named(
            "shadows_from_zero",
            &["scene4_01"],
            "shadow_acne",
            "form 0)"
        ),
        1
    );
}

#[test]
fn a_mirror_or_glass_that_shows_its_rays_instead_of_its_shading_is_the_shading_replaced() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // An if and an else: the floor, sphere, bars and glass ball show their rays alone.
    assert_eq!(
        later_named(
            "mirror_or_shading",
            &["scene4_03", "output4_04b.tga", "scene4_05", "scene4_07"],
            "shading_replaced",
            "form 0)"
        ),
        4
    );
    // A mix, (1 - kr - kt) × shading (where kr + kt is white, the same as the if and else).
    assert_eq!(
        later_named(
            "shading_mixed_with_mirror",
            &["scene4_03", "output4_04b.tga", "output4_06c.tga"],
            "shading_replaced",
            "form 1)"
        ),
        3
    );
}

#[test]
fn a_shadow_ray_cast_from_the_light_is_the_shadow_direction() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // Directional lights (4_01, 4_03) and point lights (4_10, 4_11): lit sides shadow
    // themselves, and what stands behind a point casts its shadow.
    assert_eq!(
        later_named(
            "shadow_from_the_light",
            &["output4_01", "output4_03", "output4_10", "output4_11"],
            "shadow_direction",
            ""
        ),
        4
    );
    // Only toward point lights: the lines of directional lights pass; 4_10's point light
    // and directional light need the form of its own.
    assert_eq!(
        later_named(
            "point_shadow_from_the_light",
            &["output4_01", "output4_11"],
            "shadow_direction",
            ""
        ),
        1
    );
    assert_eq!(
        later_named(
            "point_shadow_from_the_light",
            &["output4_10"],
            "shadow_direction",
            "form 1)"
        ),
        1
    );
}

#[test]
fn mirrors_added_inside_the_loop_over_the_lights_are_the_secondary_per_light() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // Two lights: the mirrored floor's reflection, the glass bars' and the glass ball's
    // views, each twice as bright.
    assert_eq!(
        later_named(
            "mirrors_in_the_light_loop",
            &["output4_03", "output4_06b", "output6_14"],
            "secondary_per_light",
            ""
        ),
        3
    );
}

#[test]
fn limits_tested_after_the_intersection_are_the_limits_tested_late() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // One bounce past -bounces: mirror and glass rays that miss bring the background.
    assert_eq!(
        later_named(
            "bounces_tested_after_the_hit",
            &["output4_04a", "output4_04b", "output4_06a", "output4_06c"],
            "limits_tested_late",
            "form 0)"
        ),
        4
    );
    // The weight too: the bars' rays below -weight 0.01 bring the background as well.
    assert_eq!(
        later_named(
            "limits_tested_after_the_hit",
            &["output4_06c", "output4_06f"],
            "limits_tested_late",
            ""
        ),
        2
    );
}

#[test]
fn a_recursion_that_never_counts_its_bounces_is_the_bounces_uncounted() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    // traceRay(..., bounces, ...) for each mirror and glass ray: only -weight 0.01 stops the
    // recursion, whatever -bounces says.
    assert_eq!(
        later_named(
            "bounces_never_counted",
            &["output4_04a", "output4_04b", "output4_06a", "output4_14a"],
            "bounces_uncounted",
            ""
        ),
        4
    );
}
