//! The pixel loop: bands of up to 16 rows spread over rayon's threads, each band walked in
//! tiles 16 pixels wide (neighbouring rays then meet the same nodes while they are in cache),
//! each pixel one camera ray through its centre, handed to the [`Tracer`] in blocks of 8×8 (or
//! as many rows as the band has), a packet that searches the scene together. Every pixel is computed the same way whichever thread takes it,
//! so any thread count gives the same image.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use arrayvec::ArrayVec;
use glam::Vec3A;
use rayon::prelude::*;

use crate::accel::{Hit, PACKET};
use crate::camera::CameraSeam;
use crate::geometry::Ray;
use crate::sample::{Film, FilmSample, SampleSeam, Sampling};
use crate::scene::Scene;
use crate::shade;
use crate::shade::{Image, PictureSeam};
use crate::trace::{RayCounts, Scratch, TraceSeam, TraceSettings, Tracer};
pub use crate::variant::Exact;

/// A way of rendering: the course's ([`Exact`]), or one of check's faults, which renders as a
/// student's tracer would. It answers at every seam of the pipeline ([`crate::variant`]).
pub trait Variant: CameraSeam + TraceSeam + PictureSeam + SampleSeam {}

impl<V: CameraSeam + TraceSeam + PictureSeam + SampleSeam> Variant for V {}

const TILE: u32 = 16;
/// Camera rays are searched in packets of this many rows and columns (see [`PACKET`]).
const PACKET_SIDE: u32 = 8;
const _: () = assert!((PACKET_SIDE * PACKET_SIDE) as usize <= PACKET);

/// What to render and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Of every picture, in pixels.
    pub width: u32,
    /// Of every picture, in pixels.
    pub height: u32,
    /// Make the shaded picture; without it, camera rays find their hits but nothing is shaded.
    pub colour: bool,
    /// Make the picture of each hit's |normal| (`-normals`).
    pub normals: bool,
    /// The t that maps to white and the t that maps to black.
    pub depth: Option<(f32, f32)>,
    /// Shadows, bounces and the rest of the tracer's switches.
    pub trace: TraceSettings,
    /// Samples per pixel and the filter (assignment 7); the default is one sample at each
    /// pixel's centre.
    pub sampling: Sampling,
    /// Keep every sample (for `-render_samples`), even where one a pixel would do.
    pub keep_film: bool,
    /// Show a progress bar on stderr if the render outlasts about a second (and stderr is a
    /// terminal).
    pub progress: bool,
    /// Where someone else watches the render's progress (the preview's page), if anyone.
    pub counter: Option<&'static RenderCounter>,
}

/// A render's progress for a watcher on another thread: the parts done, of the total.
#[derive(Debug, Default)]
pub struct RenderCounter {
    /// Parts (bands or rows) done.
    pub done: std::sync::atomic::AtomicU64,
    /// Parts in all; 0 until a render starts.
    pub total: std::sync::atomic::AtomicU64,
}

/// The same counter, not counters that happen to read the same: settings are equal when they
/// report to the same watcher.
impl PartialEq for RenderCounter {
    fn eq(&self, other: &RenderCounter) -> bool {
        std::ptr::eq(self, other)
    }
}

impl RenderCounter {
    /// The share done, 0 to 1 (0 before any render).
    pub fn fraction(&self) -> f64 {
        let total = self.total.load(Ordering::Relaxed);
        if total == 0 {
            return 0.0;
        }
        self.done.load(Ordering::Relaxed) as f64 / total as f64
    }
}

impl RenderSettings {
    /// The shaded picture alone, `width` × `height`, with the course's defaults: camera rays
    /// only, one sample at each pixel's centre, no progress bar.
    pub fn new(width: u32, height: u32) -> RenderSettings {
        RenderSettings {
            width,
            height,
            colour: true,
            normals: false,
            depth: None,
            trace: TraceSettings::default(),
            sampling: Sampling::default(),
            keep_film: false,
            progress: false,
            counter: None,
        }
    }
}

