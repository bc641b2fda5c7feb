//! Acceleration: a BVH per triangle mesh, shared by every instance of it, and a top-level BVH
//! over the scene's spheres and mesh instances; unbounded planes are tested beside the trees.

mod bvh;
pub mod grid;
mod mesh;
mod world;

pub use bvh::{Bvh, LeafSize, PACKET, PacketBounds, PartLanes, ray_meets_box};
pub use grid::{Grid, GridError};
pub use mesh::{ASKS_NOTHING, TriangleMesh};
pub use world::{Hit, Item, World, WorldStats};

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
