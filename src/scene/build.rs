//! From description to render-ready scene: meshes loaded (each file once), transforms inverted,
//! world-space shapes baked, instances placed, trees built.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::time::Instant;

use glam::{DMat4, DVec3, Vec3, Vec3A};

use super::model::{SceneDescription, Shape};
use super::obj::parse_obj;
use super::{Light, LoadStats, MaterialColour, Scene};
use crate::accel::{Item, TriangleMesh, World};
use crate::camera::Camera;
use crate::error::{Diagnostic, Error};
use crate::geometry::{Aabb, Plane, Sphere, Transform};

pub fn load(path: &Path) -> Result<(Scene, LoadStats), Error> {
    let start = Instant::now();
    let description = crate::parse::read_scene(path)?;
    build(&description, start)
}

pub fn build(description: &SceneDescription, start: Instant) -> Result<(Scene, LoadStats), Error> {
    let transforms: Vec<Transform> = description
        .transforms
        .iter()
        .map(|&m| Transform::new(m))
        .collect();
    let mut meshes = MeshLoader::new(&description.path);
    let mut loose_triangles = Vec::new();
    let mut loose_materials = Vec::new();
    let mut planes = Vec::new();
    let mut items = Vec::new();
    let mut bounds = Vec::new();
    for object in &description.objects {
        let placement = object
            .transform
            .map(|i| (&transforms[i as usize], description.transforms[i as usize]));
        let transform = object.transform.unwrap_or(Item::WORLD_SPACE);
        match &object.shape {
            Shape::Sphere { center, radius } => {
                let sphere = Sphere {
                    center: (*center).into(),
                    radius: *radius,
                };
                bounds.push(match placement {
                    None => sphere.bounds(),
                    Some((_, matrix)) => ellipsoid_bounds(&sphere, &matrix),
                });
                items.push(Item::Sphere {
                    sphere,
                    material: object.material,
                    transform,
                });
            }
            Shape::Plane { normal, offset } => {
                let plane = Plane {
                    normal: (*normal).into(),
                    offset: *offset,
                };
                let plane = match placement {
                    None => plane,
                    Some((t, matrix)) => {
                        // Carry one point of the plane and its normal into the world.
                        let point =
                            matrix.transform_point3(plane.normal.as_dvec3() * plane.offset as f64);
                        let normal = t.normal_to_world(plane.normal);
                        Plane {
                            normal,
                            offset: normal.as_dvec3().dot(point) as f32,
                        }
                    }
                };
                planes.push((plane, object.material));
            }
            Shape::Triangle { vertices } => {
                let world = match placement {
                    None => *vertices,
                    Some((_, matrix)) => {
                        let mut v =
                            vertices.map(|v| matrix.transform_point3(v.as_dvec3()).as_vec3());
                        // A mirroring transform turns the winding around; swap to keep the
                        // front side the one the inverse transpose of the normal points to.
                        if matrix.determinant() < 0.0 {
                            v.swap(1, 2);
                        }
                        v
                    }
                };
                loose_triangles.push(world);
                loose_materials.push(object.material);
            }
            Shape::Mesh { file } => {
                let mesh = meshes.load(file, object.span)?;
                bounds.push(match placement {
                    None => meshes.bounds(mesh),
                    Some((t, _)) => meshes.bounds(mesh).transformed(&t.object_to_world),
                });
                items.push(Item::Mesh {
                    mesh,
                    material: object.material,
                    transform,
                });
            }
        }
    }
    let parse = start.elapsed();

    let build_start = Instant::now();
    let mut meshes = meshes.build();
    if !loose_triangles.is_empty() {
        let (mesh, order) = TriangleMesh::new(loose_triangles);
        loose_materials = order.iter().map(|&i| loose_materials[i as usize]).collect();
        bounds.push(mesh.bounds());
        items.push(Item::Mesh {
            mesh: meshes.len() as u32,
            material: Item::PER_TRIANGLE,
            transform: Item::WORLD_SPACE,
        });
        meshes.push(mesh);
    }
    let world = World::new(meshes, loose_materials, transforms, items, &bounds, planes);
    let build = build_start.elapsed();

    let scene = Scene {
        camera: Camera::new(&description.camera),
        background: description.background.into(),
        ambient: description.ambient.into(),
        lights: description
            .lights
            .iter()
            .map(|l| Light {
                to_light: -Vec3A::from(l.direction),
                color: l.color.into(),
            })
            .collect(),
        materials: description
            .materials
            .iter()
            .map(|m| MaterialColour {
                diffuse: m.diffuse.into(),
            })
            .collect(),
        world,
    };
    let stats = LoadStats {
        parse,
        build,
        world: scene.world.stats(),
    };
    Ok((scene, stats))
}

