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

/// A corner of a box with a number kept beside it, in the fourth lane that a `Vec3A` leaves
/// unused: how the build's primitives and binary nodes carry their indices in 32 bytes rather
/// than 48, in its two largest arrays.
#[derive(Debug, Clone, Copy)]
struct Corner(Vec4);

impl Corner {
    fn new(point: Vec3A, number: u32) -> Corner {
        Corner(point.extend(f32::from_bits(number)))
    }

    /// The corner, its fourth lane cleared: a number's bits read as a float are mostly a
    /// subnormal number, and arithmetic on those is slow even in a lane whose result is unused.
    #[inline(always)]
    fn point(self) -> Vec3A {
        Vec3A::from_vec4(self.0.with_w(0.0))
    }

    #[inline(always)]
    fn number(self) -> u32 {
        self.0.w.to_bits()
    }

    fn set_number(&mut self, number: u32) {
        self.0.w = f32::from_bits(number);
    }
}

/// A binary node during the build: a leaf holds `first .. first + count` of the build order,
/// an inner node's children are `first` and `first + 1`; `first` is kept beside the box's
/// lower corner, `count` beside its upper one.
#[derive(Debug, Clone, Copy)]
struct BinaryNode {
    min: Corner,
    max: Corner,
}

impl BinaryNode {
    fn new(bounds: Aabb, first: u32, count: u32) -> BinaryNode {
        BinaryNode {
            min: Corner::new(bounds.min, first),
            max: Corner::new(bounds.max, count),
        }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min.point(),
            max: self.max.point(),
        }
    }

    #[inline(always)]
    fn first(&self) -> u32 {
        self.min.number()
    }

    /// How many primitives a leaf holds; 0 for an inner node.
    #[inline(always)]
    fn count(&self) -> u32 {
        self.max.number()
    }

    fn set_range(&mut self, first: u32, count: u32) {
        self.min.set_number(first);
        self.max.set_number(count);
    }

    /// The node of a part whose nodes after its root now start at `rest_start`.
    fn moved(&self, rest_start: usize) -> BinaryNode {
        let mut node = *self;
        if node.count() == 0 {
            node.set_range((rest_start + node.first() as usize - 1) as u32, 0);
        }
        node
    }

    /// A place held for a node laid out later.
    const UNSET: BinaryNode = BinaryNode {
        min: Corner(Vec4::new(f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0)),
        max: Corner(Vec4::new(
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
            0.0,
        )),
    };
}

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

/// The most rays searched together as one packet (the camera's rays of an 8×8 block of pixels).
pub const PACKET: usize = 64;

/// Bounds over a packet of rays whose directions have the same sign on each axis: for each
/// axis, the least and greatest origin coordinate and reciprocal of the direction, in all lanes.
///
/// A box test over these bounds is conservative by construction, not by a margin: each ray's
/// own test computes `(plane - origin) * inv_direction`, and both the subtraction and the
/// multiplication, rounded, are monotone in each operand (for an operand of fixed sign). So no
/// ray's product is below the least of the products at the bounds' corners (a corner may pair
/// one ray's origin with another's direction), which is what the packet's box test computes:
/// no ray can meet a box, or meet it sooner, than the bounds say.
pub struct PacketBounds<K: Wide> {
    /// Per axis, the origin bound that gives the earliest near-plane t: the greatest origin
    /// where the direction is positive, the least where it is negative.
    near_origin: [K::F; 3],
    /// Per axis, the origin bound that gives the latest far-plane t.
    far_origin: [K::F; 3],
    /// Per axis, the least and greatest reciprocal direction.
    inv: [[K::F; 3]; 2],
    /// Per axis, which of a box's bounds (0: min, 1: max) is its near side for every ray.
    near_side: [usize; 3],
}

