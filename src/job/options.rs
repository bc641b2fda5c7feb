//! The command line: one table of options feeds the parser's names, the help text and the
//! shell completions, so that they cannot drift apart.
//!
//! Parsed by hand rather than with `clap`: the course's options are single-dash words
//! (`-input`, `-shade_back`) and `-depth` takes three values of two kinds, which clap can only
//! imitate with workarounds, and users paste the course's command lines verbatim.

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

use crate::accel::grid::MAX_CELLS;
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

/// One option: its name (without the dash), what follows it, one line of help, and how its
/// values are read. The parser, the help text, the completions and the did-you-mean of an
/// unknown option all read [`OPTIONS`], so they cannot drift apart.
#[derive(Clone, Copy)]
pub struct OptionSpec {
    /// Without the dash.
    pub name: &'static str,
    /// The values that follow, as the help text shows them (empty for a switch).
    pub values: &'static str,
    /// The assignment it comes from.
    pub group: Group,
    /// One line for `-help`.
    pub help: &'static str,
    read: Read,
}

impl std::fmt::Debug for OptionSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OptionSpec")
            .field("name", &self.name)
            .field("values", &self.values)
            .field("group", &self.group)
            .finish_non_exhaustive()
    }
}

/// Takes an option's values from the words after it into the command line being read.
type Read = fn(&mut Draft, &mut Values) -> Result<(), String>;

const fn spec(
    name: &'static str,
    values: &'static str,
    group: Group,
    help: &'static str,
    read: Read,
) -> OptionSpec {
    OptionSpec {
        name,
        values,
        group,
        help,
        read,
    }
}

/// Every option raycast takes.
pub const OPTIONS: &[OptionSpec] = &[
    spec(
        "input",
        "FILE",
        Group::Casting,
        "the scene file (- reads it from standard input)",
        read_input,
    ),
    spec(
        "size",
        "W H",
        Group::Casting,
        "the image's width and height in pixels",
        read_size,
    ),
    spec(
        "output",
        "FILE",
        Group::Casting,
        "the picture (- writes it to standard output)",
        read_output,
    ),
    spec(
        "normals",
        "FILE",
        Group::Casting,
        "the surface normals as colours (|x|, |y|, |z|)",
        read_normals,
    ),
    spec(
        "depth",
        "TMIN TMAX FILE",
        Group::Casting,
        "distance as grey: TMIN and nearer white, TMAX and farther black",
        read_depth,
    ),
    spec(
        "shade_back",
        "",
        Group::Casting,
        "shade back faces too (otherwise black); glass needs it",
        read_shade_back,
    ),
    spec(
        "specular_fix",
        "",
        Group::Phong,
        "fade highlights by N.L (the handout's optional fix)",
        read_specular_fix,
    ),
    spec(
        "gui",
        "",
        Group::Phong,
        "the course's preview, in the browser (needs a terminal or -port)",
        read_gui,
    ),
    spec(
        "tessellation",
        "THETA PHI",
        Group::Phong,
        "the preview's sphere steps: around, pole to pole (default 20 10)",
        read_tessellation,
    ),
    spec(
        "gouraud",
        "",
        Group::Phong,
        "the preview's spheres smooth, a normal per vertex",
        read_gouraud,
    ),
    spec(
        "shadows",
        "",
        Group::Tracing,
        "one shadow ray toward each light",
        read_shadows,
    ),
    spec(
        "bounces",
        "N",
        Group::Tracing,
        "reflect and refract rays up to N times (default 0)",
        read_bounces,
    ),
    spec(
        "weight",
        "W",
        Group::Tracing,
        "trace no mirror or glass ray of weight below W (default 0)",
        read_weight,
    ),
    spec(
        "grid",
        "NX NY NZ",
        Group::Grid,
        "search the course's grid of cells instead of the BVH",
        read_grid,
    ),
    spec(
        "visualize_grid",
        "",
        Group::Grid,
        "show the grid's occupied cells instead of the scene",
        read_visualize_grid,
    ),
    spec(
        "stats",
        "",
        Group::Grid,
        "the course's statistics (stdout) and phase times (stderr)",
        read_stats,
    ),
    spec(
        "random_samples",
        "N",
        Group::Sampling,
        "N samples a pixel, anywhere in it",
        read_samples,
    ),
    spec(
        "uniform_samples",
        "N",
        Group::Sampling,
        "N samples a pixel on a square grid (N a square)",
        read_samples,
    ),
    spec(
        "jittered_samples",
        "N",
        Group::Sampling,
        "N samples a pixel, one in each cell of a square grid",
        read_samples,
    ),
    spec(
        "box_filter",
        "R",
        Group::Sampling,
        "weigh samples within R of a pixel's centre alike (default 0.5)",
        read_filter,
    ),
    spec(
        "tent_filter",
        "R",
        Group::Sampling,
        "weigh samples by 1 - d/R",
        read_filter,
    ),
    spec(
        "gaussian_filter",
        "SIGMA",
        Group::Sampling,
        "weigh samples by exp(-d^2/2 SIGMA^2), to 2 SIGMA",
        read_filter,
    ),
    spec(
        "render_samples",
        "FILE ZOOM",
        Group::Sampling,
        "a picture of where the samples fall",
        read_picture_of_sampling,
    ),
    spec(
        "render_filter",
        "FILE ZOOM",
        Group::Sampling,
        "a picture of the filter's weights",
        read_picture_of_sampling,
    ),
    spec(
        "seed",
        "S",
        Group::Own,
        "seed of the random and jittered samples (default 6837)",
        read_seed,
    ),
    spec(
        "format",
        "png|ppm|tga",
        Group::Own,
        "the format of images named - or without an extension",
        read_format,
    ),
    spec(
        "threads",
        "N",
        Group::Own,
        "use N threads (default: one per core)",
        read_threads,
    ),
    spec(
        "port",
        "N",
        Group::Own,
        "serve -gui's preview on port N (0: any), even without a terminal",
        read_port,
    ),
    spec(
        "no-browser",
        "",
        Group::Own,
        "with -gui: print the preview's address, open no browser",
        read_no_browser,
    ),
    spec(
        "inspect",
        "X Y",
        Group::Own,
        "account for one pixel: its rays, hits, lights and colour",
        read_inspect,
    ),
    spec(
        "fault",
        "NAME",
        Group::Own,
        "render with one of check's faults planted (to test graders)",
        read_fault,
    ),
    spec(
        "choose",
        "NAME",
        Group::Own,
        "render another answer the course allows to an open question",
        read_choose,
    ),
    spec(
        "json",
        "",
        Group::Own,
        "with -inspect: the account as JSON",
        read_json,
    ),
    spec("help", "", Group::Own, "print this text", read_help),
    spec("version", "", Group::Own, "print the version", read_version),
];

