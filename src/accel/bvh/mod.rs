//! An eight-wide bounding volume hierarchy: a binned-SAH binary tree, collapsed so that each
//! node holds up to eight children whose boxes one ray tests at once with SIMD (AVX, or two SSE
//! halves: see [`crate::simd`]), and a closest-hit traversal that visits hit children nearest
//! first and drops any whose entry lies beyond the nearest hit found so far.
//!
//! The tree knows only boxes; what sits in a leaf is the caller's business, tested through a
//! closure, so triangles, spheres and whole instances all use the same code, monomorphised.

use std::cmp::Ordering;

use arrayvec::ArrayVec;
use glam::{BVec3A, Vec3A, Vec4};
use rayon::prelude::*;

use crate::geometry::{Aabb, Ray};
use crate::simd::{Lanes, Wide};

/// Children a node holds.
const WIDTH: usize = 8;

/// Eight children's boxes in structure-of-arrays form, and what each child is: an inner node
/// (`count == 0`, `child` its index) or a leaf (`child` its first primitive). 256 bytes, four
/// cache lines, aligned to them.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
struct Node {
    /// `bounds[0]` the minima, `bounds[1]` the maxima, each as x, y, z lanes.
    bounds: [[[f32; WIDTH]; 3]; 2],
    child: [u32; WIDTH],
    count: [u8; WIDTH],
    /// Bit k set when lane k holds a child.
    lanes: u32,
}

const _: () = assert!(std::mem::size_of::<Node>() == 256);

impl Node {
    const EMPTY: Node = Node {
        bounds: [[[0.0; WIDTH]; 3]; 2],
        child: [0; WIDTH],
        count: [0; WIDTH],
        lanes: 0,
    };

    /// The lanes that hold a leaf (a child with primitives of its own), read from the node as
    /// it is now, so that the node can be changed while they are visited.
    fn leaf_lanes(&self) -> impl Iterator<Item = usize> + use<> {
        let (lanes, count) = (self.lanes, self.count);
        (0..WIDTH).filter(move |&lane| lanes & (1 << lane) != 0 && count[lane] > 0)
    }

    fn set_lane(&mut self, lane: usize, b: Aabb, child: u32, count: u8) {
        for axis in 0..3 {
            self.bounds[0][axis][lane] = b.min[axis];
            self.bounds[1][axis][lane] = b.max[axis];
        }
        self.child[lane] = child;
        self.count[lane] = count;
        self.lanes |= 1 << lane;
    }

    fn lane_box(&self, lane: usize) -> Aabb {
        Aabb {
            min: Vec3A::new(
                self.bounds[0][0][lane],
                self.bounds[0][1][lane],
                self.bounds[0][2][lane],
            ),
            max: Vec3A::new(
                self.bounds[1][0][lane],
                self.bounds[1][1][lane],
                self.bounds[1][2][lane],
            ),
        }
    }
}

/// A ray as the eight-wide box test wants it: every component in all lanes, and which of min
/// and max is the near side on each axis.
struct BoxRayLanes<K: Wide> {
    origin: [K::F; 3],
    inv_direction: [K::F; 3],
    near_side: [usize; 3],
}

impl<K: Wide> BoxRayLanes<K> {
    #[inline(always)]
    fn new(wide: K, ray: &Ray) -> Self {
        let side = |d: f32| usize::from(d < 0.0);
        BoxRayLanes {
            origin: [
                wide.splat(ray.origin.x),
                wide.splat(ray.origin.y),
                wide.splat(ray.origin.z),
            ],
            inv_direction: [
                wide.splat(ray.inv_direction.x),
                wide.splat(ray.inv_direction.y),
                wide.splat(ray.inv_direction.z),
            ],
            near_side: [0, 1, 2].map(|a| side(ray.inv_direction[a])),
        }
    }
}

