//! Background showing through isolated pixels inside objects: rays slipping between triangles.

use super::pixels::{SIDE_STEPS, neighbours, regions};
use super::{Diagnosis, Pair};

// Cracks: clusters of at most this many pixels, at least this many pixels in all, and this share
// of what differs.
const CRACK_CLUSTER: usize = 2;
const CRACK_MIN_PIXELS: usize = 3;
const CRACK_SHARE: f64 = 0.8;

impl Diagnosis {
    /// Isolated pixels inside objects show the background.
    pub const CRACKS: Diagnosis = Diagnosis::new(
        "cracks",
        0,
        "Isolated pixels inside objects show the background: rays slip between \
        triangles where they meet; make the triangle test inclusive at its edges \
        (barycentric coordinates >= 0, not > 0).",
    );
}

pub(super) fn cracks(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    pair.cracks(unexplained).then_some(Diagnosis::CRACKS)
}

impl Pair<'_> {
    /// Whether what differs is mostly tiny clusters inside objects that show the background;
    /// takes them out of `unexplained`.
    fn cracks(&self, unexplained: &mut [bool]) -> bool {
        let differing = unexplained.iter().filter(|&&differs| differs).count();
        let cracks: Vec<usize> = regions(unexplained, self.width, self.height)
            .into_iter()
            .filter(|region| {
                region.len() <= CRACK_CLUSTER && region.iter().all(|&i| self.is_crack(i))
            })
            .flatten()
            .collect();
        if cracks.len() < CRACK_MIN_PIXELS || (cracks.len() as f64) < CRACK_SHARE * differing as f64
        {
            return false;
        }
        for &i in &cracks {
            unexplained[i] = false;
        }
        true
    }

    /// Whether the actual picture shows its background at `index` while the reference shows an
    /// object there and all around it (inside the object, not on its outline).
    fn is_crack(&self, index: usize) -> bool {
        self.actual_shows_background(index)
            && self.reference_clearly_object(index)
            && neighbours(self.width, self.height, index, &SIDE_STEPS)
                .all(|next| self.reference_clearly_object(next))
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::*;
    use super::*;

    #[test]
    fn background_showing_through_the_rectangle() {
        let mut cracked = reference();
        for k in (0..20).step_by(3) {
            let (x, y) = (36 + k, 7 + k * 12 / 20);
            cracked.pixels[y * WIDTH as usize + x] = GREY;
        }
        assert_diagnosed(&cracked, &[Diagnosis::CRACKS]);
    }
}
