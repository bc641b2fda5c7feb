//! The pixel loop: bands of up to 16 rows, each taken by the next free worker of rayon's pool
//! (so they finish nearly top to bottom), each band walked in tiles 16 pixels wide (neighbouring
//! rays then meet the same nodes while they are in cache), each pixel one camera ray through its
//! centre, handed to the [`Tracer`] in blocks of 8×8 (or as many rows as the band has), a packet
//! that searches the scene together. The bands are drawn into the whole pictures
//! ([`render_with`]) or into a worker's own rows and handed on in order ([`render_streamed`]).
//! Every pixel is computed the same way whichever thread takes it, so any thread count gives the
//! same image.

use std::collections::BTreeMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use arrayvec::ArrayVec;
use glam::Vec3A;
use rayon::prelude::*;

use crate::accel::{Hit, PACKET};
use crate::camera::CameraSeam;
use crate::error::Error;
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
    /// A flag that ends the render early once set (check was asked to stop): the bands or rows
    /// not begun are left as they are, and the pictures are unfinished.
    pub stop: Option<&'static StopFlag>,
}

/// A flag another thread (or a signal handler) sets to end renders early: check's, set by
/// Ctrl-C, SIGTERM or SIGHUP.
#[derive(Debug, Default)]
pub struct StopFlag {
    flag: std::sync::Arc<AtomicBool>,
    /// Set with the flag where the cause is time (check's `--deadline`), not a person.
    out_of_time: AtomicBool,
}

impl StopFlag {
    /// A flag not yet set, for the program's whole life (one a run: renders on any thread
    /// read it).
    pub fn leaked() -> &'static StopFlag {
        Box::leak(Box::default())
    }

    /// Sets it: every render that reads it ends early.
    pub fn set(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }

    /// Sets it because time ran out.
    pub fn set_out_of_time(&self) {
        self.out_of_time.store(true, Ordering::Relaxed);
        self.set();
    }

    /// Whether it is set.
    pub fn is_set(&self) -> bool {
        self.flag.load(Ordering::Relaxed)
    }

    /// Whether it was set because time ran out (and not first by a person).
    pub fn is_out_of_time(&self) -> bool {
        self.out_of_time.load(Ordering::Relaxed)
    }

    /// The flag itself, for a signal handler to set (`signal_hook::flag::register`).
    pub fn shared(&self) -> std::sync::Arc<AtomicBool> {
        self.flag.clone()
    }
}

// Two flags are the same flag: there is nothing else to compare.
impl PartialEq for StopFlag {
    fn eq(&self, other: &StopFlag) -> bool {
        std::ptr::eq(self, other)
    }
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
    /// Whether the pictures can be rendered a band at a time ([`render_streamed`]): one ray
    /// through each pixel's centre and no film kept.
    pub fn streams(&self) -> bool {
        self.sampling.is_plain() && !self.keep_film
    }

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
            stop: None,
        }
    }

    /// Whether the render was asked to stop.
    pub fn stopped(&self) -> bool {
        self.stop.is_some_and(StopFlag::is_set)
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
    render_rows_with(scene, settings, variant, None)
}

/// [`render_with`], only the rows `wanted` marks (counted from the top) where it is given: the
/// other rows' pixels are left black. Every pixel is its own ray (or its own samples, filtered
/// from its neighbours' too, which are traced for it), so a wanted row is the same as in the
/// whole render: check screens a fault's render of a line by a few rows before it renders it
/// all.
pub fn render_rows_with<V: Variant>(
    scene: &Scene,
    settings: &RenderSettings,
    variant: V,
    wanted: Option<&[bool]>,
) -> Rendered {
    assert!(
        wanted.is_none_or(|wanted| wanted.len() == settings.height as usize),
        "a mark for each row"
    );
    if settings.streams() {
        render_centres(scene, settings, variant, wanted)
    } else {
        render_film(scene, settings, variant, wanted)
    }
}

