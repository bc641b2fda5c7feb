//! raycast: a ray tracer for the scene format of MIT 6.837's assignments 1 to 4, exact to the
//! course's reference images.
//!
//! The stages, each a module that knows only those before it:
//! scene text ([`parse`]) → scene description ([`scene::model`]) → render-ready [`Scene`]
//! (lights and materials in [`scene`], geometry in [`geometry`], trees in [`accel`]) → rays
//! from the [`camera`] → the pixel loop ([`render`]) → the ray tracer ([`trace`]) and pixel
//! values ([`shade`]) → files ([`image_io`]). [`cli`] is the course's command line on top.
//!
//! ```
//! use std::path::Path;
//! use raycast::{RenderSettings, Scene, parse::parse_scene, render::render};
//!
//! let text = "
//!     OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }
//!     Background { color 0 0 0 }
//!     Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }
//!     Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }";
//! let description = parse_scene(Path::new("red.txt"), text)?;
//! let (scene, _stats) = Scene::from_description(&description)?;
//! let settings = RenderSettings {
//!     width: 20, height: 20, colour: true, normals: false, depth: None,
//!     trace: Default::default(), sampling: Default::default(), keep_film: false,
//!     progress: false,
//! };
//! let image = render(&scene, &settings).colour.unwrap();
//! assert_eq!(image.pixels[10 * 20 + 10], [255, 0, 0]); // the sphere, flat red
//! assert_eq!(image.pixels[0], [0, 0, 0]); // the background
//! # Ok::<(), raycast::Error>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod camera;
pub mod cli;
mod error;
pub mod geometry;
pub mod image_io;
pub mod parse;
pub mod render;
pub mod sample;
pub mod scene;
pub mod shade;
pub mod trace;

pub use error::{Diagnostic, Error};
pub use render::{RenderSettings, Rendered};
pub use scene::Scene;
