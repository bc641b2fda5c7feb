//! A line's references: the suite's pictures, or raycast's own render of the line where the
//! suite has none; and, for a picture drawn by chance, the rule that grades it in the
//! reference's stead, made only when a picture needs it.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use super::chance::{ByChance, Drawn};
use super::output::read_image;
use super::suite::{self, Line, Suite};
use super::{Ending, cache, simulate};
use crate::render::StopFlag;
use crate::shade::Image;

/// For each image a line writes: its reference (or why there is none), whether that is
/// raycast's own render, and, for a picture drawn by chance, how it is graded.
pub(super) type References = Vec<(Result<Image, String>, bool, Option<ChanceRule>)>;

/// How a picture drawn by chance is graded: against the spread of raycast's renders of the line
/// with several seeds (or, the samples picture, by its structure). Those renders are costly (a
/// line drawn by chance takes samples a pixel), so they are made the first time one of the
/// line's pictures needs them, once for every renderer graded against the line (a class's
/// students share them). A picture that passes against raycast's own render of the line by the
/// plain rule never needs them: that render is one of the spread's draws, and a picture within
/// the tolerance of a draw lies within the spread ([`ChanceRule::plain_pass_suffices`]).
#[derive(Debug, Clone)]
pub(crate) struct ChanceRule {
    line: Arc<LineChance>,
    image: usize,
    drawn: Drawn,
    /// The reference is raycast's own render of the line with its own seed and no pinned
    /// answer: the first draw of the spread.
    reference_is_a_draw: bool,
}

#[derive(Debug)]
struct LineChance {
    line: Line,
    scenes: PathBuf,
    stop: &'static StopFlag,
    /// The rules of its traced pictures and of its samples picture: each made on first need.
    rules: [OnceLock<Result<Vec<Option<ByChance>>, String>>; 2],
}

impl ChanceRule {
    /// The picture's rule, made now (for the line's pictures drawn alike) if it was not yet: `Err`
    /// where raycast could not render the line's draws, or check was asked to stop first.
    pub fn rule(&self) -> Result<Option<&ByChance>, String> {
        let line = &self.line;
        let made = &line.rules[usize::from(self.drawn == Drawn::Samples)];
        let rules = made.get_or_init(|| {
            simulate::spreads(&line.line, &line.scenes, self.drawn, line.stop)
                .map(Option::unwrap_or_default)
                .map_err(|why| format!("raycast could not render the line's other draws: {why}"))
        });
        match rules {
            Ok(rules) => Ok(rules.get(self.image).and_then(Option::as_ref)),
            Err(why) => Err(why.clone()),
        }
    }

    /// Why check stopped, if it was asked to (by a person, or its deadline): the rule is then
    /// not made.
    pub fn stopped(&self) -> Option<Ending> {
        let stop = self.line.stop;
        stop.is_set().then(|| Ending::stopped(stop))
    }

    /// Whether a picture that passes against the reference by the suite's rule passes by this
    /// rule too, without the rule being made: for a traced picture whose reference is a draw
    /// of its spread. (A pixel within the tolerance of one of K draws lies within the tolerance
    /// and (K − 1)/√K of their standard deviations of their mean, Samuelson's bound: 2.5 for 8,
    /// inside the [`super::chance`] rule's 4.)
    pub fn plain_pass_suffices(&self) -> bool {
        self.reference_is_a_draw && self.drawn == Drawn::Traced
    }
}

/// Reads the references of `line`'s images, rendering the line with raycast for those the suite
/// lacks (once for all of them).
pub(super) fn of(suite: &Suite, line: &Line, stop: &'static StopFlag) -> References {
    let own = OnceLock::new();
    let drawn = simulate::drawn_by_chance(line);
    let chance = Arc::new(LineChance {
        line: line.clone(),
        scenes: suite.scenes.clone(),
        stop,
        rules: [OnceLock::new(), OnceLock::new()],
    });
    line.outputs
        .iter()
        .enumerate()
        .map(
            |(k, (_, name))| match suite.reference(&suite::image_name(name)) {
                Some(path) => (read_image(&path), false, None),
                None => {
                    let pictures = own.get_or_init(|| raycasts_pictures(suite, line, stop));
                    let picture = match pictures {
                        Ok(pictures) => pictures
                            .get(k)
                            .cloned()
                            .ok_or_else(|| "raycast made no such picture".to_string()),
                        Err(why) => Err(format!("raycast itself could not render it: {why}")),
                    };
                    let rule = drawn.get(k).copied().flatten().map(|drawn| ChanceRule {
                        line: chance.clone(),
                        image: k,
                        drawn,
                        reference_is_a_draw: suite.pinned.is_empty(),
                    });
                    (picture, true, rule)
                }
            },
        )
        .collect()
}

/// raycast's own pictures of `line` in `suite` (its scenes, its pinned answers): kept in the
/// cache, or rendered and kept.
pub(super) fn raycasts_pictures(
    suite: &Suite,
    line: &Line,
    stop: &'static StopFlag,
) -> Result<Vec<Image>, String> {
    cache::LineRenders::of(line, &suite.scenes).course(&suite.pinned, || {
        simulate::course_pictures(line, &suite.scenes, &suite.pinned, stop)
    })
}
