//! The scene as the file describes it: plain data, with the place each item came from kept for
//! the errors that later stages may still find (a mesh file that is missing, say).

use std::path::PathBuf;

use glam::{DMat4, Vec3};

use crate::parse::Span;

#[derive(Debug, Clone, PartialEq)]
pub struct SceneDescription {
    /// The scene file, as named by the user; messages and relative mesh paths start from it.
    pub path: PathBuf,
    pub camera: CameraSpec,
    pub background: Vec3,
    /// Already forced to white when the scene has no lights (assignment 1's flat shading).
    pub ambient: Vec3,
    pub lights: Vec<DirectionalLight>,
    pub materials: Vec<Material>,
    /// Object-to-world matrices of the scene's Transform blocks, nesting already multiplied in.
    pub transforms: Vec<DMat4>,
    /// Every primitive and mesh of the scene, groups flattened away.
    pub objects: Vec<PlacedObject>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// `size` is the side of the square the camera sees, in world units.
    Orthographic { size: f32 },
    /// `angle` is the full field of view, in radians.
    Perspective { angle: f32 },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSpec {
    pub center: Vec3,
    pub direction: Vec3,
    pub up: Vec3,
    pub projection: Projection,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    /// The direction the light travels, normalised.
    pub direction: Vec3,
    pub color: Vec3,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    pub diffuse: Vec3,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// The points P with P · normal = offset.
    Plane {
        normal: Vec3,
        offset: f32,
    },
    Triangle {
        vertices: [Vec3; 3],
    },
    /// An .obj file, named as the scene wrote it.
    Mesh {
        file: String,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct PlacedObject {
    pub shape: Shape,
    pub material: u32,
    /// Index into [`SceneDescription::transforms`]; `None` when the object is in world space.
    pub transform: Option<u32>,
    /// Where the object's keyword stands.
    pub span: Span,
}
