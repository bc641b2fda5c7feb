//! How the samples near a pixel are weighed into its colour.

/// A filter, with its size in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    /// Weight 1 in the square −r ≤ x, y < r about the pixel's centre (half-open, so a box of 0.5
    /// takes exactly the pixel's own samples), 0 outside.
    Box(f32),
    /// 1 at the centre, falling linearly to 0 at distance r.
    Tent(f32),
    /// e^(−d²/2σ²), cut to 0 from d = 2σ on (the handout allows the cut; it keeps the filter's
    /// reach finite).
    Gaussian(f32),
    /// The Gaussian not cut: e^(−d²/2σ²) over the whole support, of the integer radius given
    /// (uncut, the radius decides which samples count: the handout's other allowed answer;
    /// `check` renders it, `-choose gaussian_uncut`).
    GaussianUncut {
        /// σ, in pixels.
        sigma: f32,
        /// The support radius R: pixels i−R…i+R are taken.
        radius: u32,
    },
    /// The box with its edges in: −r ≤ x, y ≤ r (an allowed answer, `-choose box_closed`).
    BoxClosed(f32),
    /// The box with its edges out: −r < x, y < r (an allowed answer, `-choose box_open`).
    BoxOpen(f32),
    /// A mistake of check's library: the tent made of two straight ones, (1 − |x|/r)(1 − |y|/r).
    TentAcross(f32),
    /// A mistake of check's library: the box round, weight 1 nearer than r.
    BoxRound(f32),
    /// A mistake of check's library: the tent of the distance |x| + |y| (a pyramid on its
    /// corner).
    TentDiamond(f32),
    /// A mistake of check's library: the tent of the distance max(|x|, |y|) (a pyramid on its
    /// side).
    TentSquare(f32),
    /// A mistake of check's library: the box of the points with |x| + |y| < r.
    BoxDiamond(f32),
    /// A mistake of check's library: the Gaussian written without its 2, e^(−d²/σ²), still
    /// cut at 2σ.
    GaussianNarrow(f32),
    /// A mistake of check's library: the Gaussian with σ not squared, e^(−d²/2σ), still cut at
    /// 2σ.
    GaussianSigmaUnsquared(f32),
}

/// e^(−d²/`divisor`) nearer than 2σ to the centre, 0 from there on.
#[inline]
fn cut_gaussian(sigma: f32, x: f32, y: f32, divisor: f32) -> f32 {
    let d2 = x * x + y * y;
    if d2 >= 4.0 * sigma * sigma {
        0.0
    } else {
        (-d2 / divisor).exp()
    }
}

impl Filter {
    /// The weight of a sample at (x, y) from the pixel's centre, in pixels.
    #[inline]
    pub fn weight(&self, x: f32, y: f32) -> f32 {
        match *self {
            Filter::Box(r) => {
                let inside = |v: f32| -r <= v && v < r;
                if inside(x) && inside(y) { 1.0 } else { 0.0 }
            }
            Filter::BoxClosed(r) => {
                let inside = |v: f32| -r <= v && v <= r;
                if inside(x) && inside(y) { 1.0 } else { 0.0 }
            }
            Filter::BoxOpen(r) => {
                let inside = |v: f32| -r < v && v < r;
                if inside(x) && inside(y) { 1.0 } else { 0.0 }
            }
            Filter::Tent(r) => (1.0 - (x * x + y * y).sqrt() / r).max(0.0),
            Filter::TentAcross(r) => (1.0 - x.abs() / r).max(0.0) * (1.0 - y.abs() / r).max(0.0),
            Filter::TentDiamond(r) => (1.0 - (x.abs() + y.abs()) / r).max(0.0),
            Filter::TentSquare(r) => (1.0 - x.abs().max(y.abs()) / r).max(0.0),
            Filter::BoxDiamond(r) => {
                if x.abs() + y.abs() < r {
                    1.0
                } else {
                    0.0
                }
            }
            Filter::BoxRound(r) => {
                if x * x + y * y < r * r {
                    1.0
                } else {
                    0.0
                }
            }
            Filter::GaussianUncut { sigma, .. } => (-(x * x + y * y) / (2.0 * sigma * sigma)).exp(),
            Filter::Gaussian(sigma) => cut_gaussian(sigma, x, y, 2.0 * sigma * sigma),
            Filter::GaussianNarrow(sigma) => cut_gaussian(sigma, x, y, sigma * sigma),
            Filter::GaussianSigmaUnsquared(sigma) => cut_gaussian(sigma, x, y, 2.0 * sigma),
        }
    }

    /// How far the filter reaches, in pixels from the centre, before its weight is 0.
    fn reach(&self) -> f32 {
        match *self {
            Filter::Box(r)
            | Filter::BoxOpen(r)
            | Filter::Tent(r)
            | Filter::TentAcross(r)
            | Filter::TentDiamond(r)
            | Filter::TentSquare(r)
            | Filter::BoxDiamond(r)
            | Filter::BoxRound(r) => r,
            // Its edge's samples weigh 1: the support takes the next pixel where one lies there.
            Filter::BoxClosed(r) => r + f32::EPSILON * r.max(1.0),
            Filter::Gaussian(sigma)
            | Filter::GaussianNarrow(sigma)
            | Filter::GaussianSigmaUnsquared(sigma) => 2.0 * sigma,
            Filter::GaussianUncut { radius, .. } => radius as f32,
        }
    }

