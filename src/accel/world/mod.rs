//! Everything a ray can hit, and the searches for it. The world has one store and several
//! searches, each in a file of its own:
//!
//! - the store (this file): the shared meshes and their placements (items), the spheres, the
//!   planes and the transforms, the top-level tree over the items, and its sizes for `-stats`;
//! - the nearest-hit search of one ray (`nearest.rs`), and of a packet of camera rays
//!   (`packet.rs`), through the trees;
//! - the shadow search of one ray (`shadow.rs`): whether anything is hit at all in a range;
//!   and of a packet of shadow rays toward one light (`shadow_packet.rs`);
//! - the grid search (`grid_search.rs`): both questions through the course's grid instead of
//!   the trees, under `-grid`;
//! - the brute-force twins (`brute_force.rs`): both questions with no tree, which the tests
//!   compare the others with;
//! - the hit record (`Hit`): what a search's winner becomes, its normal worked out once.

mod as_student;
pub use as_student::{Carry, Struck};
mod brute_force;
mod grid_search;
pub use grid_search::Listing;
mod nearest;
mod packet;
mod shadow;
mod shadow_packet;
mod spread;

use glam::Vec3A;

use super::{Bvh, Grid, LeafSize, Tally, TriangleMesh};
use crate::geometry::{Aabb, Plane, Ray, Sphere, Transform, intersect_sphere, unit_normal};

/// An entry of the top-level tree. `transform` indexes the world's transforms, or is
/// [`Item::WORLD_SPACE`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Item {
    /// One sphere of the scene.
    Sphere {
        /// In the item's own space.
        sphere: Sphere,
        /// Index into the scene's materials.
        material: u32,
        /// Index of the sphere's Transform, or [`Item::WORLD_SPACE`].
        transform: u32,
    },
    /// A placement of a shared mesh; `material` is [`Item::PER_TRIANGLE`] for the mesh of the
    /// scene's loose triangles, whose materials the world keeps per triangle.
    Mesh {
        /// Index into the world's meshes, which each mesh file is loaded into once.
        mesh: u32,
        /// Index into the scene's materials, or [`Item::PER_TRIANGLE`].
        material: u32,
        /// Index of the placement's Transform, or [`Item::WORLD_SPACE`].
        transform: u32,
    },
}

impl Item {
    /// The `transform` of an item under no Transform: rays reach it as they are.
    pub const WORLD_SPACE: u32 = u32::MAX;
    /// The `material` of the loose triangles' mesh, each of whose triangles has its own.
    pub const PER_TRIANGLE: u32 = u32::MAX;

    pub(crate) fn transform(&self) -> u32 {
        match *self {
            Item::Sphere { transform, .. } | Item::Mesh { transform, .. } => transform,
        }
    }
}

/// The nearest surface along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// The world ray's parameter.
    pub t: f32,
    /// The geometric normal in world space, unit length, not flipped toward the ray.
    pub normal: Vec3A,
    /// Index into the scene's materials.
    pub material: u32,
}

/// Sizes of the world, for `-stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WorldStats {
    /// Meshes stored: each mesh file once, and the scene's loose triangles as one more.
    pub meshes: usize,
    /// Placements of meshes, the loose triangles' included.
    pub instances: usize,
    /// Triangles stored (a mesh placed many times counts once).
    pub triangles: usize,
    /// Triangles placed in the scene (a mesh placed many times counts each time).
    pub triangles_placed: usize,
    /// Spheres, under a Transform or not.
    pub spheres: usize,
    /// Planes, which are tested beside the trees rather than in them.
    pub planes: usize,
    /// Eight-wide tree nodes: the top-level tree's, and each mesh's once.
    pub nodes: usize,
    /// Memory the shapes take: triangles (twice: as listed and in blocks of eight), items,
    /// transforms and planes.
    pub geometry_bytes: usize,
    /// Memory the trees take; the grid is not counted.
    pub acceleration_bytes: usize,
    /// The course's grid's cells on each axis, when `-grid` searches it instead of the trees.
    pub grid_cells: Option<[u32; 3]>,
}

/// Everything a ray can hit: the shared meshes and their placements, the spheres, the planes,
/// and the top-level tree over all but the planes (or the course's grid, when one is in use).
#[derive(Debug, Clone, Default)]
pub struct World {
    pub(crate) meshes: Vec<TriangleMesh>,
    pub(crate) loose_materials: Vec<u32>,
    pub(crate) transforms: Vec<Transform>,
    pub(crate) items: Vec<Item>,
    pub(crate) top: Bvh,
    pub(crate) planes: Vec<(Plane, u32)>,
    /// The course's grid, searched instead of the trees when `-grid` asks for it.
    pub(crate) grid: Option<Grid>,
    /// Grids of the same cells as a student's tracer lists objects in them (see
    /// [`Listing`]), each made the first time a search through it is asked for.
    pub(crate) students_grids: [std::sync::OnceLock<Option<Grid>>; 4],
}

