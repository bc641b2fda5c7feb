//! From description to render-ready scene: meshes loaded (each file once), transforms inverted,
//! world-space shapes baked, instances placed, trees built.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::time::Instant;

use glam::{DMat4, DVec3, Vec3};
use rayon::prelude::*;

use super::{Light, LoadStats, Loaded, Material, Materials, Scene};
use crate::accel::{Item, TriangleMesh, World};
use crate::camera::Camera;
use crate::error::{Diagnostic, Error};
use crate::geometry::{Aabb, Plane, Sphere, Transform, triangle_normal};
use crate::parse::description::{PlacedObject, SceneDescription, Shape};
use crate::parse::obj::parse_obj;
use crate::parse::{MAX_MAGNITUDE, show_number};

/// [`Scene::load`]: reads the scene file, then builds it; the parse time includes the reading.
pub fn load(path: &Path) -> Result<Loaded, Error> {
    let start = Instant::now();
    let description = crate::parse::read_scene(path)?;
    build(&description, start)
}

/// [`Scene::from_description`]; `start` is when reading began, so that the parse time in the
/// stats counts the scene file as well as the meshes.
pub fn build(description: &SceneDescription, start: Instant) -> Result<Loaded, Error> {
    let transforms: Vec<Transform> = description
        .transforms
        .iter()
        .map(|&m| Transform::new(m))
        .collect();
    let mut meshes = MeshLoader::new(&description.path);
    let mut placed = Placed::default();
    for object in &description.objects {
        let placement = object
            .transform
            .map(|i| (&transforms[i as usize], description.transforms[i as usize]));
        let at = Placing {
            description,
            object,
            placement,
        };
        match &object.shape {
            Shape::Sphere { center, radius } => placed.sphere(&at, *center, *radius)?,
            Shape::Plane { normal, offset } => placed.plane(&at, *normal, *offset)?,
            Shape::Triangle { vertices } => placed.triangle(&at, vertices)?,
            Shape::Mesh { file } => placed.mesh(&at, &mut meshes, file)?,
        }
    }
    let parse = start.elapsed();

    let build_start = Instant::now();
    let mut mesh_files: Vec<PathBuf> = meshes.by_path.keys().cloned().collect();
    mesh_files.sort();
    let mut meshes = meshes.build();
    let Placed {
        loose_triangles,
        mut loose_materials,
        planes,
        mut items,
        mut bounds,
    } = placed;
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
        lights: description.lights.iter().map(Light::new).collect(),
        materials: Materials::new(description.materials.iter().map(Material::new).collect()),
        world,
    };
    let stats = LoadStats {
        parse,
        build,
        world: scene.world.stats(),
        mesh_files,
    };
    Ok(Loaded { scene, stats })
}

/// One object of the description on its way into the world, with its Transform (the inverted
/// form and the matrix) if it has one.
struct Placing<'a> {
    description: &'a SceneDescription,
    object: &'a PlacedObject,
    placement: Option<(&'a Transform, DMat4)>,
}

impl Placing<'_> {
    /// The object's transform as an instance refers to it.
    fn transform(&self) -> u32 {
        self.object.transform.unwrap_or(Item::WORLD_SPACE)
    }
}

/// What the objects become: instances with their boxes for the top-level tree, planes beside
/// it, and loose triangles (in world space) gathered into one mesh.
#[derive(Default)]
struct Placed {
    loose_triangles: Vec<[Vec3; 3]>,
    loose_materials: Vec<u32>,
    planes: Vec<(Plane, u32)>,
    items: Vec<Item>,
    bounds: Vec<Aabb>,
}

impl Placed {
    fn sphere(&mut self, at: &Placing, center: Vec3, radius: f32) -> Result<(), Error> {
        let sphere = Sphere {
            center: center.into(),
            radius,
        };
        let (centre, reach) = match at.placement {
            None => (center.as_dvec3(), DVec3::splat(radius as f64)),
            Some((_, matrix)) => ellipsoid_extent(&sphere, &matrix),
        };
        within_bounds(
            at.description,
            at.object,
            "sphere",
            &[centre - reach, centre + reach],
        )?;
        self.bounds.push(match at.placement {
            None => sphere.bounds(),
            Some((_, matrix)) => ellipsoid_bounds(&sphere, &matrix),
        });
        self.items.push(Item::Sphere {
            sphere,
            material: at.object.material,
            transform: at.transform(),
        });
        Ok(())
    }

