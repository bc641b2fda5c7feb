//! The nearest-hit search of one ray: the planes, then the top-level tree's items, each mesh
//! through its own tree.

use super::{Hit, Nearest, World, search_limit};
use crate::accel::{March, Tally};
use crate::geometry::{Ray, intersect_plane};
use crate::simd::Portable;

impl World {
    /// The nearest hit with t >= t_min.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        self.intersect_with(ray, t_min, &mut ())
    }

    /// [`World::intersect`], counting primitives tested and grid cells entered.
    #[inline(always)]
    pub fn intersect_with<T: Tally>(&self, ray: &Ray, t_min: f32, tally: &mut T) -> Option<Hit> {
        tally.tested(self.planes.len() as u32);
        let mut nearest = self.nearest_plane(ray, t_min);
        self.nearest_beyond_planes(ray, t_min, &mut nearest, tally);
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// Everything but the planes, through the course's grid where one is in use, else the
    /// top-level tree: replaces `nearest` with a nearer hit.
    #[inline(always)]
    pub(super) fn nearest_beyond_planes<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
    ) {
        match &self.grid {
            Some(grid) => self.grid_nearest(grid, ray, t_min, nearest, tally, March::Course),
            None => self.nearest_item(ray, t_min, nearest, tally),
        }
    }

    /// The items' part of [`World::intersect_with`]: replaces `nearest` with a nearer item hit.
    #[inline(always)]
    pub(super) fn nearest_item<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
    ) {
        let t_max = search_limit(nearest);
        let mut test = |i, t_max| {
            let (t, triangle) = self.intersect_item(i, ray, t_min, t_max, tally)?;
            Nearest::item(t, i, triangle).replaces(nearest).then_some(t)
        };
        // A scene of one mesh (the common case for big meshes) needs no top-level tree.
        match self.items.len() {
            1 => {
                test(0, t_max);
            }
            _ => {
                self.top.traverse(Portable, ray, t_min, t_max, test);
            }
        }
    }

    /// Planes have no bounds for a tree to hold: each ray tests them all, before the trees, so
    /// that a hit on a plane shortens the search through them.
    #[inline(always)]
    pub(super) fn nearest_plane(&self, ray: &Ray, t_min: f32) -> Option<Nearest> {
        let mut nearest = None;
        for (i, (plane, _)) in self.planes.iter().enumerate() {
            let t_max = search_limit(&nearest);
            if let Some(t) = intersect_plane(ray, plane, t_min, t_max) {
                Nearest::plane(t, i as u32).replaces(&mut nearest);
            }
        }
        nearest
    }

    #[inline(always)]
    pub(super) fn intersect_item<T: Tally>(
        &self,
        i: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        let item = &self.items[i as usize];
        self.in_item_space(item, ray, |local| {
            self.intersect_local(item, local, t_min, t_max, tally)
        })
    }
}