/// A ray in one item's space, with its watertight frame, kept while the grid tests that item.
struct LocalRay {
    item: u32,
    ray: Ray,
    frame: crate::geometry::RayFrame,
}

/// What the search found, before the normal is worked out (only the winner's is).
#[derive(Clone, Copy)]
enum Found {
    Plane(u32),
    Item { item: u32, triangle: u32 },
}

/// The nearest hit so far. Hits at the same t go to the lower key: planes in their order, then
/// items in their stored order (triangles of one mesh are settled by the mesh). The trees and
/// the brute-force search visit surfaces in different orders; with one rule for ties they still
/// name the same surface, and so give the same normal and material.
#[derive(Clone, Copy)]
struct Nearest {
    t: f32,
    key: u64,
    found: Found,
}

/// How far a search need still look, given the nearest hit so far.
#[inline(always)]
fn search_limit(nearest: &Option<Nearest>) -> f32 {
    nearest.map_or(f32::INFINITY, |n| n.t)
}

impl Nearest {
    fn plane(t: f32, plane: u32) -> Nearest {
        Nearest {
            t,
            key: u64::from(plane),
            found: Found::Plane(plane),
        }
    }

    fn item(t: f32, item: u32, triangle: u32) -> Nearest {
        Nearest {
            t,
            // Items after planes; within an item, its lower triangle (the meshes' own rule).
            key: (1 << 63) | (u64::from(item) << 32) | u64::from(triangle),
            found: Found::Item { item, triangle },
        }
    }

    /// Takes the place of `nearest` if it is nearer, or as near with a lower key.
    #[inline(always)]
    fn replaces(self, nearest: &mut Option<Nearest>) -> bool {
        let better = nearest.is_none_or(|n| self.t < n.t || self.t == n.t && self.key < n.key);
        if better {
            *nearest = Some(self);
        }
        better
    }
}

impl World {
    /// `items` in any order; the top-level tree is built over `bounds` (one box per item).
    pub fn new(
        meshes: Vec<TriangleMesh>,
        loose_materials: Vec<u32>,
        transforms: Vec<Transform>,
        items: Vec<Item>,
        bounds: &[Aabb],
        planes: Vec<(Plane, u32)>,
    ) -> World {
        let (top, order) = Bvh::build(bounds, LeafSize::INSTANCES);
        let items = order.iter().map(|&i| items[i as usize]).collect();
        World {
            meshes,
            loose_materials,
            transforms,
            items,
            top,
            planes,
            grid: None,
            students_grids: Default::default(),
        }
    }

    /// The box of everything but the planes (`None` for a scene of planes alone).
    pub fn bounds(&self) -> Option<Aabb> {
        let b = match &self.grid {
            Some(grid) if !self.items.is_empty() => grid.bounds(),
            _ => self.top.bounds(),
        };
        (!self.items.is_empty() && !b.is_empty()).then_some(b)
    }

    /// Whether a packet searches the world's one item directly, with no top-level tree: it is
    /// alone and in world space. One under a Transform goes through the tree all the same: its
    /// box, met by few of a packet's rays or none, spares carrying the others into its space.
    fn packets_skip_top_tree(&self) -> bool {
        self.items.len() == 1 && self.items[0].transform() == Item::WORLD_SPACE
    }

    /// Calls `f` with the ray in `item`'s own space: the world ray as it is (no copy of it on
    /// the way to the triangles) for an item placed in world space.
    #[inline(always)]
    fn in_item_space<R>(&self, item: &Item, ray: &Ray, f: impl FnOnce(&Ray) -> R) -> R {
        match item.transform() {
            Item::WORLD_SPACE => f(ray),
            t => f(&self.transforms[t as usize].ray_to_object(ray)),
        }
    }

    #[inline(always)]
    fn intersect_local<T: Tally>(
        &self,
        item: &Item,
        local: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        match *item {
            Item::Sphere { sphere, .. } => {
                tally.tested(1);
                intersect_sphere(local, &sphere, t_min, t_max).map(|t| (t, 0))
            }
            Item::Mesh { mesh, .. } => {
                self.meshes[mesh as usize].intersect_with(local, t_min, t_max, tally)
            }
        }
    }

    /// The ray in the item's own space (the same ray for items placed in world space).
    pub(crate) fn ray_into(&self, item: &Item, ray: &Ray) -> Ray {
        match item.transform() {
            Item::WORLD_SPACE => *ray,
            t => self.transforms[t as usize].ray_to_object(ray),
        }
    }

