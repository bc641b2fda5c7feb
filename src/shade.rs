//! From hits and colours to pixels: the normal and depth pictures, and the course's rule for
//! turning a colour into bytes, and the 8-bit picture they fill. (The colour itself comes from
//! the tracer.)

use glam::Vec3A;

use crate::accel::Hit;

/// An 8-bit RGB picture, top row first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// In pixels.
    pub width: u32,
    /// In pixels.
    pub height: u32,
    /// `width × height` pixels as R, G, B bytes: rows top first, each from the left.
    pub pixels: Vec<[u8; 3]>,
}

/// How hits and colours become pixels: the seam where a render may make its pictures as a
/// student's tracer would (check's fault library). The defaults are the course's.
pub trait PictureSeam: Copy + Send + Sync {
    /// A colour as bytes.
    #[inline(always)]
    fn to_rgb(&self, colour: Vec3A) -> [u8; 3] {
        to_rgb(colour)
    }

    /// The normals picture's colour of a hit.
    #[inline(always)]
    fn normal_colour(&self, hit: &Hit) -> Vec3A {
        normal_colour(hit)
    }

    /// The depth picture's grey (before [`to_byte`]) at distance `t`.
    #[inline(always)]
    fn depth_grey(&self, t: f32, t_near: f32, t_far: f32) -> f32 {
        depth_grey(t, t_near, t_far)
    }

    /// The normals and depth pictures' pixel where nothing is hit, if not the course's black.
    #[inline(always)]
    fn picture_miss(&self, _background: [u8; 3]) -> Option<[u8; 3]> {
        None
    }
}

impl PictureSeam for crate::variant::Exact {}

/// |n|: the normal's components as a colour.
#[inline]
pub fn normal_colour(hit: &Hit) -> Vec3A {
    hit.normal.abs()
}

/// Near is white, far is black: `t_near` and nearer give 1, `t_far` and farther 0. `t` is the
/// distance along the ray (for the perspective camera, from the eye).
#[inline]
pub fn depth_grey(t: f32, t_near: f32, t_far: f32) -> f32 {
    // In f64: the range itself may overflow f32 (`-depth -3e38 3e38`).
    let (t, near, far) = (f64::from(t), f64::from(t_near), f64::from(t_far));
    ((far - t) / (far - near)).clamp(0.0, 1.0) as f32
}

/// The course's float-to-byte rule: truncate, then clamp (0.2 is 51, 0.8165 is 208).
#[inline]
pub fn to_byte(value: f32) -> u8 {
    ((value * 255.0) as i32).clamp(0, 255) as u8
}

/// A colour as three bytes, each channel by [`to_byte`]'s rule.
#[inline]
pub fn to_rgb(colour: Vec3A) -> [u8; 3] {
    [to_byte(colour.x), to_byte(colour.y), to_byte(colour.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_truncate_then_clamp() {
        assert_eq!(to_byte(0.2), 51);
        assert_eq!(to_byte(0.6), 153);
        assert_eq!(to_byte(0.8165), 208);
        assert_eq!(to_byte(1.7), 255);
        assert_eq!(to_byte(-0.3), 0);
        assert_eq!(to_byte(f32::NAN), 0);
    }

    #[test]
    fn depth_is_white_near_and_black_far() {
        assert_eq!(depth_grey(8.0, 9.0, 11.0), 1.0);
        assert_eq!(depth_grey(10.0, 9.0, 11.0), 0.5);
        assert_eq!(depth_grey(12.0, 9.0, 11.0), 0.0);
        // A range wider than f32 can hold.
        assert_eq!(depth_grey(0.0, -3e38, 3e38), 0.5);
    }
}
