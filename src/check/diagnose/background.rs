//! The background wrong nearly everywhere it shows.

use super::pixels::most_common;
use super::{Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Background: the reference must show enough of it, nearly all of it must differ, and the
// actual picture must show mostly one colour there instead.
const BACKGROUND_MIN_PIXELS: usize = 20;
const BACKGROUND_WRONG_SHARE: f64 = 0.9;
const BACKGROUND_UNIFORM_SHARE: f64 = 0.8;

impl Diagnosis {
    /// Only the background colour is wrong.
    pub const BACKGROUND: Diagnosis = Diagnosis::new(
        "background",
        4,
        "Only the background differs: rays that hit nothing must take the scene's \
        background colour, unshaded.",
    );
}

/// A background is one flat colour. Where the reference's "background" is shaded (inside a
/// sphere, it is the sphere's inside) and the picture shows one colour there instead, those are
/// back faces drawn black (or flat).
pub(super) fn wrong_background(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    let flat = pair.wrong_background(unexplained)?;
    Some(if flat {
        Diagnosis::BACKGROUND
    } else {
        Diagnosis::BACK_FACES
    })
}

impl Pair<'_> {
    /// Whether the background is wrong nearly everywhere it shows, one colour instead; then
    /// takes those pixels out of `unexplained`, and says whether the reference was flat there.
    fn wrong_background(&self, unexplained: &mut [bool]) -> Option<bool> {
        let background: Vec<usize> = (0..self.reference.len())
            .filter(|&i| self.reference_shows_background[i])
            .collect();
        if background.len() < BACKGROUND_MIN_PIXELS {
            return None;
        }
        let wrong: Vec<usize> = background
            .iter()
            .copied()
            .filter(|&i| unexplained[i])
            .collect();
        if (wrong.len() as f64) < BACKGROUND_WRONG_SHARE * background.len() as f64 {
            return None;
        }
        let shown = most_common(wrong.iter().map(|&i| self.actual[i]))?;
        let uniform = wrong
            .iter()
            .filter(|&&i| channel_difference(self.actual[i], shown) <= self.tolerance)
            .count();
        if (uniform as f64) < BACKGROUND_UNIFORM_SHARE * wrong.len() as f64 {
            return None;
        }
        for &i in &wrong {
            unexplained[i] = false;
        }
        let reference = most_common(wrong.iter().map(|&i| self.reference[i]))?;
        let flat = wrong
            .iter()
            .filter(|&&i| channel_difference(self.reference[i], reference) <= self.tolerance)
            .count();
        Some(flat as f64 >= BACKGROUND_UNIFORM_SHARE * wrong.len() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::*;
    use super::*;

    #[test]
    fn background_black() {
        let black = render(Scene {
            background: [0, 0, 0],
            ..Scene::default()
        });
        assert_diagnosed(&black, &[Diagnosis::BACKGROUND]);
    }
}
