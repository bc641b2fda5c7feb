//! Acceleration: a BVH per triangle mesh, shared by every instance of it, and a top-level BVH
//! over the scene's spheres and mesh instances; unbounded planes are tested beside the trees.

mod bvh;
mod mesh;
mod world;

pub use bvh::{Bvh, LeafSize};
pub use mesh::TriangleMesh;
pub use world::{Hit, Item, World, WorldStats};
