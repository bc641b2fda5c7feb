//! Assignment 7: several samples per pixel, placed by a sampler, and combined into each pixel by
//! a filter that may reach into the neighbouring pixels; and the course's two debugging pictures
//! of where the samples fall and what the filter weighs.

mod film;
mod filter;
mod sampler;

pub use film::{Film, FilmSample, render_filter_picture, render_samples_picture};
pub use filter::Filter;
pub use sampler::{ONE_BELOW, Sampler};

/// How pixels are sampled and filtered; the default is the course's: one sample at each pixel's
/// centre, no filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    /// Where in each pixel its samples fall, and how many there are.
    pub sampler: Sampler,
    /// How the samples near each pixel are weighed into it.
    pub filter: Filter,
    /// Seeds the random and jittered samplers: the same seed gives the same image on any
    /// number of threads.
    pub seed: u64,
}

/// Where a pixel's samples fall: the seam where a render may place them as a student's tracer
/// would (check's fault library). The default is the sampler's own positions.
pub trait SampleSeam: Copy + Send + Sync {
    /// The positions of pixel `pixel`'s samples (in [0, 1)² from its lower-left corner) into
    /// `out`.
    #[inline(always)]
    fn positions(&self, sampler: Sampler, seed: u64, pixel: u64, out: &mut [glam::Vec2]) {
        sampler.positions(seed, pixel, out);
    }

    /// The filter that weighs the samples into pixels.
    #[inline(always)]
    fn filter(&self, filter: Filter) -> Filter {
        filter
    }

    /// The weight `filter` gives a sample at (x, y) from the pixel's centre, in pixels.
    #[inline(always)]
    fn weight(&self, filter: Filter, x: f32, y: f32) -> f32 {
        filter.weight(x, y)
    }

    /// The pixels whose samples a pixel's filter gathers, as offsets from it along each axis
    /// (from the first to the second, both included), for a filter that reaches `reach` pixels
    /// beyond the pixel itself.
    #[inline(always)]
    fn neighbours(&self, reach: i64) -> (i64, i64) {
        (-reach, reach)
    }

    /// A pixel's value from the `count` samples its filter weighs: their weighted `sum`, and
    /// the sum of their weights `total` (positive).
    #[inline(always)]
    fn weighted_mean(&self, sum: glam::Vec3A, total: f32, _count: u32) -> glam::Vec3A {
        sum / total
    }
}

impl SampleSeam for crate::variant::Exact {}

/// The seed used when none is given.
pub const DEFAULT_SEED: u64 = 6837;

impl Default for Sampling {
    fn default() -> Sampling {
        Sampling {
            sampler: Sampler::Uniform(1),
            filter: Filter::Box(0.5),
            seed: DEFAULT_SEED,
        }
    }
}

impl Sampling {
    /// One sample at the centre and a box of half a pixel: each pixel is its own centre's colour,
    /// as in assignments 1 to 6.
    pub fn is_plain(&self) -> bool {
        self.sampler == Sampler::Uniform(1) && self.filter.support_radius() == 0
    }
}
