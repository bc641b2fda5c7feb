//! Searches as a student's tracer makes them, for check's fault library: the same surfaces,
//! measured or accepted another way. Slower than the course's searches (no packets, several
//! passes), which is no matter for the course's small pictures.

use std::ops::ControlFlow;

use glam::{Vec3, Vec3A};

use super::{Found, Hit, Item, Listing, Nearest, World, search_limit};
use crate::accel::grid::Primitive;
use crate::accel::{Grid, March, TriangleMesh};
use crate::geometry::{Plane, Ray, Sphere, Transform, intersect_sphere};

/// What a hit lies on, in its object's own space, for [`World::intersect_noting`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Struck {
    /// A plane (its normal is the world's).
    Plane,
    /// A sphere.
    Sphere {
        /// Its radius, in its own space.
        radius: f32,
        /// Whether a Transform places it.
        transformed: bool,
    },
    /// A triangle, of a mesh or of the scene's loose ones.
    Triangle {
        /// Its corners, in its own space.
        corners: [Vec3; 3],
        /// Whether a Transform places it.
        transformed: bool,
    },
}

/// How a student's Transform carries a ray into its object's space, for
/// [`World::intersect_carried`] (the course's: origin and direction by the inverse of the
/// object's matrix, the one as a point, the other as a direction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Carry {
    /// The direction carried as a point, (d, 1): the inverse's translation added to it.
    DirectionAsPoint,
    /// The origin carried as a direction, (o, 0): the inverse's translation left out.
    OriginAsDirection,
    /// Both carried by the object's matrix, not by its inverse: the whole matrix, outer
    /// Transforms times inner (a student's Transform that carries the ray by its own matrix at
    /// each level of nested Transforms multiplies them the other way round).
    ByMatrix,
}

impl Carry {
    /// `ray` in the space of the object that `transform` places, carried this way.
    pub fn ray(self, transform: &Transform, ray: &Ray) -> Ray {
        let inverse = &transform.world_to_object;
        match self {
            Carry::DirectionAsPoint => Ray::new(
                inverse.transform_point3a(ray.origin),
                inverse.transform_point3a(ray.direction),
            ),
            Carry::OriginAsDirection => Ray::new(
                inverse.transform_vector3a(ray.origin),
                inverse.transform_vector3a(ray.direction),
            ),
            Carry::ByMatrix => Ray::new(
                transform.object_to_world.transform_point3a(ray.origin),
                transform.object_to_world.transform_vector3a(ray.direction),
            ),
        }
    }
}

/// The most hits one search skips before it gives up on a ray (a mesh whose every triangle
/// along the ray is refused).
const MOST_REFUSED: usize = 64;

impl World {
    /// The nearest hit when each object measures t along the ray in its own space made unit
    /// length (a tracer that normalises the ray after carrying it into an object's space),
    /// and the objects' t are compared, bounded by `t_min` and reported as such. The reported
    /// t is the world ray's parameter that such a t names.
    pub fn intersect_object_space_t(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        self.intersect_stretched_t(ray, t_min, 1.0)
    }

    /// The nearest hit when each object's t is the world's distance times the object space's
    /// stretch along the ray to the power `power`: 1 is [`World::intersect_object_space_t`], 2
    /// a tracer that measures t in object space and then, to carry it back, multiplies by the
    /// stretch where it should divide, 0 the course's.
    pub fn intersect_stretched_t(&self, ray: &Ray, t_min: f32, power: f32) -> Option<Hit> {
        let world_length = ray.direction.length();
        // The nearest so far: its t as the student measures it, its world parameter, and what.
        let mut nearest: Option<(f32, f32, Found)> = None;
        if let Some(plane) = self.nearest_plane(ray, t_min / world_length) {
            nearest = Some((plane.t * world_length, plane.t, plane.found));
        }
        for (i, item) in self.items.iter().enumerate() {
            let local = self.ray_into(item, ray);
            // What the student's t grows by per unit of the world ray's parameter.
            let length = if power == 1.0 {
                local.direction.length()
            } else {
                world_length * (local.direction.length() / world_length).powf(power)
            };
            let limit = nearest.map_or(f32::INFINITY, |n| n.0 / length);
            let hit = match *item {
                Item::Sphere { sphere, .. } => {
                    intersect_sphere(&local, &sphere, t_min / length, limit).map(|t| (t, 0))
                }
                Item::Mesh { mesh, .. } => {
                    self.meshes[mesh as usize].intersect(&local, t_min / length, limit)
                }
            };
            if let Some((t, triangle)) = hit {
                let found = Found::Item {
                    item: i as u32,
                    triangle,
                };
                nearest = Some((t * length, t, found));
            }
        }
        let (measured, t, found) = nearest?;
        Some(Hit {
            t: measured / world_length,
            ..self.hit(ray, t, found)
        })
    }

