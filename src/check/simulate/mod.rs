//! Diagnosis by simulation: a failing line is rendered again under each fault of the library
//! that can change its pictures, and a fault whose render passes the suite's own rule against
//! the student's picture is the cause named. Faults with a parameter are tried at each value
//! their family proposes; when no fault matches alone but the closest removes at least half of
//! the differing pixels, it is tried in pairs.

use rayon::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

use super::cache;
mod allowed;
mod draws;
mod kept_rows;
mod likely_pairs;
mod located;
mod matches;
mod remembered;
mod undone;
use super::chance::{ByChance, Drawn, Spread, depends_on_chance};
use super::envelope::Envelope;
use super::faults::{Candidate, FAULTS, Fault, LineScene, Plant};
use super::fit::{Named, Picture, Trial, fit_line};
use super::rule::{Rule, compare};
use super::screen::{Failing, Screen, mean_difference};
use super::suite::{Line, Pin};
use crate::job::{Command, parse_args, render_pictures_until, render_rows_until};
use crate::parse::read_scene;
use crate::render::StopFlag;
use crate::scene::Scene;
use crate::shade::Image;
pub use allowed::accepted;
use draws::{
    drawn_alike, plant_spreads, plant_spreads_kept, plant_spreads_of_rows, seeded_spreads, slots_of,
};
pub use draws::{drawn_by_chance, spreads};
pub use located::{Located, Place, locate};
pub use matches::FaultMatch;
use matches::{matches, reproduced};
use undone::PERMUTATIONS;

/// At most this many renders for one line, singles and pairs together, where the singles leave
/// room (a course picture renders in milliseconds; every single is tried)...
const MAX_RENDERS: usize = 64;
/// ...but at least this many pairs for each picture no single fault explains...
const MIN_PAIRS: usize = 24;
/// ...and where the line is screened by a few rows (a pair ruled out there is never rendered
/// whole), this many.
const SCREENED_PAIRS: usize = 128;
/// Where a picture drawn by chance lies as near raycast's own render as two draws do, a fault's
/// render matches it only where it lies at most this share as far from it (the same draw of a
/// fault is not a pixel off; another draw is as far as raycast's).
const NEARER_DRAW: f64 = 0.5;
/// Where no fault explains a picture alone, each close fault is first paired with this many of
/// each other close fault's renders, the closest.
const PAIRED_RENDERS: usize = 4;
/// A fit measures its renders on every this many rows of a picture.
const FIT_ROWS: usize = 3;
/// A render the screen leaves in doubt is screened again by every this many rows of a picture
/// before it is made whole.
const SPARSE_ROWS: usize = 8;

/// What simulation says of one picture of a line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Simulated {
    /// Every fault (or pair) whose render passes against the picture, closest first; empty
    /// when none does.
    pub matches: Vec<FaultMatch>,
    /// Where none does: the fault whose render comes nearest, where it accounts for at least
    /// [`NEAR_SHARE`] of the pixels by which the picture differs from its reference (the same
    /// mistake, most likely, with some other difference beside it: a guess, said to be one).
    pub near: Option<FaultMatch>,
}

/// Which search a line's diagnosis runs.
#[derive(Debug, Clone, Copy)]
pub enum Search<'a> {
    /// The whole search, the run's `likely` faults so far (commonest first, as
    /// [`super::likely::faults`] gave them when the line's diagnosis began) tried first.
    Whole {
        /// The likely faults.
        likely: &'a [&'static str],
    },
    /// Once every line is diagnosed: only the pairs of the run's `likely` faults now, for the
    /// pictures the whole search left unexplained, and only those it did not try (its own
    /// likely faults were `before`; none where its record was read from the cache). Which
    /// line finished first then decides less: a pair found on a later line is tried on the
    /// earlier ones too (not on pictures drawn by chance, whose faults that place samples
    /// are compared otherwise).
    LikelyPairs {
        /// The likely faults when the whole search ran.
        before: &'a [&'static str],
        /// The likely faults once every line is diagnosed.
        now: &'a [&'static str],
    },
}

/// The share of the pixels by which a picture differs from its reference that the nearest
/// fault's render must account for to be named as a guess where no render passes.
pub const NEAR_SHARE: f64 = 0.9;

/// A line's command line, scene and pictures, ready to be rendered under faults.
struct Prepared {
    line: LineScene,
    /// Where each of the line's images stands among the job's pictures.
    slots: Vec<usize>,
    /// How many of the job's pictures, the first, are traced row for row (the shaded, normals
    /// and depth pictures).
    traced: usize,
}

impl Prepared {
    /// A render's pictures (in the job's order) in the order of the line's images.
    fn in_line_order(&self, pictures: &[Image]) -> Vec<Image> {
        self.slots
            .iter()
            .map(|&slot| pictures[slot].clone())
            .collect()
    }
}

/// A line's renders under plants (faults, allowed answers), for its failing pictures: each
/// screened first by the rows where those pictures differ most from their references, and
/// rendered whole only where it might match one; whole renders are kept in the cache, for the
/// next student and the next run.
struct Renders<'a> {
    prepared: &'a Prepared,
    kept: cache::LineRenders,
    screen: Option<Screen>,
    /// The failing pictures: the index of each among the line's images, and the student's.
    failing: Vec<(usize, &'a Image)>,
    /// For each failing picture, where the line depends on chance, the spread of raycast's
    /// renders with several seeds (a render of the line is then one draw, compared as one).
    spreads: Vec<Option<Spread>>,
    /// For each failing picture drawn by chance that lies as near raycast's own render as two
    /// draws of the line lie to one another, how far it is from that render (the mean
    /// difference): a fault's render, itself one draw, tells nothing about it unless it lies
    /// nearer than that. `None` for the others.
    drawn_alike: Vec<Option<f64>>,
    rule: Rule,
    stop: &'static StopFlag,
}

