//! Acceleration: a BVH per triangle mesh, shared by every instance of it, and a top-level BVH
//! over the scene's spheres and mesh instances; unbounded planes are tested beside the trees.

mod bvh;
pub mod grid;
mod mesh;
mod world;

/// Test data for the acceleration structures' tests: the next number in [0, 1) of a small
/// linear congruential generator whose state is `state`.
#[cfg(test)]
pub(crate) fn test_uniform(state: &mut u64) -> f32 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*state >> 40) as f32 / (1_u64 << 24) as f32
}

pub use bvh::{Bvh, LeafSize, PACKET, PacketBounds, PartLanes, ray_meets_box};
pub use grid::{Grid, GridError, March};
pub use mesh::{ASKS_NOTHING, TriangleMesh};
pub use world::{Carry, Hit, Item, Listing, Struck, World, WorldStats};

/// What a search counts for the course's `-stats`: primitives tested (whether hit or not) and
/// grid cells entered. The searches are generic over it, so that `()`, which counts nothing,
/// costs nothing.
pub trait Tally {
    /// Counts `primitives` more intersection tests, hit or not.
    fn tested(&mut self, primitives: u32);
    /// Counts one more grid cell entered.
    fn cell(&mut self);
}

impl Tally for () {
    #[inline(always)]
    fn tested(&mut self, _: u32) {}
    #[inline(always)]
    fn cell(&mut self) {}
}

/// The course's counts of intersection tests and grid cells.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Tallies {
    /// Primitives tested, hit or not, over all the rays counted (a block of triangles counts
    /// as many as it holds).
    pub intersections: u64,
    /// Grid cells entered, over all the rays counted; 0 without a grid.
    pub cells: u64,
}

impl Tally for Tallies {
    #[inline(always)]
    fn tested(&mut self, primitives: u32) {
        self.intersections += u64::from(primitives);
    }
    #[inline(always)]
    fn cell(&mut self) {
        self.cells += 1;
    }
}
