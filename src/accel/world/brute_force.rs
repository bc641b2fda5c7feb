//! The brute-force twins of the searches: every surface tested, no tree, for the tests to
//! compare the trees and the grid with.

use super::{Hit, Item, Nearest, World, search_limit};
use crate::geometry::{Ray, intersect_sphere};

impl World {
    /// [`World::occluded`] without either tree: its brute-force twin.
    pub fn occluded_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.intersect_brute_force(ray, t_min)
            .is_some_and(|hit| hit.t <= t_max)
    }

    /// The same answer as [`World::intersect`] without either tree: the brute-force twin.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        let mut nearest = self.nearest_plane(ray, t_min);
        for (i, item) in self.items.iter().enumerate() {
            let t_max = search_limit(&nearest);
            let local = self.ray_into(item, ray);
            let hit = match *item {
                Item::Sphere { sphere, .. } => {
                    intersect_sphere(&local, &sphere, t_min, t_max).map(|t| (t, 0))
                }
                Item::Mesh { mesh, .. } => {
                    self.meshes[mesh as usize].intersect_brute_force(&local, t_min, t_max)
                }
            };
            if let Some((t, triangle)) = hit {
                Nearest::item(t, i as u32, triangle).replaces(&mut nearest);
            }
        }
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }
}