/// The help text, from [`OPTIONS`].
pub fn usage() -> String {
    let mut text = String::from(
        "usage: raycast -input SCENE -size WIDTH HEIGHT -output IMAGE [options]
       raycast check SUITE --renderer CMD [--report DIR]   (raycast check -help)
       raycast diff IMAGE REFERENCE [--out DIFF.png]
       raycast completions bash|zsh|fish|powershell

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
    /// The course's preview: `-gui` and how it draws and is served.
    pub preview: PreviewOptions,
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
    /// `-fault NAME`: render with one of check's faults planted.
    pub fault: Option<String>,
    /// `-choose NAME`: render another allowed answer to one of the course's open questions.
    pub choose: Option<String>,
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

/// A command line as far as it has been read.
#[derive(Default)]
struct Draft {
    options: Options,
    input: Option<PathBuf>,
    size: Option<(u32, u32)>,
    sampler: Option<Sampler>,
    filter: Option<Filter>,
    /// `-help` or `-version`: answered at once, whatever else the line says.
    answer: Option<Command>,
}

/// The words after an option, handed out as its values.
struct Values<'a> {
    /// The option's name, without the dash.
    name: &'static str,
    words: &'a mut std::vec::IntoIter<OsString>,
}

impl Values<'_> {
    /// The next word, as `what` the option needs.
    fn next(&mut self, what: &str) -> Result<OsString, String> {
        let name = self.name;
        let word = self
            .words
            .next()
            .ok_or_else(|| format!("-{name} needs {what}, found the end of the command line"))?;
        // `-input -size 200 200`: the value was forgotten, and the next option taken for it.
        if word.to_str().is_some_and(looks_like_option) {
            return Err(format!(
                "-{name} needs {what}, found the option '{}'",
                word.to_string_lossy()
            ));
        }
        Ok(word)
    }

    /// The next word as a whole number in `range`; `what` names it in the message.
    fn whole<T>(&mut self, what: &str, range: std::ops::RangeInclusive<T>) -> Result<T, String>
    where
        T: std::str::FromStr + PartialOrd + std::fmt::Display,
    {
        let word = self.next(what)?;
        match word.to_str().and_then(|s| s.parse::<T>().ok()) {
            Some(n) if range.contains(&n) => Ok(n),
            _ => Err(format!(
                "-{} needs {what} (a whole number from {} to {}), found '{}'",
                self.name,
                range.start(),
                range.end(),
                word.to_string_lossy()
            )),
        }
    }
}

