//! Builds a scene in code, with no scene file, and renders it with shadows, a mirror and glass.
//!
//! ```sh
//! cargo run --release --example build_in_code -- target/built_in_code.png
//! ```
//!
//! The image goes to the path given (default `target/built_in_code.png`).

use std::path::PathBuf;

use raycast::glam::DVec3;
use raycast::image_io::{self, ImageFormat};
use raycast::parse::description::{
    CameraSpec, LightSpec, MaterialSpec, Pattern, PhongSpec, Shape, TextureSpec,
};
use raycast::render::render;
use raycast::trace::TraceSettings;
use raycast::{DMat4, RenderSettings, SceneBuilder, Vec3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let output = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target/built_in_code.png"));

    let white = MaterialSpec::Phong(PhongSpec::diffuse(Vec3::splat(0.9)));
    let dark = MaterialSpec::Phong(PhongSpec::diffuse(Vec3::splat(0.15)));
    let checker = MaterialSpec::Texture(TextureSpec {
        pattern: Pattern::Checkerboard,
        to_texture: DMat4::from_translation(DVec3::new(0.0, 0.5, 0.0)),
        materials: [0, 1],
    });
    let red = MaterialSpec::Phong(PhongSpec {
        specular: Vec3::splat(0.6),
        exponent: 40.0,
        ..PhongSpec::diffuse(Vec3::new(0.85, 0.15, 0.1))
    });
    let mirror = MaterialSpec::Phong(PhongSpec {
        reflective: Vec3::splat(0.85),
        ..PhongSpec::diffuse(Vec3::splat(0.05))
    });
    let glass = MaterialSpec::Phong(PhongSpec {
        specular: Vec3::splat(0.9),
        exponent: 100.0,
        reflective: Vec3::splat(0.1),
        transparent: Vec3::splat(0.85),
        index_of_refraction: 1.5,
        ..PhongSpec::diffuse(Vec3::ZERO)
    });

    let scene = SceneBuilder::new(CameraSpec::perspective(
        Vec3::new(0.0, 2.5, 8.0),
        Vec3::new(0.0, -0.25, -1.0),
        Vec3::Y,
        40.0,
    ))
    .background(Vec3::new(0.5, 0.65, 0.9))
    .ambient_light(Vec3::splat(0.2))
    .light(LightSpec::directional(
        Vec3::new(-0.5, -1.0, -0.7),
        Vec3::splat(0.8),
    ))
    .light(LightSpec::point(Vec3::new(2.0, 4.0, 3.0), Vec3::splat(0.3)))
    // A texture picks from materials added before it, by index: white is 0, dark 1.
    .named_material("white", white)
    .named_material("dark", dark)
    .named_material("checker", checker)
    .named_material("red", red)
    .named_material("mirror", mirror)
    .named_material("glass", glass)
    .object(
        Shape::Plane {
            normal: Vec3::Y,
            offset: 0.0,
        },
        "checker",
    )
    .object(
        Shape::Sphere {
            center: Vec3::new(-1.8, 1.0, -0.5),
            radius: 1.0,
        },
        "red",
    )
    .object(
        Shape::Sphere {
            center: Vec3::new(1.8, 1.0, -1.0),
            radius: 1.0,
        },
        "mirror",
    )
    // A glass ellipsoid: a unit sphere, squashed and lifted by a transform.
    .placed(
        Shape::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        "glass",
        DMat4::from_translation(DVec3::new(0.0, 0.6, 1.2))
            * DMat4::from_scale(DVec3::new(0.8, 0.6, 0.8)),
    )
    .build()?;

    let settings = RenderSettings {
        trace: TraceSettings {
            shadows: true,
            shade_back: true,
            bounces: 4,
            cutoff_weight: 0.01,
            ..TraceSettings::default()
        },
        ..RenderSettings::new(480, 320)
    };
    let image = render(&scene, &settings)
        .colour
        .expect("the shaded picture");
    let format = ImageFormat::from_path(&output).unwrap_or(ImageFormat::Png);
    std::fs::write(&output, image_io::encode(&image, format))?;
    println!("wrote {}", output.display());
    Ok(())
}
