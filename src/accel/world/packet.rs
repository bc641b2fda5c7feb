//! The nearest-hit search of a packet of camera rays, which walk the top-level tree together.

use arrayvec::ArrayVec;

use super::{Hit, Item, Nearest, World, search_limit};
use crate::accel::bvh::{CoherentParts, PACKET, ray_meets_box};
use crate::accel::{ASKS_NOTHING, Tally};
use crate::geometry::{Aabb, Ray};
use crate::simd::Portable;

impl World {
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
}
