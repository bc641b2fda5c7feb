//! The shadow search: whether anything at all is hit in a range, answered at the first hit.

use std::ops::ControlFlow;

use super::{Item, World};
use crate::accel::Tally;
use crate::geometry::{Ray, intersect_plane, intersect_sphere};
use crate::simd::Portable;

impl World {
    /// Whether anything at all is hit with t in [t_min, t_max]: the shadow ray's question,
    /// answered at the first hit found rather than the nearest.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_with(ray, t_min, t_max, &mut ())
    }

    /// [`World::occluded`], counting primitives tested and grid cells entered.
    #[inline]
    pub fn occluded_with<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        for (plane, _) in &self.planes {
            tally.tested(1);
            if intersect_plane(ray, plane, t_min, t_max).is_some() {
                return true;
            }
        }
        if let Some(grid) = &self.grid {
            let mut blocked = false;
            let mut local = None;
            grid.walk(ray, t_min, t_max, |cell| {
                tally.cell();
                for p in cell.primitives {
                    tally.tested(1);
                    if self
                        .intersect_primitive(p, ray, t_min, t_max, &mut local)
                        .is_some()
                    {
                        blocked = true;
                        return ControlFlow::Break(());
                    }
                }
                ControlFlow::Continue(())
            });
            return blocked;
        }
        self.occluded_by_items(ray, t_min, t_max, tally)
    }

    /// Whether an item (not a plane) is hit in [t_min, t_max], through the trees.
    #[inline(always)]
    pub(super) fn occluded_by_items<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        let mut test = |i: u32| self.occluded_item(i, ray, t_min, t_max, tally);
        match self.items.len() {
            0 => false,
            1 => test(0),
            _ => self.top.occluded(Portable, ray, t_min, t_max, test),
        }
    }

    /// Whether item `i` is hit in [t_min, t_max].
    #[inline(always)]
    pub(super) fn occluded_item<T: Tally>(
        &self,
        i: u32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        let item = &self.items[i as usize];
        self.in_item_space(item, ray, |local| {
            self.occluded_local(item, local, t_min, t_max, tally)
        })
    }

    #[inline(always)]
    pub(super) fn occluded_local<T: Tally>(
        &self,
        item: &Item,
        local: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> bool {
        match *item {
            Item::Sphere { sphere, .. } => {
                tally.tested(1);
                intersect_sphere(local, &sphere, t_min, t_max).is_some()
            }
            Item::Mesh { mesh, .. } => {
                self.meshes[mesh as usize].occluded(local, t_min, t_max, tally)
            }
        }
    }
}