/// Reads a command line (without the program's name); the error is the message for the user.
pub fn parse_args(args: Vec<OsString>) -> Result<Command, String> {
    let mut draft = Draft::default();
    let mut seen: Vec<&str> = Vec::new();
    let mut words = args.into_iter();
    while let Some(arg) = words.next() {
        let Some(text) = arg.to_str() else {
            return Err(format!("unknown option '{}'", arg.to_string_lossy()));
        };
        if let Some(complaint) = misspelt(text) {
            return Err(complaint);
        }
        if !text.starts_with('-') {
            return Err(format!(
                "unexpected argument '{text}' (options start with '-')"
            ));
        }
        // `--input` is taken for `-input`, `-h` and `--help` for `-help`.
        let name = text.strip_prefix('-').unwrap_or(text);
        let name = name.strip_prefix('-').unwrap_or(name);
        let name = match name {
            "h" => "help",
            "V" => "version",
            _ => name,
        };
        let Some(option) = OPTIONS.iter().find(|o| o.name == name) else {
            return Err(unknown_option(text));
        };
        if seen.contains(&option.name) {
            return Err(format!("-{name} is given twice"));
        }
        seen.push(option.name);
        let mut values = Values {
            name: option.name,
            words: &mut words,
        };
        (option.read)(&mut draft, &mut values)?;
        if let Some(answer) = draft.answer {
            return Ok(answer);
        }
    }
    finish(draft).map(|options| Command::Render(Box::new(options)))
}

fn read_help(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.answer = Some(Command::Help);
    Ok(())
}

fn read_version(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.answer = Some(Command::Version);
    Ok(())
}

fn read_input(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.input = Some(PathBuf::from(values.next("a scene file")?));
    Ok(())
}

fn read_size(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let what = "a width and a height in pixels";
    let width = positive(&values.next(what)?, "-size", "a width in pixels")?;
    let height = positive(&values.next(what)?, "-size", "a height in pixels")?;
    draft.size = Some((width, height));
    Ok(())
}

fn read_output(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.options.output = Some(PathBuf::from(values.next("an image file")?));
    Ok(())
}

fn read_normals(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.options.normals = Some(PathBuf::from(values.next("an image file")?));
    Ok(())
}

fn read_depth(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let what = "TMIN TMAX and an image file";
    let near = finite(&values.next(what)?, "-depth", "TMIN, a number")?;
    let far = finite(&values.next(what)?, "-depth", "TMAX, a number")?;
    if near == far {
        return Err(format!(
            "-depth needs TMIN and TMAX to differ, found {near} twice"
        ));
    }
    draft.options.depth = Some((near, far, PathBuf::from(values.next(what)?)));
    Ok(())
}

fn read_shade_back(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.trace.shade_back = true;
    Ok(())
}

fn read_shadows(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.trace.shadows = true;
    Ok(())
}

fn read_specular_fix(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.trace.specular = SpecularFalloff::Fade;
    Ok(())
}

fn read_bounces(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.options.trace.bounces = values.whole("a number of bounces", 0..=u32::MAX)?;
    Ok(())
}

fn read_weight(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let weight = finite(&values.next("a weight")?, "-weight", "a weight, a number")?;
    if weight < 0.0 {
        return Err(format!(
            "-weight needs a weight of 0 or more, found '{weight}'"
        ));
    }
    draft.options.trace.cutoff_weight = weight;
    Ok(())
}