/// One ray through each pixel's centre, straight to bytes: assignments 1 to 6.
fn render_centres<V: Variant>(
    scene: &Scene,
    settings: &RenderSettings,
    variant: V,
    wanted: Option<&[bool]>,
) -> Rendered {
    let (width, height) = (settings.width, settings.height);
    let layout = BandLayout::of(settings);
    let pixels = width as usize * height as usize;
    // Only the pictures asked for, each written in place by the bands: no per-pixel record to
    // convert afterwards (at 4096² that was 170 MB of fresh pages, a tenth of the run in page
    // faults, and a serial pass).
    let picture = |wanted: bool| wanted.then(|| vec![[0_u8; 3]; pixels]);
    let mut colour = picture(settings.colour);
    let mut normals = picture(settings.normals);
    let mut depth = picture(settings.depth.is_some());
    let split = |picture| split_into_bands(picture, layout.band_len, layout.band_count);
    let bands: Vec<Mutex<Band>> = split(&mut colour)
        .into_iter()
        .zip(split(&mut normals))
        .zip(split(&mut depth))
        .map(|((colour, normals), depth)| {
            Mutex::new(Band {
                colour,
                normals,
                depth,
            })
        })
        .collect();
    let rays = render_bands(scene, settings, variant, &layout, &InPlace(bands), wanted);

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
        rays,
        film: None,
    }
}

/// Takes a render's rows as they are finished, top to bottom (see [`render_streamed`]).
pub trait RowSink: Send {
    /// The next rows of each picture asked for; an error stops the render.
    fn rows(&mut self, rows: &FinishedRows) -> Result<(), Error>;
}

/// Rows of the pictures, finished: `width × rows` pixels of each picture asked for.
#[derive(Debug)]
pub struct FinishedRows<'a> {
    /// The first of them, counted from the top.
    pub first_row: u32,
    /// The shaded picture's rows, if it was asked for.
    pub colour: Option<&'a [[u8; 3]]>,
    /// The normals picture's rows, if it was asked for.
    pub normals: Option<&'a [[u8; 3]]>,
    /// The depth picture's rows, if it was asked for.
    pub depth: Option<&'a [[u8; 3]]>,
}

/// Renders the pictures `settings` asks for, one ray through each pixel's centre, handing their
/// rows to `sink` top to bottom as they are finished, never holding more than a few bands of
/// them: a 4096² picture is 50 MB that need not be in memory at once. Only for the plain
/// sampling ([`RenderSettings::streams`]); the film's filter reaches across rows.
pub fn render_streamed<V: Variant>(
    scene: &Scene,
    settings: &RenderSettings,
    variant: V,
    sink: &mut dyn RowSink,
) -> Result<RayCounts, Error> {
    assert!(settings.streams(), "a film's pictures are filtered whole");
    let layout = BandLayout::of(settings);
    let streamed = Streamed {
        layout,
        wanted: [settings.colour, settings.normals, settings.depth.is_some()],
        in_order: Mutex::new(InOrder {
            next: 0,
            waiting: BTreeMap::new(),
            sink,
            failed: None,
        }),
    };
    let rays = render_bands(scene, settings, variant, &layout, &streamed, None);
    let in_order = streamed
        .in_order
        .into_inner()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    match in_order.failed {
        Some(error) => Err(error),
        None => Ok(rays),
    }
}

/// How a picture is cut into bands: runs of whole rows, the unit a thread takes.
#[derive(Debug, Clone, Copy)]
struct BandLayout {
    width: u32,
    height: u32,
    band_rows: u32,
    /// Pixels in a band (the last may have fewer).
    band_len: usize,
    band_count: usize,
}

impl BandLayout {
    /// Bands of TILE rows, thinner when the image is too short to give every thread eight (a
    /// 4096x16 picture would otherwise be one band on one thread, and at 1024² sixteen threads
    /// would get four bands each, too few to even out the bands' different costs).
    fn of(settings: &RenderSettings) -> BandLayout {
        let (width, height) = (settings.width, settings.height);
        let threads = rayon::current_num_threads() as u32;
        let band_rows = (height / (8 * threads)).clamp(1, TILE);
        let band_len = (width as usize * band_rows as usize).max(1);
        let pixels = width as usize * height as usize;
        BandLayout {
            width,
            height,
            band_rows,
            band_len,
            band_count: pixels.div_ceil(band_len),
        }
    }

    /// The rows of band `index`.
    fn rows(&self, index: usize) -> std::ops::Range<u32> {
        let top = index as u32 * self.band_rows;
        top..top + self.band_rows.min(self.height - top)
    }
}

/// Where the bands' pixels go.
trait Bands: Sync {
    /// What one thread keeps from band to band.
    type Worker;
    /// A thread's own, made when it starts.
    fn worker(&self) -> Self::Worker;
    /// Band `index`'s pixels, drawn by `draw`; false stops the render.
    fn band(&self, worker: &mut Self::Worker, index: usize, draw: impl FnOnce(&mut Band)) -> bool;
}

