//! How far apart a packet's rays run where they reach a mesh: whether walking its tree as a
//! packet pays, or each ray should walk it alone.

use glam::Vec3A;

use crate::geometry::{Aabb, Ray};

/// How far apart a packet's rays run: the largest distance between the first ray's unit
/// direction and another's (about the angle between them, in radians), the largest distance
/// between the first ray's origin and another's (none for a perspective camera's rays; the
/// spread of the points a shadow packet leaves from), and the first ray's origin.
#[derive(Clone, Copy)]
pub(super) struct Spread {
    angle: f32,
    apart: f32,
    origin: Vec3A,
}

impl Spread {
    /// A packet whose rays, where they reach a mesh, lie further apart than this share of the
    /// mesh's box's diagonal is searched ray by ray: its rays' walks through the mesh's tree
    /// share too little for the packet's common walk to pay (measured on 100 bunnies at
    /// 1024²: the packet's walk took 2.9 times the rays' own; on one bunny filling the view,
    /// the rays' own took 1.6 times the packet's).
    const WIDEST: f32 = 0.03;

    pub(super) fn of(rays: &[Ray]) -> Spread {
        let (direction, origin) = (rays[0].direction, rays[0].origin);
        // The ray turned furthest from the first is found by sin² of the angle between them,
        // a fraction (|d × d₀|², |d|²·|d₀|²) compared by cross-multiplying: no square root or
        // division a ray (they were a tenth of a camera packet's time through a world whose one
        // mesh is placed by a Transform). Only that ray's distance is then worked out. sin² grows
        // with the angle up to a right angle: a ray at one or more, or one with no usable
        // length, has every ray's distance worked out instead.
        let mut widest: Option<(f32, f32, usize)> = None;
        let mut every_ray = false;
        let mut apart_squared = 0.0_f32;
        let length_squared = direction.length_squared();
        for (i, ray) in rays.iter().enumerate() {
            // (Shadow rays toward a sun all share one direction: nothing to do for them.)
            if ray.direction != direction {
                let turned = ray.direction.cross(direction).length_squared();
                let lengths = ray.direction.length_squared() * length_squared;
                if !(ray.direction.dot(direction) > 0.0 && lengths.is_normal()) {
                    every_ray = true;
                } else if widest.is_none_or(|(t, l, _)| turned * l > t * lengths) {
                    widest = Some((turned, lengths, i));
                }
            }
            if ray.origin != origin {
                apart_squared = apart_squared.max((ray.origin - origin).length_squared());
            }
        }
        let first = direction.normalize_or_zero();
        let distance = |ray: &Ray| (ray.direction.normalize_or_zero() - first).length();
        let angle = if every_ray {
            rays.iter()
                .filter(|ray| ray.direction != direction)
                .map(distance)
                .fold(0.0, f32::max)
        } else {
            widest.map_or(0.0, |(_, _, i)| distance(&rays[i]))
        };
        Spread {
            angle,
            // The square root of the largest square is the largest root: the same number.
            apart: apart_squared.sqrt(),
            origin,
        }
    }

    /// Whether the packet is narrow beside a mesh whose world box is `bounds`: its rays'
    /// spread where they reach the box's centre is within [`Spread::WIDEST`] of its diagonal.
    pub(super) fn narrow_beside(self, bounds: &Aabb) -> bool {
        let distance = ((bounds.min + bounds.max) * 0.5 - self.origin).length();
        self.angle * distance + self.apart <= Spread::WIDEST * (bounds.max - bounds.min).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_packet_is_narrow_beside_a_mesh_its_rays_reach_close_together() {
        // Eight rays from the origin, 0.01 apart at unit distance (the widest 0.02).
        let rays: Vec<Ray> = (0..8)
            .map(|k| {
                Ray::new(
                    Vec3A::ZERO,
                    Vec3A::new(0.01 * (k % 2) as f32, 0.01 * (k / 2 % 2) as f32, 1.0),
                )
            })
            .collect();
        let spread = Spread::of(&rays);
        assert!(
            (spread.angle - 0.01 * 2f32.sqrt()).abs() < 1e-4,
            "{}",
            spread.angle
        );
        // A box of diagonal 1.732 at distance 10: the rays are 0.14 apart there, 8 % of it.
        let far = Aabb {
            min: Vec3A::new(-0.5, -0.5, 9.5),
            max: Vec3A::new(0.5, 0.5, 10.5),
        };
        assert!(!spread.narrow_beside(&far));
        // The same box at distance 1: 0.014 apart, 0.8 % of it.
        let near = Aabb {
            min: Vec3A::new(-0.5, -0.5, 0.5),
            max: Vec3A::new(0.5, 0.5, 1.5),
        };
        assert!(spread.narrow_beside(&near));
    }

    /// The spread found by sin² of the angles is the one that every ray's own distance gives:
    /// camera-like packets, rays at right angles and beyond, a ray of no length.
    #[test]
    fn the_widest_ray_is_found_without_every_rays_distance() {
        let by_every_ray = |rays: &[Ray]| {
            let first = rays[0].direction.normalize_or_zero();
            let angle = rays
                .iter()
                .filter(|ray| ray.direction != rays[0].direction)
                .map(|ray| (ray.direction.normalize_or_zero() - first).length())
                .fold(0.0, f32::max);
            let apart = rays
                .iter()
                .map(|ray| (ray.origin - rays[0].origin).length())
                .fold(0.0, f32::max);
            (angle, apart)
        };
        let mut seed = 7_u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32 - 0.5
        };
        for packet in 0..300 {
            // Narrow camera packets, then wider ones, then any directions at all.
            let width = [0.002, 0.3, 4.0][packet % 3];
            let mut rays: Vec<Ray> = (0..64)
                .map(|_| {
                    let origin = Vec3A::new(next(), next(), next()) * (packet % 2) as f32;
                    let turn = Vec3A::new(next(), next(), next()) * width;
                    Ray::new(origin, Vec3A::new(0.3, -0.2, -1.0) + turn)
                })
                .collect();
            if packet % 50 == 0 {
                rays[5].direction = Vec3A::ZERO;
            }
            let spread = Spread::of(&rays);
            let (angle, apart) = by_every_ray(&rays);
            assert_eq!(spread.apart, apart, "packet {packet}");
            assert!(
                (spread.angle - angle).abs() <= 1e-6 * angle.max(1e-3),
                "packet {packet}: {} against {angle}",
                spread.angle
            );
        }
    }

    #[test]
    fn shadow_rays_from_points_far_apart_are_not_narrow() {
        // Parallel rays (toward a sun) from points 0.01 apart, then 1 apart, beside a unit box.
        let box_ahead = Aabb {
            min: Vec3A::new(-0.5, -0.5, 2.5),
            max: Vec3A::new(0.5, 0.5, 3.5),
        };
        let from = |gap: f32| -> Vec<Ray> {
            (0..4)
                .map(|k| Ray::new(Vec3A::new(gap * k as f32, 0.0, 0.0), Vec3A::Z))
                .collect()
        };
        assert!(Spread::of(&from(0.01)).narrow_beside(&box_ahead));
        assert!(!Spread::of(&from(1.0)).narrow_beside(&box_ahead));
    }
}
