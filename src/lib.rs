//! raycast: a ray tracer for the scene format of MIT 6.837 (Fall 2004), every ray-tracing
//! assignment (1 to 7), exact to the course's reference images. The `raycast` program is the
//! course's command line ([`cli`]); this library is everything under it.
//!
//! A scene comes from a file ([`Scene::load`]), from text ([`parse::parse_scene`] and
//! [`Scene::from_description`]), or from code ([`SceneBuilder`]); [`render::render`] makes its
//! pictures; [`image_io`] writes them.
//!
//! ```
//! use raycast::parse::description::{CameraSpec, LightSpec, MaterialSpec, PhongSpec, Shape};
//! use raycast::{RenderSettings, Scene, SceneBuilder, Vec3, image_io};
//!
//! // A scene from a file: `Scene::load(Path::new("scene.txt"))?`; or built in code:
//! let scene: Scene = SceneBuilder::new(CameraSpec::orthographic(
//!     Vec3::new(0.0, 0.0, 10.0), Vec3::NEG_Z, Vec3::Y, 5.0))
//!     .background(Vec3::ZERO)
//!     .ambient_light(Vec3::splat(0.2))
//!     .light(LightSpec::directional(Vec3::NEG_Z, Vec3::ONE))
//!     .named_material("red", MaterialSpec::Phong(PhongSpec::diffuse(Vec3::X)))
//!     .object(Shape::Sphere { center: Vec3::ZERO, radius: 1.0 }, "red")
//!     .build()?;
//! // Rays from the camera, traced and shaded, into an 8-bit picture...
//! let image = raycast::render::render(&scene, &RenderSettings::new(20, 20)).colour.unwrap();
//! // ...lit nearly head-on: ambient 0.2 plus almost all of the white light, clamped to full red.
//! assert_eq!(image.pixels[10 * 20 + 10], [255, 0, 0]);
//! assert_eq!(image.pixels[0], [0, 0, 0]); // the background
//! // ...and to a file's bytes (TGA in the course's layout, PPM or PNG).
//! let tga = image_io::encode(&image, image_io::ImageFormat::Tga);
//! assert_eq!(tga.len(), 18 + 20 * 20 * 3);
//! # Ok::<(), raycast::Error>(())
//! ```
//!
//! The stages, each a module that imports only those before it (docs/architecture.md): scene
//! text ([`parse`]) → scene description ([`parse::description`]) → trees and the course's grid
//! over the [`geometry`] ([`accel`]) and the [`camera`] → render-ready [`Scene`] (lights and
//! materials in [`scene`]) → the ray tracer ([`trace`]), pixel values ([`shade`]) and the
//! samplers and film of [`sample`] → the pixel loop ([`render`]) and one pixel's account
//! ([`inspect`]) → files ([`image_io`]); the grader ([`check`]), the browser preview
//! ([`preview`]) and the command line ([`cli`]) on top.

// `unsafe` only in `simd`, in the cage of `check` (system calls around a fork) and in the
// console handler of `cli` on Windows, which allow it and say why each use is sound.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod camera;
pub mod check;
pub mod cli;
mod error;
pub mod geometry;
pub mod image_io;
pub mod inspect;
pub mod job;
pub mod parse;
pub mod preview;
pub mod render;
pub mod sample;
pub mod scene;
pub mod shade;
pub mod simd;
pub mod trace;
pub mod variant;

pub use error::{Diagnostic, Error, Span};
/// The vector and matrix types the API uses, from `glam`.
pub use glam::{self, DMat4, UVec3, Vec2, Vec3, Vec3A};
pub use render::{RenderSettings, Rendered};
pub use scene::{Scene, SceneBuilder};
pub use shade::Image;
