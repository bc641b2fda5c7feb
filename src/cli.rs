//! The course's command line: `raycast -input scene.txt -size 200 200 -output out.tga
//! [-normals n.tga] [-depth 9 11 d.tga] [-shade_back] [-shadows] [-bounces N] [-weight W]`,
//! assignment 3's OpenGL-preview switches (accepted, without effect), plus `-specular_fix`,
//! `-threads N` and `-stats`.
//!
//! Parsed by hand rather than with `clap`: the course's options are single-dash words
//! (`-input`, `-shade_back`) and `-depth` takes three values of two kinds, which clap can only
//! imitate with workarounds, and users paste the course's command lines verbatim.

use std::ffi::{OsStr, OsString};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use crate::error::Error;
use crate::image_io::{self, ImageFormat, PendingOutputs};
use crate::render::{RenderSettings, render};
use crate::sample::{self, Filter, Sampler, Sampling};
use crate::scene::{Scene, SpecularFalloff};
use crate::trace::TraceSettings;

pub const USAGE: &str = "\
usage: raycast -input SCENE.txt -size WIDTH HEIGHT [-output IMAGE] [-normals IMAGE]
               [-depth TMIN TMAX IMAGE] [-shade_back] [-shadows] [-bounces N] [-weight W]
               [-specular_fix] [-threads N] [-stats]

