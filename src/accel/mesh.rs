//! A triangle mesh with its own BVH, built once per mesh file and shared by every placement of
//! it.

use glam::{Vec3, Vec3A};

use super::bvh::{CoherentParts, PACKET, PartLanes};
use super::{Bvh, LeafSize, Tally};
use crate::geometry::{
    Aabb, Ray, TRIANGLE_BLOCK, Triangle8, TriangleRayLanes, intersect_triangle, triangle_normal,
};
use crate::simd::{Wide, WithWide, dispatch};

/// A triangle mesh and its BVH. The triangles are stored in the order of the BVH's leaves, and
/// again packed eight to a block per leaf, for the SIMD test the traversal uses.
#[derive(Debug, Clone, Default)]
pub struct TriangleMesh {
    triangles: Vec<[Vec3; 3]>,
    blocks: Vec<Triangle8>,
    bvh: Bvh,
}

/// Puts `items` in `order` (`items[k]` becomes what was `items[order[k]]`) where they lie,
/// following each cycle of the permutation: no second array of fresh pages.
fn permute<T: Copy>(items: &mut [T], order: &[u32]) {
    let mut placed = vec![false; items.len()];
    for start in 0..items.len() {
        if placed[start] {
            continue;
        }
        let first = items[start];
        let mut k = start;
        loop {
            placed[k] = true;
            let from = order[k] as usize;
            if from == start {
                items[k] = first;
                break;
            }
            items[k] = items[from];
            k = from;
        }
    }
}

impl TriangleMesh {
    /// Builds the BVH. Returns the mesh and, for per-triangle data the caller keeps, the input
    /// index of each stored triangle.
    pub fn new(triangles: Vec<[Vec3; 3]>) -> (TriangleMesh, Vec<u32>) {
        let box_of = |i: usize| {
            let t = triangles[i];
            Aabb::from_points(&[t[0].into(), t[1].into(), t[2].into()])
        };
        let (mut bvh, order) = Bvh::build_with(triangles.len(), box_of, LeafSize::TRIANGLES);
        let mut triangles = triangles;
        permute(&mut triangles, &order);
        // Made at its length (each leaf in blocks of its own, as below): room for a guess would
        // take pages of its own, too big for those the build has just given back.
        let block_count = bvh
            .leaf_sizes()
            .map(|size| size.div_ceil(TRIANGLE_BLOCK as u32) as usize)
            .sum();
        let mut blocks = Vec::with_capacity(block_count);
        bvh.map_leaves(|first, count| {
            let start = blocks.len() as u32;
            for chunk_start in (first..first + count).step_by(TRIANGLE_BLOCK) {
                let end = (chunk_start + TRIANGLE_BLOCK as u32).min(first + count);
                blocks.push(Triangle8::new(
                    &triangles[chunk_start as usize..end as usize],
                    chunk_start,
                ));
            }
            (start, blocks.len() as u32 - start)
        });
        (
            TriangleMesh {
                triangles,
                blocks,
                bvh,
            },
            order,
        )
    }

    /// The triangles in the tree's leaf order, which the indices of hits count in.
    pub fn triangles(&self) -> &[[Vec3; 3]] {
        &self.triangles
    }

