//! A command line of the course, understood as a render job: the table of options and its
//! parser (`options.rs`), and the rendering of the pictures a line names. The program (`cli`)
//! runs one job; the grader (`check`) runs the suite's lines through it too, as the course's
//! renderer and as a student's buggy one (a [`Variant`]).

mod options;
pub mod stats;

pub(crate) use options::same_file;
pub use options::{
    Command, Group, MAX_FILM_SAMPLES, MAX_FILTER_REACH, MAX_SAMPLES, MAX_THREADS, OPTIONS,
    OptionSpec, Options, is_stdio, parse_args, usage,
};

use std::io::{IsTerminal, Write};
use std::time::Instant;

use crate::error::Error;
use crate::image_io::{self, OpenPicture, PendingOutputs};
use crate::render::{
    FinishedRows, RenderSettings, RowSink, Variant, render_rows_with, render_streamed,
};
use crate::sample;
use crate::scene::Scene;
use crate::shade::Image;

/// The pictures the command line names, in the order of [`Options::outputs`], and the rays
/// cast for them.
pub struct Pictures {
    /// One picture for each of [`Options::outputs`], in that order.
    pub pictures: Vec<Image>,
    /// The rays cast for them.
    pub rays: crate::trace::RayCounts,
}

/// Renders what the options ask for as `variant` renders, and makes the sampling's own
/// pictures.
pub fn render_pictures<V: Variant>(options: &Options, scene: &Scene, variant: V) -> Pictures {
    render_pictures_counted(options, scene, variant, None)
}

/// [`render_pictures`], its progress kept in `counter` for a watcher on another thread.
pub fn render_pictures_counted<V: Variant>(
    options: &Options,
    scene: &Scene,
    variant: V,
    counter: Option<&'static crate::render::RenderCounter>,
) -> Pictures {
    pictures_of(
        options,
        scene,
        variant,
        render_settings(options, counter),
        None,
    )
}

/// [`render_pictures`], ended early once `stop` is set: `None` then (the pictures would be
/// unfinished).
pub fn render_pictures_until<V: Variant>(
    options: &Options,
    scene: &Scene,
    variant: V,
    stop: &'static crate::render::StopFlag,
) -> Option<Pictures> {
    let settings = RenderSettings {
        stop: Some(stop),
        ..render_settings(options, None)
    };
    let pictures = pictures_of(options, scene, variant, settings, None);
    (!stop.is_set()).then_some(pictures)
}

/// [`render_pictures_until`], only the rows `wanted` marks (top first) of the traced pictures
/// (the shaded, normals and depth pictures; the others are made whole): check screens a
/// fault's render by the rows where a student's picture differs.
pub fn render_rows_until<V: Variant>(
    options: &Options,
    scene: &Scene,
    variant: V,
    stop: &'static crate::render::StopFlag,
    wanted: &[bool],
) -> Option<Pictures> {
    let settings = RenderSettings {
        stop: Some(stop),
        ..render_settings(options, None)
    };
    let pictures = pictures_of(options, scene, variant, settings, Some(wanted));
    (!stop.is_set()).then_some(pictures)
}

fn pictures_of<V: Variant>(
    options: &Options,
    scene: &Scene,
    variant: V,
    settings: RenderSettings,
    wanted: Option<&[bool]>,
) -> Pictures {
    // Only the filter picture asked for: nothing to trace.
    let traced = options.output.is_some()
        || options.normals.is_some()
        || options.depth.is_some()
        || options.render_samples.is_some();
    let mut rendered = if traced {
        render_rows_with(scene, &settings, variant, wanted)
    } else {
        crate::render::Rendered::default()
    };
    let samples_picture = options.render_samples.as_ref().map(|&(_, zoom)| {
        let film = rendered.film.take().expect("kept for -render_samples");
        sample::render_samples_picture(&film, zoom)
    });
    // The filter as the variant weighs samples with it (a fault's or an allowed answer's).
    let filter = sample::SampleSeam::filter(&variant, options.sampling.filter);
    let filter_picture = options.render_filter.as_ref().map(|&(_, zoom)| {
        sample::render_filter_picture(options.width, options.height, filter, zoom)
    });
    if options.output.is_none() {
        rendered.colour = None;
    }
    let pictures = [
        rendered.colour,
        rendered.normals,
        rendered.depth,
        samples_picture,
        filter_picture,
    ];
    Pictures {
        pictures: pictures.into_iter().flatten().collect(),
        rays: rendered.rays,
    }
}

/// The render the options ask for.
fn render_settings(
    options: &Options,
    counter: Option<&'static crate::render::RenderCounter>,
) -> RenderSettings {
    RenderSettings {
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
        counter,
        stop: None,
    }
}