/// A child waiting to be visited, with the t at which the ray enters its box.
#[derive(Debug, Clone, Copy)]
struct Pending {
    child: u32,
    count: u32,
    t: f32,
}

/// An eight-wide BVH over boxes; the default is the tree over nothing, which every ray misses.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    bounds: Option<Aabb>,
}

const BINS: usize = 16;
/// Nodes with fewer primitives than this are binned along one axis.
const SMALL_NODE: usize = 128;
/// How many primitives a leaf holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LeafSize {
    /// Nodes of at most this many are never split (one block of triangles costs about what a
    /// node visit does).
    pub min_split: u32,
    /// Leaves never grow past this, whatever the SAH says.
    pub max: u32,
}

impl LeafSize {
    /// Up to eight triangles a leaf, tested as one block of eight.
    pub const TRIANGLES: LeafSize = LeafSize {
        min_split: 8,
        max: 8,
    };
    /// One instance a leaf: each is a whole tree of its own, best visited nearest first.
    pub const INSTANCES: LeafSize = LeafSize {
        min_split: 1,
        max: 1,
    };
}
/// Beyond this depth of the binary tree, splits are by count: a bound on the depth, and so on the
/// traversal stack, for any input.
const MAX_SAH_DEPTH: usize = 48;
/// Each eight-wide level pushes at most seven children; the binary tree is at most
/// MAX_SAH_DEPTH + 32 deep, and the wide one no deeper.
const STACK: usize = (WIDTH - 1) * (MAX_SAH_DEPTH + 32) + 1;
/// The cost of a node visit relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

mod build;
mod packet;

use build::*;
pub use packet::*;

impl Bvh {
    /// Builds over the given primitive boxes. Returns the tree and the order the primitives must
    /// be stored in for it: leaf ranges index that order, `order[i]` is the input index.
    pub fn build(boxes: &[Aabb], leaf: LeafSize) -> (Bvh, Vec<u32>) {
        Bvh::build_with(boxes.len(), |i| boxes[i], leaf)
    }

    /// [`Bvh::build`] over `count` primitives whose boxes `box_of` gives (on rayon's threads):
    /// no array of the boxes beside the build's own.
    pub fn build_with(
        count: usize,
        box_of: impl Fn(usize) -> Aabb + Sync,
        leaf: LeafSize,
    ) -> (Bvh, Vec<u32>) {
        if count == 0 {
            return (Bvh::default(), Vec::new());
        }
        let mut prims: Vec<Prim> = (0..count)
            .into_par_iter()
            .map(|i| Prim::new(box_of(i), i as u32))
            .collect();
        let binary = build_binary(&mut prims, leaf);
        let order = prims.iter().map(Prim::index).collect();
        // Given back before the wide nodes are made, which can then take its pages.
        drop(prims);
        let nodes = collapse(&binary);
        let bvh = Bvh {
            nodes,
            bounds: Some(binary[0].bounds()),
        };
        (bvh, order)
    }

    /// Replaces each leaf's range `(first, count)` with the range `f` gives, so that a caller
    /// can store a leaf's primitives in its own blocks. Counts must stay at most 255.
    pub(crate) fn map_leaves(&mut self, mut f: impl FnMut(u32, u32) -> (u32, u32)) {
        for node in &mut self.nodes {
            for lane in node.leaf_lanes() {
                let (first, count) = f(node.child[lane], node.count[lane] as u32);
                assert!((1..=255).contains(&count), "a leaf of {count} blocks");
                node.child[lane] = first;
                node.count[lane] = count as u8;
            }
        }
    }