/// Every band is a run of the whole pictures, drawn where it lies.
struct InPlace<'a>(Vec<Mutex<Band<'a>>>);

impl Bands for InPlace<'_> {
    type Worker = ();

    fn worker(&self) {}

    fn band(&self, _: &mut (), index: usize, draw: impl FnOnce(&mut Band)) -> bool {
        // Each band is taken by one thread only: the lock is never waited for.
        draw(&mut self.0[index].lock().unwrap_or_else(|p| p.into_inner()));
        true
    }
}

/// Every band drawn in a thread's own rows, then handed on in order.
struct Streamed<'s> {
    layout: BandLayout,
    /// Colour, normals, depth.
    wanted: [bool; 3],
    in_order: Mutex<InOrder<'s>>,
}

/// The bands handed on so far, and those finished early, waiting for the ones before them.
struct InOrder<'s> {
    next: usize,
    waiting: BTreeMap<usize, [Option<Vec<[u8; 3]>>; 3]>,
    sink: &'s mut dyn RowSink,
    failed: Option<Error>,
}

impl InOrder<'_> {
    /// Hands band `index` on, and after it those that were waiting for it; a band that comes
    /// early waits as a copy.
    fn finished(&mut self, layout: &BandLayout, index: usize, pixels: [Option<&[[u8; 3]]>; 3]) {
        if index != self.next {
            self.waiting
                .insert(index, pixels.map(|rows| rows.map(<[[u8; 3]]>::to_vec)));
            return;
        }
        self.hand_on(layout, index, pixels);
        while let Some(band) = self.waiting.remove(&self.next) {
            let pixels = [0, 1, 2].map(|i| band[i].as_deref());
            self.hand_on(layout, self.next, pixels);
        }
    }

    fn hand_on(&mut self, layout: &BandLayout, index: usize, pixels: [Option<&[[u8; 3]]>; 3]) {
        self.next = index + 1;
        if self.failed.is_some() {
            return;
        }
        let [colour, normals, depth] = pixels;
        let rows = FinishedRows {
            first_row: layout.rows(index).start,
            colour,
            normals,
            depth,
        };
        if let Err(error) = self.sink.rows(&rows) {
            self.failed = Some(error);
        }
    }
}

impl Bands for Streamed<'_> {
    type Worker = [Option<Vec<[u8; 3]>>; 3];

    fn worker(&self) -> Self::Worker {
        self.wanted
            .map(|wanted| wanted.then(|| vec![[0_u8; 3]; self.layout.band_len]))
    }

    fn band(&self, own: &mut Self::Worker, index: usize, draw: impl FnOnce(&mut Band)) -> bool {
        let len = self.layout.rows(index).len() * self.layout.width as usize;
        let [colour, normals, depth] = own
            .each_mut()
            .map(|rows| rows.as_deref_mut().map(|rows| &mut rows[..len]));
        draw(&mut Band {
            colour,
            normals,
            depth,
        });
        let pixels = [0, 1, 2].map(|i| own[i].as_deref().map(|rows| &rows[..len]));
        let mut in_order = self.in_order.lock().unwrap_or_else(|p| p.into_inner());
        in_order.finished(&self.layout, index, pixels);
        in_order.failed.is_none()
    }
}

/// Renders every band on the pool's threads. Each worker takes the next band not yet begun, so
/// the bands finish nearly in order (what streaming needs: rayon's splitting of a range would
/// have two threads begin at the top and the middle), and small bands even out their different
/// costs. There is a worker a thread, as ordinary tasks: where a thread is busy elsewhere (check
/// renders lines side by side), the others take its share.
fn render_bands<V: Variant, B: Bands>(
    scene: &Scene,
    settings: &RenderSettings,
    variant: V,
    layout: &BandLayout,
    bands: &B,
    wanted: Option<&[bool]>,
) -> RayCounts {
    let background = variant.to_rgb(scene.background);
    let progress = Progress::new(settings.progress, settings.counter, layout.band_count);
    let tracer = Tracer::with_variant(scene, settings.trace, variant);
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let workers = rayon::current_num_threads().min(layout.band_count);
    let counts = (0..workers).into_par_iter().with_max_len(1).map(|_| {
        let mut worker = bands.worker();
        let mut scratch = Scratch::default();
        loop {
            let index = next.fetch_add(1, Ordering::Relaxed);
            if index >= layout.band_count || stop.load(Ordering::Relaxed) || settings.stopped() {
                return scratch.counts;
            }
            let rows = layout.rows(index);
            if wanted.is_some_and(|wanted| {
                !wanted[rows.start as usize..rows.end as usize].contains(&true)
            }) {
                progress.advance();
                continue;
            }
            let go_on = bands.band(&mut worker, index, |band| {
                render_band(
                    &tracer,
                    variant,
                    settings,
                    background,
                    (rows, wanted),
                    &mut scratch,
                    band,
                )
            });
            progress.advance();
            if !go_on {
                stop.store(true, Ordering::Relaxed);
            }
        }
    });
    let counts = counts.reduce(RayCounts::default, |a, b| a + b);
    progress.finish();
    counts
}

