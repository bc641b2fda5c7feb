//! The questions the course leaves open, as data: each of STAFF_NOTES.md's "Still open" list
//! and each "may" of the handouts, with the answers the course allows. raycast renders one
//! answer by default (the first); `raycast -choose NAME` renders another, through the same
//! seams as check's faults. check accepts every allowed answer: a picture that fails against
//! raycast's answer passes when it matches the render of another allowed answer of a question
//! its line depends on, and the report says which answer the tracer took. Which lines depend
//! on which question is found by rendering (an answer whose render of a line is raycast's own
//! changes nothing there), never from a hand-kept list.
//!
//! Where the allowed answers cannot be listed (Wood is free-form, `-visualize_grid` may use any
//! colours), a picture that depends on the question and differs is informational: shown,
//! never counted as failing, with the reason.

use super::faults::{
    CameraFault, Candidate, LineScene, Planted, RayFault, SampleFault, TextureFault,
    gaussian_radius, has_material,
};

/// The fixed epsilons of shadow and secondary rays the course allows: those whose pictures of
/// the course's lines show neither acne nor a missed occluder. Measured over the 55 pictures of
/// the later assignments with shadow or secondary rays, against raycast's own: a fixed 1e-6
/// differs in 53 (acne), 1e-5 in 27, 1e-4 and 1e-3 in none, 1e-2 in 20 (occluders missed where
/// objects touch), 1e-1 in 26 (docs/decisions.md).
const EPSILONS: [f32; 2] = [1e-4, 1e-3];
use crate::parse::description::{MaterialSpec, Pattern};
use crate::sample::Filter;
use crate::trace::ThroughGlass;

/// One question the course leaves open.
#[derive(Debug)]
pub struct Choice {
    /// Its stable name.
    pub name: &'static str,
    /// The question, as a student would ask it.
    pub question: &'static str,
    /// raycast's answer: what it renders by default.
    pub raycast: &'static str,
    /// What check accepts.
    pub accepted: Accepted,
}