impl<'a> Renders<'a> {
    fn new(
        line: &Line,
        scenes: &Path,
        prepared: &'a Prepared,
        failing: &[(usize, &'a Image, Option<&'a Image>)],
        rule: Rule,
        stop: &'static StopFlag,
    ) -> Result<Renders<'a>, Unfinished> {
        // A fault's samples picture is compared dot for dot: only raycast's own generator draws
        // the same dots. The spread is for the traced pictures alone.
        let chance = depends_on_chance(&prepared.line.options)
            && failing
                .iter()
                .any(|&(image, _, _)| prepared.slots[image] < prepared.traced);
        let kept = cache::LineRenders::of(line, scenes);
        let spreads: Vec<Option<Spread>> = if chance {
            let spreads = seeded_spreads(&kept, prepared, Drawn::Traced, stop)?;
            failing
                .iter()
                .map(|&(image, _, _)| match spreads.get(image) {
                    Some(Some(ByChance::Spread(spread))) => Some(spread.clone()),
                    _ => None,
                })
                .collect()
        } else {
            vec![None; failing.len()]
        };
        let screened: Vec<Failing> = failing
            .iter()
            .zip(&spreads)
            .map(|(&(image, actual, reference), spread)| Failing {
                actual,
                reference,
                traced: prepared.slots[image] < prepared.traced,
                spread: spread.as_ref(),
            })
            .collect();
        let screen = Screen::of(&screened, rule);
        let drawn_alike = drawn_alike(failing, &spreads, rule);
        let renders = Renders {
            prepared,
            kept,
            screen,
            drawn_alike,
            failing: failing
                .iter()
                .map(|&(image, actual, _)| (image, actual))
                .collect(),
            spreads,
            rule,
            stop,
        };
        Ok(renders)
    }

    /// The share of pixels by which `picture` (a render of the line) and failing picture `k`
    /// (`actual`, or that picture undone by a fault that moves pixels) differ: by the suite's
    /// rule, or, for a picture drawn by chance, as two draws of the line's spread.
    fn bad(&self, k: usize, picture: Option<&Image>, actual: &Image) -> f64 {
        let Some(picture) = picture else {
            return 1.0;
        };
        let comparison = match &self.spreads[k] {
            Some(spread) => spread.compare_draws(actual, picture, self.rule.tolerance),
            None => compare(picture, actual, self.rule.tolerance),
        };
        comparison.map_or(1.0, |c| c.bad_fraction)
    }

    /// Of the failing pictures `waiting`, those that lie as near their `references` as the
    /// renders under `plants` lie to one another, pixel by pixel ([`Envelope`]). Each plant's
    /// screened rows first, where the line is screened: a picture already too far outside their
    /// envelope there is outside the whole one, and where that holds for every picture nothing
    /// is rendered whole.
    fn between(
        &self,
        plants: &[Plant],
        waiting: &[usize],
        references: &[Option<&Image>],
    ) -> Result<Vec<usize>, Unfinished> {
        let outside = |k: usize, renders: &[Option<&Image>], rows: Option<&[bool]>| {
            let actual = self.failing[k].1;
            let nudged: Vec<&Image> = renders.iter().filter_map(|r| *r).collect();
            let Some(envelope) = references[k].and_then(|r| Envelope::around(r, &nudged)) else {
                return true;
            };
            let differing = match rows {
                Some(rows) => envelope.differing_in(actual, self.rule.tolerance, rows),
                None => envelope
                    .compare(actual, self.rule.tolerance)
                    .map(|c| c.differing),
            };
            let pixels = actual.pixels.len().max(1);
            differing.is_none_or(|d| d as f64 / pixels as f64 > self.rule.max_bad)
        };
        if let Some(screen) = &self.screen {
            let mut rows = Vec::new();
            for &plant in plants {
                rows.push(self.rows_for(plant, screen)?);
            }
            if rows.iter().all(Option::is_some) {
                let rows: Vec<Vec<Image>> = rows.into_iter().flatten().collect();
                let ruled_out = waiting.iter().all(|&k| {
                    let image = self.failing[k].0;
                    let renders: Vec<Option<&Image>> = rows.iter().map(|r| r.get(image)).collect();
                    outside(k, &renders, Some(screen.wanted()))
                });
                if ruled_out {
                    return Ok(Vec::new());
                }
            }
        }
        let mut wholes = Vec::new();
        for &plant in plants {
            wholes.push(self.whole(plant)?);
        }
        Ok(waiting
            .iter()
            .copied()
            .filter(|&k| {
                let image = self.failing[k].0;
                let renders: Vec<Option<&Image>> = wholes.iter().map(|w| w.get(image)).collect();
                !outside(k, &renders, None)
            })
            .collect())
    }

    /// Whether a render's picture `image` matches failing picture `k`.
    fn passes(&self, k: usize, picture: Option<&Image>, actual: &Image) -> bool {
        self.bad(k, picture, actual) <= self.rule.max_bad
    }

    /// Whether the pictures of the line are drawn by chance.
    fn by_chance(&self) -> bool {
        self.spreads.iter().any(Option::is_some)
    }

    /// A screen by the rows where the failing pictures differ most from `pictures` (a fault's
    /// whole render, in the order of the line's images): what is left to explain with that
    /// fault planted, which a pair with it must explain.
    fn screen_against(&self, pictures: &[Image]) -> Option<Screen> {
        let failing: Vec<Failing> = self
            .failing
            .iter()
            .zip(&self.spreads)
            .map(|(&(image, actual), spread)| Failing {
                actual,
                reference: pictures.get(image),
                traced: self.prepared.slots[image] < self.prepared.traced,
                spread: spread.as_ref(),
            })
            .collect();
        Screen::of(&failing, self.rule)
    }

    /// Whether `plant`'s render of every [`SPARSE_ROWS`]th row lies nearer one of the `failing`
    /// pictures than that picture's reference does, in those rows: the plant explains a part
    /// of it.
    fn nearer_than_references(
        &self,
        plant: Plant,
        failing: &[(usize, &Image, Option<&Image>)],
    ) -> Result<bool, Unfinished> {
        let sparse = self.sparse_screen();
        let rows = self.render_rows(plant, sparse.wanted())?;
        Ok(failing.iter().any(|&(image, actual, reference)| {
            let off = |picture: Option<&Image>| {
                picture.map_or(f64::INFINITY, |p| sparse.mean_difference(p, actual))
            };
            off(rows.get(image)) < off(reference)
        }))
    }

    /// Whether `plant`'s render of the screened rows already matches none of the failing
    /// pictures. Never where the line is not screened, or the whole render is kept (it costs
    /// less to read than the rows to render).
    fn ruled_out(&self, plant: Plant) -> Result<bool, Unfinished> {
        Ok(match (&self.screen, self.rows(plant)?) {
            (Some(screen), Some(rows)) => {
                screen.rules_out(&self.in_order(&rows), &self.actuals(), &self.spread_refs())
            }
            _ => false,
        })
    }

    /// Whether `plant`'s render of every [`SPARSE_ROWS`]th row already matches none of the
    /// failing pictures: a second screen, for a render the first leaves in doubt, before the
    /// whole. A near miss (one of a pair's faults alone, a parameter a step off) differs from
    /// the student's picture a little all over: too little in the first screen's few rows,
    /// enough in a share of them all.
    fn sparse_rows_rule_out(&self, plant: Plant) -> Result<bool, Unfinished> {
        let sparse = self.sparse_screen();
        let rows = self.render_rows(plant, sparse.wanted())?;
        Ok(sparse.rules_out(&self.in_order(&rows), &self.actuals(), &self.spread_refs()))
    }

    /// `plant`'s render of the screened rows (the others black), in the order of the line's
    /// images; `None` where the line is not screened or the whole render is kept.
    fn rows(&self, plant: Plant) -> Result<Option<Vec<Image>>, Unfinished> {
        match &self.screen {
            Some(screen) => self.rows_for(plant, screen),
            None => Ok(None),
        }
    }

    /// `plant`'s render of the rows `screen` wants; `None` where the whole render is kept.
    fn rows_for(&self, plant: Plant, screen: &Screen) -> Result<Option<Vec<Image>>, Unfinished> {
        if self.kept.has_fault(&format!("{plant:?}")) {
            return Ok(None);
        }
        self.render_rows(plant, screen.wanted()).map(Some)
    }

    /// `plant`'s render of the rows `wanted` marks (the others black), in the order of the
    /// line's images. Not kept in the cache (a screen's rows are the student's choice), but
    /// each row is kept for the rest of the run ([`kept_rows`]): the class's next student
    /// renders only the rows no one before asked for.
    fn render_rows(&self, plant: Plant, wanted: &[bool]) -> Result<Vec<Image>, Unfinished> {
        let line = &self.prepared.line;
        let render = |wanted: &[bool]| {
            let rows = render_rows_until(&line.options, &line.scene, plant, self.stop, wanted)
                .ok_or(Unfinished::Stopped)?
                .pictures;
            Ok(self.prepared.in_line_order(&rows))
        };
        // Rows are kept only where every picture is traced row for row: a samples picture is
        // made of the film's rows as a whole.
        if self
            .prepared
            .slots
            .iter()
            .all(|&slot| slot < self.prepared.traced)
        {
            let planted = format!("{plant:?}");
            kept_rows::rows_of(self.kept.identity(), &planted, wanted, render)
        } else {
            render(wanted)
        }
    }

    /// Every [`SPARSE_ROWS`]th row of the line's pictures: the second screen's, and where an
    /// allowed answer is seen to lie nearer a picture.
    fn sparse_screen(&self) -> Screen {
        let height = self.prepared.line.options.height as usize;
        Screen::every(SPARSE_ROWS, height, self.rule)
    }

    /// Of pictures in the order of the line's images, those of the failing pictures.
    fn in_order<'p>(&self, pictures: &'p [Image]) -> Vec<Option<&'p Image>> {
        self.failing
            .iter()
            .map(|&(image, _)| pictures.get(image))
            .collect()
    }

    /// The failing pictures' spreads, where they are drawn by chance.
    fn spread_refs(&self) -> Vec<Option<&Spread>> {
        self.spreads.iter().map(Option::as_ref).collect()
    }

    fn actuals(&self) -> Vec<&'a Image> {
        self.failing.iter().map(|&(_, actual)| actual).collect()
    }

    /// How far `picture` is from `actual`: the mean difference of their channels over the
    /// screened rows where the line is screened (a render ruled out there is never made whole),
    /// else over the whole picture.
    fn difference(&self, picture: Option<&Image>, actual: &Image) -> f64 {
        match (&self.screen, picture) {
            (Some(screen), Some(picture)) => screen.mean_difference(picture, actual),
            _ => mean_difference(picture, actual),
        }
    }

    /// How far `plant`'s render is from the failing pictures `pictures` (their indices among
    /// them): the sum of their mean differences over every [`FIT_ROWS`]th row. A fit's measure,
    /// of numbers that are the student's alone: never kept.
    fn fit_distance(&self, plant: Plant, pictures: &[usize]) -> Result<f64, Unfinished> {
        let line = &self.prepared.line;
        let sample = Screen::every(FIT_ROWS, line.options.height as usize, self.rule);
        let rows = render_rows_until(
            &line.options,
            &line.scene,
            plant,
            self.stop,
            sample.wanted(),
        )
        .ok_or(Unfinished::Stopped)?
        .pictures;
        Ok(pictures
            .iter()
            .map(|&k| {
                let (image, actual) = self.failing[k];
                rows.get(self.prepared.slots[image])
                    .map_or(f64::INFINITY, |picture| {
                        sample.mean_difference(picture, actual)
                    })
            })
            .sum())
    }

    /// `plant`'s whole render of the line, in the order of the line's images: kept, or
    /// rendered and kept.
    fn whole(&self, plant: Plant) -> Result<Vec<Image>, Unfinished> {
        self.kept.fault(&format!("{plant:?}"), || {
            let line = &self.prepared.line;
            let pictures = render_pictures_until(&line.options, &line.scene, plant, self.stop)
                .ok_or(Unfinished::Stopped)?
                .pictures;
            Ok(self.prepared.in_line_order(&pictures))
        })
    }
}