/// The pixels of rows `rows` (a band, whose first row is the band's first pixel) that are
/// `wanted` (all where it is not given), tile by tile, each tile's camera rays cast in packets
/// of PACKET_SIDE × PACKET_SIDE.
fn render_band<V: Variant>(
    tracer: &Tracer<V>,
    variant: V,
    settings: &RenderSettings,
    background: [u8; 3],
    (rows, wanted): (std::ops::Range<u32>, Option<&[bool]>),
    scratch: &mut Scratch,
    out: &mut Band,
) {
    let (width, height) = (settings.width, settings.height);
    let camera = &tracer.scene().camera;
    let mut rays: ArrayVec<Ray, PACKET> = ArrayVec::new();
    let mut indices: ArrayVec<usize, PACKET> = ArrayVec::new();
    for tile_left in (0..width).step_by(TILE as usize) {
        let tile_right = (tile_left + TILE).min(width);
        for packet_top in rows.clone().step_by(PACKET_SIDE as usize) {
            for packet_left in (tile_left..tile_right).step_by(PACKET_SIDE as usize) {
                rays.clear();
                indices.clear();
                for row in packet_top..(packet_top + PACKET_SIDE).min(rows.end) {
                    if wanted.is_some_and(|wanted| !wanted[row as usize]) {
                        continue;
                    }
                    for column in packet_left..(packet_left + PACKET_SIDE).min(tile_right) {
                        // Rows are stored top first; the camera counts them from the bottom.
                        let (u, v) =
                            variant.pixel_to_screen(column, height - 1 - row, width, height);
                        rays.push(variant.ray(camera, u, v));
                        indices.push(((row - rows.start) * width + column) as usize);
                    }
                }
                tracer.camera_rays(&rays, settings.colour, scratch, |i, seen, hit| {
                    out.set(
                        variant, indices[i], settings, background, &rays[i], seen, hit,
                    );
                });
            }
        }
    }
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
    /// the normal and depth pictures are black (every pixel is written: a streamed band's
    /// rows are a thread's own, still holding the band before).
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
            let miss = variant.picture_miss(background).unwrap_or([0; 3]);
            for picture in [&mut self.normals, &mut self.depth].into_iter().flatten() {
                picture[index] = miss;
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
fn render_film<V: Variant>(
    scene: &Scene,
    settings: &RenderSettings,
    variant: V,
    wanted: Option<&[bool]>,
) -> Rendered {
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
    // A wanted row's pixels weigh the samples of the rows within the filter's reach.
    let reach = variant.filter(filter).support_radius() as usize;
    let traced = |j: usize| {
        wanted.is_none_or(|wanted| {
            let row = height as usize - 1 - j;
            wanted[row.saturating_sub(reach)..(row + reach + 1).min(height as usize)]
                .contains(&true)
        })
    };
    let rays = film
        .entries
        .par_chunks_mut(row_len)
        // Row by row among the threads: a render of a few rows (check's screen) would otherwise
        // leave them all in one thread's share.
        .with_max_len(1)
        .enumerate()
        .map(|(j, row)| {
            let mut scratch = Scratch::default();
            if settings.stopped() || !traced(j) {
                progress.advance();
                return scratch.counts;
            }
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
    let picture = |asked: bool, value: fn(&FilmSample) -> Vec3A| {
        asked.then(|| {
            film.picture_rows(
                variant,
                variant.filter(filter),
                value,
                |colour| variant.to_rgb(colour),
                wanted,
            )
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

    fn spheres() -> Scene {
        let description = parse_scene(
            Path::new("t.txt"),
            "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 }
             Lights { numLights 1 DirectionalLight { direction -1 -1 -1 color 1 1 1 } }
             Background { color 0.1 0.2 0.3 ambientLight 0.2 0.2 0.2 }
             Materials { numMaterials 2
                 Material { diffuseColor 1 0 0 }
                 Material { diffuseColor 0 1 0 } }
             Group { numObjects 3
                 MaterialIndex 0 Sphere { center 0 0 0 radius 1.5 }
                 MaterialIndex 1 Sphere { center 1.5 1.2 -1 radius 1 }
                 Sphere { center -1.2 -1.4 1 radius 0.6 } }",
        )
        .unwrap();
        Scene::from_description(&description).unwrap()
    }

    #[test]
    fn a_render_of_some_rows_is_the_whole_render_in_those_rows() {
        let scene = spheres();
        let (width, height) = (37, 29);
        let plain = RenderSettings {
            normals: true,
            depth: Some((8.0, 12.0)),
            ..RenderSettings::new(width, height)
        };
        let filtered = RenderSettings {
            sampling: Sampling {
                sampler: crate::sample::Sampler::Jittered(4),
                filter: crate::sample::Filter::Tent(1.5),
                seed: 7,
            },
            ..plain
        };
        let wanted: Vec<bool> = (0..height).map(|row| row % 7 == 3 || row == 0).collect();
        for settings in [plain, filtered] {
            let whole = render(&scene, &settings);
            let rows = render_rows_with(&scene, &settings, Exact, Some(&wanted));
            for (whole, rows) in [
                (&whole.colour, &rows.colour),
                (&whole.normals, &rows.normals),
                (&whole.depth, &rows.depth),
            ] {
                let (whole, rows) = (whole.as_ref().unwrap(), rows.as_ref().unwrap());
                for (row, &wanted) in wanted.iter().enumerate() {
                    let at = row * width as usize..(row + 1) * width as usize;
                    if wanted {
                        assert_eq!(whole.pixels[at.clone()], rows.pixels[at], "row {row}");
                    } else {
                        assert!(rows.pixels[at].iter().all(|&p| p == [0; 3]), "row {row}");
                    }
                }
            }
        }
    }

    /// Every row a sink is given, and where it began.
    #[derive(Default)]
    struct Collected {
        first_rows: Vec<u32>,
        pictures: [Vec<[u8; 3]>; 3],
        fail_at_call: Option<usize>,
    }

    impl RowSink for Collected {
        fn rows(&mut self, rows: &FinishedRows) -> Result<(), Error> {
            self.first_rows.push(rows.first_row);
            if Some(self.first_rows.len()) == self.fail_at_call {
                return Err(Error::Refused("the disk is full".into()));
            }
            let rows = [rows.colour, rows.normals, rows.depth];
            for (picture, rows) in self.pictures.iter_mut().zip(rows) {
                picture.extend_from_slice(rows.unwrap_or_default());
            }
            Ok(())
        }
    }

    #[test]
    fn streamed_rows_come_top_to_bottom_and_make_the_whole_pictures() {
        let scene = spheres();
        // Odd sides, and thin bands (67 rows over 3 threads: bands of 2 rows), on more
        // threads than the machine may have, so that bands finish out of order.
        let settings = RenderSettings {
            normals: true,
            depth: Some((8.0, 12.0)),
            ..RenderSettings::new(61, 67)
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let whole = pool.install(|| render(&scene, &settings));
        for _ in 0..5 {
            let mut sink = Collected::default();
            let rays = pool
                .install(|| render_streamed(&scene, &settings, Exact, &mut sink))
                .unwrap();
            assert_eq!(rays, whole.rays);
            let band_rows = sink.first_rows[1];
            assert!(band_rows < 16, "thin bands: {band_rows} rows");
            let expected: Vec<u32> = (0..67).step_by(band_rows as usize).collect();
            assert_eq!(sink.first_rows, expected);
            let [colour, normals, depth] = sink.pictures;
            assert_eq!(colour, whole.colour.as_ref().unwrap().pixels);
            assert_eq!(normals, whole.normals.as_ref().unwrap().pixels);
            assert_eq!(depth, whole.depth.as_ref().unwrap().pixels);
        }
    }

    #[test]
    fn a_sink_that_fails_stops_the_render_with_its_error() {
        let scene = spheres();
        let settings = RenderSettings::new(40, 200);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut sink = Collected {
            fail_at_call: Some(3),
            ..Collected::default()
        };
        let error = pool
            .install(|| render_streamed(&scene, &settings, Exact, &mut sink))
            .unwrap_err();
        assert_eq!(error.to_string(), "the disk is full");
        // Nothing after the failure reaches the sink.
        assert_eq!(sink.first_rows.len(), 3);
    }

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
