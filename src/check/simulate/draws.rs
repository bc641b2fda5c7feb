//! raycast's renders of a line drawn by chance, which grade its pictures: the spread of its
//! renders with several seeds, for the pictures traced from samples; the scene at the samples
//! picture's zoom, for that picture.

use std::path::Path;

use super::{Prepared, STOPPED, Unfinished, on_every_core, prepare};
use crate::check::cache;
use crate::check::chance::{self, ByChance, Drawn, Spread, depends_on_chance};
use crate::check::faults::Plant;
use crate::check::samples_picture::SamplesRule;
use crate::check::suite::Line;
use crate::job::{Command, Options, parse_args, render_pictures_until, render_rows_until};
use crate::render::StopFlag;
use crate::shade::Image;

/// For each of the line's images drawn as `drawn` says, where the line depends on chance, how
/// chance is allowed for: a picture traced from its samples by the spread of raycast's renders
/// of it with [`chance::seeds`] (each kept in the cache as a fault's render is), the samples
/// picture by its structure over raycast's render of the line at its zoom; `None` for the
/// others.
pub(super) fn seeded_spreads(
    kept: &cache::LineRenders,
    prepared: &Prepared,
    drawn: Drawn,
    stop: &'static StopFlag,
) -> Result<Vec<Option<ByChance>>, Unfinished> {
    let line = &prepared.line;
    let own = line.options.sampling.seed;
    let mut seeded: Vec<Vec<Image>> = Vec::new();
    for seed in chance::seeds(own).take_while(|_| drawn == Drawn::Traced) {
        let render = || render_seeded(prepared, seed, crate::render::Exact, stop);
        // The line's own seed draws raycast's own render of it: kept as the course's picture.
        seeded.push(if seed == own {
            kept.course(&[], render)?
        } else {
            kept.fault(&format!("seed {seed}"), render)?
        });
    }
    let samples_rule = match line.options.render_samples {
        Some((_, zoom)) if drawn == Drawn::Samples => Some(samples_rule(line, zoom, stop)?),
        _ => None,
    };
    Ok((0..prepared.slots.len())
        .map(|image| {
            let slot = prepared.slots[image];
            if slot < prepared.traced {
                spread_of(&seeded, image).map(ByChance::Spread)
            } else if slot == prepared.traced {
                samples_rule.clone().map(ByChance::Samples)
            } else {
                None
            }
        })
        .collect())
}

/// For each of the line's images, where `plant` places the samples of a line drawn by chance
/// otherwise than raycast does (a jittered sampler's samples anywhere in the pixel), the spread
/// of the line's renders under `plant` with [`chance::seeds`] (each kept in the cache): a
/// student's picture drawn so, with any generator, lies within it, where it lies outside the
/// spread of raycast's own samples. `None` for the images not traced from samples.
pub(super) fn plant_spreads(
    kept: &cache::LineRenders,
    prepared: &Prepared,
    plant: Plant,
    stop: &'static StopFlag,
) -> Result<Vec<Option<Spread>>, Unfinished> {
    let own = prepared.line.options.sampling.seed;
    let mut seeded: Vec<Vec<Image>> = Vec::new();
    for seed in chance::seeds(own) {
        // The line's own seed draws the plant's render of the line, kept under its own name.
        let name = match seed == own {
            true => format!("{plant:?}"),
            false => format!("seed {seed} {plant:?}"),
        };
        seeded.push(kept.fault(&name, || render_seeded(prepared, seed, plant, stop))?);
    }
    Ok(traced_spreads(prepared, &seeded))
}

/// Whether [`plant_spreads`] has its renders kept: then they cost less to read than any rows
/// of them to render.
pub(super) fn plant_spreads_kept(
    kept: &cache::LineRenders,
    prepared: &Prepared,
    plant: Plant,
) -> bool {
    let own = prepared.line.options.sampling.seed;
    chance::seeds(own)
        .filter(|&seed| seed != own)
        .all(|seed| kept.has_fault(&format!("seed {seed} {plant:?}")))
}

/// [`plant_spreads`] made from renders of the rows `wanted` alone (the others black, and the
/// spreads there meaningless), never kept: a screen's, where the rows cost a fraction of the
/// whole. With the line's own seed's rows first.
pub(super) fn plant_spreads_of_rows(
    prepared: &Prepared,
    plant: Plant,
    wanted: &[bool],
    stop: &'static StopFlag,
) -> Result<(Vec<Image>, Vec<Option<Spread>>), Unfinished> {
    let line = &prepared.line;
    let mut seeded: Vec<Vec<Image>> = Vec::new();
    for seed in chance::seeds(line.options.sampling.seed) {
        let mut options = line.options.clone();
        options.sampling.seed = seed;
        let rows = render_rows_until(&options, &line.scene, plant, stop, wanted)
            .ok_or(Unfinished::Stopped)?
            .pictures;
        seeded.push(prepared.in_line_order(&rows));
    }
    let spreads = traced_spreads(prepared, &seeded);
    Ok((seeded.swap_remove(0), spreads))
}

/// For each of the line's images, the spread of its `seeded` renders where it is traced.
fn traced_spreads(prepared: &Prepared, seeded: &[Vec<Image>]) -> Vec<Option<Spread>> {
    (0..prepared.slots.len())
        .map(|image| {
            (prepared.slots[image] < prepared.traced)
                .then(|| spread_of(seeded, image))
                .flatten()
        })
        .collect()
}

