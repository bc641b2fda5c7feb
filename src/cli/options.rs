//! The command line: one table of options feeds the parser's names, the help text and the
//! shell completions, so that they cannot drift apart.
//!
//! Parsed by hand rather than with `clap`: the course's options are single-dash words
//! (`-input`, `-shade_back`) and `-depth` takes three values of two kinds, which clap can only
//! imitate with workarounds, and users paste the course's command lines verbatim.

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

use crate::image_io::{self, ImageFormat, MAX_PIXELS, MAX_SIDE};
use crate::sample::{Filter, Sampler, Sampling};
use crate::scene::SpecularFalloff;
use crate::trace::TraceSettings;

/// The part of the course an option comes from, which groups the help text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// Assignments 1 and 2.
    Casting,
    /// Assignment 3.
    Phong,
    /// Assignment 4.
    Tracing,
    /// Assignments 5 and 6.
    Grid,
    /// Assignment 7.
    Sampling,
    /// raycast's own.
    Own,
}

impl Group {
    const ALL: [Group; 6] = [
        Group::Casting,
        Group::Phong,
        Group::Tracing,
        Group::Grid,
        Group::Sampling,
        Group::Own,
    ];

    fn title(self) -> &'static str {
        match self {
            Group::Casting => "Assignments 1 and 2: ray casting",
            Group::Phong => "Assignment 3: Phong shading",
            Group::Tracing => "Assignment 4: shadows, mirrors and glass",
            Group::Grid => "Assignments 5 and 6: the grid and statistics",
            Group::Sampling => "Assignment 7: samples and filters",
            Group::Own => "raycast's own",
        }
    }
}

/// One option: its name (without the dash), what follows it, and one line of help.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionSpec {
    /// Without the dash.
    pub name: &'static str,
    /// The values that follow, as the help text shows them (empty for a switch).
    pub values: &'static str,
    /// The assignment it comes from.
    pub group: Group,
    /// One line for `-help`.
    pub help: &'static str,
}

const fn spec(
    name: &'static str,
    values: &'static str,
    group: Group,
    help: &'static str,
) -> OptionSpec {
    OptionSpec {
        name,
        values,
        group,
        help,
    }
}

/// Every option raycast takes.
pub const OPTIONS: &[OptionSpec] = &[
    spec(
        "input",
        "FILE",
        Group::Casting,
        "the scene file (- reads it from standard input)",
    ),
    spec(
        "size",
        "W H",
        Group::Casting,
        "the image's width and height in pixels",
    ),
    spec(
        "output",
        "FILE",
        Group::Casting,
        "the picture (- writes it to standard output)",
    ),
    spec(
        "normals",
        "FILE",
        Group::Casting,
        "the surface normals as colours (|x|, |y|, |z|)",
    ),
    spec(
        "depth",
        "TMIN TMAX FILE",
        Group::Casting,
        "distance as grey: TMIN and nearer white, TMAX and farther black",
    ),
    spec(
        "shade_back",
        "",
        Group::Casting,
        "shade back faces too (otherwise black); glass needs it",
    ),
    spec(
        "specular_fix",
        "",
        Group::Phong,
        "fade highlights by N.L (the handout's optional fix)",
    ),
    spec(
        "gui",
        "",
        Group::Phong,
        "the course's OpenGL preview: accepted and ignored",
    ),
    spec(
        "tessellation",
        "THETA PHI",
        Group::Phong,
        "the preview's sphere steps: accepted and ignored",
    ),
    spec(
        "gouraud",
        "",
        Group::Phong,
        "the preview's smooth shading: accepted and ignored",
    ),
    spec(
        "shadows",
        "",
        Group::Tracing,
        "one shadow ray toward each light",
    ),
    spec(
        "bounces",
        "N",
        Group::Tracing,
        "reflect and refract rays up to N times (default 0)",
    ),
    spec(
        "weight",
        "W",
        Group::Tracing,
        "trace no mirror or glass ray of weight below W (default 0)",
    ),
    spec(
        "grid",
        "NX NY NZ",
        Group::Grid,
        "search the course's grid of cells instead of the BVH",
    ),
    spec(
        "visualize_grid",
        "",
        Group::Grid,
        "show the grid's occupied cells instead of the scene",
    ),
    spec(
        "stats",
        "",
        Group::Grid,
        "the course's statistics (stdout) and phase times (stderr)",
    ),
    spec(
        "random_samples",
        "N",
        Group::Sampling,
        "N samples a pixel, anywhere in it",
    ),
    spec(
        "uniform_samples",
        "N",
        Group::Sampling,
        "N samples a pixel on a square grid (N a square)",
    ),
    spec(
        "jittered_samples",
        "N",
        Group::Sampling,
        "N samples a pixel, one in each cell of a square grid",
    ),
    spec(
        "box_filter",
        "R",
        Group::Sampling,
        "weigh samples within R of a pixel's centre alike (default 0.5)",
    ),
    spec(
        "tent_filter",
        "R",
        Group::Sampling,
        "weigh samples by 1 - d/R",
    ),
    spec(
        "gaussian_filter",
        "SIGMA",
        Group::Sampling,
        "weigh samples by exp(-d^2/2 SIGMA^2), to 2 SIGMA",
    ),
    spec(
        "render_samples",
        "FILE ZOOM",
        Group::Sampling,
        "a picture of where the samples fall",
    ),
    spec(
        "render_filter",
        "FILE ZOOM",
        Group::Sampling,
        "a picture of the filter's weights",
    ),
    spec(
        "seed",
        "S",
        Group::Own,
        "seed of the random and jittered samples (default 6837)",
    ),
    spec(
        "format",
        "png|ppm|tga",
        Group::Own,
        "the format of images named - or without an extension",
    ),
    spec(
        "threads",
        "N",
        Group::Own,
        "use N threads (default: one per core)",
    ),
    spec("help", "", Group::Own, "print this text"),
    spec("version", "", Group::Own, "print the version"),
];