    /// How many primitives each leaf holds.
    pub(crate) fn leaf_sizes(&self) -> impl Iterator<Item = u32> + '_ {
        self.nodes
            .iter()
            .flat_map(|node| node.leaf_lanes().map(|lane| u32::from(node.count[lane])))
    }

    /// How many eight-wide nodes the tree has.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The box around every primitive; [`Aabb::EMPTY`] for a tree over nothing.
    pub fn bounds(&self) -> Aabb {
        self.bounds.unwrap_or(Aabb::EMPTY)
    }

    /// Memory the nodes take.
    pub fn size_in_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
    }

    /// Whether `hit` reports any primitive whose box the ray meets within [t_min, t_max]. An
    /// occlusion query: children in no particular order, and the search ends at the first hit.
    #[inline(always)]
    pub fn occluded<K: Wide>(
        &self,
        wide: K,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        mut hit: impl FnMut(u32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let lanes = BoxRayLanes::new(wide, ray);
        // (first child or primitive, primitive count); a count of 0 is an inner node.
        let mut stack: ArrayVec<(u32, u32), STACK> = ArrayVec::new();
        let mut current = (0, 0);
        loop {
            let (child, count) = current;
            if count == 0 {
                let node = &self.nodes[child as usize];
                let (_, mut mask) = hit_lanes(wide, node, &lanes, t_min, t_max);
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    stack.push((node.child[lane], u32::from(node.count[lane])));
                }
            } else {
                // A loop, not `any`: its `try_fold` is not always inlined, and the triangle
                // test behind it then calls each vector instruction out of line.
                for i in child..child + count {
                    if hit(i) {
                        return true;
                    }
                }
            }
            match stack.pop() {
                Some(next) => current = next,
                None => return false,
            }
        }
    }

    /// Closest-hit traversal. `hit(i, t_max)` tests leaf entry `i` (a primitive in build order,
    /// or whatever the builder of the tree made the leaves point at, such as a block of triangles)
    /// and returns its t if it is nearer than `t_max`. Returns the final t_max.
    ///
    /// One function, long: the traversal stack, the eight-wide box test and the nearest-first
    /// ordering share registers in the per-ray hot loop; helpers that are not inlined cost it
    /// measurably (benches/trace.rs), and those that are read no better.
    #[inline(always)]
    pub fn traverse<K: Wide>(
        &self,
        wide: K,
        ray: &Ray,
        t_min: f32,
        mut t_max: f32,
        mut hit: impl FnMut(u32, f32) -> Option<f32>,
    ) -> f32 {
        if self.nodes.is_empty() {
            return t_max;
        }
        let lanes = BoxRayLanes::new(wide, ray);
        // Not an array: initialising a few kilobytes for every ray cost more than the traversal.
        let mut stack: ArrayVec<Pending, STACK> = ArrayVec::new();
        let mut current = Pending {
            child: 0,
            count: 0,
            t: t_min,
        };
        loop {
            if current.count == 0 {
                let node = &self.nodes[current.child as usize];
                let (entry, mut mask) = hit_lanes(wide, node, &lanes, t_min, t_max);
                let lane_child = |lane: usize| Pending {
                    child: node.child[lane],
                    count: node.count[lane] as u32,
                    t: entry[lane],
                };
                // One child hit is the common case deep in the tree: straight down, no sorting.
                match mask.count_ones() {
                    0 => {}
                    1 => {
                        current = lane_child(mask.trailing_zeros() as usize);
                        continue;
                    }
                    2 => {
                        let a = mask.trailing_zeros() as usize;
                        let b = (mask & (mask - 1)).trailing_zeros() as usize;
                        let (near, far) = if entry[a] <= entry[b] { (a, b) } else { (b, a) };
                        stack.push(lane_child(far));
                        current = lane_child(near);
                        continue;
                    }
                    _ => {}
                }
                // The hit children, nearest first (insertion into at most eight).
                let mut hits = [current; WIDTH];
                let mut n = 0;
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let next = lane_child(lane);
                    let mut k = n;
                    while k > 0 && hits[k - 1].t > next.t {
                        hits[k] = hits[k - 1];
                        k -= 1;
                    }
                    hits[k] = next;
                    n += 1;
                }
                if n > 0 {
                    for &far in hits[1..n].iter().rev() {
                        stack.push(far);
                    }
                    current = hits[0];
                    continue;
                }
            } else {
                for i in current.child..current.child + current.count {
                    if let Some(t) = hit(i, t_max) {
                        t_max = t;
                    }
                }
            }
            // The nearest postponed child that no hit found since has ruled out.
            loop {
                let Some(next) = stack.pop() else {
                    return t_max;
                };
                if next.t <= t_max {
                    current = next;
                    break;
                }
            }
        }
    }
}

