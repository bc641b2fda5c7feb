//! The course's renderer, as one variant among those `check` simulates.
//!
//! `check` explains a student's wrong picture by rendering the same command line the way a
//! student's buggy tracer would (rays through pixel corners, the ambient term added once per
//! light, ...) and finding which such render matches. Each stage of the pipeline that such a
//! fault touches has a seam: a trait of its own whose default methods are the course's
//! formulas, called where the stage would otherwise call them directly.
//!
//! - [`crate::camera::CameraSeam`]: where each pixel's ray goes through, the ray itself, and its
//!   least t;
//! - [`crate::trace::TraceSeam`]: the hit as found (its t, its normal), the material's
//!   textures at the hit, the light that reaches it, the ambient and light terms (the
//!   highlight's formula among them), back faces, shadow rays' range, the epsilon of mirror and
//!   glass rays, refraction, and the number of bounces;
//! - [`crate::shade::PictureSeam`]: colours to bytes, and the normals and depth pictures;
//! - [`crate::sample::SampleSeam`]: where a pixel's samples fall, the filter, and how the
//!   weighted samples make a pixel.
//!
//! A render chooses its variant once: the renderer is generic over it, so the course's own,
//! [`Exact`], which keeps every default, compiles to the same code as calling the formulas
//! directly (instruction counts in docs/architecture.md).

/// The course's renderer: every seam's default.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Exact;
