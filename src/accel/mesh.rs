use glam::{Vec3, Vec3A};

use super::Bvh;
use crate::geometry::{Aabb, Ray, intersect_triangle};

/// Triangles stored in the order of their BVH's leaves, so a leaf's triangles sit side by side.
#[derive(Debug, Clone, Default)]
pub struct TriangleMesh {
    triangles: Vec<[Vec3; 3]>,
    bvh: Bvh,
}

impl TriangleMesh {
    /// Builds the BVH. Returns the mesh and, for per-triangle data the caller keeps, the input
    /// index of each stored triangle.
    pub fn new(triangles: Vec<[Vec3; 3]>) -> (TriangleMesh, Vec<u32>) {
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| Aabb::from_points(&[t[0].into(), t[1].into(), t[2].into()]))
            .collect();
        let (bvh, order) = Bvh::build(&boxes);
        let triangles = order.iter().map(|&i| triangles[i as usize]).collect();
        (TriangleMesh { triangles, bvh }, order)
    }

    pub fn triangles(&self) -> &[[Vec3; 3]] {
        &self.triangles
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The nearest triangle hit in [t_min, t_max): its t and index.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut found = None;
        self.bvh.traverse(ray, t_min, t_max, |i, t_max| {
            let t = intersect_triangle(ray, &self.triangles[i as usize], t_min, t_max)?;
            found = Some((t, i));
            Some(t)
        });
        found
    }

    /// Every triangle, no tree: the brute-force twin the BVH is tested against.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut best: Option<(f32, u32)> = None;
        for (i, triangle) in self.triangles.iter().enumerate() {
            let limit = best.map_or(t_max, |(t, _)| t);
            if let Some(t) = intersect_triangle(ray, triangle, t_min, limit) {
                best = Some((t, i as u32));
            }
        }
        best
    }

    pub fn size_in_bytes(&self) -> (usize, usize) {
        (
            self.triangles.len() * std::mem::size_of::<[Vec3; 3]>(),
            self.bvh.size_in_bytes(),
        )
    }

    pub fn normal(&self, i: u32) -> Vec3A {
        crate::geometry::triangle_normal(&self.triangles[i as usize])
    }
}
