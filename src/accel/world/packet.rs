//! The nearest-hit search of a packet of camera rays, which walk the top-level tree together.

use arrayvec::ArrayVec;

use super::spread::Spread;
use super::{Hit, Item, Nearest, World, search_limit};
use crate::accel::bvh::{CoherentParts, PACKET, ray_meets_box};
use crate::accel::{ASKS_NOTHING, Tally};
use crate::geometry::{Aabb, Ray};
use crate::simd::Portable;
use glam::Vec3A;

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
            _ if self.packets_skip_top_tree() => {
                self.packet_item(0, None, rays, t_min, nearest, tally);
            }
            _ => {
                // Worked out when a packet first reaches an item, which many never do.
                let mut spread = None;
                let all = rays;
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
                            let spread = *spread.get_or_insert_with(|| Spread::of(all));
                            for item in first..first + count {
                                self.packet_item(
                                    item,
                                    Some((bounds, spread)),
                                    rays,
                                    t_min,
                                    nearest,
                                    tally,
                                );
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
        // Every hit's triangle read first, in a loop that does nothing else: each is mostly a
        // cache miss (bunny100: three quarters of the normal's time), and so they overlap.
        let mut surfaces = [(Vec3A::ZERO, 0); PACKET];
        for ((ray, nearest), surface) in rays.iter().zip(nearest.iter()).zip(&mut surfaces) {
            if let Some(n) = nearest {
                *surface = self.surface(ray, n.t, n.found);
            }
        }
        for (((ray, nearest), hit), &surface) in
            rays.iter().zip(nearest.iter()).zip(hits).zip(&surfaces)
        {
            *hit = nearest.map(|n| self.hit_with(ray, n.t, n.found, surface));
        }
    }

    /// Item `i` against the rays of a packet that meet `placed`'s box (the item's in the
    /// top-level tree, with the packet's spread; `None` when there is no tree, and every ray
    /// tests it). A mesh is searched by the packet where the packet is narrow beside it,
    /// otherwise ray by ray, as a sphere is.
    fn packet_item<T: Tally>(
        &self,
        i: u32,
        placed: Option<(&Aabb, Spread)>,
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
            if placed.is_none_or(|(b, _)| ray_meets_box(ray, b, t_min, t_max)) {
                *limit = t_max;
            }
        }
        let item = &self.items[i as usize];
        match *item {
            Item::Mesh {
                mesh, transform, ..
            } if placed.is_none_or(|(b, spread)| spread.narrow_beside(b)) => {
                // Only the rays that meet the item's box go on: the bounds of the mesh's walk
                // are put around them alone (an instance's box is often met by part of a
                // packet), and only they are carried into its space.
                let active: ArrayVec<u8, PACKET> = (0..rays.len() as u8)
                    .filter(|&k| limits[k as usize] != ASKS_NOTHING)
                    .collect();
                if active.is_empty() {
                    return;
                }
                let mut found = [None; PACKET];
                if transform == Item::WORLD_SPACE && active.len() == rays.len() {
                    // The whole packet, as it is (a scene of one big mesh): no copies.
                    let found = &mut found[..rays.len()];
                    self.meshes[mesh as usize].intersect_packet(rays, t_min, limits, found, tally);
                    for (nearest, found) in nearest.iter_mut().zip(found.iter()) {
                        if let Some((t, triangle)) = *found {
                            Nearest::item(t, i, triangle).replaces(nearest);
                        }
                    }
                    return;
                }
                // Under a Transform, each ray is carried into the mesh's space just as it alone
                // would be; t still counts along the world's rays.
                let carry = |ray: &Ray| match transform {
                    Item::WORLD_SPACE => *ray,
                    t => self.transforms[t as usize].ray_to_object(ray),
                };
                let carried: ArrayVec<Ray, PACKET> =
                    active.iter().map(|&k| carry(&rays[k as usize])).collect();
                let mut asked: ArrayVec<f32, PACKET> =
                    active.iter().map(|&k| limits[k as usize]).collect();
                let found = &mut found[..active.len()];
                self.meshes[mesh as usize]
                    .intersect_packet(&carried, t_min, &mut asked, found, tally);
                for (&k, found) in active.iter().zip(found.iter()) {
                    if let Some((t, triangle)) = *found {
                        Nearest::item(t, i, triangle).replaces(&mut nearest[k as usize]);
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