    fn plane(&mut self, at: &Placing, normal: Vec3, offset: f32) -> Result<(), Error> {
        let plane = Plane {
            normal: normal.into(),
            offset,
        };
        let (plane, world_offset) = match at.placement {
            None => (plane, plane.offset as f64),
            Some((t, matrix)) => {
                // Carry one point of the plane and its normal into the world.
                let point = matrix.transform_point3(plane.normal.as_dvec3() * plane.offset as f64);
                let normal = t.normal_to_world(plane.normal);
                let offset = normal.as_dvec3().dot(point);
                let plane = Plane {
                    normal,
                    offset: offset as f32,
                };
                (plane, offset)
            }
        };
        // The parser divides the offset by the normal's length, so a short normal can move a
        // plane of modest offset far out even without a Transform.
        if world_offset.is_nan() || world_offset.abs() > MAX_MAGNITUDE {
            return Err(Diagnostic::expected(
                &at.description.path,
                at.object.span,
                "a plane at most 1e9 from the origin once placed in the world",
                &format!("one {} from it", show_number(world_offset.abs())),
            )
            .into());
        }
        self.planes.push((plane, at.object.material));
        Ok(())
    }

    fn triangle(&mut self, at: &Placing, vertices: &[Vec3; 3]) -> Result<(), Error> {
        let world = match at.placement {
            None => *vertices,
            Some((_, matrix)) => {
                let exact = vertices.map(|v| matrix.transform_point3(v.as_dvec3()));
                within_bounds(at.description, at.object, "triangle", &exact)?;
                let mut v = exact.map(|v| v.as_vec3());
                // A mirroring transform turns the winding around; swap to keep the front side
                // the one the inverse transpose of the normal points to.
                if matrix.determinant() < 0.0 {
                    v.swap(1, 2);
                }
                v
            }
        };
        if has_area(&world) {
            self.loose_triangles.push(world);
            self.loose_materials.push(at.object.material);
        }
        Ok(())
    }

    fn mesh(&mut self, at: &Placing, meshes: &mut MeshLoader, file: &str) -> Result<(), Error> {
        let mesh = meshes.load(file, at.object.span)?;
        let local = meshes.bounds(mesh);
        // A mesh without a face to hit has no box either; the trees have no use for it.
        if local.is_empty() {
            return Ok(());
        }
        self.bounds.push(match at.placement {
            None => local,
            Some((_, matrix)) => {
                let corners = box_corners(&local, &matrix);
                within_bounds(at.description, at.object, "mesh", &corners)?;
                outward_box(&corners)
            }
        });
        self.items.push(Item::Mesh {
            mesh,
            material: at.object.material,
            transform: at.transform(),
        });
        Ok(())
    }
}

/// Refuses a shape that reaches beyond [`MAX_MAGNITUDE`] on some axis once placed (`points`
/// are its world-space extremes): the scene's numbers are bounded, but a Transform can still
/// carry a shape past the bound, where single precision's products overflow.
fn within_bounds(
    description: &SceneDescription,
    object: &PlacedObject,
    kind: &str,
    points: &[DVec3],
) -> Result<(), Error> {
    let reach = points
        .iter()
        .fold(0.0f64, |a, p| a.max(p.abs().max_element()));
    if reach <= MAX_MAGNITUDE {
        return Ok(());
    }
    Err(Diagnostic::expected(
        &description.path,
        object.span,
        &format!("a {kind} between -1e9 and 1e9 on every axis once placed in the world"),
        &format!("one that reaches {}", show_number(reach)),
    )
    .into())
}

/// Whether a triangle has a side to face. One of zero area has none, and one whose edges' cross
/// product squares to less than the smallest normal f32 has none that single precision can
/// normalise: a hit on it would have a NaN normal. Such triangles are left out, so never hit.
fn has_area(triangle: &[Vec3; 3]) -> bool {
    triangle_normal(triangle).length_squared() >= f32::MIN_POSITIVE
}