/// What the eight-wide box test asks of a ray, or of a packet's bounds: on an axis, for each of
/// a node's boxes, when the near plane is crossed and when the far one is (for a packet, no
/// later and no earlier than any of its rays).
trait Slabs<K: Wide> {
    fn slab(&self, wide: K, node: &Node, axis: usize) -> (K::F, K::F);
}

impl<K: Wide> Slabs<K> for BoxRayLanes<K> {
    #[inline(always)]
    fn slab(&self, wide: K, node: &Node, axis: usize) -> (K::F, K::F) {
        let near = wide.load(&node.bounds[self.near_side[axis] & 1][axis]);
        let far = wide.load(&node.bounds[(self.near_side[axis] ^ 1) & 1][axis]);
        (
            (near - self.origin[axis]) * self.inv_direction[axis],
            (far - self.origin[axis]) * self.inv_direction[axis],
        )
    }
}

/// A ray (or a packet's bounds) against a node's eight boxes: entry distances, and a bit mask of
/// the lanes hit.
#[inline(always)]
fn hit_lanes<K: Wide>(
    wide: K,
    node: &Node,
    ray: &impl Slabs<K>,
    t_min: f32,
    t_max: f32,
) -> ([f32; WIDTH], u32) {
    let (nx, fx) = ray.slab(wide, node, 0);
    let (ny, fy) = ray.slab(wide, node, 1);
    let (nz, fz) = ray.slab(wide, node, 2);
    let entry = nx.max(ny).max(nz.max(wide.splat(t_min)));
    let exit = fx.min(fy).min(fz.min(wide.splat(t_max)));
    let mask = entry.le(exit) & node.lanes;
    (entry.to_array(), mask)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::test_uniform;
    use crate::simd::Portable;

    fn unit_box_at(x: f32, y: f32, z: f32) -> Aabb {
        let c = Vec3A::new(x, y, z);
        Aabb {
            min: c - 0.25,
            max: c + 0.25,
        }
    }

    /// One thread builds the tree in one piece, several build its top's parts apart and lay
    /// them out after: the same tree and the same order either way.
    #[test]
    fn one_thread_builds_the_tree_that_several_build() {
        let mut seed = 11;
        let mut next = move || test_uniform(&mut seed) * 100.0;
        // Enough boxes that the top of the tree is built in parts on several threads.
        let boxes: Vec<Aabb> = (0..3 * PARALLEL_MIN)
            .map(|_| {
                let size = Vec3A::splat(next() * 0.01);
                let corner = Vec3A::new(next(), next(), next());
                Aabb {
                    min: corner,
                    max: corner + size,
                }
            })
            .collect();
        let build_on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| Bvh::build(&boxes, LeafSize::TRIANGLES))
        };
        let (one, several) = (build_on(1), build_on(3));
        assert!(one.0.node_count() > 1000);
        assert!(one == several, "one thread built another tree than three");
    }

    /// The numbers kept in a box's fourth lanes come back whole, whatever their bits read as a
    /// float (zero, subnormal, infinite, quiet or signalling NaN), and the box reads without
    /// them.
    #[test]
    fn a_box_keeps_the_numbers_packed_beside_it_whole() {
        let b = unit_box_at(1.0, -2.0, 3.0);
        let patterns = [
            0,
            1,
            69_450,
            0x7F80_0000,
            0x7F80_0001,
            0x7FC0_0000,
            0xFF80_0001,
            u32::MAX,
        ];
        for n in patterns {
            let prim = Prim::new(b, n);
            assert_eq!((prim.index(), prim.bounds()), (n, b), "{n:#x}");
            let mut node = BinaryNode::new(b, n, 7);
            assert_eq!((node.first(), node.count(), node.bounds()), (n, 7, b));
            node.set_range(3, n);
            assert_eq!((node.first(), node.count(), node.bounds()), (3, n, b));
            // Arithmetic on the box sees only its three coordinates.
            assert_eq!(centre(&prim.bounds()), Vec3A::new(2.0, -4.0, 6.0));
            assert_eq!(node.bounds().half_area(), b.half_area());
        }
        assert_eq!(BinaryNode::UNSET.bounds(), Aabb::EMPTY);
        assert_eq!(
            (BinaryNode::UNSET.first(), BinaryNode::UNSET.count()),
            (0, 0)
        );
    }

    /// Every primitive is in exactly one leaf, and every lane's box holds what is below it.
    fn check_structure(bvh: &Bvh, order: &[u32], boxes: &[Aabb]) {
        let mut seen = vec![0; boxes.len()];
        let mut pending = vec![(0usize, bvh.bounds())];
        while let Some((i, outer)) = pending.pop() {
            let node = bvh.nodes[i];
            for lane in 0..WIDTH {
                if node.lanes & (1 << lane) == 0 {
                    continue;
                }
                let b = node.lane_box(lane);
                // Lanes are padded, so a child may stick out of its parent by the padding.
                assert_eq!(padded(padded(outer)).union(b), padded(padded(outer)));
                let (child, count) = (node.child[lane], node.count[lane] as u32);
                if count > 0 {
                    assert!(count <= LeafSize::TRIANGLES.max);
                    for k in child..child + count {
                        let prim = order[k as usize] as usize;
                        seen[prim] += 1;
                        assert_eq!(b.union(boxes[prim]), b);
                    }
                } else {
                    pending.push((child as usize, b));
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }

    #[test]
    fn every_primitive_lands_in_one_leaf() {
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| unit_box_at((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32))
            .collect();
        let (bvh, order) = Bvh::build(&boxes, LeafSize::TRIANGLES);
        check_structure(&bvh, &order, &boxes);
        assert!(bvh.node_count() > 25);
    }

    #[test]
    fn a_tree_built_in_parallel_is_whole_and_finds_the_closest_box() {
        // Enough boxes that the top of the tree is built by several rayon tasks.
        let mut seed = 12345u64;
        let mut next = move || test_uniform(&mut seed) * 100.0;
        let boxes: Vec<Aabb> = (0..3 * PARALLEL_MIN)
            .map(|_| unit_box_at(next(), next(), next()))
            .collect();
        let (bvh, order) = Bvh::build(&boxes, LeafSize::TRIANGLES);
        check_structure(&bvh, &order, &boxes);
        for _ in 0..200 {
            let origin = Vec3A::new(next(), next(), next()) * 2.0 - 50.0;
            let ray = Ray::new(origin, (Vec3A::splat(50.0) - origin).normalize());
            let closest = boxes
                .iter()
                .filter_map(|b| b.hit(&ray, 0.0, f32::INFINITY))
                .reduce(f32::min);
            let t = bvh.traverse(Portable, &ray, 0.0, f32::INFINITY, |i, t_max| {
                boxes[order[i as usize] as usize]
                    .hit(&ray, 0.0, t_max)
                    .filter(|&t| t < t_max)
            });
            assert_eq!(Some(t).filter(|t| t.is_finite()), closest);
        }
    }

    #[test]
    fn identical_boxes_still_split_into_small_leaves() {
        let boxes = vec![unit_box_at(1.0, 2.0, 3.0); 100];
        let (bvh, order) = Bvh::build(&boxes, LeafSize::TRIANGLES);
        check_structure(&bvh, &order, &boxes);
    }

    #[test]
    fn traversal_finds_the_closest_box_hit() {
        let boxes: Vec<Aabb> = (0..50).map(|i| unit_box_at(0.0, 0.0, i as f32)).collect();
        let (bvh, order) = Bvh::build(&boxes, LeafSize::TRIANGLES);
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 100.0), -Vec3A::Z);
        let mut closest = None;
        let t = bvh.traverse(Portable, &ray, 0.0, f32::INFINITY, |i, t_max| {
            let prim = order[i as usize];
            let t = boxes[prim as usize].hit(&ray, 0.0, t_max)?;
            closest = Some(prim);
            Some(t)
        });
        assert_eq!(closest, Some(49));
        assert_eq!(t, 100.0 - 49.25);
    }

    #[test]
    fn a_part_tests_a_box_against_each_ray_as_the_ray_alone_would() {
        let mut seed = 7_u64;
        let mut next = move || test_uniform(&mut seed) * 2.0 - 1.0;
        let mut met = 0;
        for k in 0..2000 {
            // Rays from around a point along directions of one sign per axis (one part), some
            // with a zero component (a reciprocal of ±f32::MAX), against boxes near and far,
            // flat ones and points included.
            let base = Vec3A::new(next(), next(), next()) * 4.0;
            let centre = Vec3A::new(next(), next(), next()) * 6.0;
            let half = Vec3A::new(next(), next(), next()).abs() * [0.0, 0.5, 3.0][k % 3];
            // Toward the box, give or take, so that about half the rays meet it.
            let toward = centre - base;
            let sign = toward.signum();
            let len = [64, 61, 9, 1][k % 4];
            let rays: Vec<Ray> = (0..len)
                .map(|i| {
                    let wobble = Vec3A::new(next(), next(), next()).abs() * 0.3;
                    let mut d = (toward.abs() * (1.0 - 0.15) + wobble * toward.length()) * sign;
                    if i % 7 == 3 {
                        d.x = 0.0_f32.copysign(sign.x);
                    }
                    Ray::new(base + Vec3A::new(next(), next(), next()) * 0.3, d)
                })
                .collect();
            let b = Aabb {
                min: centre - half,
                max: centre + half,
            };
            let t_min: Vec<f32> = (0..len)
                .map(|i| [0.0, f32::NEG_INFINITY, 0.5, 2.0][(i + k) % 4])
                .collect();
            let limits: Vec<f32> = (0..len)
                .map(|i| [f32::INFINITY, f32::NEG_INFINITY, 3.0, 0.25, 9.0][(i * 3 + k) % 5])
                .collect();
            let lanes = PartLanes::new(&rays, |i| t_min[i]);
            let meeting = lanes.meeting(Portable, &b, &limits, f32::NEG_INFINITY);
            for (i, ray) in rays.iter().enumerate() {
                let alone =
                    limits[i] != f32::NEG_INFINITY && ray_meets_box(ray, &b, t_min[i], limits[i]);
                assert_eq!(
                    meeting >> i & 1 == 1,
                    alone,
                    "ray {i} of {ray:?} against {b:?}"
                );
                met += usize::from(alone);
            }
            assert_eq!(meeting.checked_shr(len as u32).unwrap_or(0), 0);
        }
        assert!(met > 5000, "only {met} rays met their boxes");
    }

    #[test]
    fn an_empty_tree_is_never_entered() {
        let (bvh, _) = Bvh::build(&[], LeafSize::TRIANGLES);
        let ray = Ray::new(Vec3A::ZERO, Vec3A::Z);
        let t = bvh.traverse(
            Portable,
            &ray,
            f32::NEG_INFINITY,
            f32::INFINITY,
            |_, _| unreachable!(),
        );
        assert_eq!(t, f32::INFINITY);
    }
}