    fn hit(&self, ray: &Ray, t: f32, found: Found) -> Hit {
        self.hit_with(ray, t, found, self.surface(ray, t, found))
    }

    /// What the hit's normal is made from, with its material: the object's own normal (of
    /// any length, in its own space) for an item, the world's for a plane. The part of a hit
    /// that reads the object (a mesh's triangle, mostly not in the cache), so that a packet
    /// can read all of its hits' at once.
    fn surface(&self, ray: &Ray, t: f32, found: Found) -> (Vec3A, u32) {
        match found {
            Found::Plane(i) => {
                let (plane, material) = self.planes[i as usize];
                (plane.normal, material)
            }
            Found::Item { item, triangle } => self.object_normal(ray, t, item, triangle),
        }
    }

    /// The hit, from its [`World::surface`].
    fn hit_with(&self, ray: &Ray, t: f32, found: Found, (normal, material): (Vec3A, u32)) -> Hit {
        let normal = match found {
            Found::Plane(_) => normal,
            Found::Item { item, .. } => {
                let item = &self.items[item as usize];
                let normal = match item.transform() {
                    Item::WORLD_SPACE => unit_normal(normal),
                    i => self.transforms[i as usize].normal_to_world(normal),
                };
                // A surface too small for f32 to give it a direction (a sphere of radius 1e-7
                // hit dead centre): it faces the ray, so that no NaN reaches a pixel.
                if normal == Vec3A::ZERO {
                    -ray.direction.normalize()
                } else {
                    normal
                }
            }
        };
        Hit {
            t,
            normal,
            material,
        }
    }

    /// The normal of item `item` (triangle `triangle` of a mesh) where `ray` meets it at `t`, in
    /// the item's own space, not unit length; and its material.
    fn object_normal(&self, ray: &Ray, t: f32, item: u32, triangle: u32) -> (Vec3A, u32) {
        let item = &self.items[item as usize];
        match *item {
            Item::Sphere {
                sphere, material, ..
            } => {
                let local = self.ray_into(item, ray);
                (sphere.normal_at(local.at(t)), material)
            }
            Item::Mesh { mesh, material, .. } => {
                let material = if material == Item::PER_TRIANGLE {
                    self.loose_materials[triangle as usize]
                } else {
                    material
                };
                (self.meshes[mesh as usize].normal(triangle), material)
            }
        }
    }

    /// How the nearest hit's normal came about: its normal in its object's own space (of any
    /// length) and the Transform that places the object (`None` in world space, and for
    /// planes, whose normal is the world's). For check's faults of normals, which a student's
    /// tracer transforms another way.
    pub fn normal_origin(&self, ray: &Ray, t_min: f32) -> Option<(Vec3A, Option<&Transform>)> {
        let mut nearest = self.nearest_plane(ray, t_min);
        self.nearest_beyond_planes(ray, t_min, &mut nearest, &mut ());
        let nearest = nearest?;
        Some(match nearest.found {
            Found::Plane(i) => (self.planes[i as usize].0.normal, None),
            Found::Item { item, triangle } => {
                let (normal, _) = self.object_normal(ray, nearest.t, item, triangle);
                let transform = match self.items[item as usize].transform() {
                    Item::WORLD_SPACE => None,
                    i => Some(&self.transforms[i as usize]),
                };
                (normal, transform)
            }
        })
    }

    /// What the world holds and what its trees take, for `-stats`.
    pub fn stats(&self) -> WorldStats {
        let mut stats = WorldStats {
            meshes: self.meshes.len(),
            planes: self.planes.len(),
            nodes: self.top.node_count(),
            acceleration_bytes: self.top.size_in_bytes(),
            grid_cells: self.grid.as_ref().map(|grid| grid.cells().to_array()),
            geometry_bytes: self.items.len() * std::mem::size_of::<Item>()
                + self.transforms.len() * std::mem::size_of::<Transform>()
                + self.loose_materials.len() * 4
                + self.planes.len() * std::mem::size_of::<(Plane, u32)>(),
            ..WorldStats::default()
        };
        for mesh in &self.meshes {
            let (geometry, acceleration) = mesh.size_in_bytes();
            stats.triangles += mesh.triangles().len();
            stats.nodes += mesh.bvh().node_count();
            stats.geometry_bytes += geometry;
            stats.acceleration_bytes += acceleration;
        }
        for item in &self.items {
            match *item {
                Item::Sphere { .. } => stats.spheres += 1,
                Item::Mesh { mesh, .. } => {
                    stats.instances += 1;
                    stats.triangles_placed += self.meshes[mesh as usize].triangles().len();
                }
            }
        }
        stats
    }
}