/// The help text, from [`OPTIONS`].
pub fn usage() -> String {
    let mut text = String::from(
        "usage: raycast -input SCENE -size WIDTH HEIGHT -output IMAGE [options]
       raycast check SUITE --renderer CMD [--report DIR]   (raycast check -help)
       raycast diff IMAGE REFERENCE [--out DIFF.png]
       raycast completions bash|zsh|fish

Renders a scene of MIT 6.837's ray tracing assignments (Fall 2004) as the course's
renderer does. Options may come in any order, with one dash or two (--input).
",
    );
    for group in Group::ALL {
        text.push('\n');
        text.push_str(group.title());
        text.push('\n');
        for option in OPTIONS.iter().filter(|o| o.group == group) {
            let left = format!("  -{} {}", option.name, option.values);
            if left.trim_end().len() < 24 {
                text.push_str(&format!("{:<25}{}\n", left.trim_end(), option.help));
            } else {
                text.push_str(&format!("{}\n{:<25}{}\n", left.trim_end(), "", option.help));
            }
        }
    }
    text.push_str(
        "
Images are TGA (the course's layout), PPM or PNG, by their extension or -format. At least
one of -output, -normals, -depth, -render_samples and -render_filter is needed.",
    );
    text
}

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

/// A command line, understood.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Options {
    /// The scene file; `-` is standard input.
    pub input: PathBuf,
    /// `-size`, in pixels.
    pub width: u32,
    /// `-size`, in pixels.
    pub height: u32,
    /// `-output`: the shaded picture (`-` is standard output).
    pub output: Option<PathBuf>,
    /// `-normals`: the normals picture.
    pub normals: Option<PathBuf>,
    /// `-depth TMIN TMAX FILE`.
    pub depth: Option<(f32, f32, PathBuf)>,
    /// The tracer's switches: `-shade_back`, `-shadows`, `-bounces`, `-weight`,
    /// `-specular_fix`, `-visualize_grid`, and counting for `-stats`.
    pub trace: TraceSettings,
    /// The sampler, filter and seed.
    pub sampling: Sampling,
    /// `-grid NX NY NZ`.
    pub grid: Option<[u32; 3]>,
    /// `-render_samples FILE ZOOM`.
    pub render_samples: Option<(PathBuf, u32)>,
    /// `-render_filter FILE ZOOM`.
    pub render_filter: Option<(PathBuf, u32)>,
    /// The course's OpenGL preview was asked for (`-gui`, `-tessellation`, `-gouraud`).
    pub preview: bool,
    /// `-threads N`; `None` for one per core.
    pub threads: Option<usize>,
    /// `-stats`.
    pub stats: bool,
    /// `-format`: for images named `-` or without an extension.
    pub format: Option<ImageFormat>,
    /// `-inspect X Y`: the pixel to account for, y from the bottom.
    pub inspect: Option<(u32, u32)>,
    /// `-json`: the account as JSON.
    pub json: bool,
}

/// What a command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// A render (or, for a preview-only line, a check of the scene).
    Render(Box<Options>),
    /// `-help`.
    Help,
    /// `-version`.
    Version,
}

