//! Everything a ray can hit, and the two-level search for the nearest of it.

use arrayvec::ArrayVec;
use glam::Vec3A;

use std::ops::ControlFlow;

use glam::UVec3;

use super::bvh::{CoherentParts, PACKET, ray_meets_box};
use super::grid::{Extent, Primitive};
use super::{ASKS_NOTHING, Bvh, Grid, GridError, LeafSize, Tally, TriangleMesh};
use crate::geometry::{
    Aabb, Plane, Ray, Sphere, Transform, intersect_plane, intersect_sphere, intersect_triangle_in,
    unit_normal,
};
use crate::simd::Portable;

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
    /// Four-wide tree nodes: the top-level tree's, and each mesh's once.
    pub nodes: usize,
    /// Memory the shapes take: triangles (twice: as listed and in blocks of four), items,
    /// transforms and planes.
    pub geometry_bytes: usize,
    /// Memory the trees take; the grid is not counted.
    pub acceleration_bytes: usize,
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
}

/// A ray in one item's space, with its watertight frame, kept while the grid tests that item.
struct LocalRay {
    item: u32,
    ray: Ray,
    frame: glam::Mat3A,
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
        }
    }

    /// Searches the course's uniform grid of `cells` over the scene's box from now on, instead
    /// of the trees. Every sphere and triangle is listed in each cell its box reaches (a box of
    /// the eight corners of its object-space box, under a Transform), a sphere in world space by
    /// the handout's tighter test; planes stay outside the grid.
    pub fn use_grid(&mut self, cells: UVec3) -> Result<(), GridError> {
        let mut primitives = Vec::new();
        for (i, item) in self.items.iter().enumerate() {
            let transform = match item.transform() {
                Item::WORLD_SPACE => None,
                t => Some(&self.transforms[t as usize]),
            };
            let placed = |b: Aabb| match transform {
                None => b,
                Some(t) => {
                    let corners: [glam::Vec3A; 8] = std::array::from_fn(|c| {
                        let pick =
                            |bit: usize, lo: f32, hi: f32| if c & bit == 0 { lo } else { hi };
                        t.object_to_world.transform_point3a(glam::Vec3A::new(
                            pick(1, b.min.x, b.max.x),
                            pick(2, b.min.y, b.max.y),
                            pick(4, b.min.z, b.max.z),
                        ))
                    });
                    Aabb::from_points(&corners)
                }
            };
            match *item {
                Item::Sphere { sphere, .. } => {
                    let extent = match transform {
                        None => Extent::Sphere {
                            center: sphere.center,
                            radius: sphere.radius,
                        },
                        Some(_) => Extent::Box(placed(sphere.bounds())),
                    };
                    let primitive = Primitive {
                        item: i as u32,
                        triangle: 0,
                    };
                    primitives.push((primitive, extent));
                }
                Item::Mesh { mesh, .. } => {
                    for (k, v) in self.meshes[mesh as usize].triangles().iter().enumerate() {
                        let b = Aabb::from_points(&[v[0].into(), v[1].into(), v[2].into()]);
                        let primitive = Primitive {
                            item: i as u32,
                            triangle: k as u32,
                        };
                        primitives.push((primitive, Extent::Box(placed(b))));
                    }
                }
            }
        }
        let bounds = primitives.iter().fold(Aabb::EMPTY, |b, (_, e)| {
            b.union(match *e {
                Extent::Box(b) => b,
                Extent::Sphere { center, radius } => Aabb {
                    min: center - radius,
                    max: center + radius,
                },
            })
        });
        self.grid = Some(Grid::build(bounds, cells, &primitives)?);
        Ok(())
    }

    /// The course's grid, when one is in use.
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// The box of everything but the planes (`None` for a scene of planes alone).
    pub fn bounds(&self) -> Option<Aabb> {
        let b = match &self.grid {
            Some(grid) if !self.items.is_empty() => grid.bounds(),
            _ => self.top.bounds(),
        };
        (!self.items.is_empty() && !b.is_empty()).then_some(b)
    }

    /// The nearest hit with t >= t_min.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        self.intersect_with(ray, t_min, &mut ())
    }

    /// [`World::intersect`], counting primitives tested and grid cells entered.
    #[inline(always)]
    pub fn intersect_with<T: Tally>(&self, ray: &Ray, t_min: f32, tally: &mut T) -> Option<Hit> {
        tally.tested(self.planes.len() as u32);
        let mut nearest = self.nearest_plane(ray, t_min);
        if let Some(grid) = &self.grid {
            self.grid_nearest(grid, ray, t_min, &mut nearest, tally);
            return nearest.map(|n| self.hit(ray, n.t, n.found));
        }
        self.nearest_item(ray, t_min, &mut nearest, tally);
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The items' part of [`World::intersect_with`]: replaces `nearest` with a nearer item hit.
    #[inline(always)]
    fn nearest_item<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
    ) {
        let t_max = search_limit(nearest);
        let mut test = |i, t_max| {
            let (t, triangle) = self.intersect_item(i, ray, t_min, t_max, tally)?;
            Nearest::item(t, i, triangle).replaces(nearest).then_some(t)
        };
        // A scene of one mesh (the common case for big meshes) needs no top-level tree.
        match self.items.len() {
            1 => {
                test(0, t_max);
            }
            _ => {
                self.top.traverse(Portable, ray, t_min, t_max, test);
            }
        }
    }

    /// [`World::intersect_with`] for up to [`PACKET`] rays at once (the camera's rays of a block
    /// of pixels), each hit exactly as that ray alone would find it: `hits[i]` is ray i's. The
    /// primitives counted for `-stats` are those the packet's rays test, which are not always
    /// those each would test alone (a ray's limit falls in another order).
    pub fn intersect_packet_with<T: Tally>(
        &self,
        rays: &[Ray],
        t_min: f32,
        hits: &mut [Option<Hit>],
        tally: &mut T,
    ) {
        assert!(rays.len() <= PACKET && hits.len() == rays.len());
        if self.grid.is_some() {
            for (ray, hit) in rays.iter().zip(hits) {
                *hit = self.intersect_with(ray, t_min, tally);
            }
            return;
        }
        let mut nearest: [Option<Nearest>; PACKET] = [None; PACKET];
        for (ray, nearest) in rays.iter().zip(&mut nearest) {
            tally.tested(self.planes.len() as u32);
            *nearest = self.nearest_plane(ray, t_min);
        }
        let nearest = &mut nearest[..rays.len()];
        match self.items.len() {
            0 => {}
            1 => self.packet_item(0, None, rays, t_min, nearest, tally),
            _ => {
                for (part, around) in CoherentParts::new(Portable, rays) {
                    let (rays, nearest) = (&rays[part.clone()], &mut nearest[part]);
                    let Some(around) = around else {
                        for (ray, nearest) in rays.iter().zip(nearest.iter_mut()) {
                            self.nearest_item(ray, t_min, nearest, tally);
                        }
                        continue;
                    };
                    let start = nearest
                        .iter()
                        .map(search_limit)
                        .fold(f32::NEG_INFINITY, f32::max);
                    self.top.traverse_packet(
                        Portable,
                        &around,
                        t_min,
                        start,
                        |first, count, bounds| {
                            for item in first..first + count {
                                self.packet_item(item, Some(bounds), rays, t_min, nearest, tally);
                            }
                            nearest
                                .iter()
                                .map(search_limit)
                                .fold(f32::NEG_INFINITY, f32::max)
                        },
                    );
                }
            }
        }
        for ((ray, nearest), hit) in rays.iter().zip(nearest.iter()).zip(hits) {
            *hit = nearest.map(|n| self.hit(ray, n.t, n.found));
        }
    }

    /// Item `i` against the rays of a packet that meet `bounds` (its box in the top-level
    /// tree; `None` when there is no tree, and every ray tests it). A mesh is searched by the
    /// packet; a sphere ray by ray.
    fn packet_item<T: Tally>(
        &self,
        i: u32,
        bounds: Option<&Aabb>,
        rays: &[Ray],
        t_min: f32,
        nearest: &mut [Option<Nearest>],
        tally: &mut T,
    ) {
        let mut limits = [ASKS_NOTHING; PACKET];
        let limits = &mut limits[..rays.len()];
        for ((ray, nearest), limit) in rays.iter().zip(nearest.iter()).zip(limits.iter_mut()) {
            let t_max = search_limit(nearest);
            // A ray that misses the item's box never tests it.
            if bounds.is_none_or(|b| ray_meets_box(ray, b, t_min, t_max)) {
                *limit = t_max;
            }
        }
        let item = &self.items[i as usize];
        match *item {
            Item::Mesh {
                mesh, transform, ..
            } => {
                // Under a Transform, the packet is carried into the mesh's space ray by ray,
                // just as each ray alone would be; the bounds are then put around the carried
                // rays, and t still counts along the world's rays.
                let mut carried: ArrayVec<Ray, PACKET> = ArrayVec::new();
                let rays = match transform {
                    Item::WORLD_SPACE => rays,
                    t => {
                        let transform = &self.transforms[t as usize];
                        carried.extend(rays.iter().map(|ray| transform.ray_to_object(ray)));
                        &carried[..]
                    }
                };
                let mut found = [None; PACKET];
                let found = &mut found[..rays.len()];
                self.meshes[mesh as usize].intersect_packet(rays, t_min, limits, found, tally);
                for (found, nearest) in found.iter().zip(nearest) {
                    if let Some((t, triangle)) = *found {
                        Nearest::item(t, i, triangle).replaces(nearest);
                    }
                }
            }
            _ => {
                for ((ray, nearest), &limit) in rays.iter().zip(nearest).zip(limits.iter()) {
                    if limit == ASKS_NOTHING {
                        continue;
                    }
                    if let Some((t, triangle)) = self.intersect_item(i, ray, t_min, limit, tally) {
                        Nearest::item(t, i, triangle).replaces(nearest);
                    }
                }
            }
        }
    }

    /// The grid's search: cells in the ray's order, every primitive of each, until the nearest
    /// hit so far lies within the cell just searched (a hit further on may be beaten by a
    /// primitive of a later cell, so it is kept but not trusted yet).
    fn grid_nearest<T: Tally>(
        &self,
        grid: &Grid,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
    ) {
        let t_max = search_limit(nearest);
        let mut local = None;
        grid.walk(ray, t_min, t_max, |cell| {
            tally.cell();
            for p in cell.primitives {
                tally.tested(1);
                let limit = search_limit(nearest);
                if let Some(t) = self.intersect_primitive(p, ray, t_min, limit, &mut local) {
                    Nearest::item(t, p.item, p.triangle).replaces(nearest);
                }
            }
            if nearest.is_some_and(|n| n.t <= cell.t_exit) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
    }

    /// One primitive of the grid: a sphere, or one triangle of a mesh, in its item's space.
    /// `local` keeps the ray in the space of the item tested last (with its watertight frame):
    /// a cell's primitives mostly belong to one mesh, so most tests need no new transform.
    #[inline]
    fn intersect_primitive(
        &self,
        p: &Primitive,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        local: &mut Option<LocalRay>,
    ) -> Option<f32> {
        let item = &self.items[p.item as usize];
        let here = match local {
            Some(l) if l.item == p.item => l,
            _ => {
                let ray = self.ray_into(item, ray);
                local.insert(LocalRay {
                    item: p.item,
                    frame: ray.to_ray_space(),
                    ray,
                })
            }
        };
        match *item {
            Item::Sphere { sphere, .. } => intersect_sphere(&here.ray, &sphere, t_min, t_max),
            Item::Mesh { mesh, .. } => {
                let triangle = &self.meshes[mesh as usize].triangles()[p.triangle as usize];
                intersect_triangle_in(&here.frame, &here.ray, triangle, t_min, t_max)
            }
        }
    }

    /// Whether anything at all is hit with t in [t_min, t_max]: the shadow ray's question,
    /// answered at the first hit found rather than the nearest.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_with(ray, t_min, t_max, &mut ())
    }

    /// [`World::occluded`], counting primitives tested and grid cells entered.
    #[inline]
    pub fn occluded_with<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        for (plane, _) in &self.planes {
            tally.tested(1);
            if intersect_plane(ray, plane, t_min, t_max).is_some() {
                return true;
            }
        }
        if let Some(grid) = &self.grid {
            let mut blocked = false;
            let mut local = None;
            grid.walk(ray, t_min, t_max, |cell| {
                tally.cell();
                for p in cell.primitives {
                    tally.tested(1);
                    if self
                        .intersect_primitive(p, ray, t_min, t_max, &mut local)
                        .is_some()
                    {
                        blocked = true;
                        return ControlFlow::Break(());
                    }
                }
                ControlFlow::Continue(())
            });
            return blocked;
        }
        let mut test = |i: u32| {
            let item = &self.items[i as usize];
            self.in_item_space(item, ray, |local| {
                self.occluded_local(item, local, t_min, t_max, tally)
            })
        };
        match self.items.len() {
            0 => false,
            1 => test(0),
            _ => self.top.occluded(Portable, ray, t_min, t_max, test),
        }
    }

    /// [`World::occluded`] without either tree: its brute-force twin.
    pub fn occluded_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.intersect_brute_force(ray, t_min)
            .is_some_and(|hit| hit.t <= t_max)
    }

    #[inline(always)]
    fn occluded_local<T: Tally>(
        &self,
        item: &Item,
        local: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        match *item {
            Item::Sphere { sphere, .. } => {
                tally.tested(1);
                intersect_sphere(local, &sphere, t_min, t_max).is_some()
            }
            Item::Mesh { mesh, .. } => {
                self.meshes[mesh as usize].occluded(local, t_min, t_max, tally)
            }
        }
    }

    /// The same answer as [`World::intersect`] without either tree: the brute-force twin.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        let mut nearest = self.nearest_plane(ray, t_min);
        for (i, item) in self.items.iter().enumerate() {
            let t_max = search_limit(&nearest);
            let local = self.ray_into(item, ray);
            let hit = match *item {
                Item::Sphere { sphere, .. } => {
                    intersect_sphere(&local, &sphere, t_min, t_max).map(|t| (t, 0))
                }
                Item::Mesh { mesh, .. } => {
                    self.meshes[mesh as usize].intersect_brute_force(&local, t_min, t_max)
                }
            };
            if let Some((t, triangle)) = hit {
                Nearest::item(t, i as u32, triangle).replaces(&mut nearest);
            }
        }
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// Planes have no bounds for a tree to hold: each ray tests them all, before the trees, so
    /// that a hit on a plane shortens the search through them.
    #[inline(always)]
    fn nearest_plane(&self, ray: &Ray, t_min: f32) -> Option<Nearest> {
        let mut nearest = None;
        for (i, (plane, _)) in self.planes.iter().enumerate() {
            let t_max = search_limit(&nearest);
            if let Some(t) = intersect_plane(ray, plane, t_min, t_max) {
                Nearest::plane(t, i as u32).replaces(&mut nearest);
            }
        }
        nearest
    }

    #[inline(always)]
    fn intersect_item<T: Tally>(
        &self,
        i: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        let item = &self.items[i as usize];
        self.in_item_space(item, ray, |local| {
            self.intersect_local(item, local, t_min, t_max, tally)
        })
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
        let (normal, material) = match found {
            Found::Plane(i) => {
                let (plane, material) = self.planes[i as usize];
                (plane.normal, material)
            }
            Found::Item { item, triangle } => {
                let item = &self.items[item as usize];
                let (object_normal, material) = match *item {
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
                };
                let normal = match item.transform() {
                    Item::WORLD_SPACE => unit_normal(object_normal),
                    i => self.transforms[i as usize].normal_to_world(object_normal),
                };
                // A surface too small for f32 to give it a direction (a sphere of radius 1e-7
                // hit dead centre): it faces the ray, so that no NaN reaches a pixel.
                let normal = if normal == Vec3A::ZERO {
                    -ray.direction.normalize()
                } else {
                    normal
                };
                (normal, material)
            }
        };
        Hit {
            t,
            normal,
            material,
        }
    }

    /// What the world holds and what its trees take, for `-stats`.
    pub fn stats(&self) -> WorldStats {
        let mut stats = WorldStats {
            meshes: self.meshes.len(),
            planes: self.planes.len(),
            nodes: self.top.node_count(),
            acceleration_bytes: self.top.size_in_bytes(),
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