    /// The tree over the triangles; its leaves point at blocks of eight.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The box around every triangle, in the mesh's own space; empty for a mesh of none.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The nearest triangle hit in [t_min, t_max]: its t and index. Of triangles hit at the
    /// same t, the one stored first wins, here and in the brute-force search alike, so that both
    /// name the same triangle (and so the same normal) on a shared edge.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        self.intersect_with(ray, t_min, t_max, &mut ())
    }

    /// [`TriangleMesh::intersect`], counting the triangles tested.
    #[inline(always)]
    pub fn intersect_with<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        dispatch(Nearest(self.query(ray, t_min, t_max, tally)))
    }

    /// [`TriangleMesh::intersect_with`] for up to [`PACKET`] rays at once, with the same results:
    /// `limits[i]` is ray i's t_max, or [`ASKS_NOTHING`] for a ray that is not to search;
    /// `found[i]` becomes its hit, if it has one within it, and `limits[i]` that hit's t. Rays
    /// that share their directions' signs (neighbouring camera rays, mostly) walk the tree
    /// together; others each alone.
    #[inline(always)]
    pub fn intersect_packet<T: Tally>(
        &self,
        rays: &[Ray],
        t_min: f32,
        limits: &mut [f32],
        found: &mut [Option<(f32, u32)>],
        tally: &mut T,
    ) {
        assert!(rays.len() <= PACKET && limits.len() == rays.len() && found.len() == rays.len());
        found.fill(None);
        dispatch(PacketNearest {
            mesh: self,
            rays,
            t_min,
            limits,
            found,
            tally,
        });
    }

    /// [`TriangleMesh::occluded`] for up to [`PACKET`] rays at once, with the same answers: ray
    /// i asks about [`t_min[i]`, `limits[i]`], or nothing where `limits[i]` is
    /// [`ASKS_NOTHING`]; where it is hit, `blocked[i]` becomes true and `limits[i]`
    /// [`ASKS_NOTHING`]. Rays that share their directions' signs (shadow rays toward one light
    /// from neighbouring points) walk the tree together; others each alone.
    #[inline(always)]
    pub fn occluded_packet<T: Tally>(
        &self,
        rays: &[Ray],
        t_min: &[f32],
        limits: &mut [f32],
        blocked: &mut [bool],
        tally: &mut T,
    ) {
        let n = rays.len();
        assert!(n <= PACKET && t_min.len() == n && limits.len() == n && blocked.len() == n);
        dispatch(PacketAnyHit {
            mesh: self,
            rays,
            t_min,
            limits,
            blocked,
            tally,
        });
    }

    /// Whether any triangle is hit in [t_min, t_max].
    #[inline(always)]
    pub fn occluded<T: Tally>(&self, ray: &Ray, t_min: f32, t_max: f32, tally: &mut T) -> bool {
        dispatch(AnyHit(self.query(ray, t_min, t_max, tally)))
    }

    fn query<'a, T>(
        &'a self,
        ray: &'a Ray,
        t_min: f32,
        t_max: f32,
        tally: &'a mut T,
    ) -> Query<'a, T> {
        Query {
            mesh: self,
            ray,
            t_min,
            t_max,
            tally,
        }
    }

    /// Every triangle, one at a time, no tree: the brute-force twin the BVH is tested against.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut best: Option<(f32, u32)> = None;
        for (i, triangle) in self.triangles.iter().enumerate() {
            let limit = best.map_or(t_max, |(t, _)| t);
            if let Some(t) = intersect_triangle(ray, triangle, t_min, limit) {
                // A tie keeps the earlier triangle.
                if best.is_none_or(|(best_t, _)| t < best_t) {
                    best = Some((t, i as u32));
                }
            }
        }
        best
    }

    /// Bytes of geometry (triangles and their blocks) and of the tree.
    pub fn size_in_bytes(&self) -> (usize, usize) {
        (
            std::mem::size_of_val(&self.triangles[..]) + std::mem::size_of_val(&self.blocks[..]),
            self.bvh.size_in_bytes(),
        )
    }

    /// The front side of triangle `i` (the one its vertices run counter-clockwise from), in the
    /// mesh's own space and not normalised.
    pub fn normal(&self, i: u32) -> Vec3A {
        triangle_normal(&self.triangles[i as usize])
    }
}

/// A search of one mesh, before the lanes to do it with are chosen.
struct Query<'a, T> {
    mesh: &'a TriangleMesh,
    ray: &'a Ray,
    t_min: f32,
    t_max: f32,
    tally: &'a mut T,
}

