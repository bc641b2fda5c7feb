//! Eight triangles tested against one ray at once: the watertight test of `triangle.rs`, lane by
//! lane, with the same operations in the same order, so that it gives bit for bit the same t, on
//! either of [`crate::simd`]'s paths.

use glam::{Mat3A, Vec3};

use super::Ray;
use super::triangle::intersect_triangle_in;
use crate::simd::{Lanes, Wide};

/// How many triangles a block holds.
pub const BLOCK: usize = 8;

/// A ray's watertight frame with every entry in all eight lanes: worked out once per ray, not
/// once per block of triangles.
#[derive(Debug, Clone, Copy)]
pub struct RayLanes<K: Wide> {
    frame: Mat3A,
    origin: [K::F; 3],
    /// `rows[i][j]`: entry (i, j) of the ray-space matrix.
    rows: [[K::F; 3]; 3],
}

impl<K: Wide> RayLanes<K> {
    /// The ray's frame, worked out once for every block of triangles the ray meets.
    #[inline(always)]
    pub fn new(wide: K, ray: &Ray) -> RayLanes<K> {
        let m = ray.to_ray_space();
        let columns = [m.x_axis, m.y_axis, m.z_axis];
        RayLanes {
            frame: m,
            origin: [
                wide.splat(ray.origin.x),
                wide.splat(ray.origin.y),
                wide.splat(ray.origin.z),
            ],
            rows: [
                [
                    wide.splat(columns[0][0]),
                    wide.splat(columns[1][0]),
                    wide.splat(columns[2][0]),
                ],
                [
                    wide.splat(columns[0][1]),
                    wide.splat(columns[1][1]),
                    wide.splat(columns[2][1]),
                ],
                [
                    wide.splat(columns[0][2]),
                    wide.splat(columns[1][2]),
                    wide.splat(columns[2][2]),
                ],
            ],
        }
    }
}

/// One vertex of each lane's triangle in the ray's frame: row i of the matrix, one entry per
/// lane-wide multiplication, as `Mat3A * Vec3A` does.
#[inline(always)]
fn to_ray_space<K: Wide>(
    wide: K,
    lanes: &RayLanes<K>,
    vertex: &[[f32; BLOCK]; 3],
) -> (K::F, K::F, K::F) {
    let d = [
        wide.load(&vertex[0]) - lanes.origin[0],
        wide.load(&vertex[1]) - lanes.origin[1],
        wide.load(&vertex[2]) - lanes.origin[2],
    ];
    let [r0, r1, r2] = &lanes.rows;
    (
        r0[0] * d[0] + r0[1] * d[1] + r0[2] * d[2],
        r1[0] * d[0] + r1[1] * d[1] + r1[2] * d[2],
        r2[0] * d[0] + r2[1] * d[1] + r2[2] * d[2],
    )
}

/// Eight triangles' vertices in structure-of-arrays form; unused lanes hold a zero-area
/// triangle, which is never hit.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct Triangle8 {
    /// `vertices[k][axis]`: coordinate `axis` of vertex k of each lane's triangle.
    vertices: [[[f32; BLOCK]; 3]; 3],
    /// Each lane's triangle, as its index in the mesh.
    pub index: [u32; BLOCK],
    /// Bit k set when lane k holds a triangle.
    used: u32,
}

impl Triangle8 {
    /// Packs up to eight triangles, which are numbered `first`, `first + 1`, ... in their mesh.
    pub fn new(triangles: &[[Vec3; 3]], first: u32) -> Triangle8 {
        debug_assert!(triangles.len() <= BLOCK);
        let mut packed = Triangle8 {
            vertices: [[[0.0; BLOCK]; 3]; 3],
            index: [u32::MAX; BLOCK],
            used: 0,
        };
        for (lane, (triangle, i)) in triangles.iter().zip(first..).enumerate() {
            for (k, vertex) in triangle.iter().enumerate() {
                for axis in 0..3 {
                    packed.vertices[k][axis][lane] = vertex[axis];
                }
            }
            packed.index[lane] = i;
            packed.used |= 1 << lane;
        }
        packed
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
        let (p0x, p0y, p0z) = to_ray_space(wide, lanes, &self.vertices[0]);
        let (p1x, p1y, p1z) = to_ray_space(wide, lanes, &self.vertices[1]);
        let (p2x, p2y, p2z) = to_ray_space(wide, lanes, &self.vertices[2]);
        let e0 = p1x * p2y - p1y * p2x;
        let e1 = p2x * p0y - p2y * p0x;
        let e2 = p0x * p1y - p0y * p1x;
        let zero = wide.splat(0.0);
        // (Empty lanes have every edge function zero; they must not send each block that has
        // one down the slow path.)
        if (e0.eq(zero) | e1.eq(zero) | e2.eq(zero)) & self.used != 0 {
            // A ray through an edge or vertex: the scalar test settles it in f64, lane by lane.
            return self.intersect_each(ray, &lanes.frame, t_min, t_max);
        }
        let negative = e0.lt(zero) | e1.lt(zero) | e2.lt(zero);
        let positive = e0.gt(zero) | e1.gt(zero) | e2.gt(zero);
        let det = e0 + e1 + e2;
        let t = (e0 * p0z + e1 * p1z + e2 * p2z) / det;
        let inside = !(negative & positive) & det.ne(zero);
        let in_range = t.ge(wide.splat(t_min)) & t.le(wide.splat(t_max));
        let mut mask = inside & in_range;
        if mask == 0 {
            return None;
        }
        let t = t.to_array();
        let mut best = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if t[lane] < t[best] {
                best = lane;
            }
        }
        Some((t[best], best))
    }

    fn intersect_each(
        &self,
        ray: &Ray,
        frame: &Mat3A,
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

    #[test]
    fn empty_lanes_are_never_hit() {
        let packed = Triangle8::new(&[], 0);
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 1.0), -Vec3A::Z);
        let lanes = RayLanes::new(Portable, &ray);
        assert_eq!(
            packed.intersect(Portable, &ray, &lanes, f32::NEG_INFINITY, f32::INFINITY),
            None
        );
        assert_eq!(packed.index, [u32::MAX; BLOCK]);
    }
}
