//! The scene as the file describes it: plain data, with the place each item came from kept for
//! the errors that later stages may still find (a mesh file that is missing, say).

use std::path::PathBuf;

use glam::{DMat4, Vec3};

use crate::error::Span;

/// A scene file read but not yet built: what `Scene::from_description` (a later stage) turns
/// into a scene ready to render.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneDescription {
    /// The scene file, as named by the user; messages and relative mesh paths start from it.
    pub path: PathBuf,
    /// The camera; of several in the file, the last.
    pub camera: CameraSpec,
    /// The colour of rays that hit nothing: grey 0.5 when the file gives none.
    pub background: Vec3,
    /// Already forced to white when the scene has no lights (assignment 1's flat shading).
    pub ambient: Vec3,
    /// In the file's order; none for assignment 1's scenes, whose objects show their flat
    /// diffuse colour.
    pub lights: Vec<LightSpec>,
    /// In the file's order: objects and textures refer to them by index.
    pub materials: Vec<MaterialSpec>,
    /// Object-to-world matrices of the scene's Transform blocks, nesting already multiplied in.
    pub transforms: Vec<DMat4>,
    /// Every primitive and mesh of the scene, groups flattened away.
    pub objects: Vec<PlacedObject>,
}

/// How the camera spreads its rays over the view, and how much it sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Parallel rays, one from each point of a square about the camera's centre: nothing
    /// shrinks with distance.
    Orthographic {
        /// The side of the square the camera sees, in world units; above 0.
        size: f32,
    },
    /// Rays from the eye, spreading over a square field of view.
    Perspective {
        /// The full field of view, edge to edge, in degrees, as the file gives it; strictly
        /// between 0 and 180.
        angle: f32,
    },
}

/// A camera as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSpec {
    /// The middle of the orthographic camera's square, or the perspective camera's eye.
    pub center: Vec3,
    /// The way the camera looks, normalised.
    pub direction: Vec3,
    /// Up in the image, as written: of any length and not necessarily perpendicular to
    /// `direction` (only its part across the view counts), but never parallel to it.
    pub up: Vec3,
    /// Orthographic or perspective, with the size or angle of the view.
    pub projection: Projection,
}

/// A light as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightSpec {
    /// Light from infinitely far away: the same direction and colour everywhere.
    Directional {
        /// The direction the light travels, normalised.
        direction: Vec3,
        /// The light's colour, not clamped: a component above 1 is a brighter light.
        colour: Vec3,
    },
    /// Light from a point, dimmed with distance d by 1 / (constant + linear·d + quadratic·d²).
    Point {
        /// Where the light is, in world space.
        position: Vec3,
        /// The colour at the light itself, before attenuation; not clamped.
        colour: Vec3,
        /// The constant, linear and quadratic terms; none negative, not all zero.
        attenuation: [f32; 3],
    },
}

/// A material as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MaterialSpec {
    /// A Phong material (`Material` or `PhongMaterial` in the file).
    Phong(PhongSpec),
    /// A solid texture (assignment 6) over two earlier materials.
    Texture(TextureSpec),
}

/// A solid texture: a pattern in texture space that chooses, or blends, between two materials
/// listed before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureSpec {
    /// Which of the course's textures, with its parameters.
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
    Noise {
        /// How many octaves of noise are summed, 0 to 30 (0: no noise, an even blend).
        octaves: u32,
    },
    /// sin(frequency·x + amplitude·noise): veins.
    Marble {
        /// How many octaves of noise bend the veins, 0 to 30.
        octaves: u32,
        /// How fast the sine runs along texture space's x, in radians per unit.
        frequency: f64,
        /// How far the noise bends the veins: the noise's weight inside the sine.
        amplitude: f64,
    },
    /// Rings about texture space's y axis, perturbed by noise.
    Wood {
        /// How many octaves of noise bend the rings, 0 to 30.
        octaves: u32,
        /// How fast the sine runs outward from the axis, in radians per unit of radius.
        frequency: f64,
        /// How far the noise bends the rings: the noise's weight inside the sine.
        amplitude: f64,
    },
}

/// A Phong material (assignment 4's `PhongMaterial`, every field optional).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhongSpec {
    /// The colour a lit surface scatters in every direction, which ambient light is also
    /// multiplied by; white by default.
    pub diffuse: Vec3,
    /// The highlight's colour; black (no highlight) by default.
    pub specular: Vec3,
    /// The specular exponent, at least 0.
    pub exponent: f32,
    /// What a mirror ray's colour is multiplied by; black (no mirror) by default.
    pub reflective: Vec3,
    /// What a refracted ray's colour is multiplied by; black (opaque) by default.
    pub transparent: Vec3,
    /// The material's index of refraction, the outside being air (1); above 0.
    pub index_of_refraction: f32,
}

impl Default for PhongSpec {
    /// The staff parser's defaults: white diffuse, nothing else, exponent 1, index 1.
    fn default() -> PhongSpec {
        PhongSpec {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            exponent: 1.0,
            reflective: Vec3::ZERO,
            transparent: Vec3::ZERO,
            index_of_refraction: 1.0,
        }
    }
}

/// What an object is, in its own space (its Transform, if any, is named by
/// [`PlacedObject::transform`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// The points `radius` from `center`.
    Sphere {
        /// In object space.
        center: Vec3,
        /// Above 0.
        radius: f32,
    },
    /// The points P with P · normal = offset.
    Plane {
        /// Unit length (the parser divides the file's normal and offset by its length); it
        /// points to the front side.
        normal: Vec3,
        /// The plane's signed distance from the origin along `normal`.
        offset: f32,
    },
    /// One triangle; its front is the side from which its vertices run counter-clockwise.
    Triangle {
        /// `vertex0`, `vertex1` and `vertex2`, in the file's order.
        vertices: [Vec3; 3],
    },
    /// An .obj file, named as the scene wrote it.
    Mesh {
        /// The name as written: a relative one is looked for beside the scene file first,
        /// then in the working directory.
        file: String,
    },
}

/// One object of the scene with what places and colours it: the file's Groups and Transforms
/// flattened away.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedObject {
    /// What the object is, in its own space.
    pub shape: Shape,
    /// Index into [`SceneDescription::materials`]: the `MaterialIndex` in force when the object
    /// was read.
    pub material: u32,
    /// Index into [`SceneDescription::transforms`]; `None` when the object is in world space.
    pub transform: Option<u32>,
    /// Where the object's keyword stands.
    pub span: Span,
}
