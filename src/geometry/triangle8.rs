//! Eight triangles tested against one ray at once: the watertight test of `triangle.rs`, lane by
//! lane, with the same operations in the same order, so that it gives bit for bit the same t, on
//! either of [`crate::simd`]'s paths.

use glam::Vec3;

use super::triangle::intersect_triangle_in;
use super::{Ray, RayFrame};
use crate::simd::{Lanes, Wide};

/// How many triangles a block holds.
pub const BLOCK: usize = 8;

/// A ray's watertight frame with every entry in all eight lanes: worked out once per ray, not
/// once per block of triangles.
#[derive(Debug, Clone, Copy)]
pub struct RayLanes<K: Wide> {
    frame: RayFrame,
    /// The origin's coordinates in the frame's order: `[o[kx], o[ky], o[kz]]`.
    origin: [K::F; 3],
    shear: [K::F; 3],
}

impl<K: Wide> RayLanes<K> {
    /// The ray's frame, worked out once for every block of triangles the ray meets.
    #[inline(always)]
    pub fn new(wide: K, ray: &Ray) -> RayLanes<K> {
        // (No closures or `map`: the kernels' rule, as in `intersect_pair`.)
        let frame = ray.to_ray_space();
        let ([kx, ky, kz], [sx, sy, sz]) = (frame.axes, frame.shear);
        let origin = ray.origin.to_array();
        RayLanes {
            frame,
            origin: [
                wide.splat(origin[kx]),
                wide.splat(origin[ky]),
                wide.splat(origin[kz]),
            ],
            shear: [wide.splat(sx), wide.splat(sy), wide.splat(sz)],
        }
    }
}

/// One vertex of each lane's triangle in the ray's frame, its coordinates already in the
/// frame's order, as [`RayFrame::apply`] maps it.
#[inline(always)]
fn to_ray_space<F: Lanes>(vertex: [F; 3], origin: &[F; 3], shear: &[F; 3]) -> [F; 3] {
    let d = [
        vertex[0] - origin[0],
        vertex[1] - origin[1],
        vertex[2] - origin[2],
    ];
    [
        d[0] + shear[0] * d[2],
        d[1] + shear[1] * d[2],
        shear[2] * d[2],
    ]
}

/// The lane-wise part of the watertight test, for lanes of any width (eight triangles against
/// one ray, or against two rays side by side): the lanes whose edge functions are not all
/// non-zero (a ray through an edge or vertex, which the scalar test settles), the lanes hit
/// within [t_min, t_max] otherwise, and each lane's t.
struct LaneVerdict<F> {
    on_edge: u32,
    hit: u32,
    t: F,
}

#[inline(always)]
fn watertight<F: Lanes>(
    vertices: [[F; 3]; 3],
    origin: &[F; 3],
    shear: &[F; 3],
    t_min: F,
    t_max: F,
) -> LaneVerdict<F> {
    let [p0x, p0y, p0z] = to_ray_space(vertices[0], origin, shear);
    let [p1x, p1y, p1z] = to_ray_space(vertices[1], origin, shear);
    let [p2x, p2y, p2z] = to_ray_space(vertices[2], origin, shear);
    let e0 = p1x * p2y - p1y * p2x;
    let e1 = p2x * p0y - p2y * p0x;
    let e2 = p0x * p1y - p0y * p1x;
    let zero = t_min.splat_like(0.0);
    let on_edge = e0.eq(zero) | e1.eq(zero) | e2.eq(zero);
    let negative = e0.lt(zero) | e1.lt(zero) | e2.lt(zero);
    let positive = e0.gt(zero) | e1.gt(zero) | e2.gt(zero);
    let det = e0 + e1 + e2;
    let t = (e0 * p0z + e1 * p1z + e2 * p2z) / det;
    let inside = !(negative & positive) & det.ne(zero);
    let in_range = t.ge(t_min) & t.le(t_max);
    LaneVerdict {
        on_edge,
        hit: inside & in_range,
        t,
    }
}

/// A vertex's three coordinates of eight triangles, in lanes, in the order of `axes`.
#[inline(always)]
fn load3<K: Wide>(wide: K, vertex: &[[f32; BLOCK]; 3], axes: [usize; 3]) -> [K::F; 3] {
    let [kx, ky, kz] = axes;
    [
        wide.load(&vertex[kx]),
        wide.load(&vertex[ky]),
        wide.load(&vertex[kz]),
    ]
}