/// The rendered pictures; those not asked for are `None`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rendered {
    /// The shaded picture: the background where nothing is hit.
    pub colour: Option<Image>,
    /// Each hit's |normal| as a colour; black where nothing is hit.
    pub normals: Option<Image>,
    /// Grey by distance, white near and black far; black where nothing is hit.
    pub depth: Option<Image>,
    /// The rays cast to make them.
    pub rays: RayCounts,
    /// Every sample, where they were kept.
    pub film: Option<Film>,
}

/// Renders on the current rayon pool (wrap in `ThreadPool::install` to choose the threads).
pub fn render(scene: &Scene, settings: &RenderSettings) -> Rendered {
    render_with(scene, settings, Exact)
}

/// [`render`], as `variant` renders.
pub fn render_with<V: Variant>(scene: &Scene, settings: &RenderSettings, variant: V) -> Rendered {
    if settings.sampling.is_plain() && !settings.keep_film {
        render_centres(scene, settings, variant)
    } else {
        render_film(scene, settings, variant)
    }
}

/// One ray through each pixel's centre, straight to bytes: assignments 1 to 6.
fn render_centres<V: Variant>(scene: &Scene, settings: &RenderSettings, variant: V) -> Rendered {
    let (width, height) = (settings.width, settings.height);
    let pixels = width as usize * height as usize;
    // Only the pictures asked for, each written in place by the bands: no per-pixel record to
    // convert afterwards (at 4096² that was 170 MB of fresh pages, a tenth of the run in page
    // faults, and a serial pass).
    let picture = |wanted: bool| wanted.then(|| vec![[0_u8; 3]; pixels]);
    let mut colour = picture(settings.colour);
    let mut normals = picture(settings.normals);
    let mut depth = picture(settings.depth.is_some());
    // Bands of TILE rows, thinner when the image is too short to give every thread eight (a
    // 4096x16 picture would otherwise be one band on one thread, and at 1024² sixteen threads
    // would get four bands each, too few to even out the bands' different costs).
    let threads = rayon::current_num_threads() as u32;
    let band_rows = (height / (8 * threads)).clamp(1, TILE);
    let band_len = (width as usize * band_rows as usize).max(1);
    let band_count = pixels.div_ceil(band_len);
    let split = |picture| split_into_bands(picture, band_len, band_count);
    let bands: Vec<Band> = split(&mut colour)
        .into_iter()
        .zip(split(&mut normals))
        .zip(split(&mut depth))
        .map(|((colour, normals), depth)| Band {
            colour,
            normals,
            depth,
        })
        .collect();
    let background = variant.to_rgb(scene.background);
    let progress = Progress::new(settings.progress, settings.counter, band_count);
    let tracer = Tracer::with_variant(scene, settings.trace, variant);
    let traced = bands
        .into_par_iter()
        .enumerate()
        .map(|(band, mut out)| {
            let top = band as u32 * band_rows;
            let rows = band_rows.min(height - top);
            let rows = top..top + rows;
            let counts = render_band(&tracer, variant, settings, background, rows, &mut out);
            progress.advance();
            counts
        })
        .reduce(RayCounts::default, |a, b| a + b);
    progress.finish();

    let image = |pixels: Option<Vec<[u8; 3]>>| {
        pixels.map(|pixels| Image {
            width,
            height,
            pixels,
        })
    };
    Rendered {
        colour: image(colour),
        normals: image(normals),
        depth: image(depth),
        rays: traced,
        film: None,
    }
}