    /// The course's support radius: the filtered pixel (i, j) takes the samples of pixels
    /// i−R…i+R, j−R…j+R. A sample of pixel i+k lies between k − ½ and k + ½ from the centre, and
    /// weighs nothing from the filter's reach on, so R is the largest k with k − ½ < reach.
    /// (An uncut Gaussian has the radius it was given.)
    pub fn support_radius(&self) -> u32 {
        if let Filter::GaussianUncut { radius, .. } = *self {
            return radius;
        }
        ((self.reach() + 0.5).ceil() - 1.0).max(0.0) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_by_hand() {
        let b = Filter::Box(0.5);
        assert_eq!(b.weight(0.0, 0.0), 1.0);
        assert_eq!(b.weight(-0.5, 0.49), 1.0);
        assert_eq!(b.weight(0.5, 0.0), 0.0);
        let t = Filter::Tent(2.0);
        assert_eq!(t.weight(0.0, 0.0), 1.0);
        assert_eq!(t.weight(1.0, 0.0), 0.5);
        assert_eq!(t.weight(0.6, 0.8), 0.5);
        assert_eq!(t.weight(2.0, 0.0), 0.0);
        assert_eq!(t.weight(0.0, 3.0), 0.0);
        let g = Filter::Gaussian(0.5);
        assert_eq!(g.weight(0.0, 0.0), 1.0);
        // d = 0.5 = σ: e^(-1/2).
        assert!((g.weight(0.3, 0.4) - (-0.5f32).exp()).abs() < 1e-7);
        // Cut at 2σ = 1.
        assert!(g.weight(0.99, 0.0) > 0.1);
        assert_eq!(g.weight(1.0, 0.0), 0.0);
    }

    #[test]
    fn the_library_s_shapes_by_hand() {
        let across = Filter::TentAcross(2.0);
        assert_eq!(across.weight(1.0, 0.0), 0.5);
        // (1 − 0.6/2)(1 − 0.8/2) = 0.7 × 0.6; the course's tent has 0.5 at distance 1.
        assert!((across.weight(0.6, 0.8) - 0.42).abs() < 1e-6);
        assert_eq!(across.weight(2.0, 0.0), 0.0);
        let round = Filter::BoxRound(1.0);
        assert_eq!(round.weight(0.7, 0.7), 1.0);
        assert_eq!(round.weight(0.8, 0.8), 0.0);
        assert_eq!(Filter::Box(1.0).weight(0.8, 0.8), 1.0);
        // The tent and the box of the other distances: |x| + |y| = 1.4, max(|x|, |y|) = 0.8.
        assert!((Filter::TentDiamond(2.0).weight(0.6, -0.8) - 0.3).abs() < 1e-6);
        assert!((Filter::TentSquare(2.0).weight(0.6, -0.8) - 0.6).abs() < 1e-6);
        assert_eq!(Filter::BoxDiamond(1.5).weight(0.6, -0.8), 1.0);
        assert_eq!(Filter::BoxDiamond(1.0).weight(0.6, -0.8), 0.0);
        assert_eq!(across.support_radius(), 2);
        assert_eq!(round.support_radius(), 1);
    }

    #[test]
    fn support_radii() {
        assert_eq!(Filter::Box(0.5).support_radius(), 0);
        assert_eq!(Filter::Box(0.51).support_radius(), 1);
        assert_eq!(Filter::Box(1.5).support_radius(), 1);
        assert_eq!(Filter::Box(1.7).support_radius(), 2);
        assert_eq!(Filter::Tent(0.5).support_radius(), 0);
        assert_eq!(Filter::Tent(1.5).support_radius(), 1);
        assert_eq!(Filter::Tent(2.3).support_radius(), 2);
        assert_eq!(Filter::Gaussian(0.25).support_radius(), 0);
        assert_eq!(Filter::Gaussian(0.4).support_radius(), 1);
        assert_eq!(Filter::Gaussian(1.0).support_radius(), 2);
        assert_eq!(Filter::Gaussian(1.7).support_radius(), 3);
        assert_eq!(Filter::Box(0.1).support_radius(), 0);
    }

    #[test]
    fn nothing_beyond_the_support_radius_weighs_anything() {
        for filter in [
            Filter::Box(0.5),
            Filter::Box(1.7),
            Filter::Tent(1.5),
            Filter::Tent(2.3),
            Filter::Gaussian(0.4),
            Filter::Gaussian(1.7),
        ] {
            let r = filter.support_radius() as f32;
            // The nearest a sample of pixel R+1 can come is R + ½.
            for k in 0..=40 {
                let along = -20.0 + k as f32;
                assert_eq!(filter.weight(r + 0.5, along), 0.0, "{filter:?}");
                assert_eq!(filter.weight(along, -(r + 0.5) - 1e-6), 0.0, "{filter:?}");
            }
        }
    }
}
