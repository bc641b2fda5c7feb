//! Rays and the shapes they hit, each intersection a small free function over plain data so the
//! acceleration structures can call them without dynamic dispatch.

mod aabb;
mod plane;
mod ray;
mod sphere;
mod transform;
mod triangle;
mod triangle8;

pub use aabb::Aabb;
pub use plane::{Plane, intersect_plane};
pub use ray::{Ray, RayFrame};
pub use sphere::{Sphere, intersect_sphere, sphere_roots};
pub use transform::{Transform, unit_normal};
pub(crate) use triangle::intersect_triangle_in;
pub use triangle::{intersect_triangle, triangle_normal};
pub(crate) use triangle8::{BLOCK as TRIANGLE_BLOCK, RayLanes as TriangleRayLanes, Triangle8};