/// Runs `work` (raycast's renders of a line) on a pool of every core: `--jobs` says how many
/// lines run at once, and a line's renders, like the student's renderer, use the whole machine
/// (the same pictures on any number of threads).
fn on_every_core<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    static EVERY_CORE: OnceLock<Option<rayon::ThreadPool>> = OnceLock::new();
    let pool = EVERY_CORE.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .thread_name(|k| format!("raycast-render-{k}"))
            .build()
            .ok()
    });
    match pool {
        Some(pool) => pool.install(work),
        None => work(),
    }
}

/// Reads and builds what the line renders, from the suite's own `scenes` folder.
fn prepare(line: &Line, scenes: &Path) -> Result<Prepared, String> {
    let mut options = match parse_args(line.args.iter().map(Into::into).collect()) {
        Ok(Command::Render(options)) => *options,
        Ok(_) => return Err("the line asks for no render".into()),
        Err(message) => return Err(format!("raycast cannot read the line: {message}")),
    };
    options.input = scenes.join(&options.input);
    let (slots, traced) = slots_of(line, &options)?;
    let description = read_scene(&options.input).map_err(|e| e.to_string())?;
    let mut scene = Scene::from_description(&description).map_err(|e| e.to_string())?;
    if let Some([x, y, z]) = options.grid {
        scene
            .world
            .use_grid(glam::UVec3::new(x, y, z))
            .map_err(|e| e.to_string())?;
    }
    Ok(Prepared {
        traced,
        line: LineScene {
            options,
            description,
            scene,
        },
        slots,
    })
}