/// The pixels of rows `rows` (a band, whose first row is the band's first pixel), tile by
/// tile, each tile's camera rays cast in packets of PACKET_SIDE × PACKET_SIDE.
fn render_band<V: Variant>(
    tracer: &Tracer<V>,
    variant: V,
    settings: &RenderSettings,
    background: [u8; 3],
    rows: std::ops::Range<u32>,
    out: &mut Band,
) -> RayCounts {
    let (width, height) = (settings.width, settings.height);
    let camera = &tracer.scene().camera;
    let mut scratch = Scratch::default();
    let mut rays: ArrayVec<Ray, PACKET> = ArrayVec::new();
    let mut indices: ArrayVec<usize, PACKET> = ArrayVec::new();
    for tile_left in (0..width).step_by(TILE as usize) {
        let tile_right = (tile_left + TILE).min(width);
        for packet_top in rows.clone().step_by(PACKET_SIDE as usize) {
            for packet_left in (tile_left..tile_right).step_by(PACKET_SIDE as usize) {
                rays.clear();
                indices.clear();
                for row in packet_top..(packet_top + PACKET_SIDE).min(rows.end) {
                    for column in packet_left..(packet_left + PACKET_SIDE).min(tile_right) {
                        // Rows are stored top first; the camera counts them from the bottom.
                        let (u, v) =
                            variant.pixel_to_screen(column, height - 1 - row, width, height);
                        rays.push(variant.ray(camera, u, v));
                        indices.push(((row - rows.start) * width + column) as usize);
                    }
                }
                tracer.camera_rays(&rays, settings.colour, &mut scratch, |i, seen, hit| {
                    out.set(
                        variant, indices[i], settings, background, &rays[i], seen, hit,
                    );
                });
            }
        }
    }
    scratch.counts
}

/// A picture (if it was asked for) as `band_count` runs of `band_len` pixels (the last shorter).
fn split_into_bands(
    picture: &mut Option<Vec<[u8; 3]>>,
    band_len: usize,
    band_count: usize,
) -> Vec<Option<&mut [[u8; 3]]>> {
    match picture {
        Some(p) => p.chunks_mut(band_len).map(Some).collect(),
        None => (0..band_count).map(|_| None).collect(),
    }
}

/// One band's rows of each picture asked for.
struct Band<'a> {
    colour: Option<&'a mut [[u8; 3]]>,
    normals: Option<&'a mut [[u8; 3]]>,
    depth: Option<&'a mut [[u8; 3]]>,
}

impl Band<'_> {
    /// Pixel `index` of the band, from what its camera ray saw and hit. Where nothing is hit,
    /// the normal and depth pictures stay black.
    #[inline]
    #[allow(clippy::too_many_arguments)] // One pixel's inputs, called in the hot loop.
    fn set<V: Variant>(
        &mut self,
        variant: V,
        index: usize,
        settings: &RenderSettings,
        background: [u8; 3],
        ray: &Ray,
        seen: Vec3A,
        hit: Option<Hit>,
    ) {
        let Some(hit) = hit else {
            if let Some(colour) = &mut self.colour {
                colour[index] = background;
            }
            if let Some(miss) = variant.picture_miss(background) {
                for picture in [&mut self.normals, &mut self.depth].into_iter().flatten() {
                    picture[index] = miss;
                }
            }
            return;
        };
        if let Some(colour) = &mut self.colour {
            colour[index] = variant.to_rgb(seen);
        }
        if let Some(normals) = &mut self.normals {
            normals[index] = variant.to_rgb(variant.normal_colour(&hit));
        }
        if let (Some(depth), Some((near, far))) = (&mut self.depth, settings.depth) {
            let distance = hit.t * ray.direction.length();
            depth[index] = [shade::to_byte(variant.depth_grey(distance, near, far)); 3];
        }
    }
}

