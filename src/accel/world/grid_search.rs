//! The searches through the course's grid, under `-grid`: cells in the ray's order instead of
//! the trees, with the same hits.

use std::ops::ControlFlow;

use glam::UVec3;

use super::{Item, LocalRay, Nearest, World, search_limit};
use crate::accel::grid::{Extent, Primitive};
use crate::accel::{Grid, GridError, March, Tally};
use crate::geometry::{Aabb, Ray, Transform, intersect_sphere, intersect_triangle_in};

/// The cells a grid lists an object in: by which box an object under a Transform is listed,
/// and how a box's or a sphere's cells are picked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Listing {
    /// The course's: an object under a Transform by the box of the eight corners of its
    /// object-space box, carried into the world; every cell a box reaches, and a sphere's by
    /// the handout's conservative test.
    EightCorners,
    /// A student's: the box between two corners carried into the world, the lowest and the
    /// highest (a rotated object reaches past it).
    TwoCorners,
    /// A student's: its object-space box as it is, the Transform left out.
    Untransformed,
    /// A student's: a sphere in world space in the cells whose centres lie inside it.
    SphereByCentres,
    /// A student's: every object by its box, in the cells from its lowest corner's up to, and
    /// not including, its highest corner's on each axis.
    ShortOfTheEnd,
}

impl Listing {
    /// The box an object of object-space box `b`, placed by `t`, is listed by.
    fn of(self, b: Aabb, t: &Transform) -> Aabb {
        let carried = |corner| t.object_to_world.transform_point3a(corner);
        match self {
            Listing::EightCorners | Listing::SphereByCentres | Listing::ShortOfTheEnd => {
                let corners: [glam::Vec3A; 8] = std::array::from_fn(|c| {
                    let pick = |bit: usize, lo: f32, hi: f32| if c & bit == 0 { lo } else { hi };
                    carried(glam::Vec3A::new(
                        pick(1, b.min.x, b.max.x),
                        pick(2, b.min.y, b.max.y),
                        pick(4, b.min.z, b.max.z),
                    ))
                });
                Aabb::from_points(&corners)
            }
            Listing::TwoCorners => Aabb::from_points(&[carried(b.min), carried(b.max)]),
            Listing::Untransformed => b,
        }
    }
}

impl World {
    /// Searches the course's uniform grid of `cells` over the scene's box from now on, instead
    /// of the trees. Every sphere and triangle is listed in each cell its box reaches (a box of
    /// the eight corners of its object-space box, under a Transform), a sphere in world space by
    /// the handout's tighter test; planes stay outside the grid.
    pub fn use_grid(&mut self, cells: UVec3) -> Result<(), GridError> {
        self.grid = Some(self.grid_of(cells, Listing::EightCorners)?);
        Ok(())
    }

    /// A grid of `cells` over the box of what it lists, each primitive under a Transform
    /// listed by the box `listed` gives it.
    pub(super) fn grid_of(&self, cells: UVec3, listed: Listing) -> Result<Grid, GridError> {
        let primitives: Vec<(Primitive, Extent)> = self
            .grid_primitives()
            .map(|(primitive, own_box, transform)| {
                let extent = match (transform, self.items[primitive.item as usize], listed) {
                    (_, _, Listing::ShortOfTheEnd) => Extent::BoxShortOfItsEnd(
                        transform.map_or(own_box, |t| Listing::EightCorners.of(own_box, t)),
                    ),
                    (None, Item::Sphere { sphere, .. }, Listing::SphereByCentres) => {
                        Extent::SphereByCentres {
                            center: sphere.center,
                            radius: sphere.radius,
                        }
                    }
                    (None, Item::Sphere { sphere, .. }, _) => Extent::Sphere {
                        center: sphere.center,
                        radius: sphere.radius,
                    },
                    (None, _, _) => Extent::Box(own_box),
                    (Some(t), _, _) => Extent::Box(listed.of(own_box, t)),
                };
                (primitive, extent)
            })
            .collect();
        let bounds = primitives
            .iter()
            .fold(Aabb::EMPTY, |b, (_, e)| b.union(e.reach()));
        Grid::build(bounds, cells, &primitives)
    }

