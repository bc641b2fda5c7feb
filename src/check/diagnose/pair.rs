//! The two pictures of one comparison, and what every cause asks of them: where each shows its
//! background, and which pixels are clearly an object.

use super::pixels::{border_mode, border_share};
use crate::check::rule::channel_difference;
use crate::shade::Image;

// A colour is clearly not the background when a channel is this many levels off it (or the
// tolerance, if larger): noise around the background must not read as an object.
const CLEAR_MARGIN: u8 = 24;

/// The two pictures (of one size) and what the heuristics share.
pub(super) struct Pair<'a> {
    pub(super) actual: &'a [[u8; 3]],
    pub(super) reference: &'a [[u8; 3]],
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) tolerance: u8,
    pub(super) reference_background: [u8; 3],
    pub(super) actual_background: [u8; 3],
    /// Whether the reference's border is mostly one flat colour, a background.
    pub(super) reference_has_background: bool,
    /// Per pixel: the reference shows its background there.
    pub(super) reference_shows_background: Vec<bool>,
}

impl<'a> Pair<'a> {
    pub(super) fn new(actual: &'a Image, reference: &'a Image, tolerance: u8) -> Pair<'a> {
        let (width, height) = (reference.width as usize, reference.height as usize);
        let reference_background = border_mode(&reference.pixels, width, height);
        let actual_background = border_mode(&actual.pixels, width, height);
        // A picture taken from inside an object (the course's scene2_05) has no background:
        // its border is shaded, not one flat colour.
        let reference_has_background = border_share(
            &reference.pixels,
            width,
            height,
            reference_background,
            tolerance,
        ) >= 0.5;
        let reference_shows_background = reference
            .pixels
            .iter()
            .map(|&colour| {
                reference_has_background
                    && channel_difference(colour, reference_background) <= tolerance
            })
            .collect();
        Pair {
            actual: &actual.pixels,
            reference: &reference.pixels,
            width,
            height,
            tolerance,
            reference_background,
            actual_background,
            reference_has_background,
            reference_shows_background,
        }
    }

    pub(super) fn actual_shows_background(&self, index: usize) -> bool {
        channel_difference(self.actual[index], self.actual_background) <= self.tolerance
    }

    pub(super) fn reference_clearly_object(&self, index: usize) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        channel_difference(self.reference[index], self.reference_background) > margin
    }

    /// Clearly neither picture's background: a student's object must not be their background
    /// colour nor the reference's.
    pub(super) fn actual_clearly_object(&self, index: usize) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        let colour = self.actual[index];
        channel_difference(colour, self.actual_background) > margin
            && channel_difference(colour, self.reference_background) > margin
    }

    pub(super) fn is_black(&self, colour: [u8; 3]) -> bool {
        colour.iter().all(|&level| level <= self.tolerance)
    }

    pub(super) fn is_coloured(&self, colour: [u8; 3]) -> bool {
        let margin = self.tolerance.max(CLEAR_MARGIN);
        colour.iter().any(|&level| level > margin)
    }
}
