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

use crate::error::Error;
use crate::image_io::{self, PendingOutputs};
use crate::render::{RenderSettings, Variant, render_with};
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
        counter,
    };
    // Only the filter picture asked for: nothing to trace.
    let traced = options.output.is_some()
        || options.normals.is_some()
        || options.depth.is_some()
        || options.render_samples.is_some();
    let mut rendered = if traced {
        render_with(scene, &settings, variant)
    } else {
        crate::render::Rendered::default()
    };
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

/// Encodes each picture in its file's format and puts the files in place together; the one
/// named `-` goes to standard output.
pub fn write_pictures(
    options: &Options,
    pictures: Vec<Image>,
    pending: PendingOutputs,
) -> Result<(), Error> {
    let mut contents = Vec::new();
    let mut to_stdout = None;
    for (image, (_, path)) in pictures.iter().zip(options.outputs()) {
        let format = options
            .format_of(path)
            .expect("checked when parsing the command line");
        let encoded = image_io::encode_parts(image, format);
        if is_stdio(path) {
            to_stdout = Some(encoded);
        } else {
            contents.push(encoded);
        }
    }
    pending.commit(&contents)?;
    if let Some(encoded) = to_stdout {
        let mut out = std::io::stdout().lock();
        encoded
            .write_to(&mut out)
            .and_then(|()| out.flush())
            .map_err(|e| Error::Write {
                path: "standard output".into(),
                message: e.to_string(),
            })?;
    }
    Ok(())
}