/// Why a line was not simulated to the end.
#[derive(Debug, Clone, PartialEq)]
pub enum Unfinished {
    /// check was asked to stop.
    Stopped,
    /// raycast cannot render the line itself.
    Failed(String),
}

/// What a render says when check was asked to stop before it ended.
pub const STOPPED: &str = "check was interrupted before raycast finished rendering it";

/// The pictures raycast makes of `line` (as the course's renderer), in the order of the line's
/// images: the reference of a line whose suite has none. `Err` where check was asked to stop
/// before they were done ([`STOPPED`]).
///
/// Where the suite pins an open question to another answer than raycast's, the reference is
/// that answer's render (of the first two pinned answers that change the line).
pub fn course_pictures(
    line: &Line,
    scenes: &Path,
    pinned: &[Pin],
    stop: &'static StopFlag,
) -> Result<Vec<Image>, String> {
    on_every_core(|| course_pictures_here(line, scenes, pinned, stop))
}

fn course_pictures_here(
    line: &Line,
    scenes: &Path,
    pinned: &[Pin],
    stop: &'static StopFlag,
) -> Result<Vec<Image>, String> {
    let prepared = prepare(line, scenes)?;
    let answers: Vec<_> = pinned
        .iter()
        .filter_map(|pin| pin.answer)
        .filter_map(|answer| {
            (answer.candidates)(&prepared.line)
                .first()
                .map(|c| c.planted)
        })
        .collect();
    let (options, scene) = (&prepared.line.options, &prepared.line.scene);
    let pictures = match answers[..] {
        [] => render_pictures_until(options, scene, crate::render::Exact, stop),
        [one] => render_pictures_until(options, scene, Plant::one(one), stop),
        [first, second, ..] => {
            render_pictures_until(options, scene, Plant::two(first, second), stop)
        }
    }
    .ok_or(STOPPED)?
    .pictures;
    Ok(prepared.in_line_order(&pictures))
}

/// Raycast's account (`-inspect X Y`, as text) of pixel (x, y) of the line (x from the left, y
/// from the bottom).
pub fn ray_tree(line: &Line, scenes: &Path, (x, y): (u32, u32)) -> Result<String, String> {
    let prepared = prepare(line, scenes)?;
    let options = &prepared.line.options;
    if x >= options.width || y >= options.height {
        return Err(format!("pixel ({x}, {y}) is outside the image"));
    }
    let account = crate::inspect::inspect(
        &prepared.line.scene,
        options.trace,
        (options.width, options.height),
        (x, y),
    );
    Ok(crate::inspect::to_text(&account).trim_end().to_string())
}

/// What one plant's render said: the comparison with each failing picture, the pairs its
/// whole render makes with the faults that move pixels, and its screened rows where they
/// ruled it out.
struct Look {
    tried: Tried,
    permuted: Vec<(usize, Tried)>,
    rows: Option<Vec<Image>>,
}

/// The fits' renders: measured on some rows, or proven whole and kept among the singles.
struct Trials<'t, 'a, L> {
    renders: &'t Renders<'a>,
    look: &'t L,
    screen: Option<&'t Screen>,
    singles: &'t mut Vec<Look>,
}