/// How long a job took to render and to write its pictures. Where the rows went to their files
/// as they were finished, writing them is part of the render, and the write is the files' end.
pub struct Written {
    /// The rays cast.
    pub rays: crate::trace::RayCounts,
    /// Rendering (and, where streamed, writing the rows).
    pub render: std::time::Duration,
    /// Writing what was left and putting the files in place.
    pub write: std::time::Duration,
}

/// Renders what the options ask for as `variant` renders and writes the pictures into
/// `pending`'s files (standard output for `-`). One ray through each pixel's centre into files
/// only: the rows go to the files as the bands are finished ([`render_streamed`]), so the
/// pictures are never whole in memory. Otherwise rendered whole, then written.
pub fn render_to_files<V: Variant>(
    options: &Options,
    scene: &Scene,
    variant: V,
    mut pending: PendingOutputs,
) -> Result<Written, Error> {
    let start = Instant::now();
    let settings = render_settings(options, None);
    let streams = settings.streams()
        && options.render_filter.is_none()
        && !options.writes_to_stdout()
        && !options.outputs().is_empty();
    if !streams {
        let rendered = render_pictures(options, scene, variant);
        let render = start.elapsed();
        write_pictures(options, rendered.pictures, pending)?;
        return Ok(Written {
            rays: rendered.rays,
            render,
            write: start.elapsed() - render,
        });
    }
    let shapes: Vec<_> = options
        .outputs()
        .iter()
        .map(|&(_, path)| (format_of(options, path), options.width, options.height))
        .collect();
    let mut files = pending.open(&shapes)?.into_iter();
    // Outputs come in the order colour, normals, depth.
    let mut take = |wanted: bool| wanted.then(|| files.next().expect("a file for each picture"));
    let mut sink = FileRows {
        colour: take(options.output.is_some()),
        normals: take(options.normals.is_some()),
        depth: take(options.depth.is_some()),
    };
    let rays = render_streamed(scene, &settings, variant, &mut sink)?;
    let render = start.elapsed();
    for file in [sink.colour, sink.normals, sink.depth]
        .into_iter()
        .flatten()
    {
        file.finish()?;
    }
    pending.commit()?;
    Ok(Written {
        rays,
        render,
        write: start.elapsed() - render,
    })
}

/// The files of the pictures a render streams, each given its rows as they come.
struct FileRows {
    colour: Option<OpenPicture>,
    normals: Option<OpenPicture>,
    depth: Option<OpenPicture>,
}

impl RowSink for FileRows {
    fn rows(&mut self, rows: &FinishedRows) -> Result<(), Error> {
        let files = [
            (&mut self.colour, rows.colour),
            (&mut self.normals, rows.normals),
            (&mut self.depth, rows.depth),
        ];
        for (file, pixels) in files {
            if let (Some(file), Some(pixels)) = (file, pixels) {
                file.write_rows(pixels)?;
            }
        }
        Ok(())
    }
}

/// Reserves the line's output files before any work (a folder that is missing or unwritable
/// fails the run now, not after the render); standard output needs none.
pub fn reserve_outputs(options: &Options) -> Result<PendingOutputs, Error> {
    let outputs = options.outputs();
    let files: Vec<&std::path::Path> = outputs
        .iter()
        .map(|&(_, p)| p)
        .filter(|p| !is_stdio(p))
        .collect();
    PendingOutputs::reserve(&files)
}

/// The format of output `path`: its extension's, or `-format`'s.
fn format_of(options: &Options, path: &std::path::Path) -> image_io::ImageFormat {
    options
        .format_of(path)
        .expect("checked when parsing the command line")
}

/// Encodes each picture in its file's format and puts the files in place together; the one
/// named `-` goes to standard output.
pub fn write_pictures(
    options: &Options,
    pictures: Vec<Image>,
    mut pending: PendingOutputs,
) -> Result<(), Error> {
    let format = |path| format_of(options, path);
    let mut to_files = Vec::new();
    let mut to_stdout = None;
    for (image, (_, path)) in pictures.iter().zip(options.outputs()) {
        if is_stdio(path) {
            to_stdout = Some(image_io::encode(image, format(path)));
        } else {
            to_files.push((image, format(path)));
        }
    }
    let shapes: Vec<_> = to_files
        .iter()
        .map(|&(image, format)| (format, image.width, image.height))
        .collect();
    for (mut file, (image, _)) in pending.open(&shapes)?.into_iter().zip(&to_files) {
        file.write_rows(&image.pixels)?;
        file.finish()?;
    }
    pending.commit()?;
    if let Some(bytes) = to_stdout {
        let mut out = std::io::stdout().lock();
        out.write_all(&bytes)
            .and_then(|()| out.flush())
            .map_err(|e| Error::Write {
                path: "standard output".into(),
                message: e.to_string(),
            })?;
    }
    Ok(())
}
