//! Causes that change every colour by one curve: a factor (a missing or doubled light or ambient
//! term) or a power (a gamma correction), fitted on the reference's object pixels.

use std::ops::RangeInclusive;

use super::{Budget, Diagnosis, Pair};
use crate::check::rule::channel_difference;

// Colour curves (scale and gamma), fitted on the reference's object pixels. Darker channel
// levels are left out of the fit: they carry too little precision for a ratio.
const FIT_MIN_LEVEL: u8 = 20;
pub(super) const FIT_MIN_SAMPLES: usize = 20;
// The share of object pixels the curve must predict, and how much better than the identity.
const FIT_SHARE: f64 = 0.95;
const FIT_GAIN: f64 = 0.1;
// A fitted factor or exponent this close to 1 is no curve at all.
const NEAR_ONE: f64 = 0.04;
const SCALE_RANGE: RangeInclusive<f64> = 0.2..=5.0;
const GAMMA_RANGE: RangeInclusive<f64> = 0.3..=3.0;

impl Diagnosis {
    /// Every object colour is the reference's times one factor.
    pub const COLOUR_SCALE: Diagnosis = Diagnosis::new(
        "colour_scale",
        8,
        "Every colour is off by the same factor: check the ambient term (missing or \
        added twice) and that each light's colour multiplies its diffuse term.",
    );

    /// The colours follow a power curve of the reference's.
    pub const GAMMA: Diagnosis = Diagnosis::new(
        "gamma",
        8,
        "The colours follow a power curve of the reference's: apply no gamma correction \
        or sRGB conversion; write the linear colour, clamped, times 255.",
    );
}

/// A power curve, where it fits better than a factor.
pub(super) fn gamma(pair: &Pair, _: Budget) -> bool {
    let (scale, gamma) = pair.curves();
    gamma.is_some_and(|gamma| scale.is_none_or(|scale| gamma > scale))
}

/// A factor, where no power curve fits better (that is tried first).
pub(super) fn colour_scale(pair: &Pair, _: Budget) -> bool {
    pair.curves().0.is_some()
}

/// A colour curve that may map the reference's levels to the actual picture's.
#[derive(Debug, Clone, Copy)]
enum Curve {
    /// actual = reference × k, clamped.
    Scale,
    /// actual = 255 (reference / 255)^g.
    Gamma,
}

impl Curve {
    /// The parameter one channel suggests, where the channel can say.
    fn sample(self, reference: u8, actual: u8) -> Option<f64> {
        let (want, got) = (f64::from(reference), f64::from(actual));
        match self {
            // A clamped channel only bounds k from below.
            Curve::Scale if reference > FIT_MIN_LEVEL && actual < u8::MAX => Some(got / want),
            // Both levels strictly inside (0, 255), where the logarithms are finite and nonzero.
            Curve::Gamma
                if (FIT_MIN_LEVEL + 1..u8::MAX - FIT_MIN_LEVEL).contains(&reference)
                    && (1..u8::MAX).contains(&actual) =>
            {
                Some((got / 255.0).ln() / (want / 255.0).ln())
            }
            _ => None,
        }
    }

    fn range(self) -> RangeInclusive<f64> {
        match self {
            Curve::Scale => SCALE_RANGE,
            Curve::Gamma => GAMMA_RANGE,
        }
    }

    fn predict(self, parameter: f64, level: f64) -> f64 {
        match self {
            Curve::Scale => (level * parameter).min(255.0),
            Curve::Gamma => 255.0 * (level / 255.0).powf(parameter),
        }
    }
}

impl Pair<'_> {
    /// How well a factor and a power curve fit the object pixels, each where it fits at all.
    fn curves(&self) -> (Option<f64>, Option<f64>) {
        let objects: Vec<usize> = (0..self.reference.len())
            .filter(|&i| !self.reference_shows_background[i])
            .collect();
        (
            self.curve_fit(&objects, Curve::Scale),
            self.curve_fit(&objects, Curve::Gamma),
        )
    }

    /// The share of `objects` that `curve`, fitted on them, predicts, when the fit is a real
    /// curve (not the identity) that predicts nearly all of them and many more than match as is.
    fn curve_fit(&self, objects: &[usize], curve: Curve) -> Option<f64> {
        if objects.len() < FIT_MIN_SAMPLES {
            return None;
        }
        let mut samples: Vec<f64> = objects
            .iter()
            .flat_map(|&i| {
                let (want, got) = (self.reference[i], self.actual[i]);
                (0..3).filter_map(move |c| curve.sample(want[c], got[c]))
            })
            .collect();
        if samples.len() < FIT_MIN_SAMPLES {
            return None;
        }
        // The median: a few pixels that differ for another reason do not move it.
        let middle = samples.len() / 2;
        let parameter = *samples.select_nth_unstable_by(middle, f64::total_cmp).1;
        if !curve.range().contains(&parameter) || (parameter - 1.0).abs() < NEAR_ONE {
            return None;
        }
        let predicted: [f64; 256] =
            std::array::from_fn(|level| curve.predict(parameter, level as f64));
        // The reference's own rounding (a level either way) and the tolerance, plus a level for
        // the student's rounding.
        let slack = f64::from(self.tolerance) + 1.0;
        let mut fitting = 0;
        let mut matching = 0;
        for &i in objects {
            let (want, got) = (self.reference[i], self.actual[i]);
            let fits = want.iter().zip(got).all(|(&want, got)| {
                let low = predicted[usize::from(want.saturating_sub(1))] - slack;
                let high = predicted[usize::from(want.saturating_add(1))] + slack;
                (low..=high).contains(&f64::from(got))
            });
            fitting += usize::from(fits);
            matching += usize::from(channel_difference(got, want) <= self.tolerance);
        }
        let total = objects.len() as f64;
        let fit_share = fitting as f64 / total;
        let match_share = matching as f64 / total;
        (fit_share >= FIT_SHARE && fit_share - match_share >= FIT_GAIN).then_some(fit_share)
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixtures::*;
    use super::*;

    #[test]
    fn colours_halved_everywhere() {
        let halved = map_pixels(&reference(), |colour| {
            colour.map(|level| (f64::from(level) * 0.5).round() as u8)
        });
        assert_diagnosed(&halved, &[Diagnosis::COLOUR_SCALE]);
    }

    #[test]
    fn object_colours_brightened_and_clamped() {
        let brighter = map_pixels(&reference(), |colour| {
            if colour == GREY {
                colour
            } else {
                colour.map(|level| (f64::from(level) * 1.6).round().min(255.0) as u8)
            }
        });
        assert_diagnosed(&brighter, &[Diagnosis::COLOUR_SCALE]);
    }

    #[test]
    fn gamma_applied() {
        let curved = map_pixels(&reference(), |colour| {
            colour.map(|level| (255.0 * (f64::from(level) / 255.0).powf(2.2)).round() as u8)
        });
        assert_diagnosed(&curved, &[Diagnosis::GAMMA]);
    }
}
