//! Scenes built in code: the description a scene file gives, made without a file, a parser or
//! a place in a text.

use std::path::PathBuf;

use glam::{DMat4, Vec3};

use super::{Loaded, Scene};
use crate::error::{Diagnostic, Error, Span};
use crate::parse::description::{
    CameraSpec, LightSpec, MaterialSpec, PhongSpec, PlacedObject, Projection, SceneDescription,
    Shape,
};

/// What a scene built in code is called in messages.
pub const BUILT_IN_CODE: &str = "<scene built in code>";

/// Builds a scene step by step. The same rules hold as for a scene file (a positive radius, a
/// material index that exists, ...), checked by [`SceneBuilder::build`], whose errors name the
/// item at fault.
///
/// ```
/// use raycast::{Vec3, SceneBuilder};
/// use raycast::parse::description::{CameraSpec, LightSpec, MaterialSpec, PhongSpec, Shape};
///
/// let scene = SceneBuilder::new(CameraSpec::perspective(
///     Vec3::new(0.0, 1.0, 6.0), Vec3::new(0.0, -0.1, -1.0), Vec3::Y, 40.0))
///     .background(Vec3::new(0.4, 0.5, 0.7))
///     .light(LightSpec::directional(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE))
///     .material(MaterialSpec::Phong(PhongSpec::diffuse(Vec3::new(0.9, 0.2, 0.1))))
///     .object(Shape::Sphere { center: Vec3::new(0.0, 1.0, 0.0), radius: 1.0 }, 0)
///     .build()?;
/// assert_eq!(scene.world.stats().spheres, 1);
///
/// // A radius of -1 is refused, as the parser refuses it in a file.
/// let wrong = SceneBuilder::new(CameraSpec::orthographic(Vec3::Z, -Vec3::Z, Vec3::Y, 5.0))
///     .material(MaterialSpec::Phong(PhongSpec::default()))
///     .object(Shape::Sphere { center: Vec3::ZERO, radius: -1.0 }, 0)
///     .build();
/// assert_eq!(
///     wrong.unwrap_err().to_string(),
///     "<scene built in code>: object 0: expected a positive radius, found '-1'"
/// );
/// # Ok::<(), raycast::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBuilder {
    description: SceneDescription,
    /// The names given to materials, with their indices.
    names: Vec<(String, u32)>,
    /// The first object that named a material not yet added: reported by `build`.
    unknown_name: Option<(usize, String)>,
}

/// Which material an object has: its index, or the name it was added under with
/// [`SceneBuilder::named_material`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaterialRef<'a> {
    /// Materials are numbered from 0 in the order added, named or not.
    Index(u32),
    /// A name given to a material added earlier.
    Name(&'a str),
}

impl From<u32> for MaterialRef<'_> {
    fn from(index: u32) -> Self {
        MaterialRef::Index(index)
    }
}

impl<'a> From<&'a str> for MaterialRef<'a> {
    fn from(name: &'a str) -> Self {
        MaterialRef::Name(name)
    }
}

impl SceneBuilder {
    /// A scene seen by `camera`, with the course's defaults: a grey background (0.5), no
    /// ambient light, and (until one is added) no lights.
    pub fn new(camera: CameraSpec) -> SceneBuilder {
        SceneBuilder {
            description: SceneDescription {
                path: PathBuf::from(BUILT_IN_CODE),
                camera,
                background: Vec3::splat(0.5),
                ambient: Vec3::ZERO,
                lights: Vec::new(),
                materials: Vec::new(),
                transforms: Vec::new(),
                objects: Vec::new(),
            },
            names: Vec::new(),
            unknown_name: None,
        }
    }

    /// The colour of rays that hit nothing.
    pub fn background(mut self, colour: Vec3) -> Self {
        self.description.background = colour;
        self
    }

    /// The ambient light (with no lights at all it becomes white, as in the course).
    pub fn ambient_light(mut self, colour: Vec3) -> Self {
        self.description.ambient = colour;
        self
    }

    /// Adds a light.
    pub fn light(mut self, light: LightSpec) -> Self {
        self.description.lights.push(light);
        self
    }

    /// Adds a material; materials are numbered from 0 in the order added.
    pub fn material(mut self, material: MaterialSpec) -> Self {
        self.description.materials.push(material);
        self
    }