Renders a scene of MIT 6.837's ray tracing assignments (1 to 7).

  -input FILE            the scene file
  -size W H              the image size in pixels
  -output FILE           the shaded picture
  -normals FILE          the surface normals as colours (|x|, |y|, |z|)
  -depth TMIN TMAX FILE  distance as grey: TMIN and nearer white, TMAX and farther black
  -shade_back            shade back faces like front faces (otherwise they are black);
                         needed to see through glass
  -shadows               one shadow ray toward each light
  -bounces N             reflect and refract rays up to N times (default 0)
  -weight W              trace no mirror or glass ray whose weight is below W (default 0)
  -specular_fix          fade highlights by N.L (the handout's optional fix)
  -random_samples N, -uniform_samples N, -jittered_samples N
                         N samples a pixel: anywhere, on a grid, or one in each cell of a grid
                         (uniform and jittered: N a square number); default one at the centre
  -box_filter R, -tent_filter R, -gaussian_filter SIGMA
                         how samples are weighed into pixels, R and SIGMA in pixels
                         (default with samples: -box_filter 0.5, each pixel its own samples)
  -seed S                seed of the random and jittered samples (default 6837)
  -grid NX NY NZ         search the course's uniform grid of NX x NY x NZ cells instead of
                         raycast's BVH (the same image)
  -visualize_grid        show the grid's occupied cells, coloured by how many primitives
                         each lists, instead of the scene
  -render_samples FILE ZOOM
                         a picture of where the samples fall, each pixel ZOOM x ZOOM
  -render_filter FILE ZOOM
                         a picture of the filter's weights about the centre pixel
  -gui, -tessellation THETA PHI, -gouraud
                         the course's OpenGL preview: accepted, and ignored
  -threads N             render on N threads (default: one per core)
  -stats                 print the course's ray tracing statistics (stdout), and the time
                         of each phase and the scene's size (stderr)
  -help                  print this text
  -version               print the version

Images are written as TGA, PPM or PNG, by their extension (.tga, .ppm, .png).
At least one of -output, -normals and -depth is needed. Options may come in any order,
and may also be written with two dashes (--input).";

/// The largest side accepted, and the most pixels: about 270 million, which at 7 bytes a pixel
/// while rendering and up to three 3-byte pictures after is about 4.5 GB at the peak.
pub const MAX_SIDE: u32 = 32768;
pub const MAX_PIXELS: u64 = 1 << 28;
// Every size accepted fits a TGA header's 16-bit sides.
const _: () = assert!(MAX_SIDE <= image_io::TGA_MAX_SIDE);

/// The most threads `-threads` may ask for: far more than any machine has cores, and few enough
/// that starting them cannot exhaust the system's threads or memory (each has its own stack).
pub const MAX_THREADS: usize = 1024;

/// The most samples a pixel: far more than any picture needs (the course goes to 36).
pub const MAX_SAMPLES: u32 = 1024;
/// The most samples an image may keep (width × height × samples a pixel): about 3 GiB of them.
pub const MAX_FILM_SAMPLES: u64 = 1 << 26;
/// The largest filter: a box or tent of 16 pixels, a Gaussian of σ 8 (reaching 16), so each
/// pixel weighs at most 33 × 33 pixels' samples.
pub const MAX_FILTER_REACH: f32 = 16.0;

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Options {
    pub input: PathBuf,
    pub width: u32,
    pub height: u32,
    pub output: Option<PathBuf>,
    pub normals: Option<PathBuf>,
    pub depth: Option<(f32, f32, PathBuf)>,
    pub trace: TraceSettings,
    pub sampling: Sampling,
    /// `-grid NX NY NZ`.
    pub grid: Option<[u32; 3]>,
    /// `-render_samples FILE ZOOM`.
    pub render_samples: Option<(PathBuf, u32)>,
    /// `-render_filter FILE ZOOM`.
    pub render_filter: Option<(PathBuf, u32)>,
    /// The course's OpenGL preview was asked for (`-gui`, `-tessellation`, `-gouraud`).
    pub preview: bool,
    pub threads: Option<usize>,
    pub stats: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    Render(Box<Options>),
    Help,
    Version,
}

/// Runs the program on its arguments (without the program name); returns the exit status:
/// 0 done, 1 the scene or a file is at fault, 2 the command line is.
pub fn run(args: Vec<OsString>) -> ExitCode {
    match parse_args(args) {
        Ok(Command::Help) => {
            say(std::io::stdout(), USAGE);
            ExitCode::SUCCESS
        }
        Ok(Command::Version) => {
            let version = concat!("raycast ", env!("CARGO_PKG_VERSION"));
            say(std::io::stdout(), version);
            ExitCode::SUCCESS
        }
        Ok(Command::Render(options)) => {
            if options.preview {
                say(
                    std::io::stderr(),
                    "raycast: -gui, -tessellation and -gouraud drive the course's OpenGL preview, \
                     which raycast does not have; they are ignored (the image is the same)",
                );
            }
            match execute(&options) {
                Ok(()) => ExitCode::SUCCESS,
                Err(error) => {
                    say(std::io::stderr(), &error.to_string());
                    ExitCode::from(1)
                }
            }
        }
        Err(message) => {
            say(std::io::stderr(), &format!("raycast: {message}\n\n{USAGE}"));
            ExitCode::from(2)
        }
    }
}

/// Writes a line, unlike `println!` without panicking (exit status 101) when the reader has
/// gone, as in `raycast -help | head -1`: the exit status must stay the one documented.
fn say(mut to: impl Write, text: &str) {
    let _ = writeln!(to, "{text}");
}

pub fn parse_args(args: Vec<OsString>) -> Result<Command, String> {
    let mut options = Options::default();
    let mut input = None;
    let mut size = None;
    let mut sampler = None;
    let mut filter = None;
    let mut seen: Vec<String> = Vec::new();
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let Some(text) = arg.to_str() else {
            return Err(format!("unknown option '{}'", arg.to_string_lossy()));
        };
        // `--input` is taken for `-input`, `-h` and `--help` for `-help`.
        let name = text.strip_prefix('-').unwrap_or(text);
        let name = name.strip_prefix('-').unwrap_or(name);
        let name = match name {
            "h" => "help",
            "V" => "version",
            _ => name,
        };
        if !text.starts_with('-') {
            return Err(format!(
                "unexpected argument '{text}' (options start with '-')"
            ));
        }
        if seen.iter().any(|s| s == name) {
            return Err(format!("-{name} is given twice"));
        }
        seen.push(name.to_string());
        let mut value = |what: &str| -> Result<OsString, String> {
            args.next()
                .ok_or_else(|| format!("-{name} needs {what}, found the end of the command line"))
        };
        match name {
            "help" => return Ok(Command::Help),
            "version" => return Ok(Command::Version),
            "input" => input = Some(PathBuf::from(value("a scene file")?)),
            "size" => {
                let what = "a width and a height in pixels";
                let width = positive(&value(what)?, "-size", "a width in pixels")?;
                let height = positive(&value(what)?, "-size", "a height in pixels")?;
                size = Some((width, height));
            }
            "output" => options.output = Some(PathBuf::from(value("an image file")?)),
            "normals" => options.normals = Some(PathBuf::from(value("an image file")?)),
            "depth" => {
                let what = "TMIN TMAX and an image file";
                let near = finite(&value(what)?, "-depth", "TMIN, a number")?;
                let far = finite(&value(what)?, "-depth", "TMAX, a number")?;
                if near == far {
                    return Err(format!(
                        "-depth needs TMIN and TMAX to differ, found {near} twice"
                    ));
                }
                options.depth = Some((near, far, PathBuf::from(value(what)?)));
            }
            "shade_back" => options.trace.shade_back = true,
            "shadows" => options.trace.shadows = true,
            "specular_fix" => options.trace.specular = SpecularFalloff::Fade,
            "bounces" => {
                let arg = value("a number of bounces")?;
                match arg.to_str().and_then(|s| s.parse::<u32>().ok()) {
                    Some(n) => options.trace.bounces = n,
                    None => {
                        return Err(format!(
                            "-bounces needs a number of bounces (a whole number from 0 to {}), \
                             found '{}'",
                            u32::MAX,
                            arg.to_string_lossy()
                        ));
                    }
                }
            }
            "weight" => {
                let weight = finite(&value("a weight")?, "-weight", "a weight, a number")?;
                if weight < 0.0 {
                    return Err(format!(
                        "-weight needs a weight of 0 or more, found '{weight}'"
                    ));
                }
                options.trace.cutoff_weight = weight;
            }
            "gui" | "gouraud" => options.preview = true,
            "tessellation" => {
                let what = "the preview's THETA and PHI steps";
                positive(&value(what)?, "-tessellation", "THETA")?;
                positive(&value(what)?, "-tessellation", "PHI")?;
                options.preview = true;
            }
            "stats" => options.stats = true,
            "random_samples" | "uniform_samples" | "jittered_samples" => {
                let arg = value("a number of samples")?;
                let n = match arg.to_str().and_then(|s| s.parse::<u32>().ok()) {
                    Some(n) if (1..=MAX_SAMPLES).contains(&n) => n,
                    _ => {
                        return Err(format!(
                            "-{name} needs a number of samples (a whole number from 1 to \
                             {MAX_SAMPLES}), found '{}'",
                            arg.to_string_lossy()
                        ));
                    }
                };
                if name != "random_samples" && n.isqrt() * n.isqrt() != n {
                    let below = n.isqrt() * n.isqrt();
                    let above = (n.isqrt() + 1) * (n.isqrt() + 1);
                    return Err(format!(
                        "-{name} needs a square number of samples (they lie on a square grid), \
                         found {n}: try {below} or {above}"
                    ));
                }
                if sampler.is_some() {
                    return Err("give only one of -random_samples, -uniform_samples and \
                                -jittered_samples"
                        .into());
                }
                sampler = Some(match name {
                    "random_samples" => Sampler::Random(n),
                    "uniform_samples" => Sampler::Uniform(n),
                    _ => Sampler::Jittered(n),
                });
            }
            "box_filter" | "tent_filter" | "gaussian_filter" => {
                let what = if name == "gaussian_filter" {
                    "SIGMA"
                } else {
                    "a radius"
                };
                let size = finite(
                    &value(what)?,
                    &format!("-{name}"),
                    &format!("{what}, a number of pixels"),
                )?;
                let reach = if name == "gaussian_filter" {
                    2.0 * size
                } else {
                    size
                };
                if size <= 0.0 || reach > MAX_FILTER_REACH {
                    return Err(format!(
                        "-{name} needs {what} above 0 and at most {} pixels, found {size}",
                        if name == "gaussian_filter" {
                            MAX_FILTER_REACH / 2.0
                        } else {
                            MAX_FILTER_REACH
                        }
                    ));
                }
                if filter.is_some() {
                    return Err(
                        "give only one of -box_filter, -tent_filter and -gaussian_filter".into(),
                    );
                }
                filter = Some(match name {
                    "box_filter" => Filter::Box(size),
                    "tent_filter" => Filter::Tent(size),
                    _ => Filter::Gaussian(size),
                });
            }
            "grid" => {
                let what = "NX NY NZ, the numbers of cells";
                let mut cells = [0; 3];
                for (axis, n) in ["NX", "NY", "NZ"].iter().zip(&mut cells) {
                    *n = positive(&value(what)?, "-grid", axis)?;
                }
                let count = cells.iter().map(|&n| u64::from(n)).product::<u64>();
                if count > crate::accel::grid::MAX_CELLS {
                    return Err(format!(
                        "-grid {} {} {} is {count} cells, more than the {} that raycast keeps \
                         in memory",
                        cells[0],
                        cells[1],
                        cells[2],
                        crate::accel::grid::MAX_CELLS
                    ));
                }
                options.grid = Some(cells);
            }
            "visualize_grid" => options.trace.visualize_grid = true,
            "seed" => {
                let arg = value("a seed")?;
                match arg.to_str().and_then(|s| s.parse::<u64>().ok()) {
                    Some(seed) => options.sampling.seed = seed,
                    None => {
                        return Err(format!(
                            "-seed needs a whole number from 0 to {}, found '{}'",
                            u64::MAX,
                            arg.to_string_lossy()
                        ));
                    }
                }
            }
            "render_samples" | "render_filter" => {
                let what = "an image file and a zoom";
                let file = PathBuf::from(value(what)?);
                let zoom = positive(&value(what)?, &format!("-{name}"), "a zoom")?;
                if name == "render_samples" {
                    options.render_samples = Some((file, zoom));
                } else {
                    options.render_filter = Some((file, zoom));
                }
            }
            "threads" => {
                let arg = value("a number of threads")?;
                match arg.to_str().and_then(|s| s.parse::<usize>().ok()) {
                    Some(n) if (1..=MAX_THREADS).contains(&n) => options.threads = Some(n),
                    _ => {
                        return Err(format!(
                            "-threads needs a number of threads (a whole number from 1 to \
                             {MAX_THREADS}), found '{}'",
                            arg.to_string_lossy()
                        ));
                    }
                }
            }
            _ => return Err(format!("unknown option '{text}'")),
        }
    }
    options.input = input.ok_or("-input is missing: which scene should be rendered?")?;
    let (width, height) = size.ok_or("-size is missing: how many pixels wide and high?")?;
    if width > MAX_SIDE || height > MAX_SIDE || width as u64 * height as u64 > MAX_PIXELS {
        return Err(format!(
            "-size {width} {height} is too large: each side may be at most {MAX_SIDE} pixels, \
             and the image at most {MAX_PIXELS} pixels"
        ));
    }
    (options.width, options.height) = (width, height);
    if options.trace.visualize_grid && options.grid.is_none() {
        return Err("-visualize_grid needs -grid NX NY NZ: which grid should it show?".into());
    }
    options.trace.tally = options.stats;
    // Samples without a filter: each pixel its own samples. A filter without samples: the
    // pixels' centres, filtered.
    options.sampling.sampler = sampler.unwrap_or(Sampler::Uniform(1));
    options.sampling.filter = filter.unwrap_or(Filter::Box(0.5));
    let kept = u64::from(width) * u64::from(height) * u64::from(options.sampling.sampler.samples());
    if kept > MAX_FILM_SAMPLES && !options.sampling.is_plain() {
        return Err(format!(
            "{width}x{height} pixels of {} samples is too many samples to keep ({kept}); at \
             most {MAX_FILM_SAMPLES} (width x height x samples a pixel)",
            options.sampling.sampler.samples()
        ));
    }
    for (flag, picture) in [
        ("-render_samples", &options.render_samples),
        ("-render_filter", &options.render_filter),
    ] {
        let Some((_, zoom)) = picture else { continue };
        let extra = u64::from(flag == "-render_filter");
        let (w, h) = (
            u64::from(width) * u64::from(*zoom) + extra,
            u64::from(height) * u64::from(*zoom) + extra,
        );
        if w > u64::from(MAX_SIDE) || h > u64::from(MAX_SIDE) || w * h > MAX_PIXELS {
            return Err(format!(
                "{flag} with zoom {zoom} would make a {w}x{h} picture; each side may be at most \
                 {MAX_SIDE} pixels, and the picture at most {MAX_PIXELS} pixels"
            ));
        }
    }
    let outputs = options.outputs();
    // The course's preview-only lines (`-gui` and no image): the scene is still read and
    // checked, and raycast says it has no preview.
    if outputs.is_empty() && !options.preview {
        return Err(
            "nothing to write: give -output, -normals, -depth, -render_samples or -render_filter"
                .into(),
        );
    }
    for (i, &(flag, path)) in outputs.iter().enumerate() {
        // Found now rather than when the finished image is renamed into place, after the render.
        if path.to_string_lossy().ends_with(std::path::is_separator) || path.is_dir() {
            return Err(format!(
                "{flag} '{}' names a folder, not an image file",
                path.display()
            ));
        }
        // Asked before the extension: `-output scene.txt` is a slip of the scene's name, and
        // "unknown image type" would send the user looking in the wrong place.
        if same_file(path, &options.input) {
            return Err(format!(
                "{flag} '{}' would overwrite the scene file",
                path.display()
            ));
        }
        if ImageFormat::from_path(path).is_none() {
            return Err(format!(
                "{flag} '{}': unknown image type; name it {}",
                path.display(),
                ImageFormat::EXTENSIONS
            ));
        }
        if let Some(&(other, _)) = outputs[..i].iter().find(|(_, p)| same_file(p, path)) {
            return Err(format!(
                "{other} and {flag} name the same file '{}'",
                path.display()
            ));
        }
    }
    Ok(Command::Render(Box::new(options)))
}

