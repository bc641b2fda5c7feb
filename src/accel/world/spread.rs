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
        let first = direction.normalize_or_zero();
        let (mut angle, mut apart) = (0.0_f32, 0.0_f32);
        for ray in rays {
            // (Shadow rays toward a sun all share one direction: no square roots for them.)
            if ray.direction != direction {
                angle = angle.max((ray.direction.normalize_or_zero() - first).length());
            }
            if ray.origin != origin {
                apart = apart.max((ray.origin - origin).length());
            }
        }
        Spread {
            angle,
            apart,
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
