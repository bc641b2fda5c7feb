//! A triangle mesh with its own BVH, built once per mesh file and shared by every placement of
//! it.

use glam::{Vec3, Vec3A};

use super::{Bvh, LeafSize, Tally};
use crate::geometry::{
    Aabb, Ray, Triangle4, TriangleRayLanes, intersect_triangle, triangle_normal,
};

/// A triangle mesh and its BVH. The triangles are stored in the order of the BVH's leaves, and
/// again packed four to a block per leaf, for the SIMD test the traversal uses.
#[derive(Debug, Clone, Default)]
pub struct TriangleMesh {
    triangles: Vec<[Vec3; 3]>,
    blocks: Vec<Triangle4>,
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
        let (mut bvh, order) = Bvh::build(&boxes, LeafSize::TRIANGLES);
        let triangles: Vec<[Vec3; 3]> = order.iter().map(|&i| triangles[i as usize]).collect();
        let mut blocks = Vec::with_capacity(triangles.len() / 2);
        bvh.map_leaves(|first, count| {
            let start = blocks.len() as u32;
            for chunk_start in (first..first + count).step_by(4) {
                let end = (chunk_start + 4).min(first + count);
                blocks.push(Triangle4::new(
                    &triangles[chunk_start as usize..end as usize],
                    chunk_start,
                ));
            }
            (start, blocks.len() as u32 - start)
        });
        (
            TriangleMesh {
                triangles,
                blocks,
                bvh,
            },
            order,
        )
    }

    /// The triangles in the tree's leaf order, which the indices of hits count in.
    pub fn triangles(&self) -> &[[Vec3; 3]] {
        &self.triangles
    }

    /// The tree over the triangles; its leaves point at blocks of four.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The box around every triangle, in the mesh's own space; empty for a mesh of none.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The nearest triangle hit in [t_min, t_max]: its t and index. Of triangles hit at the
    /// same t, the one stored first wins, here and in the brute-force search alike, so that both
    /// name the same triangle (and so the same normal) on a shared edge.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        self.intersect_with(ray, t_min, t_max, &mut ())
    }

    /// [`TriangleMesh::intersect`], counting the triangles tested.
    #[inline(always)]
    pub fn intersect_with<T: Tally>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(f32, u32)> {
        let mut found = None;
        // Set up on the first leaf: many rays that enter a mesh's box never reach one.
        let mut lanes: Option<TriangleRayLanes> = None;
        self.bvh.traverse(ray, t_min, t_max, |block, t_max| {
            let block = &self.blocks[block as usize];
            tally.tested(block.len());
            let lanes = lanes.get_or_insert_with(|| TriangleRayLanes::new(ray));
            let (t, lane) = block.intersect(ray, lanes, t_min, t_max)?;
            let index = block.index[lane];
            if found.is_some_and(|(best, best_index)| t > best || t == best && index > best_index) {
                return None;
            }
            found = Some((t, index));
            Some(t)
        });
        found
    }

    /// Whether any triangle is hit in [t_min, t_max].
    #[inline(always)]
    pub fn occluded<T: Tally>(&self, ray: &Ray, t_min: f32, t_max: f32, tally: &mut T) -> bool {
        let mut lanes: Option<TriangleRayLanes> = None;
        self.bvh.occluded(ray, t_min, t_max, |block| {
            let block = &self.blocks[block as usize];
            tally.tested(block.len());
            let lanes = lanes.get_or_insert_with(|| TriangleRayLanes::new(ray));
            block.intersect(ray, lanes, t_min, t_max).is_some()
        })
    }

    /// Every triangle, one at a time, no tree: the brute-force twin the BVH is tested against.
    pub fn intersect_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut best: Option<(f32, u32)> = None;
        for (i, triangle) in self.triangles.iter().enumerate() {
            let limit = best.map_or(t_max, |(t, _)| t);
            if let Some(t) = intersect_triangle(ray, triangle, t_min, limit) {
                // A tie keeps the earlier triangle.
                if best.is_none_or(|(best_t, _)| t < best_t) {
                    best = Some((t, i as u32));
                }
            }
        }
        best
    }

    /// Bytes of geometry (triangles and their blocks) and of the tree.
    pub fn size_in_bytes(&self) -> (usize, usize) {
        (
            std::mem::size_of_val(&self.triangles[..]) + std::mem::size_of_val(&self.blocks[..]),
            self.bvh.size_in_bytes(),
        )
    }

    /// The front side of triangle `i` (the one its vertices run counter-clockwise from), in the
    /// mesh's own space and not normalised.
    pub fn normal(&self, i: u32) -> Vec3A {
        triangle_normal(&self.triangles[i as usize])
    }
}
