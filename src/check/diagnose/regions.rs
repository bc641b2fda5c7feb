//! Sizeable, smooth regions that differ: an object missing, an object added, or back faces
//! drawn black on one side and shaded on the other.

use super::pixels::{ALL_STEPS, neighbours, regions};
use super::{Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Regions (missing and extra objects, back faces): at least this many pixels, with a pixel whose
// eight neighbours all belong (a one- or two-pixel strip along an outline is not an object)...
const REGION_MIN_PIXELS: usize = 20;
// ...and smooth in the actual picture, as shading is and noise is not: this share of the
// region's neighbouring pairs within this many levels.
const COHERENT_STEP: u8 = 24;
const COHERENT_SHARE: f64 = 0.7;

impl Diagnosis {
    /// Regions inside objects are black in one picture and shaded in the other.
    pub const BACK_FACES: Diagnosis = Diagnosis::new(
        "back_faces",
        1,
        "Regions inside objects are black in one picture and shaded in the other: check \
        how back faces are shaded (the normal turned toward the viewer, -shade_back) \
        and the sign of the normal.",
    );

    /// An object of the reference is missing.
    pub const MISSING_OBJECT: Diagnosis = Diagnosis::new(
        "missing_object",
        2,
        "An object of the reference is missing: check that every object of the scene is \
        parsed and intersected (groups, transforms, and the nearest-hit test with tmin).",
    );

    /// An object that the reference lacks is drawn.
    pub const EXTRA_OBJECT: Diagnosis = Diagnosis::new(
        "extra_object",
        3,
        "Something is drawn that the reference does not show: check the nearest-hit \
        comparison, tmin (hits behind the eye) and the transforms' inverses.",
    );
}

pub(super) fn missing_object(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    if !pair.regions_of(RegionKind::Missing, unexplained) {
        return None;
    }
    // Seen from inside an object, "missing" black parts are its back faces.
    let inside = !pair.reference_has_background && pair.actual_background == [0; 3];
    Some(if inside {
        Diagnosis::BACK_FACES
    } else {
        Diagnosis::MISSING_OBJECT
    })
}

pub(super) fn extra_object(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    pair.regions_of(RegionKind::Extra, unexplained)
        .then_some(Diagnosis::EXTRA_OBJECT)
}

pub(super) fn back_faces(pair: &Pair, unexplained: &mut [bool]) -> Option<Diagnosis> {
    pair.regions_of(RegionKind::BackFace, unexplained)
        .then_some(Diagnosis::BACK_FACES)
}

/// What a region of differing pixels shows.
#[derive(Debug, Clone, Copy)]
enum RegionKind {
    /// The actual picture shows its background where the reference shows an object.
    Missing,
    /// The reference shows its background where the actual picture shows an object.
    Extra,
    /// Black on one side, shaded on the other, and background on neither.
    BackFace,
}

impl Pair<'_> {
    /// Whether `unexplained` holds a sizeable, smooth region of `kind`; takes every such region
    /// out of `unexplained`.
    fn regions_of(&self, kind: RegionKind, unexplained: &mut [bool]) -> bool {
        let member: Vec<bool> = (0..unexplained.len())
            .map(|i| unexplained[i] && self.is_of_kind(kind, i))
            .collect();
        let mut any = false;
        for region in regions(&member, self.width, self.height) {
            if self.has_interior(&region, &member) && self.is_coherent(&region, &member) {
                any = true;
                for &i in &region {
                    unexplained[i] = false;
                }
            }
        }
        any
    }

    fn is_of_kind(&self, kind: RegionKind, index: usize) -> bool {
        let (got, want) = (self.actual[index], self.reference[index]);
        match kind {
            RegionKind::Missing => {
                self.actual_shows_background(index) && self.reference_clearly_object(index)
            }
            RegionKind::Extra => {
                self.reference_shows_background[index] && self.actual_clearly_object(index)
            }
            RegionKind::BackFace => {
                let black_here = self.is_black(got)
                    && !self.actual_shows_background(index)
                    && self.reference_clearly_object(index)
                    && self.is_coloured(want);
                let black_there = self.is_black(want)
                    && !self.reference_shows_background[index]
                    && self.actual_clearly_object(index)
                    && self.is_coloured(got);
                black_here || black_there
            }
        }
    }

    /// Big enough, with a pixel whose eight neighbours all belong to the region.
    fn has_interior(&self, region: &[usize], member: &[bool]) -> bool {
        region.len() >= REGION_MIN_PIXELS
            && region.iter().any(|&i| {
                neighbours(self.width, self.height, i, &ALL_STEPS)
                    .filter(|&next| member[next])
                    .count()
                    == ALL_STEPS.len()
            })
    }

    /// Smooth in the actual picture: most neighbouring pairs within the region are close.
    fn is_coherent(&self, region: &[usize], member: &[bool]) -> bool {
        let (mut pairs, mut smooth) = (0_usize, 0_usize);
        for &i in region {
            let (x, y) = (i % self.width, i / self.width);
            let right = (x + 1 < self.width).then_some(i + 1);
            let below = (y + 1 < self.height).then_some(i + self.width);
            for next in [right, below]
                .into_iter()
                .flatten()
                .filter(|&next| member[next])
            {
                pairs += 1;
                let step = channel_difference(self.actual[i], self.actual[next]);
                smooth += usize::from(step <= COHERENT_STEP);
            }
        }
        pairs > 0 && smooth as f64 >= COHERENT_SHARE * pairs as f64
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::*;
    use super::*;

    #[test]
    fn half_the_disc_black() {
        let back_faces = render(Scene {
            black_lower_disc: true,
            ..Scene::default()
        });
        assert_diagnosed(&back_faces, &[Diagnosis::BACK_FACES]);
    }

    #[test]
    fn triangle_missing() {
        let missing = render(Scene {
            triangle: false,
            ..Scene::default()
        });
        assert_diagnosed(&missing, &[Diagnosis::MISSING_OBJECT]);
    }

    #[test]
    fn square_added() {
        let extra = render(Scene {
            square: true,
            ..Scene::default()
        });
        assert_diagnosed(&extra, &[Diagnosis::EXTRA_OBJECT]);
    }
}