/// The exact box of a sphere after an affine map: along each world axis, the ellipsoid reaches
/// r·|row| from its centre.
fn ellipsoid_bounds(sphere: &Sphere, matrix: &DMat4) -> Aabb {
    let centre = matrix.transform_point3(sphere.center.as_dvec3());
    let r = sphere.radius as f64;
    let linear = matrix.transpose();
    let reach = DVec3::new(
        linear.x_axis.truncate().length(),
        linear.y_axis.truncate().length(),
        linear.z_axis.truncate().length(),
    ) * r;
    // Widened by an ulp or so, so that rounding to f32 never cuts the surface.
    let pad = reach * 1e-6;
    Aabb {
        min: (centre - reach - pad).as_vec3().into(),
        max: (centre + reach + pad).as_vec3().into(),
    }
}

/// Reads each mesh file once, however often the scene places it.
struct MeshLoader<'a> {
    scene: &'a Path,
    by_path: HashMap<PathBuf, u32>,
    triangles: Vec<Vec<[Vec3; 3]>>,
    bounds: Vec<Aabb>,
}

impl<'a> MeshLoader<'a> {
    fn new(scene: &'a Path) -> Self {
        MeshLoader {
            scene,
            by_path: HashMap::new(),
            triangles: Vec::new(),
            bounds: Vec::new(),
        }
    }

    fn load(&mut self, file: &str, span: crate::parse::Span) -> Result<u32, Error> {
        let beside_scene = self.scene.parent().unwrap_or(Path::new("")).join(file);
        let mut tried = vec![beside_scene];
        // A scene in the working directory has both places the same: name it once in messages.
        let plain = |p: &Path| {
            p.components()
                .filter(|c| *c != Component::CurDir)
                .collect::<PathBuf>()
        };
        if Path::new(file).is_relative() && plain(&tried[0]) != plain(Path::new(file)) {
            tried.push(PathBuf::from(file));
        }
        let Some(found) = tried.iter().find(|p| p.is_file()) else {
            let looked = tried
                .iter()
                .map(|p| format!("'{}'", p.display()))
                .collect::<Vec<_>>()
                .join(" and ");
            return Err(Diagnostic::new(
                self.scene,
                span,
                format!("cannot open mesh file '{file}': looked for {looked}"),
            )
            .into());
        };
        let key = found.canonicalize().unwrap_or_else(|_| found.clone());
        if let Some(&index) = self.by_path.get(&key) {
            return Ok(index);
        }
        let bytes = std::fs::read(found).map_err(|source| Error::Read {
            path: found.clone(),
            source,
        })?;
        let obj = parse_obj(found, &bytes)?;
        let triangles: Vec<[Vec3; 3]> = obj
            .triangles
            .iter()
            .map(|t| t.map(|i| obj.positions[i as usize]))
            .collect();
        let bounds = triangles
            .iter()
            .flatten()
            .fold(Aabb::EMPTY, |b, &v| b.grow(v.into()));
        let index = self.triangles.len() as u32;
        self.triangles.push(triangles);
        self.bounds.push(bounds);
        self.by_path.insert(key, index);
        Ok(index)
    }

    fn bounds(&self, mesh: u32) -> Aabb {
        self.bounds[mesh as usize]
    }

    /// The meshes' trees, built in parallel when there are several.
    fn build(self) -> Vec<TriangleMesh> {
        use rayon::prelude::*;
        self.triangles
            .into_par_iter()
            .map(|triangles| TriangleMesh::new(triangles).0)
            .collect()
    }
}
