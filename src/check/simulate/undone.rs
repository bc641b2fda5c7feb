//! Pictures undone by the faults that only move their pixels (a flip, the channels swapped): a
//! render that matches a picture so undone is that fault with another.

use crate::shade::Image;

/// Takes a fault that only moves pixels out of a picture.
pub(super) type Undo = fn(&Image) -> Image;

/// Faults that only move a picture's pixels, each with the function that undoes it.
pub(super) const PERMUTATIONS: [(&str, Undo); 3] = [
    ("flip_vertical", flipped_vertically),
    ("flip_horizontal", flipped_horizontally),
    ("channel_swap", channels_swapped),
];

fn flipped_vertically(image: &Image) -> Image {
    let width = image.width as usize;
    Image {
        pixels: image
            .pixels
            .chunks(width.max(1))
            .rev()
            .flatten()
            .copied()
            .collect(),
        ..*image
    }
}

fn flipped_horizontally(image: &Image) -> Image {
    let width = image.width as usize;
    Image {
        pixels: image
            .pixels
            .chunks(width.max(1))
            .flat_map(|row| row.iter().rev().copied())
            .collect(),
        ..*image
    }
}

fn channels_swapped(image: &Image) -> Image {
    Image {
        pixels: image.pixels.iter().map(|&[r, g, b]| [b, g, r]).collect(),
        ..*image
    }
}