impl Options {
    /// The images asked for, each with the option that named it.
    pub fn outputs(&self) -> Vec<(&'static str, &Path)> {
        let mut outputs = Vec::new();
        if let Some(path) = &self.output {
            outputs.push(("-output", path.as_path()));
        }
        if let Some(path) = &self.normals {
            outputs.push(("-normals", path.as_path()));
        }
        if let Some((_, _, path)) = &self.depth {
            outputs.push(("-depth", path.as_path()));
        }
        if let Some((path, _)) = &self.render_samples {
            outputs.push(("-render_samples", path.as_path()));
        }
        if let Some((path, _)) = &self.render_filter {
            outputs.push(("-render_filter", path.as_path()));
        }
        outputs
    }
}

fn positive(arg: &OsStr, flag: &str, what: &str) -> Result<u32, String> {
    match arg.to_str().and_then(|s| s.parse::<u32>().ok()) {
        Some(n) if n > 0 => Ok(n),
        _ => Err(format!(
            "{flag} needs {what} (a whole number above 0), found '{}'",
            arg.to_string_lossy()
        )),
    }
}

fn finite(arg: &OsStr, flag: &str, what: &str) -> Result<f32, String> {
    match arg.to_str().and_then(|s| s.parse::<f32>().ok()) {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(format!(
            "{flag} needs {what}, found '{}'",
            arg.to_string_lossy()
        )),
    }
}

