//! The brute-force twins of the searches: every surface tested, no tree, for the tests to
//! compare the trees and the grid with.

use super::{Found, Hit, Item, Nearest, World, search_limit};
use crate::accel::TriangleMesh;
use crate::geometry::{Ray, Sphere, intersect_sphere};

impl World {
    /// [`World::occluded`] without either tree: its brute-force twin.
    pub fn occluded_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.intersect_brute_force(ray, t_min)
            .is_some_and(|hit| hit.t <= t_max)
    }

    /// The same answer as [`World::intersect`] without either tree: the brute-force twin.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32) -> Option<Hit> {
        self.intersect_each_item(
            ray,
            t_min,
            |item, ray| self.ray_into(item, ray),
            intersect_sphere,
            TriangleMesh::intersect_brute_force,
        )
    }

    /// The nearest hit with every object tested in turn (no tree above them: a ray's t is the
    /// same in every object's space), the ray carried into each object's space by `into`, each
    /// sphere met by `sphere_t` and each mesh by `mesh_t` (the ray in the object's space and the
    /// range of t searched), ties broken as the course's search breaks them: planes, then the
    /// first item. A sphere's normal is taken where its own ray meets it.
    pub(super) fn intersect_each_item(
        &self,
        ray: &Ray,
        t_min: f32,
        into: impl Fn(&Item, &Ray) -> Ray,
        sphere_t: impl Fn(&Ray, &Sphere, f32, f32) -> Option<f32>,
        mesh_t: impl Fn(&TriangleMesh, &Ray, f32, f32) -> Option<(f32, u32)>,
    ) -> Option<Hit> {
        let mut nearest = self.nearest_plane(ray, t_min);
        for (i, item) in self.items.iter().enumerate() {
            let t_max = search_limit(&nearest);
            let local = into(item, ray);
            let hit = match *item {
                Item::Sphere { sphere, .. } => {
                    sphere_t(&local, &sphere, t_min, t_max).map(|t| (t, 0))
                }
                Item::Mesh { mesh, .. } => {
                    mesh_t(&self.meshes[mesh as usize], &local, t_min, t_max)
                }
            };
            if let Some((t, triangle)) = hit {
                Nearest::item(t, i as u32, triangle).replaces(&mut nearest);
            }
        }
        let Nearest { t, found, .. } = nearest?;
        Some(match found {
            Found::Item { item, .. } => match self.items[item as usize] {
                Item::Sphere {
                    sphere, material, ..
                } => {
                    let local = into(&self.items[item as usize], ray);
                    self.hit_with(ray, t, found, (sphere.normal_at(local.at(t)), material))
                }
                Item::Mesh { .. } => self.hit(ray, t, found),
            },
            Found::Plane(_) => self.hit(ray, t, found),
        })
    }
}