/// [`load3`] for two rays side by side, where the path pairs: each ray's axes in its half.
#[inline(always)]
fn load3_pair<K: Wide>(
    wide: K,
    vertex: &[[f32; BLOCK]; 3],
    axes: [[usize; 3]; 2],
) -> Option<[K::Pair; 3]> {
    let [a, b] = axes;
    if a == b {
        return Some([
            wide.load_twice(&vertex[a[0]])?,
            wide.load_twice(&vertex[a[1]])?,
            wide.load_twice(&vertex[a[2]])?,
        ]);
    }
    join3(wide, &load3(wide, vertex, a), &load3(wide, vertex, b))
}

/// Three sets of lanes of one ray beside the same of another, where the path pairs.
#[inline(always)]
fn join3<K: Wide>(wide: K, a: &[K::F; 3], b: &[K::F; 3]) -> Option<[K::Pair; 3]> {
    Some([
        wide.join(a[0], b[0])?,
        wide.join(a[1], b[1])?,
        wide.join(a[2], b[2])?,
    ])
}

/// The nearest of the lanes in `hit` (bit k for lane k of `t`), ties to the lowest lane.
#[inline(always)]
fn nearest_lane(mut hit: u32, t: &[f32]) -> Option<(f32, usize)> {
    if hit == 0 {
        return None;
    }
    let mut best = hit.trailing_zeros() as usize;
    hit &= hit - 1;
    while hit != 0 {
        let lane = hit.trailing_zeros() as usize;
        hit &= hit - 1;
        if t[lane] < t[best] {
            best = lane;
        }
    }
    Some((t[best], best))
}

/// Eight triangles' vertices in structure-of-arrays form; unused lanes hold a zero-area
/// triangle, which is never hit.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct Triangle8 {
    /// `vertices[k][axis]`: coordinate `axis` of vertex k of each lane's triangle.
    vertices: [[[f32; BLOCK]; 3]; 3],
    /// The mesh's index of lane 0's triangle; lane k holds the one after it k times (a block
    /// is made of consecutive triangles, so eight indices would say no more: 32 bytes a block).
    first: u32,
    /// Bit k set when lane k holds a triangle.
    used: u32,
}

impl Triangle8 {
    /// Packs up to eight triangles, which are numbered `first`, `first + 1`, ... in their mesh.
    pub fn new(triangles: &[[Vec3; 3]], first: u32) -> Triangle8 {
        debug_assert!(triangles.len() <= BLOCK);
        let mut packed = Triangle8 {
            vertices: [[[0.0; BLOCK]; 3]; 3],
            first,
            used: 0,
        };
        for (lane, triangle) in triangles.iter().enumerate() {
            for (k, vertex) in triangle.iter().enumerate() {
                for axis in 0..3 {
                    packed.vertices[k][axis][lane] = vertex[axis];
                }
            }
            packed.used |= 1 << lane;
        }
        packed
    }

    /// The mesh's index of the triangle in `lane`.
    #[inline(always)]
    pub fn index(&self, lane: usize) -> u32 {
        self.first + lane as u32
    }

    /// How many of the eight lanes hold a triangle.
    #[inline(always)]
    pub fn len(&self) -> u32 {
        self.used.count_ones()
    }

    /// The nearest of the eight hits with t_min <= t <= t_max (ties to the lowest lane): its t
    /// and lane.
    #[inline(always)]
    pub fn intersect<K: Wide>(
        &self,
        wide: K,
        ray: &Ray,
        lanes: &RayLanes<K>,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, usize)> {
        let (v, axes) = (&self.vertices, lanes.frame.axes);
        let vertices = [
            load3(wide, &v[0], axes),
            load3(wide, &v[1], axes),
            load3(wide, &v[2], axes),
        ];
        let (low, high) = (wide.splat(t_min), wide.splat(t_max));
        let verdict = watertight(vertices, &lanes.origin, &lanes.shear, low, high);
        // (Empty lanes have every edge function zero; they must not send each block that has
        // one down the slow path.)
        if verdict.on_edge & self.used != 0 {
            // A ray through an edge or vertex: the scalar test settles it in f64, lane by lane.
            return self.intersect_each(ray, &lanes.frame, t_min, t_max);
        }
        nearest_lane(verdict.hit, &verdict.t.to_array())
    }

