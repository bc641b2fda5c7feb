//! The depth picture's range, fitted: the course's grey is (TMAX - t) / (TMAX - TMIN), straight
//! in t, and so is a student's that counts from other distances (the picture's own nearest
//! hit, a range as long as the command line's but shifted). Where neither picture is clamped,
//! the student's grey is then a straight function of the reference's, and the line through
//! them gives the distances the student counted from, whatever the code that chose them.

use crate::shade::Image;

/// Greys strictly inside this range are not clamped...
const UNCLAMPED: std::ops::RangeInclusive<u8> = 1..=254;
/// ...and a fit needs this many pixels of them.
const MIN_PIXELS: usize = 50;
/// A fitted distance this close to the command line's (as a share of its range: half a grey
/// level) is it.
const SAME_DISTANCE: f64 = 0.5 / 255.0;

/// The near and far distance whose depth picture is `actual`, where the reference was drawn
/// for `near` and `far`; `None` where too few pixels are unclamped in both, or the greys do
/// not fall as the reference's do.
pub fn fit_depth_range(
    near: f32,
    far: f32,
    actual: &Image,
    reference: &Image,
) -> Option<(f32, f32)> {
    if (actual.width, actual.height) != (reference.width, reference.height) || far <= near {
        return None;
    }
    let pairs: Vec<(f64, f64)> = actual
        .pixels
        .iter()
        .zip(&reference.pixels)
        .filter(|(a, r)| UNCLAMPED.contains(&a[0]) && UNCLAMPED.contains(&r[0]))
        .map(|(a, r)| (f64::from(r[0]) / 255.0, f64::from(a[0]) / 255.0))
        .collect();
    if pairs.len() < MIN_PIXELS {
        return None;
    }
    let n = pairs.len() as f64;
    let (mean_r, mean_a) = pairs
        .iter()
        .fold((0.0, 0.0), |(r, a), &(x, y)| (r + x / n, a + y / n));
    let (covariance, variance) = pairs.iter().fold((0.0, 0.0), |(c, v), &(x, y)| {
        (c + (x - mean_r) * (y - mean_a), v + (x - mean_r).powi(2))
    });
    if variance <= 0.0 {
        return None;
    }
    let slope = covariance / variance;
    let offset = mean_a - slope * mean_r;
    if slope <= 0.05 {
        return None;
    }
    // reference = (far - t) / (far - near), student = (b - t) / (b - a): the student's is
    // slope · reference + offset with slope = (far - near) / (b - a), offset = (b - far) / (b - a).
    let (near, far) = (f64::from(near), f64::from(far));
    let length = (far - near) / slope;
    let b = far + offset * length;
    let a = b - length;
    let snap = |value: f64, to: f64| {
        if (value - to).abs() <= SAME_DISTANCE * (far - near) {
            to
        } else {
            value
        }
    };
    Some((snap(a, near) as f32, snap(b, far) as f32))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A depth picture of a ramp of distances from 8 to 12 drawn for the range `near..far`.
    fn ramp(near: f32, far: f32) -> Image {
        let pixels = (0..200)
            .map(|i| {
                let t = 8.0 + 4.0 * i as f32 / 199.0;
                let grey = ((far - t) / (far - near)).clamp(0.0, 1.0);
                let level = (grey * 255.0).round() as u8;
                [level; 3]
            })
            .collect();
        Image {
            width: 200,
            height: 1,
            pixels,
        }
    }

    #[test]
    fn a_range_from_the_nearest_hit_is_found_from_the_greys() {
        let reference = ramp(7.0, 13.0);
        let (a, b) = fit_depth_range(7.0, 13.0, &ramp(8.0, 14.0), &reference).unwrap();
        assert!((a - 8.0).abs() < 0.02 && (b - 14.0).abs() < 0.02, "{a} {b}");
        let (a, b) = fit_depth_range(7.0, 13.0, &ramp(8.0, 13.0), &reference).unwrap();
        assert!((a - 8.0).abs() < 0.02 && (b - 13.0).abs() < 0.02, "{a} {b}");
        assert_eq!(
            fit_depth_range(7.0, 13.0, &reference, &reference),
            Some((7.0, 13.0))
        );
    }

    #[test]
    fn greys_that_do_not_fall_with_distance_fit_nothing() {
        let reference = ramp(7.0, 13.0);
        let mut inverted = reference.clone();
        for p in &mut inverted.pixels {
            *p = [255 - p[0]; 3];
        }
        assert_eq!(fit_depth_range(7.0, 13.0, &inverted, &reference), None);
    }
}