/// Reads a command line (without the program's name); the error is the message for the user.
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
        if let Some(complaint) = misspelt(text) {
            return Err(complaint);
        }
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
            let arg = args.next().ok_or_else(|| {
                format!("-{name} needs {what}, found the end of the command line")
            })?;
            // `-input -size 200 200`: the value was forgotten, and the next option taken for it.
            if arg.to_str().is_some_and(looks_like_option) {
                return Err(format!(
                    "-{name} needs {what}, found the option '{}'",
                    arg.to_string_lossy()
                ));
            }
            Ok(arg)
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
            "inspect" => {
                let what = "a pixel's X and Y";
                let whole = |arg: OsString, axis: &str| -> Result<u32, String> {
                    arg.to_str()
                        .and_then(|s| s.parse::<u32>().ok())
                        .ok_or_else(|| {
                            format!(
                                "-inspect needs {axis} (a whole number from 0), found '{}'",
                                arg.to_string_lossy()
                            )
                        })
                };
                let x = whole(value(what)?, "X")?;
                let y = whole(value(what)?, "Y")?;
                options.inspect = Some((x, y));
            }
            "json" => options.json = true,
            "format" => {
                let arg = value("an image format (png, ppm or tga)")?;
                options.format = Some(match arg.to_str() {
                    Some("png") => ImageFormat::Png,
                    Some("ppm") => ImageFormat::Ppm,
                    Some("tga") => ImageFormat::Tga,
                    _ => {
                        return Err(format!(
                            "-format needs png, ppm or tga, found '{}'",
                            arg.to_string_lossy()
                        ));
                    }
                });
            }
            _ => return Err(unknown_option(text)),
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
    if let Some((x, y)) = options.inspect
        && (x >= width || y >= height)
    {
        return Err(format!(
            "-inspect {x} {y} is outside the {width}x{height} image (x from 0 to {}, y from 0 \
             to {})",
            width - 1,
            height - 1
        ));
    }
    if options.json && options.inspect.is_none() {
        return Err("-json goes with -inspect X Y: which pixel should be accounted for?".into());
    }
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
    if outputs.is_empty() && !options.preview && options.inspect.is_none() {
        return Err(
            "nothing to write: give -output, -normals, -depth, -render_samples or -render_filter"
                .into(),
        );
    }
    for (i, &(flag, path)) in outputs.iter().enumerate() {
        // Found now rather than when the finished image is renamed into place, after the render.
        if !is_stdio(path)
            && (path.to_string_lossy().ends_with(std::path::is_separator) || path.is_dir())
        {
            return Err(format!(
                "{flag} '{}' names a folder, not an image file",
                path.display()
            ));
        }
        // Asked before the extension: `-output scene.txt` is a slip of the scene's name, and
        // "unknown image type" would send the user looking in the wrong place.
        if !is_stdio(path) && same_file(path, &options.input) {
            return Err(format!(
                "{flag} '{}' would overwrite the scene file",
                path.display()
            ));
        }
        if is_stdio(path) {
            if let Some(&(other, _)) = outputs[..i].iter().find(|(_, p)| is_stdio(p)) {
                return Err(format!(
                    "{other} and {flag} both name standard output (-); only one image can go \
                     there"
                ));
            }
            if options.format.is_none() {
                return Err(format!(
                    "{flag} - (standard output) needs -format png, ppm or tga"
                ));
            }
            continue;
        }
        if options.format_of(path).is_none() {
            return Err(format!(
                "{flag} '{}': unknown image type; name it {}, or give -format png, ppm or tga",
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
    /// An image's format: its extension's, or `-format`'s for a name without one (and `-`).
    pub fn format_of(&self, path: &Path) -> Option<ImageFormat> {
        ImageFormat::from_path(path).or(self.format)
    }

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

/// Whether a path is `-`: standard input or output.
pub fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// A word that is an option rather than a value: a dash and a letter (`-size`, `--input`), not
/// a negative number or `-` alone.
fn looks_like_option(word: &str) -> bool {
    let name = word.strip_prefix("--").or_else(|| word.strip_prefix('-'));
    name.and_then(|n| n.chars().next())
        .is_some_and(|c| c.is_ascii_alphabetic())
}

/// `--output=o.tga`: the form other programs take; raycast's values are the next word.
fn misspelt(word: &str) -> Option<String> {
    let (option, value) = word.split_once('=')?;
    let name = option.trim_start_matches('-');
    OPTIONS.iter().any(|o| o.name == name).then(|| {
        format!(
            "'{word}': raycast takes an option's values as the words after it: write \
             '-{name} {value}'"
        )
    })
}

/// The message for an unknown option, with the nearest real one when it is a likely slip.
fn unknown_option(word: &str) -> String {
    let name = word.trim_start_matches('-');
    let nearest = OPTIONS
        .iter()
        .map(|o| (edit_distance(name, o.name), o.name))
        .min();
    match nearest {
        // Two slips (a swap of two letters is two) in a long name, one in a short one.
        Some((distance, option)) if distance <= if option.len() > 3 { 2 } else { 1 } => {
            format!("unknown option '{word}' (did you mean -{option}?)")
        }
        _ => format!("unknown option '{word}' (raycast -help lists them all)"),
    }
}

/// Levenshtein distance: the fewest single-letter insertions, deletions and changes from `a`
/// to `b`.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitution = previous + usize::from(ca != cb);
            previous = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(previous + 1);
        }
    }
    row[b.len()]
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
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let resolve = |p: &Path| -> Option<PathBuf> {
        let folder = image_io::folder_of(p).canonicalize().ok()?;
        Some(folder.join(p.file_name()?))
    };
    a == b || matches!((resolve(a), resolve(b)), (Some(x), Some(y)) if x == y)
}
