//! The samples picture (`-render_samples FILE ZOOM`) of a line whose samples fall by chance:
//! each pixel a ZOOM×ZOOM block, dark grey and black in a checkerboard (grey at the lower-left
//! pixel), each sample one dot of its own colour where it falls. Another random generator puts
//! the dots elsewhere, so the picture is graded by what must hold wherever they fall: every
//! pixel is its block's background or a dot; a dot's colour is the scene's at the dot (raycast's
//! render of the line at ZOOM times its size, at the dot or a pixel beside it, for a sample on
//! an edge); a block holds at most as many dots as the line has samples; and jittered samples
//! fall one in each cell of the pixel's grid. (Fewer dots than samples is allowed: two samples
//! may fall on one dot, and a sample of the block's own colour does not show.)

use super::rule::{Comparison, channel_difference};
use crate::shade::{Image, to_rgb};

/// What a samples picture of a line must hold to.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplesRule {
    /// The line's picture size, in pixels.
    pub width: u32,
    pub height: u32,
    /// Each pixel's block, in picture pixels a side.
    pub zoom: u32,
    /// The samples a pixel.
    pub samples: u32,
    /// Whether the samples are jittered (one a cell of an s×s grid), not random.
    pub jittered: bool,
    /// The scene's colour at the centre of every picture pixel: raycast's render of the line,
    /// ZOOM times as large.
    pub scene: Image,
}

impl SamplesRule {
    /// `actual` against the rule: the pixels that break it are the differing ones. `None`
    /// where it is not of the samples picture's size.
    pub fn compare(&self, actual: &Image, tolerance: u8) -> Option<Comparison> {
        let (w, h) = (self.width * self.zoom, self.height * self.zoom);
        if (actual.width, actual.height) != (w, h)
            || actual.pixels.len() != (w * h) as usize
            || self.scene.pixels.len() != actual.pixels.len()
        {
            return None;
        }
        let (w, zoom) = (w as usize, self.zoom as usize);
        let grey = to_rgb(glam::Vec3A::splat(0.2));
        let mut mask = vec![false; actual.pixels.len()];
        for j in 0..self.height as usize {
            for i in 0..self.width as usize {
                // Block (i, j) counted from the lower left; its rows are the picture's from the
                // top.
                let from_bottom = self.height as usize - 1 - j;
                let background = if (i + from_bottom).is_multiple_of(2) {
                    grey
                } else {
                    [0, 0, 0]
                };
                let mut dots: Vec<(usize, usize, usize)> = Vec::new();
                for ly in 0..zoom {
                    for lx in 0..zoom {
                        let index = (j * zoom + ly) * w + i * zoom + lx;
                        let colour = actual.pixels[index];
                        if channel_difference(colour, background) <= tolerance {
                            continue;
                        }
                        if !self.scene_near(index, colour, tolerance) {
                            mask[index] = true;
                        }
                        // From the block's lower-left corner: x right, y up.
                        dots.push((index, lx, zoom - 1 - ly));
                    }
                }
                let too_many = dots.len() > self.samples as usize;
                if too_many || (self.jittered && !self.one_a_cell(&dots)) {
                    for &(index, _, _) in &dots {
                        mask[index] = true;
                    }
                }
            }
        }
        let differing = mask.iter().filter(|&&bad| bad).count();
        Some(Comparison {
            width: actual.width,
            height: actual.height,
            differing,
            bad_fraction: differing as f64 / mask.len().max(1) as f64,
            worst: if differing > 0 { 255 } else { 0 },
            mask,
        })
    }

    /// Whether the scene's colour at picture pixel `index`, or at one beside it, is `colour`.
    fn scene_near(&self, index: usize, colour: [u8; 3], tolerance: u8) -> bool {
        let w = self.scene.width as usize;
        let h = self.scene.height as usize;
        let (x, y) = (index % w, index / w);
        (y.saturating_sub(1)..(y + 2).min(h)).any(|ny| {
            (x.saturating_sub(1)..(x + 2).min(w))
                .any(|nx| channel_difference(self.scene.pixels[ny * w + nx], colour) <= tolerance)
        })
    }