/// Whether two paths name one file, also when written differently (`./a.txt` and `a.txt`).
fn same_file(a: &Path, b: &Path) -> bool {
    let resolve = |p: &Path| -> Option<PathBuf> {
        let folder = image_io::folder_of(p).canonicalize().ok()?;
        Some(folder.join(p.file_name()?))
    };
    a == b || matches!((resolve(a), resolve(b)), (Some(x), Some(y)) if x == y)
}

/// Runs the whole job (loading and tree building too, not only the render) on `-threads` threads.
fn execute(options: &Options) -> Result<(), Error> {
    match options.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| Error::Refused(format!("raycast: cannot start {n} threads: {e}")))?
            .install(|| execute_on_current_pool(options)),
        None => execute_on_current_pool(options),
    }
}

fn execute_on_current_pool(options: &Options) -> Result<(), Error> {
    let outputs = options.outputs();
    let paths: Vec<&Path> = outputs.iter().map(|&(_, p)| p).collect();
    // Before any work: a folder that is missing or unwritable fails the run now.
    let pending = PendingOutputs::reserve(&paths)?;

    let (mut scene, mut load) = Scene::load(&options.input)?;
    if outputs.is_empty() {
        return Ok(());
    }
    for &(flag, path) in &outputs {
        if let Some(mesh) = load.mesh_files.iter().find(|m| same_file(path, m)) {
            return Err(Error::Refused(format!(
                "raycast: {flag} '{}' would overwrite the mesh file '{}' that the scene reads",
                path.display(),
                mesh.display()
            )));
        }
    }
    if let Some([nx, ny, nz]) = options.grid {
        let start = Instant::now();
        scene
            .world
            .use_grid(glam::UVec3::new(nx, ny, nz))
            .map_err(|e| Error::Refused(format!("{}: {e}", options.input.display())))?;
        load.build += start.elapsed();
    }

    let settings = RenderSettings {
        width: options.width,
        height: options.height,
        // The samples picture shows the samples' colours.
        colour: options.output.is_some() || options.render_samples.is_some(),
        normals: options.normals.is_some(),
        depth: options.depth.as_ref().map(|&(near, far, _)| (near, far)),
        trace: options.trace,
        sampling: options.sampling,
        keep_film: options.render_samples.is_some(),
        progress: std::io::stderr().is_terminal(),
    };
    // Only the filter picture asked for: nothing to trace.
    let traced = options.output.is_some()
        || options.normals.is_some()
        || options.depth.is_some()
        || options.render_samples.is_some();
    let render_start = Instant::now();
    let mut rendered = if traced {
        render(&scene, &settings)
    } else {
        crate::render::Rendered::default()
    };
    let threads = rayon::current_num_threads();
    let render_time = render_start.elapsed();

    let write_start = Instant::now();
    let samples_picture = options.render_samples.as_ref().map(|&(_, zoom)| {
        let film = rendered.film.take().expect("kept for -render_samples");
        sample::render_samples_picture(&film, zoom)
    });
    let filter_picture = options.render_filter.as_ref().map(|&(_, zoom)| {
        sample::render_filter_picture(options.width, options.height, options.sampling.filter, zoom)
    });
    if options.output.is_none() {
        rendered.colour = None;
    }
    let images = [
        &rendered.colour,
        &rendered.normals,
        &rendered.depth,
        &samples_picture,
        &filter_picture,
    ];
    let contents = images
        .into_iter()
        .flatten()
        .zip(&paths)
        .map(|(image, path)| {
            let format =
                ImageFormat::from_path(path).expect("checked when parsing the command line");
            image_io::encode(image, format)
        })
        .collect();
    pending.commit(contents)?;
    let write_time = write_start.elapsed();

    if options.stats {
        print_course_statistics(options, &scene, &rendered.rays, render_time);
        let w = load.world;
        let rays = rendered.rays;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let mb = |bytes: usize| bytes as f64 / (1 << 20) as f64;
        eprintln!("raycast: parse and load  {:9.2} ms", ms(load.parse));
        eprintln!("raycast: build BVH       {:9.2} ms", ms(load.build));
        eprintln!(
            "raycast: render          {:9.2} ms  ({} rays on {threads} thread{}, {:.2} M rays/s)",
            ms(render_time),
            rays.primary + rays.secondary + rays.shadow,
            if threads == 1 { "" } else { "s" },
            (rays.primary + rays.secondary + rays.shadow) as f64 / render_time.as_secs_f64() / 1e6
        );
        eprintln!(
            "raycast: rays: {} primary, {} reflected or refracted, {} shadow",
            rays.primary, rays.secondary, rays.shadow
        );
        eprintln!("raycast: write images    {:9.2} ms", ms(write_time));
        eprintln!(
            "raycast: scene: {} triangles stored ({} placed) in {} mesh{}, {} instance{}, {} sphere{}, {} plane{}",
            w.triangles,
            w.triangles_placed,
            w.meshes,
            if w.meshes == 1 { "" } else { "es" },
            w.instances,
            if w.instances == 1 { "" } else { "s" },
            w.spheres,
            if w.spheres == 1 { "" } else { "s" },
            w.planes,
            if w.planes == 1 { "" } else { "s" },
        );
        eprintln!(
            "raycast: memory: geometry {:.2} MiB, acceleration {:.2} MiB ({} BVH nodes)",
            mb(w.geometry_bytes),
            mb(w.acceleration_bytes),
            w.nodes
        );
    }
    Ok(())
}