/// Every sample of every pixel kept on a film, then filtered into pixels: assignment 7.
fn render_film<V: Variant>(scene: &Scene, settings: &RenderSettings, variant: V) -> Rendered {
    let (width, height) = (settings.width, settings.height);
    let Sampling {
        sampler,
        filter,
        seed,
    } = settings.sampling;
    let n = sampler.samples() as usize;
    let row_len = width as usize * n;
    let mut film = Film {
        width,
        height,
        samples: n as u32,
        entries: vec![FilmSample::default(); row_len * height as usize],
    };
    let tracer = Tracer::with_variant(scene, settings.trace, variant);
    let progress = Progress::new(settings.progress, settings.counter, height as usize);
    let rays = film
        .entries
        .par_chunks_mut(row_len)
        .enumerate()
        .map(|(j, row)| {
            let mut scratch = Scratch::default();
            let mut positions = vec![glam::Vec2::ZERO; n];
            for (i, pixel) in row.chunks_mut(n).enumerate() {
                let index = j as u64 * u64::from(width) + i as u64;
                variant.positions(sampler, seed, index, &mut positions);
                for (sample, &position) in pixel.iter_mut().zip(&positions) {
                    let (x, y) = (i as f32 + position.x, j as f32 + position.y);
                    let (u, v) = variant.film_to_screen(x, y, width, height);
                    let ray = variant.ray(&scene.camera, u, v);
                    let (colour, hit) = tracer.camera_ray(&ray, settings.colour, &mut scratch);
                    *sample = FilmSample {
                        position,
                        colour,
                        normal: match (&hit, settings.normals) {
                            (Some(hit), true) => variant.normal_colour(hit),
                            _ => Vec3A::ZERO,
                        },
                        depth: match (&hit, settings.depth) {
                            (Some(hit), Some((near, far))) => {
                                variant.depth_grey(hit.t * ray.direction.length(), near, far)
                            }
                            _ => 0.0,
                        },
                    };
                }
            }
            progress.advance();
            scratch.counts
        })
        .reduce(RayCounts::default, |a, b| a + b);
    progress.finish();
    let picture = |wanted: bool, value: fn(&FilmSample) -> Vec3A| {
        wanted.then(|| {
            film.picture(variant, variant.filter(filter), value, |colour| {
                variant.to_rgb(colour)
            })
        })
    };
    Rendered {
        colour: picture(settings.colour, |s| s.colour),
        normals: picture(settings.normals, |s| s.normal),
        depth: picture(settings.depth.is_some(), |s| Vec3A::splat(s.depth)),
        rays,
        film: settings.keep_film.then_some(film),
    }
}

/// A progress bar that appears only once the render has taken a second, and the counter of
/// whoever else watches.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    shown: AtomicBool,
    counter: Option<&'static RenderCounter>,
}

impl Progress {
    fn new(enabled: bool, counter: Option<&'static RenderCounter>, bands: usize) -> Progress {
        if let Some(counter) = counter {
            counter.done.store(0, Ordering::Relaxed);
            counter.total.store(bands as u64, Ordering::Relaxed);
        }
        let bar = enabled.then(|| {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(bands as u64),
                indicatif::ProgressDrawTarget::hidden(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "rendering {wide_bar} {percent:>3}%, {elapsed} elapsed, about {eta} left",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Progress {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(false),
            counter,
        }
    }

    fn advance(&self) {
        if let Some(counter) = self.counter {
            counter.done.fetch_add(1, Ordering::Relaxed);
        }
        let Some(bar) = &self.bar else { return };
        bar.inc(1);
        if self.start.elapsed() > Duration::from_secs(1)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::parse::parse_scene;

    #[test]
    fn a_watcher_sees_the_render_through() {
        let description = parse_scene(
            Path::new("t.txt"),
            "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
             Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }
             Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }",
        )
        .unwrap();
        let scene = Scene::from_description(&description).unwrap();
        let counter: &'static RenderCounter = Box::leak(Box::default());
        assert_eq!(counter.fraction(), 0.0);
        let settings = RenderSettings {
            counter: Some(counter),
            ..RenderSettings::new(64, 48)
        };
        render_with(&scene, &settings, Exact);
        let total = counter.total.load(Ordering::Relaxed);
        assert!(total > 1, "{total} parts");
        assert_eq!(counter.done.load(Ordering::Relaxed), total);
        assert_eq!(counter.fraction(), 1.0);
    }
}