    /// Whether the dots (block-local x and y, from the lower left) can each be given a cell of
    /// the s×s grid of their own that the dot's pixel reaches (a dot on a cell's border may be
    /// in either).
    fn one_a_cell(&self, dots: &[(usize, usize, usize)]) -> bool {
        let side = self.samples.isqrt().max(1) as usize;
        let zoom = self.zoom as usize;
        // The cells a pixel [p, p + 1) of the block reaches along one axis.
        let cells = |p: usize| {
            let first = p * side / zoom;
            let last = ((p + 1) * side)
                .div_ceil(zoom)
                .saturating_sub(1)
                .min(side - 1);
            first..=last.max(first)
        };
        let reach: Vec<Vec<usize>> = dots
            .iter()
            .map(|&(_, x, y)| {
                cells(y)
                    .flat_map(|cy| cells(x).map(move |cx| cy * side + cx))
                    .collect()
            })
            .collect();
        // Each dot matched to a cell of its own, by augmenting paths (a few dots, a few cells).
        let mut owner: Vec<Option<usize>> = vec![None; side * side];
        fn place(
            dot: usize,
            reach: &[Vec<usize>],
            owner: &mut [Option<usize>],
            seen: &mut [bool],
        ) -> bool {
            for &cell in &reach[dot] {
                if seen[cell] {
                    continue;
                }
                seen[cell] = true;
                if owner[cell].is_none_or(|other| place(other, reach, owner, seen)) {
                    owner[cell] = Some(dot);
                    return true;
                }
            }
            false
        }
        (0..dots.len()).all(|dot| {
            let mut seen = vec![false; side * side];
            place(dot, &reach, &mut owner, &mut seen)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×1 line of 4 jittered samples, zoom 4, over a scene of one flat colour.
    fn rule(jittered: bool) -> SamplesRule {
        SamplesRule {
            width: 2,
            height: 1,
            zoom: 4,
            samples: 4,
            jittered,
            scene: Image {
                width: 8,
                height: 4,
                pixels: vec![[200, 10, 10]; 32],
            },
        }
    }

    /// The samples picture with dots at `dots` (picture x, y from the top).
    fn picture(dots: &[(usize, usize)]) -> Image {
        let grey = to_rgb(glam::Vec3A::splat(0.2));
        let mut pixels: Vec<[u8; 3]> = (0..32)
            .map(|k| if (k % 8) / 4 == 0 { grey } else { [0, 0, 0] })
            .collect();
        for &(x, y) in dots {
            pixels[y * 8 + x] = [200, 10, 10];
        }
        Image {
            width: 8,
            height: 4,
            pixels,
        }
    }

    #[test]
    fn dots_one_a_cell_pass_wherever_they_fall_in_it() {
        let one_a_cell = picture(&[
            (0, 0),
            (3, 1),
            (1, 2),
            (2, 3),
            (5, 0),
            (6, 1),
            (4, 3),
            (7, 2),
        ]);
        assert_eq!(rule(true).compare(&one_a_cell, 2).unwrap().differing, 0);
        // Two in the first block's upper-left cell: not jittered, but random.
        let two_in_a_cell = picture(&[(0, 0), (1, 1), (1, 2), (2, 3)]);
        assert_eq!(rule(true).compare(&two_in_a_cell, 2).unwrap().differing, 4);
        assert_eq!(rule(false).compare(&two_in_a_cell, 2).unwrap().differing, 0);
    }

    #[test]
    fn too_many_dots_or_a_colour_not_the_scenes_break_the_rule() {
        let five = picture(&[(0, 0), (1, 0), (2, 0), (3, 0), (0, 3)]);
        assert_eq!(rule(false).compare(&five, 2).unwrap().differing, 5);
        let mut wrong = picture(&[(5, 1)]);
        wrong.pixels[8 + 5] = [10, 200, 10];
        assert_eq!(rule(false).compare(&wrong, 2).unwrap().differing, 1);
        assert!(rule(false).compare(&picture(&[]).clone(), 2).is_some());
    }
}
