//! Where in a pixel its samples fall.

use glam::Vec2;
use rand_core::Rng;
use rand_pcg::Pcg32;

/// A sampling pattern with its number of samples per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampler {
    /// Anywhere in the pixel, independently.
    Random(u32),
    /// The centres of an s × s grid of cells (s² samples); one sample is the pixel's centre.
    Uniform(u32),
    /// One random point in each cell of an s × s grid.
    Jittered(u32),
}

impl Sampler {
    /// How many samples each pixel gets.
    pub fn samples(&self) -> u32 {
        match *self {
            Sampler::Random(n) | Sampler::Uniform(n) | Sampler::Jittered(n) => n,
        }
    }

    /// The samples of pixel `pixel` (its index in the image), as offsets from its lower-left
    /// corner in [0, 1)², written into `out` (of length [`Sampler::samples`]). Random and
    /// jittered positions come from a generator seeded by `seed` and the pixel alone, so any
    /// thread computes the same ones.
    pub fn positions(&self, seed: u64, pixel: u64, out: &mut [Vec2]) {
        let mut random = Pcg32::new(seed, pixel);
        let mut unit = move || (random.next_u32() >> 8) as f32 * (1.0 / (1 << 24) as f32);
        match *self {
            Sampler::Random(_) => {
                for p in out.iter_mut() {
                    let x = unit();
                    *p = Vec2::new(x, unit());
                }
            }
            Sampler::Uniform(n) | Sampler::Jittered(n) => {
                let side = n.isqrt();
                let cell = 1.0 / side as f32;
                let jitter = matches!(self, Sampler::Jittered(_));
                for (k, p) in out.iter_mut().enumerate() {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    let (dx, dy) = if jitter {
                        let dx = unit();
                        (dx, unit())
                    } else {
                        (0.5, 0.5)
                    };
                    // Below 1 even where rounding would reach it.
                    *p = Vec2::new(
                        ((a + dx) * cell).min(ONE_BELOW),
                        ((b + dy) * cell).min(ONE_BELOW),
                    );
                }
            }
        }
    }
}

/// The largest f32 below 1.
pub const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    fn positions(sampler: Sampler, seed: u64, pixel: u64) -> Vec<Vec2> {
        let mut out = vec![Vec2::ZERO; sampler.samples() as usize];
        sampler.positions(seed, pixel, &mut out);
        out
    }

    #[test]
    fn uniform_positions_are_cell_centres() {
        assert_eq!(positions(Sampler::Uniform(1), 0, 0), [Vec2::splat(0.5)]);
        assert_eq!(
            positions(Sampler::Uniform(4), 0, 0),
            [
                Vec2::new(0.25, 0.25),
                Vec2::new(0.75, 0.25),
                Vec2::new(0.25, 0.75),
                Vec2::new(0.75, 0.75)
            ]
        );
        let nine = positions(Sampler::Uniform(9), 3, 99);
        assert_eq!(nine[0], Vec2::splat(1.0 / 6.0));
        assert_eq!(nine[5], Vec2::new(2.5 * (1.0 / 3.0), 1.5 * (1.0 / 3.0)));
        // The same everywhere and for every seed.
        assert_eq!(nine, positions(Sampler::Uniform(9), 4, 7));
    }

    #[test]
    fn jittered_samples_stay_in_their_cells() {
        for pixel in 0..50 {
            let p = positions(Sampler::Jittered(16), 1, pixel);
            for (k, q) in p.iter().enumerate() {
                let (a, b) = ((k % 4) as f32, (k / 4) as f32);
                assert!(q.x >= a / 4.0 && q.x < (a + 1.0) / 4.0, "{k}: {q}");
                assert!(q.y >= b / 4.0 && q.y < (b + 1.0) / 4.0, "{k}: {q}");
            }
        }
    }

    #[test]
    fn random_samples_repeat_with_a_seed_and_differ_with_another() {
        let a = positions(Sampler::Random(9), 5, 12);
        assert_eq!(a, positions(Sampler::Random(9), 5, 12));
        assert_ne!(a, positions(Sampler::Random(9), 6, 12));
        assert_ne!(a, positions(Sampler::Random(9), 5, 13));
        assert!(
            a.iter()
                .all(|p| p.x >= 0.0 && p.x < 1.0 && p.y >= 0.0 && p.y < 1.0)
        );
        let j = positions(Sampler::Jittered(9), 5, 12);
        assert_eq!(j, positions(Sampler::Jittered(9), 5, 12));
        assert_ne!(j, positions(Sampler::Jittered(9), 6, 12));
    }
}