/// The course's preview (`-gui`), and how it draws and is served.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PreviewOptions {
    /// `-gui`: show the scene in the browser, from a terminal or with `-port`.
    pub gui: bool,
    /// `-tessellation THETA PHI`: a sphere's steps around its axis and from pole to pole.
    pub tessellation: Option<(u32, u32)>,
    /// `-gouraud`: spheres with a normal per vertex instead of one per face.
    pub gouraud: bool,
    /// `-port N`: the port to serve on (0: any free one); it also starts the preview when
    /// standard input is not a terminal.
    pub port: Option<u16>,
    /// `-no-browser`: print the address only.
    pub no_browser: bool,
}

impl PreviewOptions {
    /// Whether the line names any of the preview's options.
    pub fn named(&self) -> bool {
        self.gui
            || self.tessellation.is_some()
            || self.gouraud
            || self.port.is_some()
            || self.no_browser
    }
}

fn read_gui(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.preview.gui = true;
    Ok(())
}

fn read_gouraud(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.preview.gouraud = true;
    Ok(())
}

fn read_tessellation(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let what = "the preview's THETA and PHI steps";
    let theta = positive(&values.next(what)?, "-tessellation", "THETA")?;
    let phi = positive(&values.next(what)?, "-tessellation", "PHI")?;
    draft.options.preview.tessellation = Some((theta, phi));
    Ok(())
}

fn read_port(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.options.preview.port = Some(values.whole("a port number", 0..=u16::MAX)?);
    Ok(())
}

fn read_no_browser(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.preview.no_browser = true;
    Ok(())
}

fn read_stats(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.stats = true;
    Ok(())
}

/// `-random_samples`, `-uniform_samples` and `-jittered_samples`.
fn read_samples(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let name = values.name;
    let n = values.whole("a number of samples", 1..=MAX_SAMPLES)?;
    if name != "random_samples" && n.isqrt() * n.isqrt() != n {
        let below = n.isqrt() * n.isqrt();
        let above = (n.isqrt() + 1) * (n.isqrt() + 1);
        return Err(format!(
            "-{name} needs a square number of samples (they lie on a square grid), found {n}: \
             try {below} or {above}"
        ));
    }
    if draft.sampler.is_some() {
        return Err(
            "give only one of -random_samples, -uniform_samples and -jittered_samples".into(),
        );
    }
    draft.sampler = Some(match name {
        "random_samples" => Sampler::Random(n),
        "uniform_samples" => Sampler::Uniform(n),
        _ => Sampler::Jittered(n),
    });
    Ok(())
}

/// `-box_filter`, `-tent_filter` and `-gaussian_filter`.
fn read_filter(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let name = values.name;
    let gaussian = name == "gaussian_filter";
    let what = if gaussian { "SIGMA" } else { "a radius" };
    let size = finite(
        &values.next(what)?,
        &format!("-{name}"),
        &format!("{what}, a number of pixels"),
    )?;
    // A Gaussian is cut off at 2 sigma.
    let largest = if gaussian {
        MAX_FILTER_REACH / 2.0
    } else {
        MAX_FILTER_REACH
    };
    if size <= 0.0 || size > largest {
        return Err(format!(
            "-{name} needs {what} above 0 and at most {largest} pixels, found {size}"
        ));
    }
    if draft.filter.is_some() {
        return Err("give only one of -box_filter, -tent_filter and -gaussian_filter".into());
    }
    draft.filter = Some(match name {
        "box_filter" => Filter::Box(size),
        "tent_filter" => Filter::Tent(size),
        _ => Filter::Gaussian(size),
    });
    Ok(())
}

fn read_grid(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let what = "NX NY NZ, the numbers of cells";
    let mut cells = [0; 3];
    for (axis, n) in ["NX", "NY", "NZ"].iter().zip(&mut cells) {
        *n = positive(&values.next(what)?, "-grid", axis)?;
    }
    let count = cells.iter().map(|&n| u64::from(n)).product::<u64>();
    if count > MAX_CELLS {
        return Err(format!(
            "-grid {} {} {} is {count} cells, more than the {MAX_CELLS} that raycast keeps in \
             memory",
            cells[0], cells[1], cells[2],
        ));
    }
    draft.options.grid = Some(cells);
    Ok(())
}

fn read_visualize_grid(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.trace.visualize_grid = true;
    Ok(())
}

fn read_seed(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let word = values.next("a seed")?;
    draft.options.sampling.seed = word
        .to_str()
        .and_then(|s| s.parse::<u64>().ok())
        .ok_or_else(|| {
            format!(
                "-seed needs a whole number from 0 to {}, found '{}'",
                u64::MAX,
                word.to_string_lossy()
            )
        })?;
    Ok(())
}