/// The line's pictures under `variant` with its samples drawn from `seed`, in the line's order.
fn render_seeded(
    prepared: &Prepared,
    seed: u64,
    variant: impl crate::render::Variant,
    stop: &'static StopFlag,
) -> Result<Vec<Image>, Unfinished> {
    let line = &prepared.line;
    let mut options = line.options.clone();
    options.sampling.seed = seed;
    let pictures = render_pictures_until(&options, &line.scene, variant, stop)
        .ok_or(Unfinished::Stopped)?
        .pictures;
    Ok(prepared.in_line_order(&pictures))
}

/// The spread of image `image` over the `seeded` renders of the line.
fn spread_of(seeded: &[Vec<Image>], image: usize) -> Option<Spread> {
    let renders: Vec<&Image> = seeded.iter().filter_map(|r| r.get(image)).collect();
    Spread::of(&renders)
}

/// For each failing picture (its image, the student's, and raycast's own render) drawn by
/// chance with `spreads`, the mean difference from raycast's render where it lies as near that
/// render as two draws of the line do by `rule`: there a fault's render, one more draw, tells
/// nothing unless it lies nearer.
pub(super) fn drawn_alike(
    failing: &[(usize, &Image, Option<&Image>)],
    spreads: &[Option<Spread>],
    rule: crate::check::rule::Rule,
) -> Vec<Option<f64>> {
    failing
        .iter()
        .zip(spreads)
        .map(|(&(_, actual, reference), spread)| {
            let (spread, reference) = (spread.as_ref()?, reference?);
            let bad = spread.compare_draws(actual, reference, rule.tolerance)?;
            (bad.bad_fraction <= rule.max_bad)
                .then(|| crate::check::screen::mean_difference(Some(reference), actual))
        })
        .collect()
}

/// The rule of the line's samples picture: raycast's render of the scene at `zoom` times the
/// line's size, a ray through each picture pixel's centre, is the colour a dot there may have.
fn samples_rule(
    line: &crate::check::faults::LineScene,
    zoom: u32,
    stop: &'static StopFlag,
) -> Result<SamplesRule, Unfinished> {
    let mut options = line.options.clone();
    options.width *= zoom;
    options.height *= zoom;
    options.sampling = crate::sample::Sampling::default();
    options.render_samples = None;
    options.render_filter = None;
    options.normals = None;
    options.depth = None;
    options.output = Some(std::path::PathBuf::from("scene.tga"));
    let scene = render_pictures_until(&options, &line.scene, crate::render::Exact, stop)
        .ok_or(Unfinished::Stopped)?
        .pictures
        .into_iter()
        .next()
        .ok_or_else(|| Unfinished::Failed("raycast drew no scene for the samples".into()))?;
    let sampler = line.options.sampling.sampler;
    Ok(SamplesRule {
        width: line.options.width,
        height: line.options.height,
        zoom,
        samples: sampler.samples(),
        jittered: matches!(sampler, crate::sample::Sampler::Jittered(_)),
        scene,
    })
}

/// How the images of `line` drawn as `drawn` says are graded ([`seeded_spreads`]): `None` for a
/// line that does not depend on chance; within it, `None` for its other images.
pub fn spreads(
    line: &Line,
    scenes: &Path,
    drawn: Drawn,
    stop: &'static StopFlag,
) -> Result<Option<Vec<Option<ByChance>>>, String> {
    on_every_core(|| spreads_here(line, scenes, drawn, stop))
}

fn spreads_here(
    line: &Line,
    scenes: &Path,
    drawn: Drawn,
    stop: &'static StopFlag,
) -> Result<Option<Vec<Option<ByChance>>>, String> {
    // Not refused once stopped: renders kept in the cache still grade a picture (a stop just
    // after a line ran leaves it graded); a render that is not kept ends at the stop.
    if drawn_by_chance(line).iter().all(Option::is_none) {
        return Ok(None);
    }
    let prepared = prepare(line, scenes)?;
    let kept = cache::LineRenders::of(line, scenes);
    match seeded_spreads(&kept, &prepared, drawn, stop) {
        Ok(spreads) => Ok(Some(spreads)),
        Err(Unfinished::Stopped) => Err(STOPPED.to_string()),
        Err(Unfinished::Failed(why)) => Err(why),
    }
}

/// For each of the line's images, its place among raycast's outputs; and how many of those
/// are traced (the picture, normals and depth, before the samples and filter pictures).
pub(super) fn slots_of(line: &Line, options: &Options) -> Result<(Vec<usize>, usize), String> {
    let outputs: Vec<String> = options
        .outputs()
        .iter()
        .map(|(_, path)| path.to_string_lossy().into_owned())
        .collect();
    let slots = line
        .outputs
        .iter()
        .map(|(_, name)| {
            outputs
                .iter()
                .position(|o| o == name)
                .ok_or_else(|| format!("the line's image {name} is not among its outputs"))
        })
        .collect::<Result<_, _>>()?;
    let traced = [
        options.output.is_some(),
        options.normals.is_some(),
        options.depth.is_some(),
    ]
    .into_iter()
    .filter(|&traced| traced)
    .count();
    Ok((slots, traced))
}

/// For each of the line's images, how it is drawn by chance, if it is: from the command line
/// alone (no scene is built). Every image is `None` for a line that does not depend on chance
/// or that raycast cannot read.
pub fn drawn_by_chance(line: &Line) -> Vec<Option<Drawn>> {
    let none = vec![None; line.outputs.len()];
    let options = match parse_args(line.args.iter().map(Into::into).collect()) {
        Ok(Command::Render(options)) if depends_on_chance(&options) => options,
        _ => return none,
    };
    let Ok((slots, traced)) = slots_of(line, &options) else {
        return none;
    };
    slots
        .iter()
        .map(|&slot| {
            if slot < traced {
                Some(Drawn::Traced)
            } else if slot == traced && options.render_samples.is_some() {
                Some(Drawn::Samples)
            } else {
                None
            }
        })
        .collect()
}