    /// Every sphere and triangle a grid lists, with its box in its own space and the Transform
    /// that places it (`None` in world space), in the order a grid lists them.
    pub fn grid_primitives(&self) -> impl Iterator<Item = (Primitive, Aabb, Option<&Transform>)> {
        self.items.iter().enumerate().flat_map(move |(i, item)| {
            let transform = match item.transform() {
                Item::WORLD_SPACE => None,
                t => Some(&self.transforms[t as usize]),
            };
            let boxes: Vec<Aabb> = match *item {
                Item::Sphere { sphere, .. } => vec![sphere.bounds()],
                Item::Mesh { mesh, .. } => self.meshes[mesh as usize]
                    .triangles()
                    .iter()
                    .map(|v| Aabb::from_points(&[v[0].into(), v[1].into(), v[2].into()]))
                    .collect(),
            };
            boxes.into_iter().enumerate().map(move |(k, own_box)| {
                let primitive = Primitive {
                    item: i as u32,
                    triangle: k as u32,
                };
                (primitive, own_box, transform)
            })
        })
    }

    /// The course's grid, when one is in use.
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// The grid's search: cells in the ray's order (the march's steps set up as `march` says:
    /// the course's, or a student's), every primitive of each, until the nearest hit so far lies
    /// within the cell just searched (a hit further on may be beaten by a primitive of a later
    /// cell, so it is kept but not trusted yet). Inlined, so that the course's march folds
    /// away where it is a constant.
    #[inline(always)]
    pub(super) fn grid_nearest<T: Tally>(
        &self,
        grid: &Grid,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
        march: March,
    ) {
        let t_max = search_limit(nearest);
        let mut local = None;
        grid.walk_marching(ray, t_min, t_max, march, |cell| {
            tally.cell();
            for p in cell.primitives {
                tally.tested(1);
                let limit = search_limit(nearest);
                if let Some(t) = self.intersect_primitive(p, ray, t_min, limit, &mut local) {
                    Nearest::item(t, p.item, p.triangle).replaces(nearest);
                }
            }
            if nearest.is_some_and(|n| n.t <= cell.t_exit) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
    }

    /// One primitive of the grid: a sphere, or one triangle of a mesh, in its item's space.
    /// `local` keeps the ray in the space of the item tested last (with its watertight frame):
    /// a cell's primitives mostly belong to one mesh, so most tests need no new transform.
    #[inline]
    pub(super) fn intersect_primitive(
        &self,
        p: &Primitive,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        local: &mut Option<LocalRay>,
    ) -> Option<f32> {
        let item = &self.items[p.item as usize];
        let here = match local {
            Some(l) if l.item == p.item => l,
            _ => {
                let ray = self.ray_into(item, ray);
                local.insert(LocalRay {
                    item: p.item,
                    frame: ray.to_ray_space(),
                    ray,
                })
            }
        };
        match *item {
            Item::Sphere { sphere, .. } => intersect_sphere(&here.ray, &sphere, t_min, t_max),
            Item::Mesh { mesh, .. } => {
                let triangle = &self.meshes[mesh as usize].triangles()[p.triangle as usize];
                intersect_triangle_in(&here.frame, &here.ray, triangle, t_min, t_max)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, Vec3A};

    fn close(a: Aabb, b: Aabb) -> bool {
        (a.min - b.min).abs().max_element() < 1e-5 && (a.max - b.max).abs().max_element() < 1e-5
    }

    #[test]
    fn a_turned_box_is_reached_by_its_eight_corners_alone() {
        let own = Aabb {
            min: Vec3A::splat(-1.0),
            max: Vec3A::splat(1.0),
        };
        // An eighth of a turn about z, then up by 5.
        let matrix = DMat4::from_translation(glam::DVec3::new(0.0, 5.0, 0.0))
            * DMat4::from_rotation_z(std::f64::consts::FRAC_PI_4);
        let placed = Transform::new(matrix);
        let reach = std::f32::consts::SQRT_2;
        let whole = Aabb {
            min: Vec3A::new(-reach, 5.0 - reach, -1.0),
            max: Vec3A::new(reach, 5.0 + reach, 1.0),
        };
        assert!(close(Listing::EightCorners.of(own, &placed), whole));
        // (−1, −1) and (1, 1) turn onto the y axis: no width left in x.
        let two = Listing::TwoCorners.of(own, &placed);
        assert!(close(
            two,
            Aabb {
                min: Vec3A::new(0.0, 5.0 - reach, -1.0),
                max: Vec3A::new(0.0, 5.0 + reach, 1.0),
            }
        ));
        assert_eq!(Listing::Untransformed.of(own, &placed), own);
    }
}
