//! The film's forms: sample positions, filters and their weights.

use std::sync::atomic::Ordering;

use raycast::Vec3A;
use raycast::glam::Vec2;
use raycast::sample::{Filter, ONE_BELOW, SampleSeam, Sampler};

use crate::{Form, PIXEL_SAMPLES};

impl SampleSeam for Form {
    fn positions(&self, sampler: Sampler, seed: u64, pixel: u64, out: &mut [Vec2]) {
        match (self, sampler) {
            (Form::UniformEdgeToEdge, Sampler::Uniform(n)) if n > 1 => {
                let side = n.isqrt();
                let step = 1.0 / (side - 1) as f32;
                for (k, p) in out.iter_mut().enumerate() {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    *p = Vec2::new((a * step).min(ONE_BELOW), (b * step).min(ONE_BELOW));
                }
            }
            (Form::UniformUpperCorners, Sampler::Uniform(n)) => {
                let side = n.isqrt().max(1);
                for (k, p) in out.iter_mut().enumerate() {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    let corner = |c: f32| ((c + 1.0) / side as f32).min(ONE_BELOW);
                    *p = Vec2::new(corner(a), corner(b));
                }
            }
            (Form::JitterAroundCells, Sampler::Jittered(n)) => {
                let side = n.isqrt().max(1);
                let mut unit = student_generator(pixel);
                for (k, p) in out.iter_mut().enumerate().take(n as usize) {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    let mut place =
                        |c: f32| ((c + 0.5) / side as f32 + unit() - 0.5).clamp(0.0, ONE_BELOW);
                    let x = place(a);
                    *p = Vec2::new(x, place(b));
                }
            }
            (Form::JitterAnywhere, Sampler::Jittered(n)) => {
                let mut unit = student_generator(pixel);
                for p in out.iter_mut().take(n as usize) {
                    let x = unit();
                    *p = Vec2::new(x, unit());
                }
            }
            _ => sampler.positions(seed, pixel, out),
        }
    }

    fn weighted_mean(&self, sum: Vec3A, total: f32, count: u32) -> Vec3A {
        match self {
            Form::WeightsOverCount => sum / count as f32,
            Form::WeightsOverPixelSamples => sum / PIXEL_SAMPLES.load(Ordering::Relaxed) as f32,
            _ => sum / total,
        }
    }

    fn weight(&self, filter: Filter, x: f32, y: f32) -> f32 {
        let (dx, dy) = (x.abs(), y.abs());
        match (self, filter) {
            (Form::TentManhattan, Filter::Tent(r)) => {
                let d = dx + dy;
                if d < r { 1.0 - d / r } else { 0.0 }
            }
            (Form::TentChebyshev, Filter::Tent(r)) => (1.0 - dx.max(dy) / r).max(0.0),
            (Form::BoxDisc, Filter::Box(r)) => f32::from(u8::from(dx * dx + dy * dy <= r * r)),
            // A sample at (x, y) from the centre lies in the pixel's own square where both are
            // in [-1/2, 1/2).
            (Form::FilterOwnPixel, _) if !(-0.5..0.5).contains(&x) || !(-0.5..0.5).contains(&y) => {
                0.0
            }
            // The last neighbour r pixels on, whose samples lie from r - 1/2 on.
            (Form::NeighboursLoopShort, _) => {
                let last = filter.support_radius() as f32 - 0.5;
                if x >= last || y >= last {
                    0.0
                } else {
                    filter.weight(x, y)
                }
            }
            (Form::FilterFromCorner, _) => filter.weight(x + 0.5, y + 0.5),
            // Rows counted down from the top: the pixel's corner above its centre.
            (Form::FilterFromTopCorner, _) => filter.weight(x + 0.5, y - 0.5),
            (Form::GaussianWithoutTwo | Form::GaussianSigmaUnsquared, Filter::Gaussian(s)) => {
                let d2 = x * x + y * y;
                let spread = match self {
                    Form::GaussianWithoutTwo => s * s,
                    _ => 2.0 * s,
                };
                if d2 < 4.0 * s * s {
                    (-d2 / spread).exp()
                } else {
                    0.0
                }
            }
            _ => filter.weight(x, y),
        }
    }

    fn filter(&self, filter: Filter) -> Filter {
        match (self, filter) {
            (Form::FilterHalfPixelWider, Filter::Box(r)) => Filter::Box(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Tent(r)) => Filter::Tent(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Gaussian(s)) => Filter::Gaussian(s + 0.5),
            (Form::GaussianVarianceAsSigma, Filter::Gaussian(s)) => Filter::Gaussian(s.sqrt()),
            _ => filter,
        }
    }
}

/// The student's own generator of numbers in [0, 1): a 64-bit LCG seeded by the pixel.
fn student_generator(pixel: u64) -> impl FnMut() -> f32 {
    let mut state = pixel.wrapping_mul(6_364_136_223_846_793_005) ^ 0x5DEE_CE66;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 40) as f32 / (1u64 << 24) as f32).min(ONE_BELOW)
    }
}