    /// [`Triangle8::intersect`] for two rays at once, on a path with sixteen-lane registers
    /// (`None` on others): each ray's lanes side by side, the same operations lane by lane, so
    /// the same answers; ray k searches [`t_min[k]`, `t_max[k]`].
    #[inline(always)]
    pub fn intersect_pair<K: Wide>(
        &self,
        wide: K,
        rays: [&Ray; 2],
        lanes: [&RayLanes<K>; 2],
        t_min: [f32; 2],
        t_max: [f32; 2],
    ) -> Option<[Option<(f32, usize)>; 2]> {
        // (Helpers marked inline, no closures: a closure left out of line would call each
        // vector instruction behind it.)
        let [a, b] = lanes;
        let origin = join3(wide, &a.origin, &b.origin)?;
        let shear = join3(wide, &a.shear, &b.shear)?;
        let (v, axes) = (&self.vertices, [a.frame.axes, b.frame.axes]);
        let vertices = [
            load3_pair(wide, &v[0], axes)?,
            load3_pair(wide, &v[1], axes)?,
            load3_pair(wide, &v[2], axes)?,
        ];
        let low = wide.join(wide.splat(t_min[0]), wide.splat(t_min[1]))?;
        let high = wide.join(wide.splat(t_max[0]), wide.splat(t_max[1]))?;
        let verdict = watertight(vertices, &origin, &shear, low, high);
        let t = verdict.t.to_array();
        let mut found = [None; 2];
        for (k, found) in found.iter_mut().enumerate() {
            let shift = k * BLOCK;
            *found = if (verdict.on_edge >> shift) & self.used != 0 {
                self.intersect_each(rays[k], &lanes[k].frame, t_min[k], t_max[k])
            } else {
                nearest_lane((verdict.hit >> shift) & 0xff, &t[shift..shift + BLOCK])
            };
        }
        Some(found)
    }

    fn intersect_each(
        &self,
        ray: &Ray,
        frame: &RayFrame,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, usize)> {
        let mut best: Option<(f32, usize)> = None;
        for lane in 0..BLOCK {
            if self.used & (1 << lane) == 0 {
                continue;
            }
            let limit = best.map_or(t_max, |(t, _)| t);
            if let Some(t) = intersect_triangle_in(frame, ray, &self.triangle(lane), t_min, limit) {
                // A tie keeps the lower lane, as the eight-wide path does.
                if best.is_none_or(|(best_t, _)| t < best_t) {
                    best = Some((t, lane));
                }
            }
        }
        best
    }

