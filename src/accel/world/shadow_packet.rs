//! The shadow search of a packet of rays: the shadow rays toward one light from the points a
//! packet of camera rays hit, which walk the trees together as the camera rays did.

use arrayvec::ArrayVec;

use super::spread::Spread;
use super::{Item, World};
use crate::accel::bvh::{CoherentParts, PACKET, ray_meets_box};
use crate::accel::{ASKS_NOTHING, Tally};
use crate::geometry::{Aabb, Ray, intersect_plane};
use crate::simd::Portable;

impl World {
    /// [`World::occluded_with`] for up to [`PACKET`] rays at once, each answered exactly as it
    /// alone would be: `blocked[i]` becomes whether anything is hit with t in
    /// [`t_min[i]`, `t_max[i]`]. The primitives counted for `-stats` are those the packet's
    /// rays test, which are not always those each would test alone.
    pub fn occluded_packet_with<T: Tally>(
        &self,
        rays: &[Ray],
        t_min: &[f32],
        t_max: &[f32],
        blocked: &mut [bool],
        tally: &mut T,
    ) {
        let n = rays.len();
        assert!(n <= PACKET && t_min.len() == n && t_max.len() == n && blocked.len() == n);
        if n == 0 {
            return;
        }
        if self.grid.is_some() {
            for (i, ray) in rays.iter().enumerate() {
                blocked[i] = self.occluded_with(ray, t_min[i], t_max[i], tally);
            }
            return;
        }
        // A ray a plane blocks asks the trees nothing.
        let mut limits = [ASKS_NOTHING; PACKET];
        let limits = &mut limits[..n];
        for (i, ray) in rays.iter().enumerate() {
            blocked[i] = self.planes.iter().any(|(plane, _)| {
                tally.tested(1);
                intersect_plane(ray, plane, t_min[i], t_max[i]).is_some()
            });
            if !blocked[i] {
                limits[i] = t_max[i];
            }
        }
        let spread = Spread::of(rays);
        match self.items.len() {
            0 => {}
            _ if self.packets_skip_top_tree() => {
                self.packet_item_occluded(0, None, spread, rays, t_min, limits, blocked, tally);
            }
            _ => {
                for (part, around) in CoherentParts::new(Portable, rays) {
                    let (rays, t_min, limits, blocked) = (
                        &rays[part.clone()],
                        &t_min[part.clone()],
                        &mut limits[part.clone()],
                        &mut blocked[part],
                    );
                    let Some(around) = around else {
                        for (i, ray) in rays.iter().enumerate() {
                            if limits[i] != ASKS_NOTHING {
                                blocked[i] =
                                    self.occluded_by_items(ray, t_min[i], limits[i], tally);
                            }
                        }
                        continue;
                    };
                    let greatest =
                        |limits: &[f32]| limits.iter().fold(ASKS_NOTHING, |a, &b| a.max(b));
                    let start = greatest(limits);
                    if start == ASKS_NOTHING {
                        continue;
                    }
                    let least = t_min.iter().fold(f32::INFINITY, |a, &b| a.min(b));
                    self.top.traverse_packet(
                        Portable,
                        &around,
                        least,
                        start,
                        |first, count, bounds| {
                            for item in first..first + count {
                                self.packet_item_occluded(
                                    item,
                                    Some(bounds),
                                    spread,
                                    rays,
                                    t_min,
                                    limits,
                                    blocked,
                                    tally,
                                );
                            }
                            greatest(limits)
                        },
                    );
                }
            }
        }
    }

    /// Item `i` against the rays of a packet that still ask (`limits[k]` not
    /// [`ASKS_NOTHING`]) and meet `placed`, the item's box in the top-level tree (`None` when
    /// there is no tree, and every ray asks it). A ray it blocks asks nothing more. A mesh is
    /// searched by the packet where the packet (of `spread`) is narrow beside it, otherwise ray
    /// by ray, as a sphere is: shadow rays leave from points that may lie far apart.
    #[allow(clippy::too_many_arguments)]
    fn packet_item_occluded<T: Tally>(
        &self,
        i: u32,
        placed: Option<&Aabb>,
        spread: Spread,
        rays: &[Ray],
        t_min: &[f32],
        limits: &mut [f32],
        blocked: &mut [bool],
        tally: &mut T,
    ) {
        let active: ArrayVec<u8, PACKET> = (0..rays.len() as u8)
            .filter(|&k| {
                let k = k as usize;
                limits[k] != ASKS_NOTHING
                    && placed.is_none_or(|b| ray_meets_box(&rays[k], b, t_min[k], limits[k]))
            })
            .collect();
        if active.is_empty() {
            return;
        }
        let world_box = placed.copied().unwrap_or_else(|| self.top.bounds());
        match self.items[i as usize] {
            Item::Mesh {
                mesh, transform, ..
            } if spread.narrow_beside(&world_box) => {
                let mesh = &self.meshes[mesh as usize];
                if transform == Item::WORLD_SPACE && active.len() == rays.len() {
                    // The whole packet, as it is (a scene of one big mesh): no copies.
                    mesh.occluded_packet(rays, t_min, limits, blocked, tally);
                    return;
                }
                // Each ray carried into the mesh's space just as it alone would be.
                let carried: ArrayVec<Ray, PACKET> = active
                    .iter()
                    .map(|&k| match transform {
                        Item::WORLD_SPACE => rays[k as usize],
                        t => self.transforms[t as usize].ray_to_object(&rays[k as usize]),
                    })
                    .collect();
                let starts: ArrayVec<f32, PACKET> =
                    active.iter().map(|&k| t_min[k as usize]).collect();
                let mut asked: ArrayVec<f32, PACKET> =
                    active.iter().map(|&k| limits[k as usize]).collect();
                let mut hit = [false; PACKET];
                let hit = &mut hit[..active.len()];
                mesh.occluded_packet(&carried, &starts, &mut asked, hit, tally);
                for (&k, &hit) in active.iter().zip(hit.iter()) {
                    if hit {
                        blocked[k as usize] = true;
                        limits[k as usize] = ASKS_NOTHING;
                    }
                }
            }
            _ => {
                for &k in &active {
                    let k = k as usize;
                    if self.occluded_item(i, &rays[k], t_min[k], limits[k], tally) {
                        blocked[k] = true;
                        limits[k] = ASKS_NOTHING;
                    }
                }
            }
        }
    }
}