    /// The nearest hit that `accepts` takes: a triangle is offered with the ray in its object's
    /// space and its corners there (a tracer whose triangle test refuses some hits the
    /// course's takes); spheres and planes are taken as they are.
    pub fn intersect_accepting(
        &self,
        ray: &Ray,
        t_min: f32,
        accepts: impl Fn(&Ray, &[Vec3; 3]) -> bool,
    ) -> Option<Hit> {
        let mut from = t_min;
        for _ in 0..MOST_REFUSED {
            let mut nearest = self.nearest_plane(ray, from);
            self.nearest_beyond_planes(ray, from, &mut nearest, &mut ());
            let Nearest { t, found, .. } = nearest?;
            if let Found::Item { item, triangle } = found {
                let item = &self.items[item as usize];
                if let Item::Mesh { mesh, .. } = *item {
                    let corners = &self.meshes[mesh as usize].triangles()[triangle as usize];
                    if !accepts(&self.ray_into(item, ray), corners) {
                        from = t.next_up();
                        continue;
                    }
                }
            }
            return Some(self.hit(ray, t, found));
        }
        None
    }

    /// The grid's search stopped at the first cell in which any primitive is hit, whether or
    /// not the hit lies inside that cell (a tracer that trusts a hit before the cells it
    /// crosses later are searched). Without a grid, the course's search.
    pub fn intersect_first_cell(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        let Some(grid) = &self.grid else {
            return self.intersect(ray, t_min);
        };
        let mut nearest = self.nearest_plane(ray, t_min);
        let mut local = None;
        grid.walk(ray, t_min, search_limit(&nearest), |cell| {
            let mut hit_here = false;
            for p in cell.primitives {
                let limit = search_limit(&nearest);
                if let Some(t) = self.intersect_primitive(p, ray, t_min, limit, &mut local) {
                    hit_here |= Nearest::item(t, p.item, p.triangle).replaces(&mut nearest);
                }
            }
            if hit_here {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The grid's search with the march's steps set up as `march` says (a tracer whose march
    /// steps wrongly along an axis the ray runs down: cells skipped, objects in them missed).
    /// Without a grid, the course's search.
    pub fn intersect_marched(&self, ray: &Ray, t_min: f32, march: March) -> Option<Hit> {
        let Some(grid) = &self.grid else {
            return self.intersect(ray, t_min);
        };
        let mut nearest = self.nearest_plane(ray, t_min);
        self.grid_nearest(grid, ray, t_min, &mut nearest, &mut (), march);
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The grid's search through a grid of the same cells whose objects are listed as `listed`
    /// says (a student's listing, not the course's): where it falls short of an object, the
    /// cells it leaves out never find it. Without a grid, the course's search.
    pub fn intersect_listed_by(&self, listed: Listing, ray: &Ray, t_min: f32) -> Option<Hit> {
        let Some(cells) = self.grid.as_ref().map(Grid::cells) else {
            return self.intersect(ray, t_min);
        };
        let slot = match listed {
            Listing::EightCorners => return self.intersect(ray, t_min),
            Listing::TwoCorners => 0,
            Listing::Untransformed => 1,
            Listing::SphereByCentres => 2,
            Listing::ShortOfTheEnd => 3,
        };
        let grid = self.students_grids[slot].get_or_init(|| self.grid_of(cells, listed).ok());
        let Some(grid) = grid else {
            return self.intersect(ray, t_min);
        };
        let mut nearest = self.nearest_plane(ray, t_min);
        self.grid_nearest(grid, ray, t_min, &mut nearest, &mut (), March::Course);
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The grid's search as a tracer that walks the grid only from outside its box: a ray that
    /// begins inside it (every shadow, mirror and glass ray leaving a surface in the grid)
    /// meets the planes alone. Without a grid, the course's search.
    pub fn intersect_walked_from_outside(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        match &self.grid {
            Some(grid) if grid.bounds().contains(ray.origin) => {
                let nearest = self.nearest_plane(ray, t_min);
                nearest.map(|n| self.hit(ray, n.t, n.found))
            }
            _ => self.intersect(ray, t_min),
        }
    }

    /// The grid's search with each primitive tested once (mailboxed) and a hit beyond the cell
    /// that tested it dropped for good (a tracer that marks a primitive as tested before it
    /// knows whether its hit counts there): an object reaching over several cells, met beyond
    /// the first, vanishes along those rays. Without a grid, the course's search.
    pub fn intersect_mailboxed(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        let Some(grid) = &self.grid else {
            return self.intersect(ray, t_min);
        };
        let mut nearest = self.nearest_plane(ray, t_min);
        let mut local = None;
        let mut tested: Vec<Primitive> = Vec::new();
        grid.walk(ray, t_min, search_limit(&nearest), |cell| {
            for p in cell.primitives {
                if tested.contains(p) {
                    continue;
                }
                tested.push(*p);
                let limit = search_limit(&nearest).min(cell.t_exit);
                if let Some(t) = self.intersect_primitive(p, ray, t_min, limit, &mut local) {
                    Nearest::item(t, p.item, p.triangle).replaces(&mut nearest);
                }
            }
            if nearest.is_some_and(|n| n.t <= cell.t_exit) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The nearest hit with each plane met where `plane_t` says (the ray, the plane, and the
    /// range of t searched; `None` for no hit): a tracer whose planes are tested another way,
    /// or not at all. Everything else is searched as the course's.
    pub fn intersect_planes_by(
        &self,
        ray: &Ray,
        t_min: f32,
        plane_t: impl Fn(&Ray, &Plane, f32, f32) -> Option<f32>,
    ) -> Option<Hit> {
        let mut nearest = None;
        for (i, (plane, _)) in self.planes.iter().enumerate() {
            if let Some(t) = plane_t(ray, plane, t_min, search_limit(&nearest)) {
                Nearest::plane(t, i as u32).replaces(&mut nearest);
            }
        }
        self.nearest_beyond_planes(ray, t_min, &mut nearest, &mut ());
        nearest.map(|n| self.hit(ray, n.t, n.found))
    }

    /// The nearest hit with each sphere met where `sphere_t` says (the ray in the sphere's own
    /// space, the sphere, and the range of t searched; `None` for no hit): a tracer whose
    /// sphere test takes another root of its quadratic. Planes and triangles as the course's.
    pub fn intersect_spheres_by(
        &self,
        ray: &Ray,
        t_min: f32,
        sphere_t: impl Fn(&Ray, &Sphere, f32, f32) -> Option<f32>,
    ) -> Option<Hit> {
        self.intersect_each_item(
            ray,
            t_min,
            |item, ray| self.ray_into(item, ray),
            sphere_t,
            TriangleMesh::intersect,
        )
    }

    /// The nearest hit when each object under a Transform meets the ray carried into its
    /// space as `carry` says: a tracer whose Transform moves the ray another way than by the
    /// inverse of its matrix, points as points and directions as directions. Each object's t
    /// is still the world ray's parameter, as the course's Transform keeps it.
    pub fn intersect_carried(&self, ray: &Ray, t_min: f32, carry: Carry) -> Option<Hit> {
        self.intersect_each_item(
            ray,
            t_min,
            |item, ray| match item.transform() {
                Item::WORLD_SPACE => *ray,
                t => carry.ray(&self.transforms[t as usize], ray),
            },
            intersect_sphere,
            TriangleMesh::intersect,
        )
    }

    /// The course's nearest hit, and what it lies on: for a tracer that makes its normals
    /// another way (from a triangle's corners, a sphere's radius), in one search.
    pub fn intersect_noting(&self, ray: &Ray, t_min: f32) -> Option<(Hit, Struck)> {
        let mut nearest = self.nearest_plane(ray, t_min);
        self.nearest_beyond_planes(ray, t_min, &mut nearest, &mut ());
        let Nearest { t, found, .. } = nearest?;
        let struck = match found {
            Found::Plane(_) => Struck::Plane,
            Found::Item { item, triangle } => {
                let item = &self.items[item as usize];
                let transformed = item.transform() != Item::WORLD_SPACE;
                match *item {
                    Item::Sphere { sphere, .. } => Struck::Sphere {
                        radius: sphere.radius,
                        transformed,
                    },
                    Item::Mesh { mesh, .. } => Struck::Triangle {
                        corners: self.meshes[mesh as usize].triangles()[triangle as usize],
                        transformed,
                    },
                }
            }
        };
        Some((self.hit(ray, t, found), struck))
    }

    /// The scene's planes, each with its material: for a tracer that tests them its own way.
    pub fn planes(&self) -> &[(Plane, u32)] {
        &self.planes
    }

    /// The t of `ray`'s hit on the grid's primitive `p` within `t_min..t_max`: for a tracer that
    /// walks the grid its own way.
    pub fn primitive_t(&self, p: &Primitive, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        self.intersect_primitive(p, ray, t_min, t_max, &mut None)
    }

    /// The centre and radius of the grid's primitive `p` in its own space, where it is a
    /// sphere: for a tracer that lists spheres in its own grid its own way.
    pub fn primitive_sphere(&self, p: &Primitive) -> Option<(Vec3A, f32)> {
        match self.items.get(p.item as usize)? {
            Item::Sphere { sphere, .. } => Some((sphere.center, sphere.radius)),
            Item::Mesh { .. } => None,
        }
    }

    /// The hit of `ray` at `t` on the grid's primitive `p`.
    pub fn primitive_hit(&self, ray: &Ray, t: f32, p: &Primitive) -> Hit {
        let found = Found::Item {
            item: p.item,
            triangle: p.triangle,
        };
        self.hit(ray, t, found)
    }

    /// The nearest hit of `ray` from `t_min` on among the planes, which stand outside the grid.
    pub fn plane_hit(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        let nearest = self.nearest_plane(ray, t_min)?;
        Some(self.hit(ray, nearest.t, nearest.found))
    }
}
