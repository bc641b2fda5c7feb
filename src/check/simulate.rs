//! Diagnosis by simulation: a failing line is rendered again under each fault of the library
//! that can change its pictures, and a fault whose render passes the suite's own rule against
//! the student's picture is the cause named. Faults with a parameter are tried at each value
//! their family proposes; when no fault matches alone but the closest removes at least half of
//! the differing pixels, it is tried in pairs.

use std::path::Path;

use super::faults::{FAULTS, Fault, LineScene, Plant, Planted};
use super::rule::{Rule, compare};
use super::suite::Line;
use crate::job::{Command, parse_args, render_pictures};
use crate::parse::read_scene;
use crate::scene::Scene;
use crate::shade::Image;

/// At most this many renders for one line, pairs included (a course picture renders in
/// milliseconds).
const MAX_RENDERS: usize = 64;

/// Faults (one, or two planted together) whose render of a line matches a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultMatch {
    /// The fault, or the two faults planted together.
    pub faults: Vec<&'static Fault>,
    /// The fitted parameters, by name.
    pub parameters: Vec<(&'static str, f64)>,
    /// The share of pixels by which the render and the student's picture still differ.
    pub bad_fraction: f64,
}

impl FaultMatch {
    /// The faults' names, joined by `+` for a pair.
    pub fn code(&self) -> String {
        self.faults
            .iter()
            .map(|f| f.name)
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// What simulation says of one picture of a line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Simulated {
    /// Every fault (or pair) whose render passes against the picture, closest first; empty
    /// when none does.
    pub matches: Vec<FaultMatch>,
}

/// A line's command line, scene and pictures, ready to be rendered under faults.
struct Prepared {
    line: LineScene,
    /// Where each of the line's images stands among the job's pictures.
    slots: Vec<usize>,
}

/// Reads and builds what the line renders, from the suite's own `scenes` folder.
fn prepare(line: &Line, scenes: &Path) -> Result<Prepared, String> {
    let mut options = match parse_args(line.args.iter().map(Into::into).collect()) {
        Ok(Command::Render(options)) => *options,
        Ok(_) => return Err("the line asks for no render".into()),
        Err(message) => return Err(format!("raycast cannot read the line: {message}")),
    };
    options.input = scenes.join(&options.input);
    let description = read_scene(&options.input).map_err(|e| e.to_string())?;
    let mut scene = Scene::from_description(&description).map_err(|e| e.to_string())?;
    if let Some([x, y, z]) = options.grid {
        scene
            .world
            .use_grid(glam::UVec3::new(x, y, z))
            .map_err(|e| e.to_string())?;
    }
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
    Ok(Prepared {
        line: LineScene {
            options,
            description,
            scene,
        },
        slots,
    })
}

/// One render tried: the plant, the faults in it and their parameters, and the share of pixels
/// off against each failing picture.
struct Tried {
    plant: Plant,
    faults: Vec<&'static Fault>,
    parameters: Vec<(&'static str, f64)>,
    bad: Vec<f64>,
}

/// For each of `failing` (the index of an image among the line's outputs, and the student's
/// picture of it), the faults whose render matches it.
pub fn simulate(
    line: &Line,
    scenes: &Path,
    failing: &[(usize, &Image)],
    rule: Rule,
) -> Result<Vec<Simulated>, String> {
    let prepared = prepare(line, scenes)?;
    let render = |plant: Plant| -> Vec<f64> {
        let pictures = render_pictures(&prepared.line.options, &prepared.line.scene, plant);
        failing
            .iter()
            .map(|&(image, actual)| {
                pictures
                    .pictures
                    .get(prepared.slots[image])
                    .and_then(|picture| compare(picture, actual, rule.tolerance))
                    .map_or(1.0, |c| c.bad_fraction)
            })
            .collect()
    };
    let mut tried: Vec<Tried> = Vec::new();
    for fault in FAULTS {
        for candidate in (fault.candidates)(&prepared.line) {
            if tried.len() >= MAX_RENDERS {
                break;
            }
            let plant = Plant::one(candidate.planted);
            tried.push(Tried {
                plant,
                faults: vec![fault],
                parameters: candidate.parameter.into_iter().collect(),
                bad: render(plant),
            });
        }
    }
    let mut results: Vec<Simulated> = (0..failing.len())
        .map(|k| Simulated {
            matches: matches(&tried, k, rule),
        })
        .collect();
    // Pairs, for the pictures no single fault explains but the closest goes at least halfway.
    let unexplained: Vec<usize> = (0..failing.len())
        .filter(|&k| results[k].matches.is_empty())
        .collect();
    for k in unexplained {
        let plain = compare_plain(&prepared, failing[k], rule);
        let Some(best) = closest(&tried, k) else {
            continue;
        };
        if tried[best].bad[k] > plain / 2.0 {
            continue;
        }
        let first = single_planted(&tried[best]);
        let mut pairs = Vec::new();
        for (other, candidate) in tried.iter().enumerate() {
            if other == best || candidate.faults[0].name == tried[best].faults[0].name {
                continue;
            }
            if tried.len() + pairs.len() >= MAX_RENDERS {
                break;
            }
            let plant = Plant::two(first, single_planted(candidate));
            let mut parameters = tried[best].parameters.clone();
            parameters.extend(candidate.parameters.iter().copied());
            pairs.push(Tried {
                plant,
                faults: vec![tried[best].faults[0], candidate.faults[0]],
                parameters,
                bad: render(plant),
            });
        }
        results[k].matches = matches(&pairs, k, rule);
        tried.extend(pairs);
    }
    Ok(results)
}

/// The one fault planted in a single render.
fn single_planted(tried: &Tried) -> Planted {
    tried.plant.first()
}

/// How far the student's picture is from the course's render of the line.
fn compare_plain(prepared: &Prepared, (image, actual): (usize, &Image), rule: Rule) -> f64 {
    let pictures = render_pictures(
        &prepared.line.options,
        &prepared.line.scene,
        crate::render::Exact,
    );
    pictures
        .pictures
        .get(prepared.slots[image])
        .and_then(|picture| compare(picture, actual, rule.tolerance))
        .map_or(1.0, |c| c.bad_fraction)
}

/// The render closest to picture `k`.
fn closest(tried: &[Tried], k: usize) -> Option<usize> {
    (0..tried.len()).min_by(|&a, &b| tried[a].bad[k].total_cmp(&tried[b].bad[k]))
}

/// The renders that pass against picture `k`, the closest of each fault (or pair), closest
/// first; among equals, in the library's order.
fn matches(tried: &[Tried], k: usize, rule: Rule) -> Vec<FaultMatch> {
    let mut found: Vec<FaultMatch> = Vec::new();
    for t in tried.iter().filter(|t| t.bad[k] <= rule.max_bad) {
        let names: Vec<&str> = t.faults.iter().map(|f| f.name).collect();
        match found
            .iter_mut()
            .find(|m| m.faults.iter().map(|f| f.name).eq(names.iter().copied()))
        {
            Some(m) if m.bad_fraction <= t.bad[k] => {}
            Some(m) => {
                m.bad_fraction = t.bad[k];
                m.parameters = t.parameters.clone();
            }
            None => found.push(FaultMatch {
                faults: t.faults.clone(),
                parameters: t.parameters.clone(),
                bad_fraction: t.bad[k],
            }),
        }
    }
    // Stable: among equal figures, the library's order stands.
    found.sort_by(|a, b| a.bad_fraction.total_cmp(&b.bad_fraction));
    found
}