impl<K: Wide> PacketBounds<K> {
    /// The bounds over `rays`; `None` when there are none, or when their directions differ in
    /// sign on some axis (rays on either side of an axis plane meet boxes in different orders).
    #[inline(always)]
    pub fn new(wide: K, rays: &[Ray]) -> Option<Self> {
        let first = rays.first()?;
        let negative = first.inv_direction.cmplt(Vec3A::ZERO);
        let (mut origin_lo, mut origin_hi) = (first.origin, first.origin);
        let (mut inv_lo, mut inv_hi) = (first.inv_direction, first.inv_direction);
        for ray in &rays[1..] {
            if ray.inv_direction.cmplt(Vec3A::ZERO) != negative {
                return None;
            }
            origin_lo = origin_lo.min(ray.origin);
            origin_hi = origin_hi.max(ray.origin);
            inv_lo = inv_lo.min(ray.inv_direction);
            inv_hi = inv_hi.max(ray.inv_direction);
        }
        // Where a direction is negative, the near plane is the far side of the origin bounds.
        let near_origin = Vec3A::select(negative, origin_lo, origin_hi);
        let far_origin = Vec3A::select(negative, origin_hi, origin_lo);
        let negative = negative.bitmask();
        Some(PacketBounds {
            near_origin: splat3(wide, near_origin),
            far_origin: splat3(wide, far_origin),
            inv: [splat3(wide, inv_lo), splat3(wide, inv_hi)],
            near_side: [0, 1, 2].map(|axis| ((negative >> axis) & 1) as usize),
        })
    }
}

/// Each of `v`'s coordinates in all lanes (not `map` with a closure: that is not inlined, which
/// would leave AVX instructions behind a call).
#[inline(always)]
fn splat3<K: Wide>(wide: K, v: Vec3A) -> [K::F; 3] {
    [wide.splat(v.x), wide.splat(v.y), wide.splat(v.z)]
}

/// A packet's rays in parts whose directions agree in sign, each with its bounds: the whole
/// packet where it can be; else its halves (a block's top and bottom four rows), and theirs,
/// down to parts of [`SMALLEST_PART`]; a part that still disagrees comes with `None`, to be
/// searched ray by ray.
pub struct CoherentParts<'r, K: Wide> {
    wide: K,
    rays: &'r [Ray],
    pending: ArrayVec<std::ops::Range<usize>, 8>,
}

/// Parts of a packet are not split below this many rays.
pub const SMALLEST_PART: usize = 16;

impl<'r, K: Wide> CoherentParts<'r, K> {
    /// The parts of `rays`, in the rays' order.
    #[inline(always)]
    pub fn new(wide: K, rays: &'r [Ray]) -> Self {
        let mut pending = ArrayVec::new();
        pending.push(0..rays.len());
        CoherentParts {
            wide,
            rays,
            pending,
        }
    }
}

impl<K: Wide> Iterator for CoherentParts<'_, K> {
    type Item = (std::ops::Range<usize>, Option<PacketBounds<K>>);

    #[inline(always)]
    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let part = self.pending.pop()?;
            if part.is_empty() {
                continue;
            }
            if let Some(bounds) = PacketBounds::new(self.wide, &self.rays[part.clone()]) {
                return Some((part, Some(bounds)));
            }
            if part.len() <= SMALLEST_PART {
                return Some((part, None));
            }
            let middle = part.start + part.len() / 2;
            self.pending.push(middle..part.end);
            self.pending.push(part.start..middle);
        }
    }
}

/// A child waiting to be visited by a packet: lane `lane` of node `node`, entered at `t` at the
/// earliest.
#[derive(Debug, Clone, Copy)]
struct PacketPending {
    node: u32,
    lane: u32,
    t: f32,
}