impl<T: Tally> Query<'_, T> {
    /// The nearest hit, with the lanes of `wide`.
    #[inline(always)]
    fn nearest<K: Wide>(mut self, wide: K) -> Option<(f32, u32)> {
        let mut found = None;
        // Set up on the first leaf: many rays that enter a mesh's box never reach one.
        let mut lanes: Option<TriangleRayLanes<K>> = None;
        let (ray, t_min) = (self.ray, self.t_min);
        self.mesh.bvh.traverse(
            wide,
            ray,
            t_min,
            self.t_max,
            #[inline(always)]
            |block, t_max| {
                let hit = self.hit_block(wide, &mut lanes, block, t_max)?;
                keep_nearer(&mut found, hit)
            },
        );
        found
    }

    /// Whether anything is hit, with the lanes of `wide`.
    #[inline(always)]
    fn any_hit<K: Wide>(mut self, wide: K) -> bool {
        let mut lanes: Option<TriangleRayLanes<K>> = None;
        let (ray, t_min, t_max) = (self.ray, self.t_min, self.t_max);
        self.mesh.bvh.occluded(
            wide,
            ray,
            t_min,
            t_max,
            #[inline(always)]
            |block| self.hit_block(wide, &mut lanes, block, t_max).is_some(),
        )
    }

    /// The nearest hit in leaf block `block` up to `t_max`: its t and triangle. The ray's lanes
    /// are set up on the first block it reaches.
    #[inline(always)]
    fn hit_block<K: Wide>(
        &mut self,
        wide: K,
        lanes: &mut Option<TriangleRayLanes<K>>,
        block: u32,
        t_max: f32,
    ) -> Option<(f32, u32)> {
        self.mesh
            .hit_block(wide, self.ray, lanes, block, self.t_min, t_max, self.tally)
    }
}

impl TriangleMesh {
    /// The nearest hit of `ray` in leaf block `block` with t_min <= t <= t_max: its t and
    /// triangle. The ray's lanes are set up on the first block it reaches.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn hit_block<K: Wide, T: Tally>(
        &self,
        wide: K,
        ray: &Ray,
        lanes: &mut Option<TriangleRayLanes<K>>,
        block: u32,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        let block = &self.blocks[block as usize];
        tally.tested(block.len());
        // (Not `get_or_insert_with`: it is not inlined, which leaves the AVX set-up outlined.)
        let lanes = match lanes {
            Some(lanes) => lanes,
            None => lanes.insert(TriangleRayLanes::new(wide, ray)),
        };
        let (t, lane) = block.intersect(wide, ray, lanes, t_min, t_max)?;
        Some((t, block.index(lane)))
    }

    /// [`TriangleMesh::hit_block`] for two rays, ray k over [`t_min[k]`, `t_max[k]`]: at once
    /// on a path that pairs, one after the other on others.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn hit_block_pair<K: Wide, T: Tally>(
        &self,
        wide: K,
        rays: [&Ray; 2],
        lanes: [&mut Option<TriangleRayLanes<K>>; 2],
        block: u32,
        t_min: [f32; 2],
        t_max: [f32; 2],
        tally: &mut T,
    ) -> [Option<(f32, u32)>; 2] {
        let block = &self.blocks[block as usize];
        tally.tested(2 * block.len());
        let [a, b] = lanes;
        let a = match a {
            Some(lanes) => lanes,
            None => a.insert(TriangleRayLanes::new(wide, rays[0])),
        };
        let b = match b {
            Some(lanes) => lanes,
            None => b.insert(TriangleRayLanes::new(wide, rays[1])),
        };
        let found = match block.intersect_pair(wide, rays, [a, b], t_min, t_max) {
            Some(found) => found,
            None => [
                block.intersect(wide, rays[0], a, t_min[0], t_max[0]),
                block.intersect(wide, rays[1], b, t_min[1], t_max[1]),
            ],
        };
        found.map(|hit| hit.map(|(t, lane)| (t, block.index(lane))))
    }
}

/// Keeps `hit` if it is nearer than `found`, or as near and of a lower triangle: a rule that
/// does not depend on the order triangles are met in, so that a ray searched alone, in a
/// packet, or by brute force names the same triangle. Returns the new limit if kept.
#[inline(always)]
fn keep_nearer(found: &mut Option<(f32, u32)>, (t, index): (f32, u32)) -> Option<f32> {
    if found.is_some_and(|(best, best_index)| t > best || t == best && index > best_index) {
        return None;
    }
    *found = Some((t, index));
    Some(t)
}