/// What check accepts for a question.
#[derive(Debug)]
pub enum Accepted {
    /// raycast's answer, or any of these (each rendered where a line depends on it).
    Answers(&'static [Answer]),
    /// Anything: pictures that depend on the question are informational where they differ.
    Anything {
        /// Whether a line's shaded picture depends on it.
        depends: fn(&LineScene) -> bool,
        /// Why, for the report.
        why: &'static str,
    },
    /// No line of the course's suites depends on it (said with what was tried).
    NoLineDepends(&'static str),
    /// Any picture as near its reference, pixel by pixel, as this answer's renders lie to one
    /// another (and the tolerance beyond): answers that cannot be listed one by one, only
    /// bounded.
    Between(&'static Answer),
}

/// An answer the course allows besides raycast's.
#[derive(Debug)]
pub struct Answer {
    /// Its stable name (`-choose NAME`).
    pub name: &'static str,
    /// What the tracer does, said to the student ("your Gaussian is not cut at 2σ").
    pub said: &'static str,
    /// The renders of it for a line: none where it cannot change the line's pictures.
    pub candidates: fn(&LineScene) -> Vec<Candidate>,
}

/// Whether the line filters its samples with a filter of this kind.
fn filters_with(line: &LineScene, kind: fn(&Filter) -> bool) -> bool {
    (line.options.render_filter.is_some() || !line.options.sampling.is_plain())
        && kind(&line.options.sampling.filter)
}

/// Whether the line's shaded picture shows a texture with this pattern.
fn shows_pattern(line: &LineScene, kind: fn(&Pattern) -> bool) -> bool {
    line.has_image()
        && line.description.materials.iter().any(|m| match m {
            MaterialSpec::Texture(t) => kind(&t.pattern),
            MaterialSpec::Phong(_) => false,
        })
}

fn when(applies: bool, planted: Planted) -> Vec<Candidate> {
    if applies {
        vec![Candidate::plain(planted)]
    } else {
        Vec::new()
    }
}

/// How far the point of the view a ray goes through is nudged to show which pixels turn on a
/// ray's last digits, in pixels: at the course's sizes (100 to 400 pixels across a view of 30°
/// to 60°) it turns a camera ray by about 1e-7 to 1e-6 radians, a few ulps of its direction,
/// which is where a float tracer's rounding leaves it (a double tracer's is nearer the exact
/// ray). Measured on the checkerboards seen through glass and by uniform samples: in
/// docs/decisions.md.
const NUDGE: f32 = 1e-4;

/// The line's renders with every ray (a pixel's centre's, or a sample's) through a point of
/// the view nudged by [`NUDGE`] pixels each way along each axis.
fn nudged(line: &LineScene) -> Vec<Candidate> {
    if !line.has_image() {
        return Vec::new();
    }
    let (du, dv) = (
        NUDGE / line.options.width.max(1) as f32,
        NUDGE / line.options.height.max(1) as f32,
    );
    [[du, 0.0], [-du, 0.0], [0.0, dv], [0.0, -dv]]
        .into_iter()
        .map(|nudge| {
            Candidate::plain(Planted::Camera(CameraFault::Nudged(
                line.scene.camera,
                nudge,
            )))
        })
        .collect()
}

/// Every open question, in STAFF_NOTES.md's order, then the handouts' "may"s.
pub static CHOICES: &[Choice] = &[
    Choice {
        name: "gaussian_cut",
        question: "Is the Gaussian filter cut to 0 beyond 2σ?",
        raycast: "cut at 2σ (the handout: it \"may be\")",
        accepted: Accepted::Answers(&[Answer {
            name: "gaussian_uncut",
            said: "your Gaussian is not cut at 2σ",
            // Uncut, the support radius decides which samples weigh: the course's for a reach
            // of 2σ or 3σ, or those reaches rounded up; each distinct radius once.
            candidates: |line| {
                let Filter::Gaussian(sigma) = line.options.sampling.filter else {
                    return Vec::new();
                };
                if !filters_with(line, |f| matches!(f, Filter::Gaussian(_))) {
                    return Vec::new();
                }
                let mut radii = Vec::new();
                let mut candidates = Vec::new();
                for (sigmas, ceil) in [(2.0, false), (2.0, true), (3.0, false), (3.0, true)] {
                    let radius = gaussian_radius(sigma * sigmas, ceil);
                    if !radii.contains(&radius) {
                        radii.push(radius);
                        candidates.push(Candidate::with(
                            Planted::Sample(SampleFault::GaussianUncut { sigmas, ceil }),
                            "radius",
                            f64::from(radius),
                        ));
                    }
                }
                candidates
            },
        }]),
    },
    Choice {
        name: "box_edge",
        question: "Does the box filter take a sample that lies exactly on its edge?",
        raycast: "the near edges in, the far edges out (−r ≤ x < r)",
        accepted: Accepted::Answers(&[
            Answer {
                name: "box_closed",
                said: "your box filter takes samples on both its edges",
                candidates: |line| {
                    when(
                        filters_with(line, |f| matches!(f, Filter::Box(_))),
                        Planted::Sample(SampleFault::BoxClosed),
                    )
                },
            },
            Answer {
                name: "box_open",
                said: "your box filter takes no sample on its edges",
                candidates: |line| {
                    when(
                        filters_with(line, |f| matches!(f, Filter::Box(_))),
                        Planted::Sample(SampleFault::BoxOpen),
                    )
                },
            },
        ]),
    },
    Choice {
        name: "checkerboard_parity",
        question: "Which material has the checkerboard's cube at the origin?",
        raycast: "the first (materialIndex m1)",
        accepted: Accepted::Answers(&[Answer {
            name: "checker_swapped",
            said: "your checkerboard gives the cube at the origin the second material",
            candidates: |line| {
                when(
                    shows_pattern(line, |p| matches!(p, Pattern::Checkerboard)),
                    Planted::Texture(TextureFault::CheckerSwapped),
                )
            },
        }]),
    },
    Choice {
        name: "noise_mapping",
        question: "How is Noise's sum, about −1 to 1, made a weight from 0 to 1?",
        raycast: "(N + 1) / 2, clamped",
        accepted: Accepted::Answers(&[Answer {
            name: "noise_clamped",
            said: "your Noise clamps its sum to [0, 1]",
            candidates: |line| {
                when(
                    shows_pattern(line, |p| matches!(p, Pattern::Noise { .. })),
                    Planted::Texture(TextureFault::NoiseClamped),
                )
            },
        }]),
    },
    Choice {
        name: "marble_mapping",
        question: "How is Marble's sine, −1 to 1, made a weight from 0 to 1?",
        raycast: "(sin + 1) / 2",
        accepted: Accepted::Answers(&[
            Answer {
                name: "marble_clamped",
                said: "your Marble clamps its sine to [0, 1]",
                candidates: |line| {
                    when(
                        shows_pattern(line, |p| matches!(p, Pattern::Marble { .. })),
                        Planted::Texture(TextureFault::MarbleClamped),
                    )
                },
            },
            Answer {
                name: "marble_absolute",
                said: "your Marble takes the sine's absolute value",
                candidates: |line| {
                    when(
                        shows_pattern(line, |p| matches!(p, Pattern::Marble { .. })),
                        Planted::Texture(TextureFault::MarbleAbsolute),
                    )
                },
            },
        ]),
    },
    Choice {
        name: "wood",
        question: "What does Wood look like?",
        raycast: "rings about the y axis, perturbed by the noise",
        accepted: Accepted::Anything {
            depends: |line| shows_pattern(line, |p| matches!(p, Pattern::Wood { .. })),
            why: "the course leaves Wood free-form (extra credit), so a picture with Wood is \
                  shown, not graded",
        },
    },
    Choice {
        name: "visualize_grid_colours",
        question: "Which colours does -visualize_grid draw its cells in?",
        raycast: "a colour for the number of objects a cell holds",
        accepted: Accepted::Anything {
            depends: |line| line.has_image() && line.options.trace.visualize_grid,
            why: "the handout lets -visualize_grid use any colour scheme, so its picture is \
                  shown, not graded",
        },
    },
    Choice {
        name: "ray_epsilon",
        question: "How far from its surface does a shadow, mirror or glass ray start?",
        raycast: "past a clearance scaled to the hit point's coordinates (a few ulps of them)",
        accepted: Accepted::Answers(&[Answer {
            name: "epsilon_fixed",
            said: "your shadow and secondary rays ignore hits nearer than a fixed epsilon",
            candidates: |line| {
                if !spawns_rays(line) {
                    return Vec::new();
                }
                EPSILONS
                    .iter()
                    .map(|&epsilon| {
                        Candidate::with(
                            Planted::Ray(RayFault::FixedStart(epsilon)),
                            "epsilon",
                            f64::from(epsilon),
                        )
                    })
                    .collect()
            },
        }]),
    },
    Choice {
        name: "light_distance",
        question: "Does a hit exactly at the light's distance block it?",
        raycast: "no: t < distance",
        accepted: Accepted::Answers(&[Answer {
            name: "light_distance_inclusive",
            said: "your shadow rays count a hit exactly at the light (t ≤ distance)",
            candidates: |line| {
                when(
                    line.has_image() && line.options.trace.shadows,
                    Planted::Ray(RayFault::ShadowToLight),
                )
            },
        }]),
    },
    Choice {
        name: "transparent_shadows",
        question: "Does glass let light through to what it shadows (the handout's optional \
                   transparent shadows, extra credit)?",
        raycast: "no: glass casts opaque shadows, as the required images show",
        accepted: Accepted::Answers(&[
            Answer {
                name: "shadows_through_each_surface",
                said: "your glass lets light through to its shadows, times its transparent \
                       colour at each surface crossed (the handout's optional transparent \
                       shadows)",
                candidates: |line| through_glass(line, ThroughGlass::EachSurface),
            },
            Answer {
                name: "shadows_through_each_object",
                said: "your glass lets light through to its shadows, times its transparent \
                       colour once for each glass object crossed (the handout's optional \
                       transparent shadows)",
                candidates: |line| through_glass(line, ThroughGlass::EachObject),
            },
            Answer {
                name: "shadows_through_by_distance",
                said: "your glass lets light through to its shadows, its transparent colour \
                       raised to the distance travelled inside (the handout's optional \
                       transparent shadows)",
                candidates: |line| through_glass(line, ThroughGlass::ByDistance),
            },
        ]),
    },
    Choice {
        name: "shadow_rays_facing_away",
        question: "Is a shadow ray sent where N·L ≤ 0?",
        raycast: "no: a light that adds nothing to a point gets no shadow ray",
        accepted: Accepted::NoLineDepends(
            "where N·L ≤ 0 a light adds nothing (the highlight is cut there too), so a shadow \
             ray changes no pixel: only -stats' count of shadow rays",
        ),
    },
    Choice {
        name: "weight_default",
        question: "What is -weight when a line gives -bounces but not -weight?",
        raycast: "0: every mirror and glass ray up to -bounces is traced",
        accepted: Accepted::Answers(&[Answer {
            name: "weight_default_course",
            said: "your -weight is 0.01 when the line does not give one (the course's value)",
            candidates: |line| {
                let given = line.options.trace.cutoff_weight > 0.0;
                when(
                    spawns_rays(line) && line.options.trace.bounces > 0 && !given,
                    Planted::Ray(RayFault::DefaultWeight(0.01)),
                )
            },
        }]),
    },
    Choice {
        name: "bounces_default",
        question: "What is -bounces when a line does not give it?",
        raycast: "0: camera rays only",
        accepted: Accepted::NoLineDepends(
            "the course's lines that do not give -bounces are -visualize_grid's (informational) \
             and scenes without mirrors or glass",
        ),
    },
    Choice {
        name: "uniform_positions",
        question: "Where does the uniform sampler put a pixel's samples?",
        raycast: "at the centres of an s × s grid's cells",
        accepted: Accepted::NoLineDepends(
            "the cells' centres are the only even grid inside a pixel that the handout's \
             pictures show; corners are the fault uniform_corners",
        ),
    },
    Choice {
        name: "arithmetic",
        question: "Is the tracer's arithmetic float or double, and in which order?",
        raycast: "float (the course's Vec3f), in the handouts' order",
        accepted: Accepted::Between(&Answer {
            name: "last_digits",
            said: "your picture differs from raycast's only where a ray's colour turns on the \
                   last digits of its arithmetic (double against float, another order of \
                   operations)",
            candidates: nudged,
        }),
    },
    Choice {
        name: "default_filter",
        question: "Which filter is used when samples are given without one?",
        raycast: "a box of radius 0.5 (each pixel its own samples)",
        accepted: Accepted::NoLineDepends(
            "no command line of the course gives samples without a filter",
        ),
    },
];

/// How a picture that differs from raycast's answer was accepted.
#[derive(Debug, Clone)]
pub enum Acceptance {
    /// It matches the render of another allowed answer to this question.
    Answer(&'static Choice, &'static Answer),
    /// It matches the render of other allowed answers to two questions at once (a scene with
    /// Noise and Marble, each mapped otherwise).
    Answers([(&'static Choice, &'static Answer); 2]),
    /// It depends on a question the course leaves free: shown, not graded, for this reason.
    Informational(&'static str),
}

// Questions and answers are known by their names.
impl PartialEq for Acceptance {
    fn eq(&self, other: &Acceptance) -> bool {
        match (self, other) {
            (Acceptance::Answer(_, a), Acceptance::Answer(_, b)) => a.name == b.name,
            (Acceptance::Answers(a), Acceptance::Answers(b)) => a
                .iter()
                .map(|(_, x)| x.name)
                .eq(b.iter().map(|(_, x)| x.name)),
            (Acceptance::Informational(a), Acceptance::Informational(b)) => a == b,
            _ => false,
        }
    }
}

impl Acceptance {
    /// What the student reads: which answer the tracer took, or why the picture is not graded.
    pub fn sentence(&self) -> String {
        match self {
            Acceptance::Answer(choice, answer) => format!(
                "Your picture matches another answer the course allows: {} (\"{}\" raycast \
                 answers {}). Accepted.",
                answer.said, choice.question, choice.raycast
            ),
            Acceptance::Answers([(first_choice, first), (second_choice, second)]) => format!(
                "Your picture matches other answers the course allows, taken together: {} \
                 (\"{}\" raycast answers {}); and {} (\"{}\" raycast answers {}). Accepted.",
                first.said,
                first_choice.question,
                first_choice.raycast,
                second.said,
                second_choice.question,
                second_choice.raycast
            ),
            Acceptance::Informational(why) => {
                let mut why = why.to_string();
                if let Some(first) = why.get(..1) {
                    why.replace_range(..1, &first.to_uppercase());
                }
                format!("Informational: {why}.")
            }
        }
    }

    /// As summary.json writes it.
    pub fn json(&self) -> serde_json::Value {
        match self {
            Acceptance::Answer(choice, answer) => serde_json::json!({
                "choice": choice.name, "answer": answer.name, "said": answer.said,
            }),
            // The first answer where one is read; the second beside it.
            Acceptance::Answers([(choice, answer), (also_choice, also)]) => serde_json::json!({
                "choice": choice.name, "answer": answer.name, "said": answer.said,
                "also": { "choice": also_choice.name, "answer": also.name, "said": also.said },
            }),
            Acceptance::Informational(why) => serde_json::json!({ "informational": why }),
        }
    }

    /// Back from summary.json (a shard's), where it names a question and answer still known.
    pub fn from_json(value: &serde_json::Value) -> Option<Acceptance> {
        if let Some(name) = value["answer"].as_str() {
            let first = answer(name)?;
            return Some(match value["also"]["answer"].as_str() {
                Some(also) => Acceptance::Answers([first, answer(also)?]),
                None => Acceptance::Answer(first.0, first.1),
            });
        }
        let why = value["informational"].as_str()?;
        CHOICES.iter().find_map(|choice| match choice.accepted {
            Accepted::Anything { why: known, .. } if known == why => {
                Some(Acceptance::Informational(known))
            }
            _ => None,
        })
    }
}

/// Transparent shadows of `through`'s way, where the line's shaded picture has shadows and its
/// scene glass.
fn through_glass(line: &LineScene, through: ThroughGlass) -> Vec<Candidate> {
    when(
        line.has_image() && line.options.trace.shadows && has_material(line, true),
        Planted::Ray(RayFault::ThroughGlass(through)),
    )
}

/// Whether the line's shaded picture sends shadow, mirror or glass rays.
fn spawns_rays(line: &LineScene) -> bool {
    line.has_image() && (line.options.trace.shadows || line.options.trace.bounces > 0)
}

/// The allowed answer named `name`.
pub fn answer(name: &str) -> Option<(&'static Choice, &'static Answer)> {
    CHOICES.iter().find_map(|choice| match &choice.accepted {
        Accepted::Answers(answers) => answers
            .iter()
            .find(|a| a.name == name)
            .map(|answer| (choice, answer)),
        Accepted::Between(answer) if answer.name == name => Some((choice, *answer)),
        _ => None,
    })
}

/// Every question whose answers are bounded, not listed, with its answer's renders.
pub fn bounded() -> impl Iterator<Item = (&'static Choice, &'static Answer)> {
    CHOICES.iter().filter_map(|choice| match &choice.accepted {
        Accepted::Between(answer) => Some((choice, *answer)),
        _ => None,
    })
}

/// The allowed answer named `name` (listed or bounded), with its question.
pub fn answer_named(name: &str) -> Option<(&'static Choice, &'static Answer)> {
    answers()
        .chain(bounded())
        .find(|(_, answer)| answer.name == name)
}

/// The reason a question the course leaves free gives, where it is `why`.
pub fn reason_named(why: &str) -> Option<&'static str> {
    CHOICES.iter().find_map(|choice| match choice.accepted {
        Accepted::Anything { why: reason, .. } if reason == why => Some(reason),
        _ => None,
    })
}

/// Every allowed answer besides raycast's, with its question.
pub fn answers() -> impl Iterator<Item = (&'static Choice, &'static Answer)> {
    CHOICES.iter().flat_map(|choice| {
        let answers: &'static [Answer] = match &choice.accepted {
            Accepted::Answers(answers) => answers,
            _ => &[],
        };
        answers.iter().map(move |answer| (choice, answer))
    })
}

/// The answer `-choose NAME` renders for `line` (`NAME:K`: its K-th render, from 0, where it
/// has several: radii, epsilons): `None` where it cannot change the line's pictures (the line
/// renders as raycast's default).
pub fn planted_for(spec: &str, line: &LineScene) -> Result<Option<Planted>, String> {
    let (name, index) = match spec.split_once(':') {
        Some((name, k)) => (
            name,
            k.parse::<usize>().map_err(|_| {
                format!("-choose {spec}: expected a render number after ':', found '{k}'")
            })?,
        ),
        None => (spec, 0),
    };
    let (_, answer) = answer(name).ok_or_else(|| {
        let names: Vec<&str> = answers().map(|(_, a)| a.name).collect();
        format!(
            "-choose: unknown answer '{name}' (one of {})",
            names.join(", ")
        )
    })?;
    let candidates = (answer.candidates)(line);
    match (candidates.get(index), candidates.len()) {
        (Some(candidate), _) => Ok(Some(candidate.planted)),
        (None, 0) => Ok(None),
        (None, n) => Err(format!(
            "-choose {spec}: the answer has {n} renders for this line (0 to {})",
            n - 1
        )),
    }
}

/// The question a line's shaded picture depends on that allows any answer, if any: why it is
/// informational where it differs.
pub fn informational(line: &LineScene) -> Option<&'static str> {
    CHOICES.iter().find_map(|choice| match choice.accepted {
        Accepted::Anything { depends, why } if depends(line) => Some(why),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_answer_has_one_name_and_none_is_a_fault() {
        let mut names: Vec<&str> = answers().map(|(_, a)| a.name).collect();
        let count = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), count, "two answers share a name");
        for name in names {
            assert!(
                super::super::faults::fault(name).is_none(),
                "{name} is both an allowed answer and a fault"
            );
        }
    }
}
