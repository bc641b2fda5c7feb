//! The searches through the course's grid, under `-grid`: cells in the ray's order instead of
//! the trees, with the same hits.

use std::ops::ControlFlow;

use glam::UVec3;

use super::{Item, LocalRay, Nearest, World, search_limit};
use crate::accel::grid::{Extent, Primitive};
use crate::accel::{Grid, GridError, Tally};
use crate::geometry::{Aabb, Ray, intersect_sphere, intersect_triangle_in};

impl World {
    /// Searches the course's uniform grid of `cells` over the scene's box from now on, instead
    /// of the trees. Every sphere and triangle is listed in each cell its box reaches (a box of
    /// the eight corners of its object-space box, under a Transform), a sphere in world space by
    /// the handout's tighter test; planes stay outside the grid.
    pub fn use_grid(&mut self, cells: UVec3) -> Result<(), GridError> {
        let mut primitives = Vec::new();
        for (i, item) in self.items.iter().enumerate() {
            let transform = match item.transform() {
                Item::WORLD_SPACE => None,
                t => Some(&self.transforms[t as usize]),
            };
            let placed = |b: Aabb| match transform {
                None => b,
                Some(t) => {
                    let corners: [glam::Vec3A; 8] = std::array::from_fn(|c| {
                        let pick =
                            |bit: usize, lo: f32, hi: f32| if c & bit == 0 { lo } else { hi };
                        t.object_to_world.transform_point3a(glam::Vec3A::new(
                            pick(1, b.min.x, b.max.x),
                            pick(2, b.min.y, b.max.y),
                            pick(4, b.min.z, b.max.z),
                        ))
                    });
                    Aabb::from_points(&corners)
                }
            };
            match *item {
                Item::Sphere { sphere, .. } => {
                    let extent = match transform {
                        None => Extent::Sphere {
                            center: sphere.center,
                            radius: sphere.radius,
                        },
                        Some(_) => Extent::Box(placed(sphere.bounds())),
                    };
                    let primitive = Primitive {
                        item: i as u32,
                        triangle: 0,
                    };
                    primitives.push((primitive, extent));
                }
                Item::Mesh { mesh, .. } => {
                    for (k, v) in self.meshes[mesh as usize].triangles().iter().enumerate() {
                        let b = Aabb::from_points(&[v[0].into(), v[1].into(), v[2].into()]);
                        let primitive = Primitive {
                            item: i as u32,
                            triangle: k as u32,
                        };
                        primitives.push((primitive, Extent::Box(placed(b))));
                    }
                }
            }
        }
        let bounds = primitives.iter().fold(Aabb::EMPTY, |b, (_, e)| {
            b.union(match *e {
                Extent::Box(b) => b,
                Extent::Sphere { center, radius } => Aabb {
                    min: center - radius,
                    max: center + radius,
                },
            })
        });
        self.grid = Some(Grid::build(bounds, cells, &primitives)?);
        Ok(())
    }

    /// The course's grid, when one is in use.
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// The grid's search: cells in the ray's order, every primitive of each, until the nearest
    /// hit so far lies within the cell just searched (a hit further on may be beaten by a
    /// primitive of a later cell, so it is kept but not trusted yet).
    pub(super) fn grid_nearest<T: Tally>(
        &self,
        grid: &Grid,
        ray: &Ray,
        t_min: f32,
        nearest: &mut Option<Nearest>,
        tally: &mut T,
    ) {
        let t_max = search_limit(nearest);
        let mut local = None;
        grid.walk(ray, t_min, t_max, |cell| {
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
