//! Pictures that turn on the last digits: where a ray's colour turns on the last digits of its
//! arithmetic (a refracted ray landing on a checkerboard's edge, a grazing shadow), a correct
//! tracer in double precision, or in float with its operations in another order, draws another
//! colour than raycast does. raycast's renders of the line with each pixel's film point nudged
//! by a few ulps of a camera ray show which pixels those are and how far they swing: a
//! picture's pixel may then lie as far from its reference as the nudged renders lie from one
//! another there, and the tolerance beyond. A pixel no nudge moves allows what the rule allows,
//! so a fault that changes pixels a tracer's arithmetic does not is still seen.

use super::rule::Comparison;
use crate::shade::Image;

/// Per pixel and channel, the lowest and highest level a picture may have.
#[derive(Debug, Clone, PartialEq)]
pub struct Envelope {
    width: u32,
    height: u32,
    low: Vec<[u8; 3]>,
    high: Vec<[u8; 3]>,
}

impl Envelope {
    /// `reference` widened, pixel by pixel and channel by channel, by how far `renders` (of
    /// the same picture, nudged) lie from one another; `None` for renders of another size.
    pub fn around(reference: &Image, renders: &[&Image]) -> Option<Envelope> {
        let (width, height) = (reference.width, reference.height);
        let count = width as usize * height as usize;
        if reference.pixels.len() != count
            || renders
                .iter()
                .any(|r| (r.width, r.height, r.pixels.len()) != (width, height, count))
        {
            return None;
        }
        let mut low = reference.pixels.clone();
        let mut high = reference.pixels.clone();
        for (i, (l, h)) in low.iter_mut().zip(&mut high).enumerate() {
            for c in 0..3 {
                let levels = renders.iter().map(|r| r.pixels[i][c]);
                let swing = levels.clone().max().unwrap_or(0) - levels.min().unwrap_or(0);
                l[c] = l[c].saturating_sub(swing);
                h[c] = h[c].saturating_add(swing);
            }
        }
        Some(Envelope {
            width,
            height,
            low,
            high,
        })
    }

    /// How far channel `level` of pixel `i` lies outside the envelope, in levels.
    fn outside(&self, i: usize, pixel: [u8; 3]) -> u8 {
        (0..3)
            .map(|c| {
                let level = pixel[c];
                self.low[i][c]
                    .saturating_sub(level)
                    .max(level.saturating_sub(self.high[i][c]))
            })
            .max()
            .unwrap_or(0)
    }

    /// `actual` against the envelope: a pixel differs where a channel lies further outside it
    /// than `tolerance`. `None` for a picture of another size.
    pub fn compare(&self, actual: &Image, tolerance: u8) -> Option<Comparison> {
        if !self.fits(actual) {
            return None;
        }
        let mut worst = 0_u8;
        let mask: Vec<bool> = actual
            .pixels
            .iter()
            .enumerate()
            .map(|(i, &pixel)| {
                let off = self.outside(i, pixel);
                worst = worst.max(off);
                off > tolerance
            })
            .collect();
        Some(Comparison::of_mask(self.width, self.height, mask, worst))
    }

    /// How many pixels of the rows `wanted` (counted from the top) of `actual` lie outside the
    /// envelope by more than `tolerance`: a part of [`Envelope::compare`]'s count, so where it
    /// is already too many, the whole is too. `None` for a picture of another size.
    pub fn differing_in(&self, actual: &Image, tolerance: u8, wanted: &[bool]) -> Option<usize> {
        if !self.fits(actual) {
            return None;
        }
        let width = self.width.max(1) as usize;
        Some(
            (0..self.height as usize)
                .filter(|&row| wanted.get(row).copied().unwrap_or(false))
                .flat_map(|row| row * width..(row + 1) * width)
                .filter(|&i| self.outside(i, actual.pixels[i]) > tolerance)
                .count(),
        )
    }

    fn fits(&self, actual: &Image) -> bool {
        (actual.width, actual.height) == (self.width, self.height)
            && actual.pixels.len() == self.low.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(levels: &[u8]) -> Image {
        Image {
            width: levels.len() as u32,
            height: 1,
            pixels: levels.iter().map(|&l| [l; 3]).collect(),
        }
    }

    #[test]
    fn a_pixel_may_swing_from_its_reference_as_far_as_the_nudged_renders_do() {
        // Pixel 1 turns on the last digits: 0 in one nudged render, 200 in another.
        let reference = row(&[10, 0, 50]);
        let nudged = [row(&[10, 0, 50]), row(&[10, 200, 50])];
        let envelope = Envelope::around(&reference, &[&nudged[0], &nudged[1]]).unwrap();
        let compared = envelope.compare(&row(&[12, 120, 50]), 2).unwrap();
        assert_eq!(compared.differing, 0);
        assert_eq!(compared.worst, 2);
        // Pixel 0 no render moves: 13 is 3 levels off; pixel 2 is 60 off.
        let compared = envelope.compare(&row(&[13, 120, 110]), 2).unwrap();
        assert_eq!(compared.mask, [true, false, true]);
        assert_eq!(compared.worst, 60);
        assert_eq!(
            envelope.differing_in(&row(&[13, 120, 110]), 2, &[true]),
            Some(2)
        );
        assert_eq!(
            envelope.differing_in(&row(&[13, 120, 110]), 2, &[false]),
            Some(0)
        );
        // Renders that agree with one another widen nothing, whatever the reference.
        let black = row(&[0, 0, 0]);
        let envelope = Envelope::around(&black, &[&reference, &reference]).unwrap();
        assert_eq!(envelope.compare(&reference, 2).unwrap().differing, 2);
    }

    #[test]
    fn renders_or_pictures_of_other_sizes_have_no_envelope() {
        assert_eq!(Envelope::around(&row(&[1, 2]), &[&row(&[1])]), None);
        let envelope = Envelope::around(&row(&[1, 2]), &[]).unwrap();
        assert_eq!(envelope.compare(&row(&[1]), 2), None);
        assert_eq!(envelope.differing_in(&row(&[1]), 2, &[true]), None);
    }
}