/// A packet ray's limit that asks nothing of it (it missed the mesh's box, say): not "below
/// t_min", since the orthographic camera's t_min is already -∞.
pub const ASKS_NOTHING: f32 = f32::NEG_INFINITY;

/// The closest-hit search of a packet of rays, as work for [`dispatch`]: `limits[i]` is ray
/// i's t_max on the way in, and on the way out the t of its hit if it found one (in `found`).
struct PacketNearest<'a, T> {
    mesh: &'a TriangleMesh,
    rays: &'a [Ray],
    t_min: f32,
    limits: &'a mut [f32],
    found: &'a mut [Option<(f32, u32)>],
    tally: &'a mut T,
}

impl<T: Tally> WithWide for PacketNearest<'_, T> {
    type Output = ();

    #[inline(always)]
    fn run<K: Wide>(self, wide: K) {
        let PacketNearest {
            mesh,
            rays,
            t_min,
            limits,
            found,
            tally,
        } = self;
        let mut lanes: [Option<TriangleRayLanes<K>>; PACKET] = std::array::from_fn(|_| None);
        for (part, around) in CoherentParts::new(wide, rays) {
            let offset = part.start;
            let (rays, limits, found) = (
                &rays[part.clone()],
                &mut limits[part.clone()],
                &mut found[part],
            );
            let Some(around) = around else {
                for ((ray, limit), found) in rays.iter().zip(limits.iter_mut()).zip(found) {
                    if *limit != ASKS_NOTHING {
                        *found = mesh.query(ray, t_min, *limit, tally).nearest(wide);
                        if let Some((t, _)) = *found {
                            *limit = t;
                        }
                    }
                }
                continue;
            };
            let start = limits.iter().fold(ASKS_NOTHING, |a, &b| a.max(b));
            if start == ASKS_NOTHING {
                continue;
            }
            // Set up on the first leaf: most packets of a big scene reach none.
            let mut part_lanes = None;
            mesh.bvh.traverse_packet(
                wide,
                &around,
                t_min,
                start,
                #[inline(always)]
                |first, count, bounds| {
                    let part_lanes = match &mut part_lanes {
                        Some(lanes) => lanes,
                        None => part_lanes.insert(PartLanes::new(rays, |_| t_min)),
                    };
                    let mut meeting = part_lanes.meeting(wide, bounds, limits, ASKS_NOTHING);
                    while meeting != 0 {
                        let i = meeting.trailing_zeros() as usize;
                        meeting &= meeting - 1;
                        // Two rays at a time against each block, where the path pairs.
                        if K::PAIRS && meeting != 0 {
                            let j = meeting.trailing_zeros() as usize;
                            meeting &= meeting - 1;
                            for block in first..first + count {
                                let (low, high) = lanes.split_at_mut(offset + j);
                                let pair = [&mut low[offset + i], &mut high[0]];
                                let hits = mesh.hit_block_pair(
                                    wide,
                                    [&rays[i], &rays[j]],
                                    pair,
                                    block,
                                    [t_min; 2],
                                    [limits[i], limits[j]],
                                    tally,
                                );
                                for (k, hit) in [i, j].into_iter().zip(hits) {
                                    if let Some(t) =
                                        hit.and_then(|hit| keep_nearer(&mut found[k], hit))
                                    {
                                        limits[k] = t;
                                    }
                                }
                            }
                            continue;
                        }
                        for block in first..first + count {
                            let hit = mesh.hit_block(
                                wide,
                                &rays[i],
                                &mut lanes[offset + i],
                                block,
                                t_min,
                                limits[i],
                                tally,
                            );
                            if let Some(t) = hit.and_then(|hit| keep_nearer(&mut found[i], hit)) {
                                limits[i] = t;
                            }
                        }
                    }
                    limits.iter().fold(ASKS_NOTHING, |a, &b| a.max(b))
                },
            );
        }
    }
}

