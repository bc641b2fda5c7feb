//! What is left along the reference's outlines: every edge half a pixel off (rays through pixel
//! corners), or outline pixels off without that pattern.

use super::pixels::{ALL_STEPS, SIDE_STEPS, distance, neighbours};
use super::{Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Outlines: this share of what is left must lie within a pixel of the reference's edges.
const EDGE_SHARE: f64 = 0.98;
// Half a pixel: this share of what differs must be nearer one half-pixel shift of the reference
// than the reference itself, and what differs must be at least this share of the edge pixels
// (a half-pixel mistake moves outlines everywhere; jitter moves a few).
const HALF_PIXEL_CONSISTENT: f64 = 0.8;
const HALF_PIXEL_COVERAGE: f64 = 0.05;

impl Diagnosis {
    /// Every outline is off by about half a pixel.
    pub const HALF_PIXEL: Diagnosis = Diagnosis::new(
        "pixel_corner",
        6,
        "Every edge is off by about half a pixel: the camera rays go through pixel \
        corners instead of centres; sample at (i + 0.5, j + 0.5).",
    );

    /// Pixels along outlines differ, each within a pixel of an edge, with no half-pixel pattern.
    pub const SILHOUETTE: Diagnosis = Diagnosis::new(
        "silhouette",
        7,
        "Pixels along object outlines differ: check the intersection tests' epsilon and \
        tmin handling, the objects' exact size, and where within each pixel the rays are \
        sampled.",
    );
}

pub(super) fn half_pixel(pair: &Pair, residual: &[usize]) -> bool {
    pair.along_edges(residual)
        .is_some_and(|edge_count| pair.is_half_pixel(residual, edge_count))
}

pub(super) fn silhouette(pair: &Pair, residual: &[usize]) -> bool {
    pair.along_edges(residual).is_some()
}

impl Pair<'_> {
    /// When the `residual` pixels lie along the reference's edges, how many edge pixels the
    /// reference has.
    fn along_edges(&self, residual: &[usize]) -> Option<usize> {
        let (width, height) = (self.width, self.height);
        let edge: Vec<bool> = (0..self.reference.len())
            .map(|i| {
                neighbours(width, height, i, &SIDE_STEPS).any(|next| {
                    channel_difference(self.reference[i], self.reference[next]) > self.tolerance
                })
            })
            .collect();
        let edge_count = edge.iter().filter(|&&is_edge| is_edge).count();
        let near_edge = residual
            .iter()
            .filter(|&&i| edge[i] || neighbours(width, height, i, &ALL_STEPS).any(|n| edge[n]))
            .count();
        ((near_edge as f64) >= EDGE_SHARE * residual.len() as f64).then_some(edge_count)
    }

    /// Whether the `residual` pixels are systematically nearer the reference resampled half a
    /// pixel off, in one direction, than the reference itself. Which corner a student's rays go
    /// through depends on the direction of their rows and columns, so every direction is tried.
    fn is_half_pixel(&self, residual: &[usize], edge_count: usize) -> bool {
        if (residual.len() as f64) < HALF_PIXEL_COVERAGE * edge_count as f64 {
            return false;
        }
        let consistent = ALL_STEPS
            .iter()
            .map(|&(dx, dy)| {
                residual
                    .iter()
                    .filter(|&&i| {
                        let got = self.actual[i];
                        let shifted = self.half_pixel_reference(i, dx, dy);
                        let unshifted = self.reference[i].map(f64::from);
                        distance(got, shifted) + 0.5 < distance(got, unshifted)
                    })
                    .count()
            })
            .max()
            .unwrap_or(0);
        consistent as f64 >= HALF_PIXEL_CONSISTENT * residual.len() as f64
    }

    /// The reference bilinearly resampled half a pixel from `index` toward (dx, dy): the mean of
    /// the pixel and its neighbours that way (clamped at the picture's sides).
    fn half_pixel_reference(&self, index: usize, dx: isize, dy: isize) -> [f64; 3] {
        let (x, y) = (index % self.width, index / self.width);
        let toward = |at: usize, step: isize, length: usize| {
            at.checked_add_signed(step)
                .filter(|&next| next < length)
                .unwrap_or(at)
        };
        let xs = [x, toward(x, dx, self.width)];
        let ys = [y, toward(y, dy, self.height)];
        let mut sum = [0.0_f64; 3];
        for &sample_y in &ys {
            for &sample_x in &xs {
                let colour = self.reference[sample_y * self.width + sample_x];
                for (total, level) in sum.iter_mut().zip(colour) {
                    *total += f64::from(level);
                }
            }
        }
        sum.map(|total| total / 4.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::*;
    use super::super::pixels::neighbours;
    use super::*;
    use crate::check::rule::channel_difference;

    #[test]
    fn sampled_at_pixel_corners() {
        let corners = render(Scene {
            offset: (0.0, 0.0),
            ..Scene::default()
        });
        assert_diagnosed(&corners, &[Diagnosis::HALF_PIXEL]);
    }

    #[test]
    fn a_few_outline_pixels_jittered() {
        // Each edge pixel with the first neighbour (right, left, below, above) it differs from.
        const FIRST_DIFFERENT: [(isize, isize); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
        let reference = reference();
        let (width, height) = (WIDTH as usize, HEIGHT as usize);
        let edges: Vec<(usize, usize)> = (0..width * height)
            .filter_map(|i| {
                neighbours(width, height, i, &FIRST_DIFFERENT)
                    .find(|&j| channel_difference(reference.pixels[i], reference.pixels[j]) > 2)
                    .map(|j| (i, j))
            })
            .collect();
        let mut jittered = reference.clone();
        for &(i, j) in edges.iter().step_by(40) {
            jittered.pixels[i] = reference.pixels[j];
        }
        assert_diagnosed(&jittered, &[Diagnosis::SILHOUETTE]);
    }
}
