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
