//! The pictures beside the colour: depth greys, normals' colours, and the bytes written.

use crate::*;

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
fn colours_read_blue_first_are_the_channel_swap_of_the_shaded_pictures_alone() {
    if conformance_dir().is_none() {
        return;
    }
    // The normals pictures' colours come from no file: they are right.
    let failing = all_named(
        "colours_read_blue_first+rounded",
        &[
            "scene1_03.txt",
            "scene2_03_colored_lights.txt",
            "scene2_04_perspective.txt",
        ],
        "channel_swap",
    );
    assert_eq!(failing.len(), 3, "{}", failing.join("\n"));
    assert!(failing.iter().all(|l| l.contains(" output")));
}

#[test]
fn a_clamp_written_before_the_scale_is_no_clamp() {
    if common::later_dir("the fitted forms of assignment 4").is_none() {
        return;
    }
    assert_eq!(
        later_named(
            "clamp_before_scaling+rounded",
            &["output4_05.tga", "output4_12.tga"],
            "no_clamp",
            ""
        ),
        2
    );
}

#[test]
fn a_depth_clamped_at_one_end_is_the_depth_clamp_with_the_end_that_wraps() {
    if conformance_dir().is_none() {
        return;
    }
    // scene2_06's plane reaches nearer than 8, where the grey is above 1 and wraps; farther
    // than 12 it is clamped at 0 by the student's bound in bytes.
    assert_eq!(
        conformance_named(
            "depth_clamp_before_scaling+rounded",
            &["scene2_06_plane.txt"],
            "depth_clamp",
            "form 1)"
        ),
        1
    );
    // Both ends wrapping is the form listed first.
    assert_eq!(
        conformance_named(
            "depth_wraps",
            &["scene2_06_plane.txt"],
            "depth_clamp",
            "form 0)"
        ),
        1
    );
}

#[test]
fn hits_nearer_than_the_depths_near_end_thrown_away_are_the_depth_tmin() {
    if conformance_dir().is_none() {
        return;
    }
    assert_eq!(
        conformance_named(
            "depth_near_drops_hits+rounded",
            &["scene2_06_plane.txt"],
            "depth_tmin",
            "t_min 8)"
        ),
        3
    );
}
