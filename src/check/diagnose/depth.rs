//! Depth pictures whose objects are off by factors of their own: t measured in an object's space.

use super::curve::FIT_MIN_SAMPLES;
use super::pixels::{ALL_STEPS, SIDE_STEPS, neighbours};
use super::{Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Depth per object: the reference's surfaces are split where neighbouring levels jump by more
// than this; a surface counts when it has this many pixels, and a surface is kept, or fitted by
// a map, when this share of its pixels agree. Two maps agree within this many levels.
const SURFACE_STEP: u8 = 8;
const SURFACE_MIN_PIXELS: usize = 50;
const SURFACE_SHARE: f64 = 0.9;
const MAP_AGREEMENT: f64 = 8.0;
// How far, in pixels, a surface's steep rim reaches beyond it.
const RIM_WIDTH: usize = 2;

impl Diagnosis {
    /// In a depth picture, some objects' depths are off by factors of their own while others
    /// match: the hit's t was measured in an object's space, under a scaling Transform.
    pub const OBJECT_SPACE_T: Diagnosis = Diagnosis::new(
        "object_space_t",
        5,
        "Some objects' depths are off by factors of their own while others match: t is \
        measured in the object's space under a scaling Transform. Keep the transformed \
        ray's direction unnormalized, so that its t is the world ray's t (or convert t \
        back), and compare hits by world t.",
    );
}

pub(super) fn object_space_t(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    pair.depths_per_object(unexplained)
        .then_some(Diagnosis::OBJECT_SPACE_T)
}

/// An affine change of levels, clamped, as a depth picture's levels change when one object's t is
/// scaled.
#[derive(Debug, Clone, Copy)]
struct LevelMap {
    slope: f64,
    offset: f64,
}

impl LevelMap {
    fn apply(self, level: f64) -> f64 {
        (self.slope * level + self.offset).clamp(0.0, 255.0)
    }

    /// Whether the two maps send every level to about the same place.
    fn agrees(&self, other: &LevelMap) -> bool {
        [0.0, 128.0, 255.0]
            .iter()
            .all(|&level| (self.apply(level) - other.apply(level)).abs() <= MAP_AGREEMENT)
    }
}

impl Pair<'_> {
    /// Whether the pictures are depth pictures (grey) in which some of the reference's surfaces
    /// are drawn with depths of their own (an affine change of levels, possibly clamped), and
    /// they are not all changed alike; takes those surfaces out of `unexplained`.
    fn depths_per_object(&self, unexplained: &mut [bool]) -> bool {
        let grey = |colour: &[u8; 3]| colour[0] == colour[1] && colour[1] == colour[2];
        if !self.reference.iter().all(grey) || !self.actual.iter().all(grey) {
            return false;
        }
        let mut kept = 0;
        let mut changed: Vec<(Vec<usize>, LevelMap)> = Vec::new();
        for surface in self.surfaces() {
            if surface.len() < SURFACE_MIN_PIXELS {
                continue;
            }
            let matching = surface
                .iter()
                .filter(|&&i| {
                    channel_difference(self.actual[i], self.reference[i]) <= self.tolerance
                })
                .count();
            if matching as f64 >= SURFACE_SHARE * surface.len() as f64 {
                kept += 1;
            } else if let Some(map) = self.level_map(&surface) {
                changed.push((surface, map));
            }
        }
        let distinct = changed
            .iter()
            .any(|(_, map)| changed.iter().any(|(_, other)| !map.agrees(other)));
        if changed.is_empty() || (kept == 0 && !distinct) {
            return false;
        }
        let mut explained = vec![false; unexplained.len()];
        for i in changed.into_iter().flat_map(|(surface, _)| surface) {
            explained[i] = true;
        }
        // A sphere's rim is too steep to join its surface: its few pixels go with the surface
        // they border.
        for _ in 0..RIM_WIDTH {
            let rim: Vec<usize> = (0..explained.len())
                .filter(|&i| {
                    !explained[i]
                        && !self.reference_shows_background[i]
                        && neighbours(self.width, self.height, i, &ALL_STEPS).any(|n| explained[n])
                })
                .collect();
            for i in rim {
                explained[i] = true;
            }
        }
        for (unexplained, explained) in unexplained.iter_mut().zip(explained) {
            *unexplained &= !explained;
        }
        true
    }

    /// The reference's object pixels split into smooth surfaces: 4-connected, each step between
    /// neighbours within `SURFACE_STEP` levels, so a jump in depth separates two objects.
    fn surfaces(&self) -> Vec<Vec<usize>> {
        let mut seen = self.reference_shows_background.clone();
        let mut found = Vec::new();
        let mut stack = Vec::new();
        for start in 0..self.reference.len() {
            if seen[start] {
                continue;
            }
            seen[start] = true;
            stack.push(start);
            let mut surface = Vec::new();
            while let Some(index) = stack.pop() {
                surface.push(index);
                for next in neighbours(self.width, self.height, index, &SIDE_STEPS) {
                    let step = channel_difference(self.reference[index], self.reference[next]);
                    if !seen[next] && step <= SURFACE_STEP {
                        seen[next] = true;
                        stack.push(next);
                    }
                }
            }
            found.push(surface);
        }
        found
    }

    /// The affine map of levels, clamped to 0..=255, that takes the reference's `surface` to
    /// the actual picture's, fitted by least squares on the levels left unclamped; `None` when
    /// it fails to predict nearly all of the surface, or when the surface went to the background
    /// (a missing object, not a moved one).
    fn level_map(&self, surface: &[usize]) -> Option<LevelMap> {
        let level = |pixels: &[[u8; 3]], i: usize| f64::from(pixels[i][0]);
        let gone = surface
            .iter()
            .filter(|&&i| self.actual_shows_background(i))
            .count();
        if gone as f64 >= SURFACE_SHARE * surface.len() as f64 {
            return None;
        }
        let inside: Vec<(f64, f64)> = surface
            .iter()
            .map(|&i| (level(self.reference, i), level(self.actual, i)))
            .filter(|&(_, got)| got > 0.0 && got < 255.0)
            .collect();
        let map = if inside.len() >= FIT_MIN_SAMPLES {
            let n = inside.len() as f64;
            let (sum_x, sum_y) = inside
                .iter()
                .fold((0.0, 0.0), |(sx, sy), &(x, y)| (sx + x, sy + y));
            let (mean_x, mean_y) = (sum_x / n, sum_y / n);
            let (mut sxx, mut sxy) = (0.0, 0.0);
            for &(x, y) in &inside {
                sxx += (x - mean_x) * (x - mean_x);
                sxy += (x - mean_x) * (y - mean_y);
            }
            // A surface of one level fixes no slope: take its levels as moved by an offset.
            let slope = if sxx > 0.0 { sxy / sxx } else { 1.0 };
            LevelMap {
                slope,
                offset: mean_y - slope * mean_x,
            }
        } else {
            // Clamped throughout: the whole surface moved past the near or the far plane.
            let got = level(self.actual, surface[0]);
            LevelMap {
                slope: 0.0,
                offset: got,
            }
        };
        let slack = f64::from(self.tolerance) + 2.0;
        let fitting = surface
            .iter()
            .filter(|&&i| {
                (map.apply(level(self.reference, i)) - level(self.actual, i)).abs() <= slack
            })
            .count();
        (fitting as f64 >= SURFACE_SHARE * surface.len() as f64).then_some(map)
    }
}

