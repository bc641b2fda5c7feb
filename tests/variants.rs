//! The seams where check's fault library renders as a student's tracer would
//! (`raycast::variant`): two real faults, each changing the pixels as the fault must.

use glam::Vec3A;
use raycast::camera::{CameraSeam, film_to_screen};
use raycast::parse::description::{CameraSpec, LightSpec, MaterialSpec, PhongSpec, Shape};
use raycast::render::{RenderSettings, render, render_with};
use raycast::sample::SampleSeam;
use raycast::shade::PictureSeam;
use raycast::trace::TraceSeam;
use raycast::{Scene, SceneBuilder, Vec3};

/// Camera rays through each pixel's lower-left corner, not its centre: the most common
/// student bug of assignment 1.
#[derive(Debug, Clone, Copy)]
struct PixelCorners;

impl CameraSeam for PixelCorners {
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        film_to_screen(i as f32, j as f32, width, height)
    }
}
impl TraceSeam for PixelCorners {}
impl PictureSeam for PixelCorners {}
impl SampleSeam for PixelCorners {}

/// The ambient term added inside the loop over the lights: once per light.
#[derive(Debug, Clone, Copy)]
struct AmbientPerLight;

impl CameraSeam for AmbientPerLight {}
impl TraceSeam for AmbientPerLight {
    fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        term * lights as f32
    }
}
impl PictureSeam for AmbientPerLight {}
impl SampleSeam for AmbientPerLight {}

/// Spheres of several sizes and colours seen by an orthographic camera of size 4 centred on
/// `center`, lit by one directional light.
fn spheres(center: Vec3) -> Scene {
    SceneBuilder::new(CameraSpec::orthographic(center, Vec3::NEG_Z, Vec3::Y, 4.0))
        .background(Vec3::new(0.1, 0.2, 0.3))
        .ambient_light(Vec3::splat(0.1))
        .light(LightSpec::directional(
            Vec3::new(0.3, -0.5, -1.0),
            Vec3::splat(0.9),
        ))
        .named_material("red", MaterialSpec::Phong(PhongSpec::diffuse(Vec3::X)))
        .named_material("green", MaterialSpec::Phong(PhongSpec::diffuse(Vec3::Y)))
        .object(
            Shape::Sphere {
                center: Vec3::new(-0.7, 0.3, 0.0),
                radius: 1.1,
            },
            "red",
        )
        .object(
            Shape::Sphere {
                center: Vec3::new(1.0, -0.9, 0.5),
                radius: 0.6,
            },
            "green",
        )
        .build()
        .unwrap()
}

#[test]
fn rays_through_pixel_corners_see_the_view_moved_by_half_a_pixel() {
    // 16 pixels across a view 4 wide: a pixel is a quarter unit, and its lower-left corner
    // lies an eighth of a unit left of and below its centre. Every coordinate involved is exact
    // in binary, so the corner rays are exactly the centre rays of the moved camera.
    let settings = RenderSettings::new(16, 16);
    let course = spheres(Vec3::new(0.0, 0.0, 10.0));
    let corners = render_with(&course, &settings, PixelCorners)
        .colour
        .unwrap();
    let centres = render(&course, &settings).colour.unwrap();
    let moved = spheres(Vec3::new(-0.125, -0.125, 10.0));
    let moved_centres = render(&moved, &settings).colour.unwrap();
    assert_eq!(corners, moved_centres);
    let differing = corners
        .pixels
        .iter()
        .zip(&centres.pixels)
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 10, "only {differing} pixels moved");
}

#[test]
fn ambient_added_once_per_light_doubles_it_with_two_lights() {
    // A wall facing the camera, lit only from behind by both lights: what the camera sees is
    // the ambient term alone, 0.2 × 0.5 = 0.1 of white (25 of 255, truncated), and with it
    // added once per light, 0.2 (51).
    let scene = SceneBuilder::new(CameraSpec::orthographic(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::NEG_Z,
        Vec3::Y,
        4.0,
    ))
    .ambient_light(Vec3::splat(0.2))
    .light(LightSpec::directional(Vec3::Z, Vec3::ONE))
    .light(LightSpec::directional(Vec3::new(0.2, 0.0, 1.0), Vec3::ONE))
    .named_material(
        "grey",
        MaterialSpec::Phong(PhongSpec::diffuse(Vec3::splat(0.5))),
    )
    .object(
        Shape::Plane {
            normal: Vec3::Z,
            offset: 0.0,
        },
        "grey",
    )
    .build()
    .unwrap();
    let settings = RenderSettings::new(8, 8);
    let course = render(&scene, &settings).colour.unwrap();
    let per_light = render_with(&scene, &settings, AmbientPerLight)
        .colour
        .unwrap();
    assert!(
        course.pixels.iter().all(|&p| p == [25; 3]),
        "{:?}",
        course.pixels[0]
    );
    assert!(
        per_light.pixels.iter().all(|&p| p == [51; 3]),
        "{:?}",
        per_light.pixels[0]
    );
}