/// `-render_samples` and `-render_filter`.
fn read_picture_of_sampling(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let name = values.name;
    let what = "an image file and a zoom";
    let file = PathBuf::from(values.next(what)?);
    let zoom = positive(&values.next(what)?, &format!("-{name}"), "a zoom")?;
    if name == "render_samples" {
        draft.options.render_samples = Some((file, zoom));
    } else {
        draft.options.render_filter = Some((file, zoom));
    }
    Ok(())
}

fn read_threads(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    draft.options.threads = Some(values.whole("a number of threads", 1..=MAX_THREADS)?);
    Ok(())
}

fn read_inspect(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let what = "a pixel's X and Y";
    let mut whole = |axis: &str| -> Result<u32, String> {
        let word = values.next(what)?;
        word.to_str()
            .and_then(|s| s.parse::<u32>().ok())
            .ok_or_else(|| {
                format!(
                    "-inspect needs {axis} (a whole number from 0), found '{}'",
                    word.to_string_lossy()
                )
            })
    };
    let x = whole("X")?;
    let y = whole("Y")?;
    draft.options.inspect = Some((x, y));
    Ok(())
}

fn read_fault(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let name = values.next("a fault's name")?;
    draft.options.fault = Some(name.to_string_lossy().into_owned());
    Ok(())
}

fn read_choose(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let name = values.next("an answer's name")?;
    draft.options.choose = Some(name.to_string_lossy().into_owned());
    Ok(())
}

fn read_json(draft: &mut Draft, _: &mut Values) -> Result<(), String> {
    draft.options.json = true;
    Ok(())
}

fn read_format(draft: &mut Draft, values: &mut Values) -> Result<(), String> {
    let word = values.next("an image format (png, ppm or tga)")?;
    draft.options.format = Some(match word.to_str() {
        Some("png") => ImageFormat::Png,
        Some("ppm") => ImageFormat::Ppm,
        Some("tga") => ImageFormat::Tga,
        _ => {
            return Err(format!(
                "-format needs png, ppm or tga, found '{}'",
                word.to_string_lossy()
            ));
        }
    });
    Ok(())
}

/// The rules that join options, checked once the whole line is read.
fn finish(draft: Draft) -> Result<Options, String> {
    let mut options = draft.options;
    options.input = draft
        .input
        .ok_or("-input is missing: which scene should be rendered?")?;
    let (width, height) = draft
        .size
        .ok_or("-size is missing: how many pixels wide and high?")?;
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
    options.sampling.sampler = draft.sampler.unwrap_or(Sampler::Uniform(1));
    options.sampling.filter = draft.filter.unwrap_or(Filter::Box(0.5));
    check_film(&options)?;
    check_outputs(&options)?;
    Ok(options)
}

/// The samples a film keeps, and the pictures of the sampling, within memory's bounds.
fn check_film(options: &Options) -> Result<(), String> {
    let (width, height) = (options.width, options.height);
    let samples = options.sampling.sampler.samples();
    let kept = u64::from(width) * u64::from(height) * u64::from(samples);
    if kept > MAX_FILM_SAMPLES && !options.sampling.is_plain() {
        return Err(format!(
            "{width}x{height} pixels of {samples} samples is too many samples to keep ({kept}); \
             at most {MAX_FILM_SAMPLES} (width x height x samples a pixel)"
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
    Ok(())
}

/// The images asked for: at least one, each a file of a known type (or standard output, once),
/// none the scene and no two the same.
fn check_outputs(options: &Options) -> Result<(), String> {
    let outputs = options.outputs();
    // The course's preview-only lines (`-gui` and no image): the scene is still read and
    // checked, and raycast says it has no preview.
    if outputs.is_empty() && !options.preview.named() && options.inspect.is_none() {
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
    Ok(())
}

impl Options {
    /// An image's format: its extension's, or `-format`'s for a name without one (and `-`).
    pub fn format_of(&self, path: &Path) -> Option<ImageFormat> {
        ImageFormat::from_path(path).or(self.format)
    }

    /// Whether an image goes to standard output (`-`), so that text must go to stderr.
    pub fn writes_to_stdout(&self) -> bool {
        self.outputs().iter().any(|&(_, path)| is_stdio(path))
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
