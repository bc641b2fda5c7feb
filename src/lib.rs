//! raycast: a ray tracer for the scene format of MIT 6.837 (Fall 2004), every ray-tracing
//! assignment (1 to 7), exact to the course's reference images. The `raycast` program is the
//! course's command line ([`cli`]); this library is everything under it.
//!
//! A scene comes from a file ([`Scene::load`]), from text ([`parse::parse_scene`] and
//! [`Scene::from_description`]), or from code ([`SceneBuilder`]); [`render::render`] makes its
//! pictures; [`image_io`] writes them.
//!
//! ```
//! use raycast::{RenderSettings, SceneBuilder, Vec3};
//! use raycast::parse::description::{CameraSpec, LightSpec, Material, Phong, Shape};
//!
//! let scene = SceneBuilder::new(CameraSpec::orthographic(
//!     Vec3::new(0.0, 0.0, 10.0), Vec3::NEG_Z, Vec3::Y, 5.0))
//!     .background(Vec3::ZERO)
//!     .material(Material::Phong(Phong::diffuse(Vec3::X)))
//!     .object(Shape::Sphere { center: Vec3::ZERO, radius: 1.0 }, 0)
//!     .build()?;
//! let image = raycast::render::render(&scene, &RenderSettings::new(20, 20)).colour.unwrap();
//! assert_eq!(image.pixels[10 * 20 + 10], [255, 0, 0]); // the sphere, flat red (no lights)
//! assert_eq!(image.pixels[0], [0, 0, 0]); // the background
//! # Ok::<(), raycast::Error>(())
//! ```
//!
//! The stages, each a module that knows only those before it: scene text ([`parse`]) → scene
//! description ([`parse::description`]) → render-ready [`Scene`] (lights and materials in [`scene`],
//! geometry in [`geometry`], trees and the course's grid in [`accel`]) → rays from the
//! [`camera`], placed by the samplers of [`sample`] → the pixel loop ([`render`]) → the ray
//! tracer ([`trace`]) and pixel values ([`shade`]) → files ([`image_io`]).

// `unsafe` only in `simd`, which allows it and says why each use is sound.
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
pub mod parse;
pub mod render;
pub mod sample;
pub mod scene;
pub mod shade;
pub mod simd;
pub mod trace;

pub use error::{Diagnostic, Error, Span};
/// The vector and matrix types the API uses, from `glam`.
pub use glam::{self, DMat4, UVec3, Vec2, Vec3, Vec3A};
pub use render::{RenderSettings, Rendered};
pub use scene::{Scene, SceneBuilder};
pub use shade::Image;