/// The occlusion search of a packet of rays, as work for [`dispatch`]: ray i asks about
/// [`t_min[i]`, `limits[i]`]; a ray found blocked asks nothing more.
struct PacketAnyHit<'a, T> {
    mesh: &'a TriangleMesh,
    rays: &'a [Ray],
    t_min: &'a [f32],
    limits: &'a mut [f32],
    blocked: &'a mut [bool],
    tally: &'a mut T,
}

impl<T: Tally> WithWide for PacketAnyHit<'_, T> {
    type Output = ();

    #[inline(always)]
    fn run<K: Wide>(self, wide: K) {
        let PacketAnyHit {
            mesh,
            rays,
            t_min,
            limits,
            blocked,
            tally,
        } = self;
        let mut lanes: [Option<TriangleRayLanes<K>>; PACKET] = std::array::from_fn(|_| None);
        for (part, around) in CoherentParts::new(wide, rays) {
            let offset = part.start;
            let (rays, t_min, limits, blocked) = (
                &rays[part.clone()],
                &t_min[part.clone()],
                &mut limits[part.clone()],
                &mut blocked[part],
            );
            let Some(around) = around else {
                for (i, ray) in rays.iter().enumerate() {
                    if limits[i] != ASKS_NOTHING
                        && mesh.query(ray, t_min[i], limits[i], tally).any_hit(wide)
                    {
                        blocked[i] = true;
                        limits[i] = ASKS_NOTHING;
                    }
                }
                continue;
            };
            let start = limits.iter().fold(ASKS_NOTHING, |a, &b| a.max(b));
            if start == ASKS_NOTHING {
                continue;
            }
            // The packet's box tests start from the earliest of its rays' starts.
            let least = t_min.iter().fold(f32::INFINITY, |a, &b| a.min(b));
            let mut part_lanes = None;
            mesh.bvh.traverse_packet(
                wide,
                &around,
                least,
                start,
                #[inline(always)]
                |first, count, bounds| {
                    let part_lanes = match &mut part_lanes {
                        Some(lanes) => lanes,
                        None => part_lanes.insert(PartLanes::new(rays, |i| t_min[i])),
                    };
                    let mut meeting = part_lanes.meeting(wide, bounds, limits, ASKS_NOTHING);
                    while meeting != 0 {
                        let i = meeting.trailing_zeros() as usize;
                        meeting &= meeting - 1;
                        // (A loop, not `any`: its closure is not always inlined.)
                        for block in first..first + count {
                            let lanes = &mut lanes[offset + i];
                            let (ray, limit) = (&rays[i], limits[i]);
                            if mesh
                                .hit_block(wide, ray, lanes, block, t_min[i], limit, tally)
                                .is_some()
                            {
                                blocked[i] = true;
                                limits[i] = ASKS_NOTHING;
                                break;
                            }
                        }
                    }
                    limits.iter().fold(ASKS_NOTHING, |a, &b| a.max(b))
                },
            );
        }
    }
}

/// A closest-hit query, as work for [`dispatch`].
struct Nearest<'a, T>(Query<'a, T>);

impl<T: Tally> WithWide for Nearest<'_, T> {
    type Output = Option<(f32, u32)>;

    #[inline(always)]
    fn run<K: Wide>(self, wide: K) -> Self::Output {
        self.0.nearest(wide)
    }
}

/// An occlusion query, as work for [`dispatch`].
struct AnyHit<'a, T>(Query<'a, T>);