#[cfg(test)]
mod tests {
    use super::super::diagnose;
    use super::super::fixtures::*;
    use super::*;
    use crate::shade::Image;

    /// A depth picture (grey, nearer is brighter, black background) of two spheres seen along
    /// the view axis, each at depth `centre` with radius `radius`, with the far sphere's depths
    /// divided by `far_divisor` (1: drawn right), and `near` to `far` mapped to 255 to 0.
    fn depth_picture(far_divisor: f64, near_divisor: f64) -> Image {
        let (near, far) = (2.0, 7.0);
        let spheres = [
            ((20.0, 22.0), 14.0, 5.0, near_divisor),
            ((46.0, 24.0), 12.0, 4.0, far_divisor),
        ];
        let mut pixels = Vec::new();
        for row in 0..HEIGHT {
            for column in 0..WIDTH {
                let (x, y) = (f64::from(column) + 0.5, f64::from(row) + 0.5);
                let mut nearest = f64::INFINITY;
                for ((cx, cy), radius, centre, divisor) in spheres {
                    let r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (radius * radius);
                    if r2 <= 1.0 {
                        nearest = nearest.min((centre - (1.0 - r2).sqrt()) / divisor);
                    }
                }
                let level = if nearest.is_finite() {
                    (255.0 * ((far - nearest) / (far - near)).clamp(0.0, 1.0)) as u8
                } else {
                    0
                };
                pixels.push([level; 3]);
            }
        }
        Image {
            width: WIDTH,
            height: HEIGHT,
            pixels,
        }
    }

    #[test]
    fn depths_off_per_object_are_object_space_t() {
        let reference = depth_picture(1.0, 1.0);
        let diagnosed = |actual: &Image| diagnose(actual, &reference, RULE);
        assert!(diagnosed(&reference).is_empty());
        // One sphere under `Scale 2`, the other untransformed.
        assert_eq!(
            diagnosed(&depth_picture(2.0, 1.0)),
            [Diagnosis::OBJECT_SPACE_T]
        );
        // Two spheres scaled differently, neither drawn right.
        assert_eq!(
            diagnosed(&depth_picture(1.25, 0.8)),
            [Diagnosis::OBJECT_SPACE_T]
        );
        // Every depth off alike (a wrong near plane, say) is not one object's t.
        assert!(!diagnosed(&depth_picture(1.25, 1.25)).contains(&Diagnosis::OBJECT_SPACE_T));
        // Colour pictures are not depth pictures.
        let coloured = map_pixels(&depth_picture(2.0, 1.0), |[l, _, _]| [l, l / 2, 0]);
        let coloured_reference = map_pixels(&reference, |[l, _, _]| [l, l / 2, 0]);
        assert!(
            !diagnose(&coloured, &coloured_reference, RULE).contains(&Diagnosis::OBJECT_SPACE_T)
        );
    }
}
