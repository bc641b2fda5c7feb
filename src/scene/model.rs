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
    pub lights: Vec<LightSpec>,
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

/// A light as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightSpec {
    /// Light from infinitely far away: the same direction and colour everywhere.
    Directional {
        /// The direction the light travels, normalised.
        direction: Vec3,
        color: Vec3,
    },
    /// Light from a point, dimmed with distance d by 1 / (constant + linear·d + quadratic·d²).
    Point {
        position: Vec3,
        color: Vec3,
        /// The constant, linear and quadratic terms; none negative, not all zero.
        attenuation: [f32; 3],
    },
}

/// A material as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    Phong(Phong),
    /// A solid texture (assignment 6) over two earlier materials.
    Texture(Texture),
}

/// A solid texture: a pattern in texture space that chooses, or blends, between two materials
/// listed before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texture {
    pub pattern: Pattern,
    /// World space to texture space (the identity when the file gives no `Transform`).
    pub to_texture: DMat4,
    /// Indices of the two materials: where the pattern is 0, and where it is 1.
    pub materials: [u32; 2],
}

/// The course's four solid textures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pattern {
    /// Unit cubes in texture space, alternating.
    Checkerboard,
    /// Perlin noise summed over `octaves`.
    Noise { octaves: u32 },
    /// sin(frequency·x + amplitude·noise): veins.
    Marble {
        octaves: u32,
        frequency: f64,
        amplitude: f64,
    },
    /// Rings about texture space's y axis, perturbed by noise.
    Wood {
        octaves: u32,
        frequency: f64,
        amplitude: f64,
    },
}

/// A Phong material (assignment 4's `PhongMaterial`, every field optional).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// The specular exponent, at least 0.
    pub exponent: f32,
    pub reflective: Vec3,
    pub transparent: Vec3,
    /// Above 0.
    pub index_of_refraction: f32,
}

impl Default for Phong {
    /// The staff parser's defaults: white diffuse, nothing else, exponent 1, index 1.
    fn default() -> Phong {
        Phong {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            exponent: 1.0,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            index_of_refraction: 1.0,
        }
    }
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