    /// The vertices of the triangle in `lane` (a zero-area triangle in an unused lane).
    pub fn triangle(&self, lane: usize) -> [Vec3; 3] {
        self.vertices
            .map(|v| Vec3::new(v[0][lane], v[1][lane], v[2][lane]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::intersect_triangle;
    use crate::simd::Portable;
    use glam::Vec3A;

    #[test]
    fn a_tie_on_a_shared_edge_goes_to_the_lower_lane() {
        // Two triangles sharing the edge (1,0,0)-(0,1,0), hit exactly on it: both at t = 1.
        // The edge makes an edge function zero, which takes the lane-by-lane path.
        let triangles = [
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
        ];
        let ray = Ray::new(Vec3A::new(0.5, 0.5, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        for t in &triangles {
            assert_eq!(intersect_triangle(&ray, t, 0.0, f32::INFINITY), Some(1.0));
        }
        let block = Triangle8::new(&triangles, 0);
        let lanes = RayLanes::new(Portable, &ray);
        assert_eq!(
            block.intersect(Portable, &ray, &lanes, 0.0, f32::INFINITY),
            Some((1.0, 0))
        );
    }

    #[test]
    fn agrees_with_the_scalar_test_bit_for_bit() {
        let triangles = [
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.1),
                Vec3::new(0.0, 1.0, 0.2),
            ],
            [
                Vec3::new(0.3, 0.1, -1.0),
                Vec3::new(1.0, 0.7, -1.3),
                Vec3::new(0.1, 0.9, -0.4),
            ],
            [
                Vec3::new(-0.5, -0.5, 2.0),
                Vec3::new(0.9, -0.2, 2.5),
                Vec3::new(0.2, 0.8, 1.5),
            ],
        ];
        let packed = Triangle8::new(&triangles, 7);
        let mut hits = 0;
        for i in 0..400 {
            let x = (i % 20) as f32 / 13.0 - 0.4;
            let y = (i / 20) as f32 / 13.0 - 0.4;
            let ray = Ray::new(
                Vec3A::new(x, y, 5.0),
                Vec3A::new(0.1 * x, -0.05, -1.0).normalize(),
            );
            let scalar = triangles
                .iter()
                .enumerate()
                .filter_map(|(lane, t)| {
                    Some((intersect_triangle(&ray, t, 0.0, f32::INFINITY)?, lane))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let lanes = RayLanes::new(Portable, &ray);
            assert_eq!(
                packed.intersect(Portable, &ray, &lanes, 0.0, f32::INFINITY),
                scalar
            );
            hits += scalar.is_some() as usize;
        }
        assert!(
            hits > 50,
            "only {hits} hits: the test rays miss too often to mean much"
        );
    }

    /// Two rays at once answer as each alone, where the machine pairs (AVX-512): rays through
    /// the triangles, beside them, through a shared edge and vertex (the scalar path for one of
    /// the two), with ranges of their own.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn two_rays_at_once_answer_as_each_alone() {
        let Some(avx512) = crate::simd::Avx512::detect() else {
            return;
        };
        let triangles: Vec<[Vec3; 3]> = (0..8)
            .map(|k| {
                let (x, y) = ((k % 4) as f32 - 2.0, (k / 4) as f32 - 1.0);
                [
                    Vec3::new(x, y, -0.1 * k as f32),
                    Vec3::new(x + 1.0, y, 0.0),
                    Vec3::new(x, y + 1.0, 0.1),
                ]
            })
            .collect();
        let packed = Triangle8::new(&triangles[..7], 0);
        let rays: Vec<Ray> = (0..300)
            .map(|i| {
                let (x, y) = ((i % 20) as f32 / 4.0 - 2.5, (i / 20) as f32 / 6.0 - 1.2);
                // Every seventh ray straight through a vertex the triangles share.
                if i % 7 == 0 {
                    return Ray::new(Vec3A::new(-1.0, 0.0, 4.0), -Vec3A::Z);
                }
                Ray::new(Vec3A::new(x, y, 4.0), Vec3A::new(0.01 * x, 0.02, -1.0))
            })
            .collect();
        let mut hits = 0;
        for (k, pair) in rays.windows(2).enumerate() {
            let limits = [[f32::INFINITY, 4.0][k % 2], [3.9, f32::INFINITY][k % 2]];
            let lanes = [
                RayLanes::new(avx512, &pair[0]),
                RayLanes::new(avx512, &pair[1]),
            ];
            let together = packed
                .intersect_pair(
                    avx512,
                    [&pair[0], &pair[1]],
                    [&lanes[0], &lanes[1]],
                    [0.0; 2],
                    limits,
                )
                .expect("an AVX-512 path pairs");
            for r in 0..2 {
                let alone = RayLanes::new(Portable, &pair[r]);
                let expected = packed.intersect(Portable, &pair[r], &alone, 0.0, limits[r]);
                assert_eq!(
                    together[r].map(|(t, lane)| (t.to_bits(), lane)),
                    expected.map(|(t, lane)| (t.to_bits(), lane)),
                    "ray {:?}",
                    pair[r]
                );
                hits += usize::from(expected.is_some());
            }
        }
        assert!(hits > 50, "only {hits} hits");
        // Where the path does not pair, there is no answer for two at once.
        let lanes = RayLanes::new(Portable, &rays[1]);
        let unpaired = [&rays[1], &rays[1]];
        let none = packed.intersect_pair(Portable, unpaired, [&lanes, &lanes], [0.0; 2], [1.0; 2]);
        assert!(none.is_none());
    }

    #[test]
    fn empty_lanes_are_never_hit() {
        let packed = Triangle8::new(&[], 0);
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 1.0), -Vec3A::Z);
        let lanes = RayLanes::new(Portable, &ray);
        assert_eq!(
            packed.intersect(Portable, &ray, &lanes, f32::NEG_INFINITY, f32::INFINITY),
            None
        );
        assert_eq!(packed.len(), 0);
    }
}
