//! Fits: a stage of a student's tracer as a family of forms with numbers in them, the numbers
//! found by rendering the line under the family and bringing the render as close as it comes to
//! the student's picture, and the fault named from what was found. A list of faults names only
//! the forms someone thought of; a fit also names a mistake written another way, by where its
//! numbers land (an offset of half a pixel is a ray through a pixel's corner, whatever the
//! formula that put it there).

mod camera;
mod depth;
mod line;
mod minimise;
mod parameters;
mod shading;
mod texture;

pub use camera::Named;
pub use line::{Picture, Trial, fit_line};