impl<L> Trial for Trials<'_, '_, L>
where
    L: Fn(
        Plant,
        &[&'static Fault],
        &[(&'static str, f64)],
        Option<&Screen>,
    ) -> Result<Look, Unfinished>,
{
    type Error = Unfinished;

    fn distance(&mut self, plant: Plant, pictures: &[usize]) -> Result<f64, Unfinished> {
        self.renders.fit_distance(plant, pictures)
    }

    fn prove(&mut self, plant: Plant, (faults, numbers): &Named) -> Result<Vec<bool>, Unfinished> {
        let look = (self.look)(plant, faults, numbers, self.screen)?;
        let rule = self.renders.rule;
        let proven = look
            .tried
            .bad
            .iter()
            .map(|&bad| bad <= rule.max_bad)
            .collect();
        self.singles.push(look);
        Ok(proven)
    }
}

#[derive(Clone)]
/// One render tried: the plant, the faults in it and their parameters, and the share of pixels
/// off against each failing picture.
struct Tried {
    plant: Plant,
    faults: Vec<&'static Fault>,
    parameters: Vec<(&'static str, f64)>,
    bad: Vec<f64>,
    /// The mean difference of the channels against each failing picture, which falls as a fault
    /// explains part of a picture even where every pixel is still off.
    error: Vec<f64>,
    /// Whether `bad` was measured against the spread of the plant's renders with several seeds.
    against_spread: bool,
}

impl Tried {
    /// This single fault's render planted with `second`'s: the pair's plant, faults and
    /// parameters.
    fn paired_with(&self, second: &Tried) -> (Plant, [&'static Fault; 2], Parameters) {
        let plant = Plant::two(self.plant.first(), second.plant.first());
        let mut parameters = self.parameters.clone();
        parameters.extend(second.parameters.iter().copied());
        (plant, [self.faults[0], second.faults[0]], parameters)
    }
}

/// Fitted parameters, by name.
type Parameters = Vec<(&'static str, f64)>;

/// For each of `failing` (the index of an image among the line's outputs, and the student's
/// picture of it), the faults whose render matches it, and whether that was read from the
/// cache's record of an earlier run (whose search tried the likely faults of that run, not
/// `search`'s). Ends between renders, and within one, once `stop` is set.
pub fn simulate(
    line: &Line,
    scenes: &Path,
    failing: &[(usize, &Image, Option<&Image>)],
    rule: Rule,
    stop: &'static StopFlag,
    search: Search<'_>,
) -> Result<(Vec<Simulated>, bool), Unfinished> {
    // The whole search's record stands for the line whatever the likely faults were: the
    // pairs' search that may follow it is kept apart, by the faults it pairs.
    let asked = match search {
        Search::Whole { .. } => "faults".to_string(),
        Search::LikelyPairs { before, now } => {
            format!(
                "likely pairs of {} after {}",
                now.join(","),
                before.join(",")
            )
        }
    };
    let kept = cache::LineRenders::of(line, scenes).diagnosis(&asked, &[], failing, rule);
    if let Some(simulated) = kept
        .read()
        .and_then(|text| remembered::simulated_from(&text, failing.len()))
    {
        simulated.iter().for_each(count_explained);
        return Ok((simulated, true));
    }
    let simulated = on_every_core(|| simulate_here(line, scenes, failing, rule, stop, search))?;
    kept.keep(&remembered::simulated_text(&simulated));
    Ok((simulated, false))
}

fn simulate_here(
    line: &Line,
    scenes: &Path,
    failing: &[(usize, &Image, Option<&Image>)],
    rule: Rule,
    stop: &'static StopFlag,
    search: Search<'_>,
) -> Result<Vec<Simulated>, Unfinished> {
    let prepared = prepare(line, scenes).map_err(Unfinished::Failed)?;
    // Each failing picture, and each undone by a fault that only moves its pixels (a flip, the
    // channels swapped): a render that matches one of those is that fault with another.
    let undone: Vec<Vec<(&'static Fault, Image)>> = failing
        .iter()
        .map(|&(_, actual, _)| {
            PERMUTATIONS
                .iter()
                .filter_map(|&(name, undo)| Some((super::faults::fault(name)?, undo(actual))))
                .collect()
        })
        .collect();
    let renders = Renders::new(line, scenes, &prepared, failing, rule, stop)?;
    let bad = |k: usize, picture: Option<&Image>, actual: &Image| renders.bad(k, picture, actual);
    // The pairs a single fault's render of image `k` makes with the faults that only move
    // pixels: compared with the student's picture undone by each.
    let moved = |k: usize,
                 plant: Plant,
                 fault: &'static Fault,
                 parameters: &[(&'static str, f64)],
                 picture: Option<&Image>| {
        undone[k]
            .iter()
            .filter(|(mover, _)| mover.name != fault.name)
            .map(|&(mover, ref undone_picture)| {
                let mut found = vec![f64::INFINITY; failing.len()];
                found[k] = bad(k, picture, undone_picture);
                let pair = Tried {
                    plant,
                    faults: vec![mover, fault],
                    parameters: parameters.to_vec(),
                    bad: found,
                    error: vec![f64::INFINITY; failing.len()],
                    against_spread: false,
                };
                (k, pair)
            })
            .collect::<Vec<_>>()
    };
    // The line under `plant`, seen against each failing picture: by its screened rows where
    // they rule it out (kept, for the pictures undone by a fault that moves pixels), else by
    // its whole render, with the pairs that render makes with the faults that only move pixels.
    // Whether a plant places the samples of this line, drawn by chance, otherwise.
    let options = &prepared.line.options;
    let redraws =
        |plant: Plant| depends_on_chance(options) && plant.places_samples(options.sampling.sampler);
    let look_drawn = |plant: Plant,
                      faults: &[&'static Fault],
                      parameters: &[(&'static str, f64)],
                      screen: Option<&Screen>,
                      own_spread: bool| {
        let mut tried = Tried {
            plant,
            faults: faults.to_vec(),
            parameters: parameters.to_vec(),
            bad: Vec::with_capacity(failing.len()),
            error: Vec::with_capacity(failing.len()),
            against_spread: false,
        };
        // A plant that places the samples of a line drawn by chance otherwise draws its
        // pictures with another spread: with `own_spread`, the student's picture is measured
        // against its own, whole (rows screened against raycast's spread would rule it out).
        let redrawn = own_spread && redraws(plant);
        let rows = match screen {
            Some(screen) if !redrawn => renders.rows_for(plant, screen)?,
            _ => None,
        };
        // Redrawn, by the rows: the plant's own spread made of them and their neighbours (a
        // screen's rows of eight renders cost less than one whole render).
        if let Some(screen) =
            screen.filter(|_| redrawn && !plant_spreads_kept(&renders.kept, &prepared, plant))
        {
            let (own_rows, spreads) =
                plant_spreads_of_rows(&prepared, plant, &screen.with_neighbours(), stop)?;
            let spreads: Vec<Option<&Spread>> = failing
                .iter()
                .map(|&(image, _, _)| spreads.get(image).and_then(Option::as_ref))
                .collect();
            if screen.rules_out_spreads(&spreads, &renders.actuals()) {
                for (picture, &(_, actual, _)) in
                    renders.in_order(&own_rows).into_iter().zip(failing)
                {
                    tried.bad.push(1.0);
                    tried.error.push(renders.difference(picture, actual));
                }
                return Ok(Look {
                    tried,
                    permuted: Vec::new(),
                    rows: None,
                });
            }
        }
        if let (Some(screen), Some(seen)) = (screen, &rows) {
            let rendered = renders.in_order(seen);
            if screen.rules_out(&rendered, &renders.actuals(), &renders.spread_refs())
                || renders.sparse_rows_rule_out(plant)?
            {
                for (picture, &(_, actual, _)) in rendered.into_iter().zip(failing) {
                    tried.bad.push(1.0);
                    tried.error.push(renders.difference(picture, actual));
                }
                return Ok(Look {
                    tried,
                    permuted: Vec::new(),
                    rows,
                });
            }
        }
        let pictures = renders.whole(plant)?;
        let own_spreads = if redrawn {
            Some(plant_spreads(&renders.kept, &prepared, plant, stop)?)
        } else {
            None
        };
        let mut permuted = Vec::new();
        for (k, &(image, actual, _)) in failing.iter().enumerate() {
            let picture = pictures.get(image);
            let own_spread = own_spreads
                .as_ref()
                .and_then(|spreads| spreads.get(image)?.as_ref());
            tried.bad.push(match own_spread {
                Some(spread) => {
                    tried.against_spread = true;
                    spread
                        .compare(actual, rule.tolerance)
                        .map_or(1.0, |c| c.bad_fraction)
                }
                // Where raycast's own render is as good a draw, a fault's must be nearer.
                None => match renders.drawn_alike[k] {
                    Some(own) if mean_difference(picture, actual) >= NEARER_DRAW * own => 1.0,
                    _ => bad(k, picture, actual),
                },
            });
            tried.error.push(renders.difference(picture, actual));
            if faults.len() == 1 {
                permuted.extend(moved(k, plant, faults[0], parameters, picture));
            }
        }
        Ok::<_, Unfinished>(Look {
            tried,
            permuted,
            rows: None,
        })
    };
    let look =
        |plant: Plant,
         faults: &[&'static Fault],
         parameters: &[(&'static str, f64)],
         screen: Option<&Screen>| { look_drawn(plant, faults, parameters, screen, false) };
    // Every fault's candidates, in the library's order: each is screened by a few rows before
    // it is rendered whole, so none is left out (a cap here once dropped the library's last
    // faults on a line that can show most of the others).
    let candidates: Vec<(&'static Fault, Candidate)> = FAULTS
        .iter()
        .flat_map(|fault| {
            (fault.candidates)(&prepared.line)
                .into_iter()
                .map(move |candidate| (fault, candidate))
        })
        .collect();
    let likely = match search {
        Search::Whole { likely } => likely,
        Search::LikelyPairs { before, now } => {
            return likely_pairs_again(&candidates, before, now, &renders, failing, rule, &look);
        }
    };
    // The likely first: where a fault that explained pictures before in this run draws each
    // failing picture itself, and the line's kept record says which faults draw a picture
    // alike to it, those are compared and nothing else is rendered.
    let planted = |index: usize| format!("{:?}", Plant::one(candidates[index].1.planted));
    let mut exact: Vec<Option<Vec<FaultMatch>>> = vec![None; failing.len()];
    for &name in likely.iter().filter(|_| !renders.by_chance()) {
        for index in (0..candidates.len()).filter(|&i| candidates[i].0.name == name) {
            if exact.iter().all(Option::is_some) {
                break;
            }
            let plant = Plant::one(candidates[index].1.planted);
            let mut pictures: Option<Vec<Image>> = None;
            for (k, &(image, actual, _)) in failing.iter().enumerate() {
                if exact[k].is_some() {
                    continue;
                }
                let Some(same) = renders.kept.same_pictures(&planted(index), image) else {
                    continue;
                };
                if pictures.is_none() {
                    pictures = Some(renders.whole(plant)?);
                }
                // Only the very picture the fault draws: every fault that matches it is then
                // alike to the fault's render, and the record names them all.
                if pictures.as_ref().and_then(|p| p.get(image)) != Some(actual) {
                    continue;
                }
                // Each fault alike, compared again with this picture, as the search would.
                let mut alike: Vec<Tried> = Vec::new();
                for (other, &(fault, candidate)) in candidates.iter().enumerate() {
                    if !same.contains(&planted(other)) {
                        continue;
                    }
                    let plant = Plant::one(candidate.planted);
                    let rendered = renders.whole(plant)?;
                    let mut score = vec![f64::INFINITY; failing.len()];
                    score[k] = bad(k, rendered.get(image), actual);
                    alike.push(Tried {
                        plant,
                        faults: vec![fault],
                        parameters: candidate.parameter.into_iter().collect(),
                        bad: score,
                        error: vec![f64::INFINITY; failing.len()],
                        against_spread: false,
                    });
                }
                exact[k] = Some(matches(&alike, k, rule));
            }
        }
    }
    // Every picture drawn by a likely fault itself: its record names every match, and nothing
    // else is rendered.
    if exact.iter().all(Option::is_some) {
        let mut results: Vec<Simulated> = exact
            .into_iter()
            .map(|matches| Simulated {
                matches: matches.unwrap_or_default(),
                near: None,
            })
            .collect();
        account(&mut results, failing, &renders);
        return Ok(results);
    }
    let mut singles = singles_of(&candidates, &look, renders.screen.as_ref())?;
    let explained_by = |singles: &[Look]| -> Vec<bool> {
        (0..failing.len())
            .map(|k| {
                singles
                    .iter()
                    .any(|single| single.tried.bad[k] <= rule.max_bad)
            })
            .collect()
    };
    let mut explained = explained_by(&singles);
    // A fault that places the samples otherwise, against the spread of its own seeded renders
    // (eight renders of the line each): only where no listed fault explains a picture.
    if explained.iter().any(|e| !e) {
        for (index, &(fault, candidate)) in candidates.iter().enumerate() {
            let plant = Plant::one(candidate.planted);
            if redraws(plant) {
                let parameters: Vec<_> = candidate.parameter.into_iter().collect();
                singles[index] =
                    look_drawn(plant, &[fault], &parameters, renders.screen.as_ref(), true)?;
            }
        }
        explained = explained_by(&singles);
    }
    let likely = likely_pairs::likely_pairs(
        &candidates,
        &singles,
        &mut explained,
        rule,
        renders.screen.as_ref(),
        &look,
        (&likely_pairs::likely_faults(&candidates, likely), &[]),
    )?;
    // The fits, for the pictures no listed fault explains: a mistake written in a form the
    // library does not list is named by where the fit's numbers land.
    if explained.iter().any(|e| !e) {
        let pictures: Vec<Picture<'_>> = failing
            .iter()
            .map(|&(image, actual, reference)| Picture {
                slot: prepared.slots[image],
                actual,
                reference,
            })
            .collect();
        let mut trial = Trials {
            renders: &renders,
            look: &look,
            screen: renders.screen.as_ref(),
            singles: &mut singles,
        };
        fit_line(&prepared.line, &pictures, &mut explained, rule, &mut trial)?;
    }
    let unexplained: Vec<usize> = (0..failing.len()).filter(|&k| !explained[k]).collect();
    // For a picture no single fault explains, a fault that moves pixels with another: made whole
    // where the screened rows do not rule the other out against the picture undone.
    if let Some(screen) = &renders.screen {
        for (index, &(fault, candidate)) in candidates.iter().enumerate() {
            let Some(rows) = &singles[index].rows else {
                continue;
            };
            let rendered = renders.in_order(rows);
            let might = unexplained.iter().any(|&k| {
                undone[k].iter().any(|(_, undone_picture)| {
                    !screen.rules_out(
                        &rendered[k..=k],
                        &[undone_picture],
                        &[renders.spreads[k].as_ref()],
                    )
                })
            });
            if might {
                let parameters: Vec<_> = candidate.parameter.into_iter().collect();
                let plant = Plant::one(candidate.planted);
                let whole = renders.whole(plant)?;
                for &k in &unexplained {
                    let picture = whole.get(failing[k].0);
                    let pairs = moved(k, plant, fault, &parameters, picture);
                    singles[index].permuted.extend(pairs);
                }
            }
        }
    }
    let mut tried: Vec<Tried> = Vec::with_capacity(candidates.len());
    let mut permuted: Vec<Vec<Tried>> = vec![Vec::new(); failing.len()];
    for single in singles {
        tried.push(single.tried);
        for (k, pair) in single.permuted {
            permuted[k].push(pair);
        }
    }
    tried.extend(likely);
    let mut results: Vec<Simulated> = (0..failing.len())
        .map(|k| Simulated {
            matches: matches(&tried, k, rule),
            near: None,
        })
        .collect();
    // Which faults draw the same picture (to the rule) as one that matched a picture exactly:
    // kept for the next picture of the line it explains (every such fault came through the screen and was
    // rendered whole, so it is among these).
    // Never for pictures drawn by chance: alike there is a matter of spread, not of pixels.
    for k in (0..failing.len()).filter(|_| renders.kept.keeps() && !renders.by_chance()) {
        let exactly: Vec<usize> = (0..candidates.len())
            .filter(|&i| tried[i].bad[k] == 0.0)
            .collect();
        let image = failing[k].0;
        for &one in &exactly {
            if renders.kept.same_pictures(&planted(one), image).is_some() {
                continue;
            }
            // Kept only where the fault draws this very picture: then the faults that match it
            // are exactly those alike to the fault's render, all of them.
            let pictures = renders.whole(tried[one].plant)?;
            if pictures.get(image) != Some(failing[k].1) {
                continue;
            }
            // Alike to the rule: the image passes against the other's.
            let mut same = Vec::new();
            for other in (0..candidates.len()).filter(|&i| tried[i].bad[k] <= rule.max_bad) {
                let others = renders.whole(tried[other].plant)?;
                let alike = match (pictures.get(image), others.get(image)) {
                    (Some(a), Some(b)) => {
                        compare(a, b, rule.tolerance).is_some_and(|c| rule.passes(&c))
                    }
                    _ => false,
                };
                if other == one || alike {
                    same.push(planted(other));
                }
            }
            renders.kept.keep_same_pictures(&planted(one), image, &same);
        }
    }
    // Pairs, for the pictures no single fault explains: the closest render of each fault, the
    // closest faults first, paired in order of their closeness while the budget lasts.
    // How far each picture is from the course's render of the line, rendered once.
    let plain: Vec<f64> = if unexplained.is_empty() {
        Vec::new()
    } else {
        let course = render_pictures_until(
            &prepared.line.options,
            &prepared.line.scene,
            crate::render::Exact,
            stop,
        )
        .ok_or(Unfinished::Stopped)?;
        failing
            .iter()
            .map(|&(image, actual, _)| {
                renders.difference(course.pictures.get(prepared.slots[image]), actual)
            })
            .collect()
    };
    for k in unexplained {
        let plain = plain[k];
        let mut closest: Vec<usize> = Vec::new();
        for (index, t) in tried
            .iter()
            .enumerate()
            .filter(|(_, t)| t.faults.len() == 1)
        {
            match closest
                .iter_mut()
                .find(|c| tried[**c].faults[0].name == t.faults[0].name)
            {
                Some(c) if tried[*c].error[k] <= t.error[k] => {}
                Some(c) => *c = index,
                None => closest.push(index),
            }
        }
        // A fault that moves pixels, with another: found without a render.
        let moved = matches(&permuted[k], k, rule);
        if !moved.is_empty() {
            results[k].matches = moved;
            continue;
        }
        closest.sort_by(|&a, &b| tried[a].error[k].total_cmp(&tried[b].error[k]));
        // The closest faults first (at their closest render), each with every render of the
        // other faults (a parameter that fits with another fault need not fit alone): one of a
        // pair usually brings the picture nearest alone.
        let singles: Vec<usize> = (0..tried.len())
            .filter(|&t| tried[t].faults.len() == 1)
            .collect();
        // First the closest render of each of the closest faults with the closest few renders
        // of each other, the two closest faults' pairs first (a line of many faults, or a fault
        // of many renders, can spend the budget on the closest fault's pairs alone); then the
        // closest faults with every render of the others.
        let firsts: Vec<usize> = closest
            .iter()
            .copied()
            .filter(|&first| tried[first].error[k] < plain)
            .collect();
        // Each close fault's nearest renders, once.
        let nearest_renders: Vec<Vec<usize>> = closest
            .iter()
            .map(|&c| {
                let fault = tried[c].faults[0].name;
                let mut them: Vec<usize> = singles
                    .iter()
                    .copied()
                    .filter(|&t| tried[t].faults[0].name == fault)
                    .collect();
                them.sort_by(|&a, &b| tried[a].error[k].total_cmp(&tried[b].error[k]));
                them.truncate(PAIRED_RENDERS);
                them
            })
            .collect();
        // `closest` holds each fault once, sorted, and `firsts` is its head: the same place is
        // the same fault.
        let mut ranked: Vec<((usize, usize), (usize, usize))> = Vec::new();
        for (first_rank, &first) in firsts.iter().enumerate() {
            for (other_rank, renders) in nearest_renders.iter().enumerate() {
                if other_rank == first_rank {
                    continue;
                }
                for (nearness, &render) in renders.iter().enumerate() {
                    ranked.push(((first_rank + other_rank, nearness), (first, render)));
                }
            }
        }
        // Stable: among pairs of the same places, the closer first fault's.
        ranked.sort_by_key(|&(key, _)| key);
        let mut order: Vec<(usize, usize)> = ranked.into_iter().map(|(_, pair)| pair).collect();
        let mut seen: std::collections::HashSet<(usize, usize)> = order.iter().copied().collect();
        for &first in &firsts {
            for &other in &singles {
                if tried[other].faults[0].name != tried[first].faults[0].name
                    && seen.insert((first, other))
                {
                    order.push((first, other));
                }
            }
        }
        // A pair screened by a few rows costs a few rows: the closest faults are paired with
        // every other.
        let budget = if renders.screen.is_some() {
            SCREENED_PAIRS
        } else {
            MAX_RENDERS.saturating_sub(tried.len()).max(MIN_PAIRS)
        };
        // A pair is screened by the rows its first fault leaves most unexplained (where the
        // first fault alone already draws the student's rows, every pair with it would pass
        // the line's own screen).
        let mut residuals: Vec<(usize, Option<Screen>)> = Vec::new();
        let mut pairs: Vec<Tried> = Vec::new();
        // Every pair the budget allows: a pair that matches as well as the first found may
        // begin with another fault (one drawing the same picture as a fault of the first).
        for (first_index, second_index) in order.into_iter().take(budget) {
            let (first, second) = (&tried[first_index], &tried[second_index]);
            if renders.screen.is_some() && !residuals.iter().any(|(i, _)| *i == first_index) {
                let alone = renders.whole(first.plant)?;
                residuals.push((first_index, renders.screen_against(&alone)));
            }
            let screen = residuals
                .iter()
                .find(|(i, _)| *i == first_index)
                .and_then(|(_, residual)| residual.as_ref())
                .or(renders.screen.as_ref());
            let (plant, faults, parameters) = first.paired_with(second);
            pairs.push(look(plant, &faults, &parameters, screen)?.tried);
        }
        results[k].matches = matches(&pairs, k, rule);
        // Still none: the nearest fault, at its nearest render, rendered whole and measured
        // (`account` keeps it where it explains most of the picture's difference).
        let (_, actual, reference) = failing[k];
        if let (Some(&nearest), Some(reference), None) = (
            firsts.first().filter(|_| results[k].matches.is_empty()),
            reference,
            &renders.spreads[k],
        ) {
            let near = &tried[nearest];
            let pictures = renders.whole(near.plant)?;
            let picture = renders.in_order(&pictures)[k];
            results[k].near = Some(FaultMatch {
                faults: near.faults.clone(),
                parameters: near.parameters.clone(),
                bad_fraction: renders.bad(k, picture, actual),
                accounts_for: picture
                    .and_then(|picture| reproduced(actual, reference, picture, rule.tolerance)),
                against_spread: false,
            });
        }
        tried.extend(pairs);
    }
    account(&mut results, failing, &renders);
    Ok(results)
}

/// Each of `candidates` alone, seen with `look` (by `screen`'s rows first, where there is one),
/// side by side: a screen's render of a few rows leaves most of the machine's threads idle, so
/// the candidates share the threads instead. In the order of `candidates`.
fn singles_of(
    candidates: &[(&'static Fault, Candidate)],
    look: &(
         impl Fn(
        Plant,
        &[&'static Fault],
        &[(&'static str, f64)],
        Option<&Screen>,
    ) -> Result<Look, Unfinished>
         + Sync
     ),
    screen: Option<&Screen>,
) -> Result<Vec<Look>, Unfinished> {
    candidates
        .par_iter()
        .map(|&(fault, candidate)| {
            let parameters: Vec<_> = candidate.parameter.into_iter().collect();
            look(Plant::one(candidate.planted), &[fault], &parameters, screen)
        })
        .collect()
}

/// [`Search::LikelyPairs`]: the likely faults' renders of the line, and the pairs among them
/// the whole search did not try, for each picture (every one left unexplained by it).
fn likely_pairs_again(
    candidates: &[(&'static Fault, Candidate)],
    before: &[&'static str],
    now: &[&'static str],
    renders: &Renders<'_>,
    failing: &[(usize, &Image, Option<&Image>)],
    rule: Rule,
    look: &(
         impl Fn(
        Plant,
        &[&'static Fault],
        &[(&'static str, f64)],
        Option<&Screen>,
    ) -> Result<Look, Unfinished>
         + Sync
     ),
) -> Result<Vec<Simulated>, Unfinished> {
    let before = likely_pairs::likely_faults(candidates, before);
    let now = likely_pairs::likely_faults(candidates, now);
    let mut results = vec![Simulated::default(); failing.len()];
    if renders.by_chance() {
        return Ok(results);
    }
    let new_pair = now.iter().enumerate().any(|(rank, first)| {
        now[rank + 1..]
            .iter()
            .any(|second| !before.contains(first) || !before.contains(second))
    });
    if !new_pair {
        return Ok(results);
    }
    let candidates: Vec<(&'static Fault, Candidate)> = candidates
        .iter()
        .copied()
        .filter(|(fault, _)| now.contains(&fault.name))
        .collect();
    let singles = singles_of(&candidates, look, renders.screen.as_ref())?;
    let mut explained = vec![false; failing.len()];
    let pairs = likely_pairs::likely_pairs(
        &candidates,
        &singles,
        &mut explained,
        rule,
        renders.screen.as_ref(),
        look,
        (&now, &before),
    )?;
    let tried: Vec<Tried> = singles
        .into_iter()
        .map(|single| single.tried)
        .chain(pairs)
        .collect();
    for (k, result) in results.iter_mut().enumerate() {
        if explained[k] {
            result.matches = matches(&tried, k, rule);
        }
    }
    account(&mut results, failing, renders);
    Ok(results)
}

/// Says, of each match, how much of its picture's difference from the reference it accounts
/// for; and notes the faults that explained pictures, to be tried first on the next lines.
fn account(
    results: &mut [Simulated],
    failing: &[(usize, &Image, Option<&Image>)],
    renders: &Renders<'_>,
) {
    // (A picture drawn by chance has a spread, not one reference.)
    for (k, (result, &(_, actual, reference))) in results.iter_mut().zip(failing).enumerate() {
        let off = reference
            .filter(|_| renders.spreads[k].is_none())
            .and_then(|r| compare(r, actual, renders.rule.tolerance));
        let off = off.map(|c| c.bad_fraction);
        if let Some(off) = off {
            for m in &mut result.matches {
                m.accounts_for =
                    (off > 0.0).then(|| ((off - m.bad_fraction) / off).clamp(0.0, 1.0));
            }
        }
        // A near render is a guess only where it explains most of the difference.
        if result
            .near
            .as_ref()
            .is_some_and(|m| m.accounts_for.is_none_or(|share| share < NEAR_SHARE))
        {
            result.near = None;
        }
        count_explained(result);
    }
}

/// The faults named first for a picture explained it: the likely first for the next line.
fn count_explained(result: &Simulated) {
    for fault in result.matches.first().map_or(&[][..], |m| &m.faults[..]) {
        super::likely::explained(fault.name);
    }
}
