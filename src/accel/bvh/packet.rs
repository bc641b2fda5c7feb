//! Packets of rays: the camera's coherent rays searched together, with bounds over a packet
//! (or a part of one) tested against a node's boxes as one ray is.

use super::*;

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
pub(super) fn splat3<K: Wide>(wide: K, v: Vec3A) -> [K::F; 3] {
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
pub(super) struct PacketPending {
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