impl Bvh {
    /// Closest-hit traversal for a packet of rays at once, under the bounds `packet` puts
    /// around them: each node's eight boxes are tested once for the whole packet, nearest
    /// first. `t_max` is the greatest of the rays' limits; `leaf(first, count, bounds)` tests
    /// the leaf's entries against each ray that meets the leaf's box `bounds` (see
    /// [`ray_meets_box`]) and returns the new greatest limit. Returns the final one.
    ///
    /// Every ray reaches every leaf its own [`Bvh::traverse`] would reach with the same limit.
    /// Its limit may fall in another order here, so the hits are the same given an order-free
    /// rule for ties and boxes whose entry never rounds past a hit inside them (they are padded
    /// by a few ulps: see `padded`).
    #[inline(always)]
    pub fn traverse_packet<K: Wide>(
        &self,
        wide: K,
        packet: &PacketBounds<K>,
        t_min: f32,
        mut t_max: f32,
        mut leaf: impl FnMut(u32, u32, &Aabb) -> f32,
    ) -> f32 {
        if self.nodes.is_empty() {
            return t_max;
        }
        let mut stack: ArrayVec<PacketPending, STACK> = ArrayVec::new();
        let mut open = Some(0_u32);
        loop {
            if let Some(index) = open.take() {
                let node = &self.nodes[index as usize];
                let (entry, mut mask) = hit_lanes(wide, node, packet, t_min, t_max);
                // The hit children, farthest first, so that the nearest is popped first.
                let mut hits = [PacketPending {
                    node: index,
                    lane: 0,
                    t: 0.0,
                }; WIDTH];
                let mut n = 0;
                while mask != 0 {
                    let lane = mask.trailing_zeros();
                    mask &= mask - 1;
                    let next = PacketPending {
                        node: index,
                        lane,
                        t: entry[lane as usize],
                    };
                    let mut k = n;
                    while k > 0 && hits[k - 1].t < next.t {
                        hits[k] = hits[k - 1];
                        k -= 1;
                    }
                    hits[k] = next;
                    n += 1;
                }
                stack.extend(hits[..n].iter().copied());
            }
            let next = loop {
                let Some(next) = stack.pop() else {
                    return t_max;
                };
                if next.t <= t_max {
                    break next;
                }
            };
            let node = &self.nodes[next.node as usize];
            let lane = next.lane as usize;
            let (child, count) = (node.child[lane], u32::from(node.count[lane]));
            if count == 0 {
                open = Some(child);
            } else {
                t_max = leaf(child, count, &node.lane_box(lane));
            }
        }
    }
}

/// Whether one ray meets a box within [t_min, t_max], by the very arithmetic of the eight-wide
/// test in [`Bvh::traverse`] (one lane of it), so that a packet's rays test a leaf's contents
/// exactly when each ray alone would.
#[inline(always)]
pub fn ray_meets_box(ray: &Ray, b: &Aabb, t_min: f32, t_max: f32) -> bool {
    let slab = |axis: usize| {
        let inv = ray.inv_direction[axis];
        let (near, far) = if inv < 0.0 {
            (b.max[axis], b.min[axis])
        } else {
            (b.min[axis], b.max[axis])
        };
        (
            (near - ray.origin[axis]) * inv,
            (far - ray.origin[axis]) * inv,
        )
    };
    // `Lanes::max` and `min`, grouped as in `hit_lanes`: the same answer even for a NaN.
    let max = |a: f32, b: f32| if a > b { a } else { b };
    let min = |a: f32, b: f32| if a < b { a } else { b };
    let ((nx, fx), (ny, fy), (nz, fz)) = (slab(0), slab(1), slab(2));
    let entry = max(max(nx, ny), max(nz, t_min));
    let exit = min(min(fx, fy), min(fz, t_max));
    entry <= exit
}

/// The rays of a packet's part (rays whose directions share their signs), eight to a set of
/// lanes, for testing a leaf's box against all of them at once: bit for bit
/// [`ray_meets_box`] for each, since every lane does its operations, in its order.
pub struct PartLanes {
    /// Per set of eight rays, per axis: their origins' coordinates.
    origin: [[[f32; 8]; 3]; PACKET / 8],
    /// Per set, per axis: their reciprocal directions.
    inv: [[[f32; 8]; 3]; PACKET / 8],
    /// Per set: their least t.
    t_min: [[f32; 8]; PACKET / 8],
    /// Per axis, which of a box's bounds is the near side for every ray (0: min, 1: max).
    near_side: [usize; 3],
    len: usize,
}