    /// Adds a material that objects can name; it also takes the next index. A name given
    /// twice names the later material.
    pub fn named_material(mut self, name: &str, material: MaterialSpec) -> Self {
        let index = self.description.materials.len() as u32;
        self.names.push((name.to_string(), index));
        self.material(material)
    }

    /// Adds a shape in world space, with a material given by index or by name.
    pub fn object<'a>(self, shape: Shape, material: impl Into<MaterialRef<'a>>) -> Self {
        let material = material.into();
        self.push(shape, material, None)
    }

    /// Adds a shape placed by `object_to_world` (a scene file's Transform: maps the shape's
    /// points into the world).
    pub fn placed<'a>(
        mut self,
        shape: Shape,
        material: impl Into<MaterialRef<'a>>,
        object_to_world: DMat4,
    ) -> Self {
        self.description.transforms.push(object_to_world);
        let index = self.description.transforms.len() as u32 - 1;
        self.push(shape, material.into(), Some(index))
    }

    fn push(mut self, shape: Shape, material: MaterialRef, transform: Option<u32>) -> Self {
        let material = match material {
            MaterialRef::Index(index) => index,
            MaterialRef::Name(name) => {
                match self.names.iter().rev().find(|(known, _)| known == name) {
                    Some(&(_, index)) => index,
                    None => {
                        let object = self.description.objects.len();
                        self.unknown_name.get_or_insert((object, name.to_string()));
                        u32::MAX
                    }
                }
            }
        };
        self.description.objects.push(PlacedObject {
            shape,
            material,
            transform,
            span: Span::default(),
        });
        self
    }

    /// The description built so far (with the course's rule applied: no lights, white ambient
    /// light).
    pub fn description(&self) -> SceneDescription {
        let mut description = self.description.clone();
        if description.lights.is_empty() {
            description.ambient = Vec3::ONE;
        }
        description
    }

    /// Checks the description and builds the render-ready scene. Mesh files are looked for in
    /// the working directory.
    pub fn build(self) -> Result<Scene, Error> {
        self.build_with_stats().map(|loaded| loaded.scene)
    }

    /// [`SceneBuilder::build`], with the time it took and what it made.
    pub fn build_with_stats(self) -> Result<Loaded, Error> {
        if let Some((object, name)) = &self.unknown_name {
            let known: Vec<String> = self.names.iter().map(|(n, _)| format!("'{n}'")).collect();
            let expected = if known.is_empty() {
                "a material added by name before it (none has a name)".to_string()
            } else {
                format!("one of the material names {}", known.join(", "))
            };
            return Err(Diagnostic::new(
                &self.description.path,
                Span::default(),
                format!("object {object}: expected {expected}, found '{name}'"),
            )
            .into());
        }
        Scene::from_description_with_stats(&self.description())
    }
}

impl CameraSpec {
    /// A perspective camera: rays from `center`, `angle` the full field of view in degrees.
    pub fn perspective(center: Vec3, direction: Vec3, up: Vec3, angle: f32) -> CameraSpec {
        CameraSpec {
            center,
            direction,
            up,
            projection: Projection::Perspective { angle },
        }
    }

    /// An orthographic camera: parallel rays, `size` the side of the square it sees.
    pub fn orthographic(center: Vec3, direction: Vec3, up: Vec3, size: f32) -> CameraSpec {
        CameraSpec {
            center,
            direction,
            up,
            projection: Projection::Orthographic { size },
        }
    }
}

impl LightSpec {
    /// Light travelling along `direction` everywhere.
    pub fn directional(direction: Vec3, colour: Vec3) -> LightSpec {
        LightSpec::Directional {
            direction: direction.normalize_or_zero(),
            colour,
        }
    }

    /// Light from `position`, not fading with distance (attenuation 1 0 0).
    pub fn point(position: Vec3, colour: Vec3) -> LightSpec {
        LightSpec::Point {
            position,
            colour,
            attenuation: [1.0, 0.0, 0.0],
        }
    }
}

impl PhongSpec {
    /// A plain diffuse material of `colour`, the rest the course's defaults.
    pub fn diffuse(colour: Vec3) -> PhongSpec {
        PhongSpec {
            diffuse: colour,
            ..PhongSpec::default()
        }
    }
}
