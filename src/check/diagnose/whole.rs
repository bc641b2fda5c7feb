//! Causes that move every pixel: the picture flipped, transposed, its channels swapped, or moved
//! by whole pixels. Each is tested by undoing it: the picture must then match nearly everywhere.

use std::ops::Range;

use super::pixels::overlap;
use super::{Budget, Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Global causes. A transform undoing the mistake must leave at most this fraction of pixels off
// (or `max_bad`, if larger: a student's flipped picture may differ slightly besides)...
const GLOBAL_SLACK: f64 = 0.005;
// ...and must leave this many times fewer pixels off than the picture as it is, so that a small
// local difference in a symmetric or plain picture is not taken for a flip or a shift.
const GLOBAL_GAIN: f64 = 4.0;
// The largest whole-pixel shift tried along each axis.
const MAX_SHIFT: isize = 3;

impl Diagnosis {
    /// The picture is upside down.
    pub const FLIPPED_VERTICAL: Diagnosis = Diagnosis::new(
        "flip_vertical",
        8,
        "The picture is upside down: image rows run from the top, while the camera's \
        screen y runs up, so row j is screen y = height - 1 - j (or the up vector is \
        reversed).",
    );

    /// The picture is mirrored left to right.
    pub const FLIPPED_HORIZONTAL: Diagnosis = Diagnosis::new(
        "flip_horizontal",
        8,
        "The picture is mirrored left to right: check the camera's horizontal vector \
        (direction × up, in that order) and the sign of the screen x coordinate.",
    );

    /// Rows and columns exchanged: the pixel at (x, y) written to (y, x).
    pub const TRANSPOSED: Diagnosis = Diagnosis::new(
        "transposed",
        8,
        "The picture is mirrored across its diagonal (rows and columns exchanged): the pixel \
         of column i and row j is stored at index j * width + i, so index i * width + j is \
         the wrong one (or x and y are swapped when the ray is made).",
    );
    /// Red and blue are exchanged.
    pub const CHANNEL_SWAP: Diagnosis = Diagnosis::new(
        "channel_swap",
        8,
        "Red and blue are swapped: the colour channels are written in the wrong order \
        (a TGA file stores blue, green, red).",
    );

    /// The whole picture is moved by a few whole pixels.
    pub const SHIFT: Diagnosis = Diagnosis::new(
        "shift",
        8,
        "The whole picture is moved by whole pixels: check the mapping from pixel \
        indices to screen coordinates for an off-by-one (the image's corner or size).",
    );
}

pub(super) fn flipped_vertical(pair: &Pair, budget: Budget) -> bool {
    let (width, height, actual) = (pair.width, pair.height, pair.actual);
    pair.fits_undone(budget, &(0..width), &(0..height), |x, y| {
        actual[(height - 1 - y) * width + x]
    })
}

pub(super) fn flipped_horizontal(pair: &Pair, budget: Budget) -> bool {
    let (width, height, actual) = (pair.width, pair.height, pair.actual);
    pair.fits_undone(budget, &(0..width), &(0..height), |x, y| {
        actual[y * width + (width - 1 - x)]
    })
}

/// Only a square picture can be transposed into its own shape.
pub(super) fn transposed(pair: &Pair, budget: Budget) -> bool {
    let (width, height, actual) = (pair.width, pair.height, pair.actual);
    width == height
        && pair.fits_undone(budget, &(0..width), &(0..height), |x, y| {
            actual[x * width + y]
        })
}

pub(super) fn channel_swap(pair: &Pair, budget: Budget) -> bool {
    let (width, height, actual) = (pair.width, pair.height, pair.actual);
    pair.fits_undone(budget, &(0..width), &(0..height), |x, y| {
        let [red, green, blue] = actual[y * width + x];
        [blue, green, red]
    })
}

pub(super) fn shifted(pair: &Pair, budget: Budget) -> bool {
    pair.fits_shifted(budget)
}

impl Pair<'_> {
    /// Whether the actual picture, read through `undone` over the reference's pixels `xs` × `ys`,
    /// matches there, and by far better than as it is.
    fn fits_undone(
        &self,
        budget: Budget,
        xs: &Range<usize>,
        ys: &Range<usize>,
        undone: impl Fn(usize, usize) -> [u8; 3],
    ) -> bool {
        let overlap = xs.len() * ys.len();
        if overlap == 0 {
            return false;
        }
        let ceiling = budget.max_bad.max(GLOBAL_SLACK);
        let allowed_fraction = ceiling.min(budget.plain_bad / GLOBAL_GAIN);
        let allowed = (allowed_fraction * overlap as f64).floor() as usize;
        let mut bad = 0;
        for y in ys.clone() {
            for x in xs.clone() {
                if channel_difference(undone(x, y), self.reference[y * self.width + x])
                    > self.tolerance
                {
                    bad += 1;
                    // Most candidates fail within a few pixels: stop there.
                    if bad > allowed {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Whether the actual picture moved by a few whole pixels matches the reference where the two
    /// overlap (the strip uncovered by the move is ignored).
    fn fits_shifted(&self, budget: Budget) -> bool {
        let (width, actual) = (self.width, self.actual);
        (-MAX_SHIFT..=MAX_SHIFT)
            .flat_map(|dy| (-MAX_SHIFT..=MAX_SHIFT).map(move |dx| (dx, dy)))
            .filter(|&shift| shift != (0, 0))
            .any(|(dx, dy)| {
                let xs = overlap(width, dx);
                let ys = overlap(self.height, dy);
                self.fits_undone(budget, &xs, &ys, |x, y| {
                    actual[y.wrapping_add_signed(dy) * width + x.wrapping_add_signed(dx)]
                })
            })
    }
}

#[cfg(test)]
mod tests {
    use super::super::diagnose;
    use super::super::fixtures::*;
    use super::*;
    use crate::shade::Image;

    #[test]
    fn transposed_square_picture() {
        let side = HEIGHT as usize;
        // The reference's left square, and it transposed.
        let square = Image {
            width: HEIGHT,
            height: HEIGHT,
            pixels: reference()
                .pixels
                .chunks(WIDTH as usize)
                .flat_map(|row| row[..side].to_vec())
                .collect(),
        };
        let transposed = Image {
            pixels: (0..side * side)
                .map(|i| square.pixels[(i % side) * side + i / side])
                .collect(),
            ..square.clone()
        };
        assert_eq!(
            diagnose(&transposed, &square, RULE),
            [Diagnosis::TRANSPOSED]
        );
    }

    #[test]
    fn flipped_vertically() {
        let flipped = rearranged(&reference(), |x, y| (x, HEIGHT as usize - 1 - y));
        assert_diagnosed(&flipped, &[Diagnosis::FLIPPED_VERTICAL]);
    }

    #[test]
    fn flipped_horizontally() {
        let flipped = rearranged(&reference(), |x, y| (WIDTH as usize - 1 - x, y));
        assert_diagnosed(&flipped, &[Diagnosis::FLIPPED_HORIZONTAL]);
    }

    #[test]
    fn channels_swapped() {
        let swapped = map_pixels(&reference(), |[r, g, b]| [b, g, r]);
        assert_diagnosed(&swapped, &[Diagnosis::CHANNEL_SWAP]);
    }

    #[test]
    fn shifted_two_pixels_right() {
        let shifted = render(Scene {
            offset: (2.5, 0.5),
            ..Scene::default()
        });
        assert_diagnosed(&shifted, &[Diagnosis::SHIFT]);
    }

    #[test]
    fn shifted_one_pixel_up() {
        let shifted = render(Scene {
            offset: (0.5, -0.5),
            ..Scene::default()
        });
        assert_diagnosed(&shifted, &[Diagnosis::SHIFT]);
    }
}