impl PartLanes {
    /// The lanes of `rays` (at most [`PACKET`], their directions of the same signs), ray i
    /// starting at `t_min(i)`.
    #[inline(always)]
    pub fn new(rays: &[Ray], t_min: impl Fn(usize) -> f32) -> PartLanes {
        debug_assert!(rays.len() <= PACKET);
        let mut lanes = PartLanes {
            origin: [[[0.0; 8]; 3]; PACKET / 8],
            inv: [[[0.0; 8]; 3]; PACKET / 8],
            t_min: [[0.0; 8]; PACKET / 8],
            near_side: [0, 1, 2].map(|axis| {
                rays.first()
                    .map_or(0, |ray| usize::from(ray.inv_direction[axis] < 0.0))
            }),
            len: rays.len(),
        };
        for (i, ray) in rays.iter().enumerate() {
            let (set, lane) = (i / 8, i % 8);
            for axis in 0..3 {
                lanes.origin[set][axis][lane] = ray.origin[axis];
                lanes.inv[set][axis][lane] = ray.inv_direction[axis];
            }
            lanes.t_min[set][lane] = t_min(i);
        }
        lanes
    }

    /// Bit i set where ray i asks (`limits[i]` is not `asks_nothing`) and meets `b` within
    /// [its t_min, `limits[i]`].
    ///
    /// (No closures or `map`: they are not always inlined, which leaves the vector
    /// instructions behind calls compiled without the path's features.)
    #[inline(always)]
    pub fn meeting<K: Wide>(&self, wide: K, b: &Aabb, limits: &[f32], asks_nothing: f32) -> u64 {
        let sides = [b.min, b.max];
        let mut near = [wide.splat(0.0); 3];
        let mut far = [wide.splat(0.0); 3];
        for axis in 0..3 {
            let side = self.near_side[axis];
            near[axis] = wide.splat(sides[side & 1][axis]);
            far[axis] = wide.splat(sides[(side ^ 1) & 1][axis]);
        }
        let mut meeting = 0;
        for set in 0..self.len.div_ceil(8) {
            let mut limit = [asks_nothing; 8];
            let mut asks = 0_u32;
            let end = self.len.min(set * 8 + 8);
            for lane in 0..end - set * 8 {
                let l = limits[set * 8 + lane];
                limit[lane] = l;
                asks |= u32::from(l != asks_nothing) << lane;
            }
            if asks == 0 {
                continue;
            }
            let origin = &self.origin[set];
            let inv = &self.inv[set];
            let (ox, oy, oz) = (
                wide.load(&origin[0]),
                wide.load(&origin[1]),
                wide.load(&origin[2]),
            );
            let (ix, iy, iz) = (wide.load(&inv[0]), wide.load(&inv[1]), wide.load(&inv[2]));
            let (nx, fx) = ((near[0] - ox) * ix, (far[0] - ox) * ix);
            let (ny, fy) = ((near[1] - oy) * iy, (far[1] - oy) * iy);
            let (nz, fz) = ((near[2] - oz) * iz, (far[2] - oz) * iz);
            let entry = nx.max(ny).max(nz.max(wide.load(&self.t_min[set])));
            let exit = fx.min(fy).min(fz.min(wide.load(&limit)));
            meeting |= u64::from(entry.le(exit) & asks) << (set * 8);
        }
        meeting
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

impl<K: Wide> Slabs<K> for PacketBounds<K> {
    #[inline(always)]
    fn slab(&self, wide: K, node: &Node, axis: usize) -> (K::F, K::F) {
        let [inv_lo, inv_hi] = &self.inv;
        let side = self.near_side[axis];
        let near = wide.load(&node.bounds[side & 1][axis]) - self.near_origin[axis];
        let far = wide.load(&node.bounds[(side ^ 1) & 1][axis]) - self.far_origin[axis];
        (
            (near * inv_lo[axis]).min(near * inv_hi[axis]),
            (far * inv_lo[axis]).max(far * inv_hi[axis]),
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

/// Centroids are kept doubled (min + max): the same order, one multiplication fewer.
fn centre(b: &Aabb) -> Vec3A {
    b.min + b.max
}

/// A primitive as the build sorts it: its box, with its index in the input kept beside the
/// lower corner.
#[derive(Debug, Clone, Copy)]
struct Prim {
    min: Corner,
    max: Vec3A,
}

impl Prim {
    fn new(bounds: Aabb, index: u32) -> Prim {
        Prim {
            min: Corner::new(bounds.min, index),
            max: bounds.max,
        }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min.point(),
            max: self.max,
        }
    }

    /// The primitive's index in the input.
    #[inline(always)]
    fn index(&self) -> u32 {
        self.min.number()
    }
}

/// The boxes of a range of primitives and of their (doubled) centroids.
#[derive(Debug, Clone, Copy)]
struct Extent {
    bounds: Aabb,
    centres: Aabb,
}

impl Extent {
    const EMPTY: Extent = Extent {
        bounds: Aabb::EMPTY,
        centres: Aabb::EMPTY,
    };

    fn of(prims: &[Prim]) -> Extent {
        prims.iter().fold(Extent::EMPTY, |e, p| {
            let b = p.bounds();
            Extent {
                bounds: e.bounds.union(b),
                centres: e.centres.grow(centre(&b)),
            }
        })
    }

    /// [`Extent::of`] on rayon's threads, for the whole input: the same boxes in any grouping.
    fn of_all(prims: &[Prim]) -> Extent {
        prims.par_chunks(PARALLEL_MIN).map(Extent::of).reduce(
            || Extent::EMPTY,
            |a, b| Extent {
                bounds: a.bounds.union(b.bounds),
                centres: a.centres.union(b.centres),
            },
        )
    }
}

/// Binary binned-SAH build; `prims` ends in leaf order. Node 0 is the root; an inner node's
/// children are `first` and `first + 1`. The top of the tree is built in parallel on rayon's
/// threads; the tree is the same whatever the number of threads.
fn build_binary(prims: &mut [Prim], leaf: LeafSize) -> Vec<BinaryNode> {
    let root = Extent::of_all(prims);
    // On one thread the parts would be built one after another all the same: the tree is
    // built as one part, in its own array, with no second array to lay parts out in (a
    // megabyte of fresh pages for a 100k-triangle mesh, at the peak of a one-thread run).
    if rayon::current_num_threads() == 1 {
        return build_sequential(prims, root, 0, 0, leaf);
    }
    let built = build_subtree(prims, root, 0, 0, leaf);
    // The parts built apart are laid out once, in one array made at its size: merged level by
    // level, every level was a copy of the nodes below it into fresh pages.
    let mut nodes = Vec::with_capacity(built.len());
    nodes.push(BinaryNode::UNSET);
    built.lay_out(&mut nodes, 0);
    nodes
}

/// Subtrees at least this large are split off to be built in parallel.
const PARALLEL_MIN: usize = 8192;

/// A subtree as built: one part built alone, or a node whose two sides were built in parallel.
enum Built {
    /// Its root at 0, each inner node's children at `first` and `first + 1` of this array.
    Alone(Vec<BinaryNode>),
    Split {
        bounds: Aabb,
        sides: Box<[Built; 2]>,
    },
}

impl Built {
    /// How many nodes it has.
    fn len(&self) -> usize {
        match self {
            Built::Alone(nodes) => nodes.len(),
            Built::Split { sides, .. } => 1 + sides[0].len() + sides[1].len(),
        }
    }

    /// Puts the root at `nodes[root]` (already there, to be filled) and the rest at the end of
    /// `nodes`: a node, then its two children side by side, then the rest of each side.
    fn lay_out(self, nodes: &mut Vec<BinaryNode>, root: usize) {
        match self {
            Built::Alone(part) => {
                // Node i > 0 of the part goes to rest_start + i - 1.
                let rest_start = nodes.len();
                nodes[root] = part[0].moved(rest_start);
                nodes.extend(part[1..].iter().map(|node| node.moved(rest_start)));
            }
            Built::Split { bounds, sides } => {
                let first = nodes.len();
                nodes[root] = BinaryNode::new(bounds, first as u32, 0);
                nodes.extend([BinaryNode::UNSET; 2]);
                let [left, right] = *sides;
                left.lay_out(nodes, first);
                right.lay_out(nodes, first + 1);
            }
        }
    }
}

/// The subtree over `prims` (which start at `offset` in the whole build order).
fn build_subtree(
    prims: &mut [Prim],
    extent: Extent,
    depth: usize,
    offset: usize,
    leaf: LeafSize,
) -> Built {
    if prims.len() < PARALLEL_MIN || depth >= MAX_SAH_DEPTH {
        return Built::Alone(build_sequential(prims, extent, depth, offset, leaf));
    }
    let Some((mid, left, right)) = split(prims, extent, depth, leaf) else {
        return Built::Alone(build_sequential(prims, extent, depth, offset, leaf));
    };
    let (left_prims, right_prims) = prims.split_at_mut(mid);
    let sides = rayon::join(
        || build_subtree(left_prims, left, depth + 1, offset, leaf),
        || build_subtree(right_prims, right, depth + 1, offset + mid, leaf),
    );
    Built::Split {
        bounds: extent.bounds,
        sides: Box::new(sides.into()),
    }
}

/// How a node is divided: the size of the left part and the extents of both parts, with `items`
/// partitioned in place; `None` for a leaf.
fn split(
    items: &mut [Prim],
    extent: Extent,
    depth: usize,
    leaf: LeafSize,
) -> Option<(usize, Extent, Extent)> {
    let count = items.len() as u32;
    let sah = if depth < MAX_SAH_DEPTH && count > leaf.min_split {
        sah_split(items, extent.bounds, extent.centres, leaf)
    } else {
        None
    };
    match sah {
        Some(split) => Some(split),
        None if count <= leaf.max => None,
        None => {
            // All centroids in one spot, or too deep: halve by count along the widest axis.
            let centres = extent.centres;
            let axis = (centres.max - centres.min).max_position();
            let half = items.len() / 2;
            items.select_nth_unstable_by(half, |a, b| {
                centre(&a.bounds())[axis].total_cmp(&centre(&b.bounds())[axis])
            });
            Some((half, Extent::of(&items[..half]), Extent::of(&items[half..])))
        }
    }
}

fn build_sequential(
    prims: &mut [Prim],
    extent: Extent,
    depth: usize,
    offset: usize,
    leaf: LeafSize,
) -> Vec<BinaryNode> {
    let mut nodes = Vec::with_capacity(prims.len() / 2 + 1);
    nodes.push(BinaryNode::new(extent.bounds, 0, 0));
    let mut pending = vec![(0usize, 0usize, prims.len(), depth, extent.centres)];
    while let Some((index, start, end, depth, centres)) = pending.pop() {
        let extent = Extent {
            bounds: nodes[index].bounds(),
            centres,
        };
        let Some((mid, left, right)) = split(&mut prims[start..end], extent, depth, leaf) else {
            nodes[index].set_range((offset + start) as u32, (end - start) as u32);
            continue;
        };
        let first = nodes.len();
        nodes[index].set_range(first as u32, 0);
        for side in [left, right] {
            nodes.push(BinaryNode::new(side.bounds, 0, 0));
        }
        pending.push((first + 1, start + mid, end, depth + 1, right.centres));
        pending.push((first, start, start + mid, depth + 1, left.centres));
    }
    nodes
}

/// The best binned-SAH split of `items`, partitioned in place: the size of the left part and
/// the extents of both parts; or `None` when keeping a leaf is cheaper (or no split separates
/// anything).
///
/// One function, long: binning, the sweep over the bins and the partition share the bins and
/// bounds, and this is the build's inner loop (every node of every mesh), measured in
/// performance.md; split, each part would hand its arrays to the next.
fn sah_split(
    items: &mut [Prim],
    bounds: Aabb,
    centres: Aabb,
    leaf: LeafSize,
) -> Option<(usize, Extent, Extent)> {
    let count = items.len();
    let (lo, extent) = (centres.min, centres.max - centres.min);
    let scale = Vec3A::splat(BINS as f32) / extent;
    // Bin k takes the centroids that round to k. The rounding is done by adding 2^23, which
    // leaves the integer in the low bits of the float: a saturating `as` cast, three per
    // primitive and level, was a fifth of the whole build.
    let top = Vec3A::splat((BINS - 1) as f32);
    const ROUND: f32 = (1 << 23) as f32;
    let bins_of = |c: Vec3A| -> [usize; 3] {
        let b = ((c - lo) * scale).clamp(Vec3A::ZERO, top) + ROUND;
        [b.x, b.y, b.z].map(|x| (x.to_bits() & 0xFF) as usize)
    };
    let bin_on = |c: Vec3A, axis: usize| -> usize {
        let b = ((c[axis] - lo[axis]) * scale[axis]).clamp(0.0, top.x) + ROUND;
        (b.to_bits() & 0xFF) as usize
    };
    // Small nodes are binned along their widest axis only: near the leaves a split along another
    // axis rarely wins, and the bottom levels hold most of the nodes.
    let widest = extent.max_position();
    let binnable = |axis: usize| extent[axis].partial_cmp(&0.0) == Some(Ordering::Greater);
    // (cost, axis, boundary, left box, right box)
    let mut best: Option<(f32, usize, usize, Aabb, Aabb)> = None;
    let mut consider = |axis: usize, bins: &Bins| {
        if let Some((cost, k, left, right)) = bins.best_boundary(count)
            && best.is_none_or(|best| cost < best.0)
        {
            best = Some((cost, axis, k, left, right));
        }
    };
    if count >= SMALL_NODE {
        let bin_all = |mut bins: [Bins; 3], items: &[Prim]| {
            for p in items {
                let b = p.bounds();
                let bin = bins_of(centre(&b));
                for (axis, axis_bins) in bins.iter_mut().enumerate() {
                    axis_bins.add(bin[axis], &b);
                }
            }
            bins
        };
        // The top nodes hold most of the primitives and are split before their subtrees can be
        // built in parallel, so their binning is shared out; unions and counts give the same
        // bins in any grouping.
        let bins = if count >= PARALLEL_MIN {
            items
                .par_chunks(PARALLEL_MIN / 2)
                .fold(|| [Bins::EMPTY; 3], bin_all)
                .reduce(
                    || [Bins::EMPTY; 3],
                    |a, b| [0, 1, 2].map(|axis| a[axis].merge(&b[axis])),
                )
        } else {
            bin_all([Bins::EMPTY; 3], items)
        };
        for (axis, axis_bins) in bins.iter().enumerate() {
            if binnable(axis) {
                consider(axis, axis_bins);
            }
        }
    } else if binnable(widest) {
        let mut bins = Bins::EMPTY;
        for p in items.iter() {
            let b = p.bounds();
            bins.add(bin_on(centre(&b), widest), &b);
        }
        consider(widest, &bins);
    }
    let (cost, axis, boundary, left_bounds, right_bounds) = best?;
    let split_cost = TRAVERSAL_COST + cost / bounds.half_area().max(f32::MIN_POSITIVE);
    if split_cost >= count as f32 && count as u32 <= leaf.max {
        return None;
    }
    let (mut left_centres, mut right_centres) = (Aabb::EMPTY, Aabb::EMPTY);
    let mut left = 0;
    // Without branches: which side a primitive falls on is a coin toss to the branch predictor,
    // and its misses were half the build's time. The same moves as the branching loop (a swap of
    // an item with itself moves nothing), so the same order and the same tree.
    for i in 0..count {
        let c = centre(&items[i].bounds());
        let goes_left = bin_on(c, axis) < boundary;
        let mask = BVec3A::splat(goes_left);
        left_centres = Aabb {
            min: Vec3A::select(mask, left_centres.min.min(c), left_centres.min),
            max: Vec3A::select(mask, left_centres.max.max(c), left_centres.max),
        };
        right_centres = Aabb {
            min: Vec3A::select(mask, right_centres.min, right_centres.min.min(c)),
            max: Vec3A::select(mask, right_centres.max, right_centres.max.max(c)),
        };
        items.swap(i, if goes_left { left } else { i });
        left += usize::from(goes_left);
    }
    let side = |bounds, centres| Extent { bounds, centres };
    Some((
        left,
        side(left_bounds, left_centres),
        side(right_bounds, right_centres),
    ))
}

/// The boxes and counts of one axis's bins.
#[derive(Clone, Copy)]
struct Bins {
    boxes: [Aabb; BINS],
    counts: [u32; BINS],
}

impl Bins {
    const EMPTY: Bins = Bins {
        boxes: [Aabb::EMPTY; BINS],
        counts: [0; BINS],
    };

    /// The bins of both `self`'s primitives and `other`'s.
    fn merge(&self, other: &Bins) -> Bins {
        let mut merged = *self;
        for k in 0..BINS {
            merged.boxes[k] = merged.boxes[k].union(other.boxes[k]);
            merged.counts[k] += other.counts[k];
        }
        merged
    }

    #[inline(always)]
    fn add(&mut self, bin: usize, b: &Aabb) {
        self.boxes[bin] = self.boxes[bin].union(*b);
        self.counts[bin] += 1;
    }

    /// The cheapest boundary between bins by the SAH: its cost (areas times counts, not yet
    /// divided by the parent's area), the first bin on its right, and both sides' boxes.
    fn best_boundary(&self, count: usize) -> Option<(f32, usize, Aabb, Aabb)> {
        // The right side of each boundary, swept from the right. Entries whose right side is
        // empty are never read: their left side holds everything, which is no split.
        let mut right_boxes = [Aabb::EMPTY; BINS];
        let mut right_costs = [0.0f32; BINS];
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in (1..BINS).rev() {
            b = b.union(self.boxes[k]);
            n += self.counts[k];
            if n > 0 {
                right_boxes[k] = b;
                right_costs[k] = b.half_area_unchecked() * n as f32;
            }
        }
        let mut best: Option<(f32, usize, Aabb, Aabb)> = None;
        let (mut b, mut n) = (Aabb::EMPTY, 0u32);
        for k in 1..BINS {
            b = b.union(self.boxes[k - 1]);
            n += self.counts[k - 1];
            if n == 0 || n as usize == count {
                continue;
            }
            let cost = b.half_area_unchecked() * n as f32 + right_costs[k];
            if best.is_none_or(|best| cost < best.0) {
                best = Some((cost, k, b, right_boxes[k]));
            }
        }
        best
    }
}

/// Eight-wide nodes from the binary tree: each takes its binary node's children and keeps
/// opening the largest inner one among them until it has eight.
fn collapse(binary: &[BinaryNode]) -> Vec<Node> {
    // No more wide nodes than binary inner nodes: room made once (what is not used is never
    // touched), not grown by doubling into fresh pages.
    let mut nodes = Vec::with_capacity(binary.len() / 2 + 1);
    nodes.push(Node::EMPTY);
    // (binary node, wide node to fill)
    let mut pending = vec![(0usize, 0usize)];
    while let Some((source, target)) = pending.pop() {
        let root = binary[source];
        let mut children: Vec<usize> = if root.count() > 0 {
            vec![source]
        } else {
            vec![root.first() as usize, root.first() as usize + 1]
        };
        while children.len() < WIDTH {
            let widest = children
                .iter()
                .enumerate()
                .filter(|&(_, &c)| binary[c].count() == 0)
                .max_by(|a, b| {
                    binary[*a.1]
                        .bounds()
                        .half_area()
                        .total_cmp(&binary[*b.1].bounds().half_area())
                });
            let Some((slot, &open)) = widest else { break };
            let first = binary[open].first() as usize;
            children[slot] = first;
            children.push(first + 1);
        }
        for (lane, &c) in children.iter().enumerate() {
            let child = binary[c];
            if child.count() > 0 {
                let count = child.count() as u8;
                nodes[target].set_lane(lane, padded(child.bounds()), child.first(), count);
            } else {
                let index = nodes.len();
                nodes.push(Node::EMPTY);
                nodes[target].set_lane(lane, padded(child.bounds()), index as u32, 0);
                pending.push((c, index));
            }
        }
    }
    nodes
}

/// A box grown by a few ulps of its coordinates, so that rounding in the slab test never loses
/// a hit on its surface (a ray through a triangle's edge on the box's face, say).
fn padded(b: Aabb) -> Aabb {
    let pad =
        (b.min.abs().max(b.max.abs()) * (4.0 * f32::EPSILON)).max(Vec3A::splat(f32::MIN_POSITIVE));
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
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