impl<T: Tally> WithWide for AnyHit<'_, T> {
    type Output = bool;

    #[inline(always)]
    fn run<K: Wide>(self, wide: K) -> bool {
        self.0.any_hit(wide)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::test_uniform;

    #[test]
    fn a_permutation_puts_each_item_where_the_order_says() {
        // Cycles of one, two and five, and the identity.
        let order = [0_u32, 2, 1, 4, 5, 6, 7, 3];
        let mut items: Vec<u32> = (10..18).collect();
        permute(&mut items, &order);
        let expected: Vec<u32> = order.iter().map(|&i| 10 + i).collect();
        assert_eq!(items, expected);
        let mut items: Vec<u32> = (0..4).collect();
        permute(&mut items, &[0, 1, 2, 3]);
        assert_eq!(items, [0, 1, 2, 3]);
    }
    use crate::simd::Portable;
    use glam::Vec3A;

    /// A bumpy closed surface of `n` × `n` × 2 triangles, with shared edges and vertices.
    fn bumpy_sphere(n: usize) -> Vec<[Vec3; 3]> {
        let point = |i: usize, j: usize| {
            let (theta, phi) = (
                std::f32::consts::PI * i as f32 / n as f32,
                std::f32::consts::TAU * j as f32 / n as f32,
            );
            let r = 1.0 + 0.1 * (5.0 * phi).sin() * (3.0 * theta).cos();
            Vec3::new(
                r * theta.sin() * phi.cos(),
                r * theta.cos(),
                r * theta.sin() * phi.sin(),
            )
        };
        let mut triangles = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (point(i, j), point(i, j + 1));
                let (c, d) = (point(i + 1, j), point(i + 1, j + 1));
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            }
        }
        triangles
    }

    /// Rays from all around, many of them through the mesh's vertices and edges.
    fn rays() -> Vec<Ray> {
        let mut seed = 99_u64;
        let mut next = move || test_uniform(&mut seed) * 2.0 - 1.0;
        let vertices = bumpy_sphere(24);
        (0..4000)
            .map(|k| {
                let origin = Vec3A::new(next(), next(), next()) * 3.0;
                let target = if k % 4 == 0 {
                    Vec3A::from(vertices[k % vertices.len()][0])
                } else {
                    Vec3A::new(next(), next(), next())
                };
                Ray::new(origin, (target - origin).normalize())
            })
            .collect()
    }

    #[test]
    fn the_avx_and_portable_paths_find_the_same_hits_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        let Some(avx) = crate::simd::Avx::detect() else {
            return;
        };
        #[cfg(not(target_arch = "x86_64"))]
        let avx = Portable;
        let (mesh, _) = TriangleMesh::new(bumpy_sphere(24));
        let mut hits = 0;
        for ray in rays() {
            let portable = mesh
                .query(&ray, 0.0, f32::INFINITY, &mut ())
                .nearest(Portable);
            let wide = mesh.query(&ray, 0.0, f32::INFINITY, &mut ()).nearest(avx);
            assert_eq!(
                portable.map(|(t, i)| (t.to_bits(), i)),
                wide.map(|(t, i)| (t.to_bits(), i))
            );
            // The same t as every triangle tried (which of two triangles tied at one t is
            // named may differ: the tree can prune a box whose entry rounds past the tie).
            let brute = mesh.intersect_brute_force(&ray, 0.0, f32::INFINITY);
            assert_eq!(portable.map(|(t, _)| t), brute.map(|(t, _)| t));
            for t_max in [0.5, 2.0, 4.0] {
                assert_eq!(
                    mesh.query(&ray, 1e-4, t_max, &mut ()).any_hit(Portable),
                    mesh.query(&ray, 1e-4, t_max, &mut ()).any_hit(avx)
                );
            }
            hits += usize::from(portable.is_some());
        }
        assert!(hits > 1000, "only {hits} hits");
    }

    type Hits = Option<(f32, u32)>;

    #[test]
    fn shadow_packets_answer_what_each_ray_answers_alone_on_both_paths() {
        let (mesh, _) = TriangleMesh::new(bumpy_sphere(24));
        let mut blocked_rays = 0;
        for (k, centre) in rays().iter().enumerate().take(400) {
            // Shadow rays from a patch of points near the surface along one direction (toward a
            // sun), or from one patch toward one point (a lamp), each over a range of its own.
            let spread = [0.0, 1e-3, 3e-2, 0.4][k % 4];
            let across = centre.direction.any_orthonormal_vector();
            let up = centre.direction.cross(across);
            let lamp = centre.origin + centre.direction * 6.0;
            let packet: Vec<Ray> = (0..PACKET)
                .map(|i| {
                    let offset = ((i % 8) as f32 * across + (i / 8) as f32 * up) * spread;
                    let origin = centre.origin + centre.direction * 2.0 + offset;
                    if k % 8 < 4 {
                        Ray::new(origin, centre.direction)
                    } else {
                        Ray::new(origin, lamp - origin)
                    }
                })
                .collect();
            let t_min: Vec<f32> = (0..PACKET).map(|i| [0.0, 1e-3, 0.2][i % 3]).collect();
            let start: Vec<f32> = (0..PACKET)
                .map(|i| [f32::INFINITY, 0.9, ASKS_NOTHING, 0.3][i % 4])
                .collect();
            let alone: Vec<bool> = packet
                .iter()
                .enumerate()
                .map(|(i, ray)| {
                    start[i] != ASKS_NOTHING
                        && mesh
                            .query(ray, t_min[i], start[i], &mut ())
                            .any_hit(Portable)
                })
                .collect();
            let run = |job: &dyn Fn(&mut [f32], &mut [bool])| {
                let (mut limits, mut blocked) = (start.clone(), vec![false; PACKET]);
                job(&mut limits, &mut blocked);
                assert_eq!(blocked, alone, "packet around {centre:?}");
                for i in 0..PACKET {
                    let asks_still = start[i] != ASKS_NOTHING && !alone[i];
                    assert_eq!(limits[i] != ASKS_NOTHING, asks_still);
                }
            };
            run(&|limits, blocked| mesh.occluded_packet(&packet, &t_min, limits, blocked, &mut ()));
            run(&|limits, blocked| {
                PacketAnyHit {
                    mesh: &mesh,
                    rays: &packet,
                    t_min: &t_min,
                    limits,
                    blocked,
                    tally: &mut (),
                }
                .run(Portable)
            });
            blocked_rays += alone.iter().filter(|&&b| b).count();
        }
        assert!(blocked_rays > 1000, "only {blocked_rays} blocked");
    }

    #[test]
    fn packets_find_what_each_ray_finds_alone_on_both_paths() {
        let (mesh, _) = TriangleMesh::new(bumpy_sphere(24));
        let mut hits = 0;
        for (k, centre) in rays().iter().enumerate().take(400) {
            // An 8×8 packet of rays around each test ray, from one point or along one direction,
            // some so wide that their directions' signs differ (and the packet is searched in
            // parts).
            let spread = [0.0, 1e-3, 3e-2, 0.4][k % 4];
            let across = centre.direction.any_orthonormal_vector();
            let up = centre.direction.cross(across);
            let packet: Vec<Ray> = (0..PACKET)
                .map(|i| {
                    let offset = ((i % 8) as f32 * across + (i / 8) as f32 * up) * spread;
                    if k % 8 < 4 {
                        Ray::new(centre.origin, centre.direction + offset)
                    } else {
                        Ray::new(centre.origin + offset, centre.direction)
                    }
                })
                .collect();
            // Some rays start with a limit (a nearer hit elsewhere), one has none to give.
            let start: Vec<f32> = (0..PACKET)
                .map(|i| [f32::INFINITY, 3.0, f32::NEG_INFINITY, 2.5][i % 4])
                .collect();
            let alone: Vec<_> = packet
                .iter()
                .zip(&start)
                .map(|(ray, &t_max)| {
                    if t_max < 0.0 {
                        return None;
                    }
                    mesh.query(ray, 0.0, t_max, &mut ()).nearest(Portable)
                })
                .collect();
            let run = |job: &dyn Fn(&mut [f32], &mut [Hits])| {
                let (mut limits, mut found) = (start.clone(), vec![None; PACKET]);
                job(&mut limits, &mut found);
                assert_eq!(found, alone, "packet around {centre:?}");
            };
            run(&|limits, found| mesh.intersect_packet(&packet, 0.0, limits, found, &mut ()));
            run(&|limits, found| {
                PacketNearest {
                    mesh: &mesh,
                    rays: &packet,
                    t_min: 0.0,
                    limits,
                    found,
                    tally: &mut (),
                }
                .run(Portable)
            });
            hits += alone.iter().flatten().count();
        }
        assert!(hits > 1000, "only {hits} hits");
    }
}
