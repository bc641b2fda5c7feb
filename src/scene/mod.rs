//! The scene: its description as parsed, and the render-ready form built from it.

mod build;
mod builder;
pub mod highlight;
pub mod light;
pub mod material;
pub mod perlin;

use std::path::Path;
use std::time::Duration;

use glam::Vec3A;

pub use build::find_mesh;
pub use builder::{BUILT_IN_CODE, MaterialRef, SceneBuilder};
pub use highlight::{Highlight, HighlightAt, HighlightBase, HighlightColour, HighlightForm};
pub use light::{Illumination, Light};
pub use material::{Material, Materials, Phong, SpecularFalloff, Surface, Texture};

use crate::accel::{World, WorldStats};
use crate::camera::Camera;
use crate::error::Error;
pub use crate::parse::SceneDescription;
use crate::parse::validate;

/// A scene ready to render.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Where each pixel's ray starts and which way it goes.
    pub camera: Camera,
    /// The colour of rays that hit nothing.
    pub background: Vec3A,
    /// The light everywhere, multiplied by each surface's diffuse colour; white in a scene
    /// without lights, so that its objects show their flat diffuse colour.
    pub ambient: Vec3A,
    /// In the file's order.
    pub lights: Vec<Light>,
    /// Asked by the material index a hit carries.
    pub materials: Materials,
    /// Everything a ray can hit, and the trees (or the grid) that find it.
    pub world: World,
}

/// How long loading took and what it made, for `-stats`.
#[derive(Debug, Clone, Default)]
pub struct LoadStats {
    /// Reading and parsing the scene and its mesh files.
    pub parse: Duration,
    /// Building the acceleration structures.
    pub build: Duration,
    /// What the world holds, and the size of its trees.
    pub world: WorldStats,
    /// The mesh files read, as found on disk (so that no output overwrites one).
    pub mesh_files: Vec<std::path::PathBuf>,
}

/// A scene loaded, with how long loading took and what it made (for `-stats`).
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The scene, ready to render.
    pub scene: Scene,
    /// Times and sizes of the loading.
    pub stats: LoadStats,
}

impl Scene {
    /// Reads a scene file and the meshes it names, and builds the acceleration structures.
    pub fn load(path: &Path) -> Result<Scene, Error> {
        Ok(Scene::load_with_stats(path)?.scene)
    }

    /// [`Scene::load`], with the times and sizes of the loading.
    pub fn load_with_stats(path: &Path) -> Result<Loaded, Error> {
        build::load(path)
    }

    /// Builds a scene from a description; relative mesh paths are looked for beside
    /// `description.path` first, then in the working directory.
    pub fn from_description(description: &SceneDescription) -> Result<Scene, Error> {
        Ok(Scene::from_description_with_stats(description)?.scene)
    }

    /// [`Scene::from_description`], with the times and sizes of the building.
    pub fn from_description_with_stats(description: &SceneDescription) -> Result<Loaded, Error> {
        validate::validate(description)?;
        build::build(description, std::time::Instant::now())
    }
}