/// The course's `RayTracingStats::PrintStatistics`, line for line: the render's time in whole
/// seconds (at least 1), the image, the scene's box and the grid, then the rays cast (camera,
/// mirror and glass rays are the course's "non-shadow" rays), the primitives tested and the grid
/// cells entered, and their rates.
fn print_course_statistics(
    options: &Options,
    scene: &Scene,
    rays: &crate::trace::RayCounts,
    render_time: std::time::Duration,
) {
    let seconds = render_time.as_secs().max(1);
    let non_shadow = rays.primary + rays.secondary;
    let all = non_shadow + rays.shadow;
    let pixels = u64::from(options.width) * u64::from(options.height);
    // As the course's floats: no rays at all give nan.
    let per = |count: u64, of: u64| count as f32 / of as f32;
    let bounds = match scene.world.bounds() {
        Some(b) => format!(
            "{:.6} {:.6} {:.6}  -> {:.6} {:.6} {:.6}",
            b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
        ),
        None => "NULL".to_string(),
    };
    let cells = match options.grid {
        Some([x, y, z]) => format!(
            "{} ({x}x{y}x{z})",
            u64::from(x) * u64::from(y) * u64::from(z)
        ),
        None => "NULL".to_string(),
    };
    let stars = "*".repeat(44);
    let text = format!(
        "{stars}
RAY TRACING STATISTICS
  total time                 {}:{:02}:{:02}
  num pixels                 {pixels} ({}x{})
  scene bounds               {bounds}
  num grid cells             {cells}
  num non-shadow rays        {non_shadow}
  num shadow rays            {}
  total intersections        {}
  total cells traversed      {}
  rays per second            {:.1}
  rays per pixel             {:.1}
  intersections per ray      {:.1}
  cells traversed per ray    {:.1}
{stars}",
        seconds / 3600,
        (seconds / 60) % 60,
        seconds % 60,
        options.width,
        options.height,
        rays.shadow,
        rays.tallies.intersections,
        rays.tallies.cells,
        per(all, seconds),
        per(all, pixels),
        per(rays.tallies.intersections, all),
        per(rays.tallies.cells, all),
    );
    say(std::io::stdout(), &text);
}
