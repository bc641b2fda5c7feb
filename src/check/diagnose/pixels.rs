//! Pixel helpers the causes share: borders, neighbours, connected regions.

use std::cmp::Reverse;
use std::collections::HashMap;
use std::ops::Range;

use crate::check::rule::channel_difference;

// Neighbours as (dx, dy), y down.
pub(super) const SIDE_STEPS: [(isize, isize); 4] = [(0, -1), (-1, 0), (1, 0), (0, 1)];
pub(super) const ALL_STEPS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// The sum of the channels' differences.
pub(super) fn distance(colour: [u8; 3], to: [f64; 3]) -> f64 {
    colour
        .iter()
        .zip(to)
        .map(|(&level, target)| (f64::from(level) - target).abs())
        .sum()
}

/// The reference's pixels off `length` where a picture moved by `offset` still covers them.
pub(super) fn overlap(length: usize, offset: isize) -> Range<usize> {
    let uncovered = offset.unsigned_abs().min(length);
    if offset >= 0 {
        0..length - uncovered
    } else {
        uncovered..length
    }
}

/// The colours along a picture's border (empty for a picture without pixels).
pub(super) fn border(pixels: &[[u8; 3]], width: usize, height: usize) -> Vec<[u8; 3]> {
    if width == 0 || height == 0 || pixels.len() < width * height {
        return Vec::new();
    }
    let top = &pixels[..width];
    let bottom = &pixels[(height - 1) * width..height * width];
    let sides = (0..height).flat_map(|y| [pixels[y * width], pixels[y * width + width - 1]]);
    top.iter().chain(bottom).copied().chain(sides).collect()
}

/// The most common colour along a picture's border: its background.
pub(super) fn border_mode(pixels: &[[u8; 3]], width: usize, height: usize) -> [u8; 3] {
    most_common(border(pixels, width, height).into_iter()).unwrap_or_default()
}

/// The share of the border's pixels within `tolerance` of `colour`.
pub(super) fn border_share(
    pixels: &[[u8; 3]],
    width: usize,
    height: usize,
    colour: [u8; 3],
    tolerance: u8,
) -> f64 {
    let border = border(pixels, width, height);
    if border.is_empty() {
        return 0.0;
    }
    let near = border
        .iter()
        .filter(|&&c| channel_difference(c, colour) <= tolerance)
        .count();
    near as f64 / border.len() as f64
}

/// The most frequent colour (the least, by value, among equals, so that the answer does not
/// depend on hashing); `None` when there are none.
pub(super) fn most_common(colours: impl Iterator<Item = [u8; 3]>) -> Option<[u8; 3]> {
    let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
    for colour in colours {
        *counts.entry(colour).or_insert(0) += 1;
    }
    counts
        .into_iter()
        .max_by_key(|&(colour, count)| (count, Reverse(colour)))
        .map(|(colour, _)| colour)
}

/// The pixels `steps` away from `index` that lie inside the picture.
pub(super) fn neighbours(
    width: usize,
    height: usize,
    index: usize,
    steps: &'static [(isize, isize)],
) -> impl Iterator<Item = usize> {
    let (x, y) = (index % width, index / width);
    steps.iter().filter_map(move |&(dx, dy)| {
        let next_x = x.checked_add_signed(dx).filter(|&next| next < width)?;
        let next_y = y.checked_add_signed(dy).filter(|&next| next < height)?;
        Some(next_y * width + next_x)
    })
}

/// The 8-connected regions of the pixels in `member`, each as its pixels' indices.
pub(super) fn regions(member: &[bool], width: usize, height: usize) -> Vec<Vec<usize>> {
    let mut seen = vec![false; member.len()];
    let mut found = Vec::new();
    let mut stack = Vec::new();
    for (start, &is_member) in member.iter().enumerate() {
        if !is_member || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut region = Vec::new();
        while let Some(index) = stack.pop() {
            region.push(index);
            for next in neighbours(width, height, index, &ALL_STEPS) {
                if member[next] && !seen[next] {
                    seen[next] = true;
                    stack.push(next);
                }
            }
        }
        found.push(region);
    }
    found
}