/// The centre of a sphere after an affine map, and how far the ellipsoid reaches from it along
/// each world axis: r·|row|.
fn ellipsoid_extent(sphere: &Sphere, matrix: &DMat4) -> (DVec3, DVec3) {
    let centre = matrix.transform_point3(sphere.center.as_dvec3());
    let r = sphere.radius as f64;
    let linear = matrix.transpose();
    let reach = DVec3::new(
        linear.x_axis.truncate().length(),
        linear.y_axis.truncate().length(),
        linear.z_axis.truncate().length(),
    ) * r;
    (centre, reach)
}

/// The corners of a box, placed by `matrix`, in f64.
fn box_corners(b: &Aabb, matrix: &DMat4) -> [DVec3; 8] {
    std::array::from_fn(|corner| {
        let pick =
            |bit: usize, lo: f32, hi: f32| f64::from(if corner & bit == 0 { lo } else { hi });
        matrix.transform_point3(DVec3::new(
            pick(1, b.min.x, b.max.x),
            pick(2, b.min.y, b.max.y),
            pick(4, b.min.z, b.max.z),
        ))
    })
}

/// The f32 box around points worked out in f64. Placed in f32, a far-off mesh moved back near
/// the origin loses its box's edges to cancellation and rays that hit it would be culled; in f64
/// the only error left is the final rounding, which the pad covers.
fn outward_box(points: &[DVec3]) -> Aabb {
    let (lo, hi) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let pad = lo.abs().max(hi.abs()) * 1e-6;
    Aabb {
        min: (lo - pad).as_vec3().into(),
        max: (hi + pad).as_vec3().into(),
    }
}

/// The box of a sphere after an affine map: exact in f64, then padded outward to f32.
fn ellipsoid_bounds(sphere: &Sphere, matrix: &DMat4) -> Aabb {
    let (centre, reach) = ellipsoid_extent(sphere, matrix);
    outward_box(&[centre - reach, centre + reach])
}

/// Reads each mesh file once, however often the scene places it.
/// Where the mesh file `file`, named at `span` of the scene file `scene`, is: beside the scene
/// file first, then (for a relative name) in the working directory.
pub fn find_mesh(scene: &Path, file: &str, span: crate::error::Span) -> Result<PathBuf, Error> {
    let beside_scene = scene.parent().unwrap_or(Path::new("")).join(file);
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
    match tried.iter().find(|p| p.is_file()) {
        Some(found) => Ok(found.clone()),
        None => {
            let looked = tried
                .iter()
                .map(|p| format!("'{}'", p.display()))
                .collect::<Vec<_>>()
                .join(" and ");
            Err(Diagnostic::new(
                scene,
                span,
                format!("cannot open mesh file '{file}': looked for {looked}"),
            )
            .into())
        }
    }
}

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

    fn load(&mut self, file: &str, span: crate::error::Span) -> Result<u32, Error> {
        let found = find_mesh(self.scene, file, span)?;
        let found = &found;
        let key = found.canonicalize().unwrap_or_else(|_| found.clone());
        if let Some(&index) = self.by_path.get(&key) {
            return Ok(index);
        }
        let bytes = std::fs::read(found).map_err(|source| Error::Read {
            path: found.clone(),
            source,
        })?;
        let obj = parse_obj(found, &bytes)?;
        // The file's text goes before the triangles are made, so that they can take its pages.
        drop(bytes);
        // On rayon's threads (the file's order kept): for 100k triangles this was 3.5 ms. Made
        // at its length, then the flat ones dropped in place: a filtered parallel collect grew
        // its array push by push, each doubling a copy into fresh pages.
        let mut triangles: Vec<[Vec3; 3]> = obj
            .triangles
            .par_iter()
            .map(|t| t.map(|i| obj.positions[i as usize]))
            .collect();
        drop(obj);
        triangles.retain(has_area);
        let bounds = triangles
            .par_iter()
            .map(|t| Aabb::from_points(&[t[0].into(), t[1].into(), t[2].into()]))
            .reduce(|| Aabb::EMPTY, Aabb::union);
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
        self.triangles
            .into_par_iter()
            .map(|triangles| TriangleMesh::new(triangles).0)
            .collect()
    }
}
