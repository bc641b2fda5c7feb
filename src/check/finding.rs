//! What check found a picture's fault to be, for the terminal, the report and `summary.json`.

use serde_json::{Value, json};

use super::diagnose::Diagnosis;
use super::simulate::FaultMatch;
use super::suite::PictureKind;

/// A guess's advice for the kind of picture it is about: the pixel guesses were written for the
/// shaded picture, and some say the opposite of what a depth or normals picture needs.
fn advice(diagnosis: Diagnosis, kind: PictureKind) -> String {
    let depth = "The depth picture's grey is (TMAX - t) / (TMAX - TMIN) with -depth's TMIN and \
                 TMAX, clamped to [0, 1], where t is the distance along the ray (from the eye, \
                 for a perspective camera).";
    let normals = "The normals picture is (|x|, |y|, |z|) of the unit normal in world space: \
                   carried by the inverse transpose of a Transform, made unit again, and taken \
                   absolute, whichever side the ray meets.";
    let miss = "rays that hit nothing are black in the depth and normals pictures (the scene's \
                background belongs to the shaded picture alone).";
    match (kind, diagnosis) {
        (PictureKind::Depth | PictureKind::Normals, d) if d == Diagnosis::BACKGROUND => {
            format!("Only the background differs: {miss}")
        }
        (PictureKind::Depth, d) if d == Diagnosis::COLOUR_SCALE || d == Diagnosis::GAMMA => {
            format!("Every depth is off by one curve. {depth}")
        }
        (PictureKind::Normals, d)
            if [
                Diagnosis::COLOUR_SCALE,
                Diagnosis::GAMMA,
                Diagnosis::BACK_FACES,
            ]
            .contains(&d) =>
        {
            format!("The normals' colours are off. {normals}")
        }
        (PictureKind::Samples, _) => format!(
            "In the picture of the samples (-render_samples): {} Where each sample falls comes \
             from the sampler (random, uniform at the cells' centres, or jittered one a cell).",
            diagnosis.explanation()
        ),
        (PictureKind::Filter, _) => format!(
            "In the picture of the filter's weights (-render_filter): {} The weights come from \
             the filter alone (box, tent or Gaussian, with the radius or σ of the line).",
            diagnosis.explanation()
        ),
        _ => diagnosis.explanation().to_string(),
    }
}

/// One cause named for a picture.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// raycast's render of the line with these faults planted matches the picture: the cause.
    Fault(FaultMatch),
    /// No render matches; this fault's comes nearest and accounts for most of the pixels by
    /// which the picture differs from its reference: a guess (the same mistake, most likely,
    /// with another difference beside it).
    Near(FaultMatch),
    /// Decided from the run (a crash, no picture, the wrong size) or, where no fault of the
    /// library reproduces the picture, guessed from the pixels.
    Diagnosis(Diagnosis),
}

impl Finding {
    /// The fault's name (two joined by `+`), or the diagnosis's code.
    pub fn code(&self) -> String {
        match self {
            Finding::Fault(m) | Finding::Near(m) => m.code(),
            Finding::Diagnosis(d) => d.code().to_string(),
        }
    }

    /// Whether it is a guess from the pixels rather than a fault reproduced or a fact of the run.
    pub fn is_guess(&self) -> bool {
        match self {
            Finding::Diagnosis(d) => !d.is_fact(),
            Finding::Near(_) => true,
            Finding::Fault(_) => false,
        }
    }

    /// As `summary.json` carries it: `code`, `kind` (`fault`, `near`, `run` or `guess`), and
    /// for a fault (matched, or near) the faults' names, fitted parameters, the match figure (the share of pixels off
    /// between the student's picture and the fault's render), assignment, sentence and what to
    /// look for; for the others the explanation.
    pub fn json(&self) -> Value {
        match self {
            Finding::Fault(m) | Finding::Near(m) => json!({
                "code": m.code(),
                "kind": if matches!(self, Finding::Near(_)) { "near" } else { "fault" },
                "faults": m.faults.iter().map(|f| f.name).collect::<Vec<_>>(),
                "parameters": m
                    .parameters
                    .iter()
                    .map(|&(name, value)| (name.to_string(), json!(value)))
                    .collect::<serde_json::Map<_, _>>(),
                "parameter_order": m.parameters.iter().map(|&(name, _)| name).collect::<Vec<_>>(),
                "match": m.bad_fraction,
                "against": if m.against_spread { "spread" } else { "render" },
                "accounts_for": m.accounts_for,
                "assignment": m.faults.iter().map(|f| f.assignment).collect::<Vec<_>>(),
                "sentence": m.faults.iter().map(|f| f.sentence).collect::<Vec<_>>().join(" "),
                "look_for": m.faults.iter().map(|f| f.look_for).collect::<Vec<_>>().join(" "),
            }),
            Finding::Diagnosis(d) => json!({
                "code": d.code(),
                "kind": if d.is_fact() { "run" } else { "guess" },
                "explanation": d.explanation(),
            }),
        }
    }
}

impl Finding {
    /// A finding as [`Finding::json`] wrote it (a shard's `summary.json`); `None` for a code
    /// this raycast does not know.
    pub fn from_json(value: &Value) -> Option<Finding> {
        let code = value["code"].as_str()?;
        if value["kind"] != "fault" && value["kind"] != "near" {
            return Diagnosis::all()
                .find(|d| d.code() == code)
                .map(Finding::Diagnosis);
        }
        let faults = value["faults"]
            .as_array()?
            .iter()
            .map(|name| super::faults::fault(name.as_str()?))
            .collect::<Option<Vec<_>>>()?;
        let parameters = value["parameter_order"]
            .as_array()?
            .iter()
            .map(|name| {
                let name = name.as_str()?;
                Some((static_name(name), value["parameters"][name].as_f64()?))
            })
            .collect::<Option<Vec<_>>>()?;
        let m = FaultMatch {
            faults,
            parameters,
            bad_fraction: value["match"].as_f64()?,
            accounts_for: value["accounts_for"].as_f64(),
            against_spread: value["against"] == "spread",
        };
        Some(if value["kind"] == "near" {
            Finding::Near(m)
        } else {
            Finding::Fault(m)
        })
    }
}

/// A parameter's name read back, as the `&'static str` a fault names it by: each distinct name
/// is kept once for the life of the process (a merge reads a handful).
fn static_name(name: &str) -> &'static str {
    static NAMES: std::sync::Mutex<Vec<&'static str>> = std::sync::Mutex::new(Vec::new());
    let mut names = NAMES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(known) = names.iter().find(|&&known| known == name) {
        return known;
    }
    let kept: &'static str = Box::leak(name.to_string().into_boxed_str());
    names.push(kept);
    kept
}

/// The fault matches among `findings`, in their order.
fn fault_matches(findings: &[Finding]) -> Vec<&FaultMatch> {
    findings
        .iter()
        .filter_map(|f| match f {
            Finding::Fault(m) => Some(m),
            Finding::Near(_) | Finding::Diagnosis(_) => None,
        })
        .collect()
}

/// A match's fitted parameters as `, name value` each (empty without any).
fn parameters_text(m: &FaultMatch) -> String {
    m.parameters
        .iter()
        .map(|(name, value)| format!(", {name} {}", show(*value)))
        .collect()
}

/// What a student reads about a failing picture of `kind`: the faults whose render matches it
/// (all of them, where the line cannot tell them apart), or the guesses from the pixels, in
/// words for that kind of picture.
pub fn explain(findings: &[Finding], kind: PictureKind) -> String {
    let faults = fault_matches(findings);
    let Some(first) = faults.first() else {
        let guesses: Vec<&Finding> = findings.iter().filter(|f| f.is_guess()).collect();
        let text = findings
            .iter()
            .filter_map(|f| match f {
                Finding::Diagnosis(d) if !d.is_fact() => Some(advice(*d, kind)),
                Finding::Diagnosis(d) => Some(d.explanation().to_string()),
                Finding::Fault(_) | Finding::Near(_) => None,
            })
            .collect::<Vec<_>>()
            .join(" ");
        let near = findings.iter().find_map(|f| match f {
            Finding::Near(m) => Some(m),
            _ => None,
        });
        return match near {
            Some(near) => near_guess(near, &text),
            None if guesses.is_empty() => text,
            None => format!(
                "No fault in raycast's library reproduces this picture; a guess from the \
                 pixels: {text}"
            ),
        };
    };
    let planted = match first.faults.len() {
        1 => "this fault".to_string(),
        2 => "these two faults".to_string(),
        n => format!("these {n} faults"),
    };
    let parameters = parameters_text(first);
    // "Equals" only where not a pixel is off; otherwise as close as the suite's rule asks. A
    // picture drawn by chance equals no render: it lies within their spread, or near it.
    let likeness = if first.against_spread {
        format!(
            "lies within the spread of raycast's renders of this line with {planted} planted and \
             several seeds ({:.3}% of pixels outside it{parameters})",
            100.0 * first.bad_fraction
        )
    } else {
        format!(
            "{} raycast's render of this line with {planted} planted ({:.3}% of pixels \
             off{parameters})",
            if first.bad_fraction == 0.0 {
                "equals"
            } else {
                "matches, within the suite's rule,"
            },
            100.0 * first.bad_fraction
        )
    };
    let mut text = format!(
        "Your picture {likeness}{}. {} Look for: {}",
        accounted(first, ": it accounts for"),
        first
            .faults
            .iter()
            .map(|f| format!("\"{}\"", f.sentence))
            .collect::<Vec<_>>()
            .join(" and "),
        first
            .faults
            .iter()
            .map(|f| f.look_for)
            .collect::<Vec<_>>()
            .join(" ")
    );
    if faults.len() > 1 {
        let others: Vec<String> = faults[1..].iter().map(|m| m.code()).collect();
        text.push_str(&format!(
            " {} match{} as well: this line alone cannot tell them apart.",
            others.join(", "),
            if others.len() == 1 { "es" } else { "" }
        ));
    }
    text
}

/// A picture no render matches, with the fault whose render comes nearest: named as the guess
/// it is, how near, and what to look for; then what the pixels suggest (`pixels`), if anything.
fn near_guess(near: &FaultMatch, pixels: &str) -> String {
    let planted = match near.faults.len() {
        1 => "this fault",
        _ => "these faults",
    };
    let mut text = format!(
        "No fault in raycast's library reproduces this picture within the suite's rule. A \
         guess: raycast's render of this line with {planted} planted comes nearest, {:.3}% of \
         pixels off{}{}, so the same mistake, in part of its cases or with another difference \
         beside it, is likely. \
         {} Look for: {}",
        100.0 * near.bad_fraction,
        parameters_text(near),
        accounted(near, ": it accounts for"),
        near.faults
            .iter()
            .map(|f| format!("\"{}\"", f.sentence))
            .collect::<Vec<_>>()
            .join(" and "),
        near.faults
            .iter()
            .map(|f| f.look_for)
            .collect::<Vec<_>>()
            .join(" ")
    );
    if !pixels.is_empty() {
        text.push_str(&format!(" The pixels suggest too: {pixels}"));
    }
    text
}

/// The terminal's short account of a failing picture: the faults that match it (the figure and
/// fitted parameters), their sentences and what to look for being in the verdict above; or the
/// full explanation where no fault matches.
pub fn headline(findings: &[Finding], explanation: &str) -> String {
    let faults = fault_matches(findings);
    let Some(first) = faults.first() else {
        return explanation.to_string();
    };
    let planted = if first.faults.len() == 1 {
        "this fault"
    } else {
        "these faults"
    };
    let mut text = if first.against_spread {
        format!(
            "raycast's renders with {planted} planted and several seeds draw it ({:.3}% of \
             pixels outside their spread{}){}",
            100.0 * first.bad_fraction,
            parameters_text(first),
            accounted(first, ", accounting for"),
        )
    } else {
        format!(
            "raycast's render with {planted} planted matches ({:.3}% of pixels off{}){}",
            100.0 * first.bad_fraction,
            parameters_text(first),
            accounted(first, ", accounting for"),
        )
    };
    if faults.len() > 1 {
        text.push_str("; this line alone cannot tell the faults named apart");
    }
    text
}

/// How much of the picture's difference from its reference a match accounts for, after
/// `lead`: empty where that is not known.
fn accounted(m: &FaultMatch, lead: &str) -> String {
    match m.accounts_for {
        Some(share) if share >= 0.9995 => {
            format!("{lead} every pixel that differs from the reference")
        }
        Some(share) => format!(
            "{lead} {:.1}% of the pixels that differ from the reference",
            100.0 * share
        ),
        None => String::new(),
    }
}

/// A parameter as a person reads it: whole numbers without a fraction, others to at most four
/// places,
/// those too small for four places in scientific notation (1e-7).
fn show(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e9 {
        format!("{value:.0}")
    } else if value != 0.0 && value.abs() < 1e-3 {
        // Four significant digits: a float's 1e-5 is 9.999999747e-6 as a double.
        let text = format!("{value:.3e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    } else if value.is_infinite() {
        if value > 0.0 { "infinity" } else { "-infinity" }.to_string()
    } else {
        let text = format!("{value:.4}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_read_as_people_write_them() {
        assert_eq!(show(2.0), "2");
        assert_eq!(show(0.8165), "0.8165");
        assert_eq!(show(1.5), "1.5");
        assert_eq!(show(1.000_01), "1");
        assert_eq!(show(1e-7), "1e-7");
        assert_eq!(show(2.5e-5), "2.5e-5");
        assert_eq!(show(f64::from(1e-5f32)), "1e-5");
        assert_eq!(show(-1.2345e-4), "-1.234e-4");
        assert_eq!(show(f64::INFINITY), "infinity");
    }

    #[test]
    fn a_match_against_a_spread_is_worded_as_one_and_read_back() {
        let fault = crate::check::faults::fault("jitter_whole_pixel").unwrap();
        let drawn = FaultMatch {
            faults: vec![fault],
            parameters: Vec::new(),
            bad_fraction: 0.0,
            accounts_for: None,
            against_spread: true,
        };
        let findings = [Finding::Fault(drawn.clone())];
        // Never "equals" or "matches" one render: a picture drawn by chance lies in a spread.
        assert_eq!(
            headline(&findings, ""),
            "raycast's renders with this fault planted and several seeds draw it (0.000% of \
             pixels outside their spread)"
        );
        let text = explain(&findings, PictureKind::Image);
        assert!(
            text.starts_with(
                "Your picture lies within the spread of raycast's renders of this line with this \
                 fault planted and several seeds (0.000% of pixels outside it)"
            ),
            "{text}"
        );
        let read = Finding::from_json(&findings[0].json());
        assert_eq!(read, Some(Finding::Fault(drawn.clone())));
        let one = FaultMatch {
            against_spread: false,
            ..drawn
        };
        let text = explain(&[Finding::Fault(one)], PictureKind::Image);
        assert!(
            text.starts_with("Your picture equals raycast's render"),
            "{text}"
        );
    }

    #[test]
    fn a_near_render_is_named_as_a_guess_with_how_near_it_comes() {
        let near = FaultMatch {
            faults: vec![crate::check::faults::fault("grid_rays_from_inside").unwrap()],
            parameters: Vec::new(),
            bad_fraction: 0.006_12,
            accounts_for: Some(0.981),
            against_spread: false,
        };
        let findings = [
            Finding::Near(near.clone()),
            Finding::Diagnosis(Diagnosis::BACKGROUND),
        ];
        assert!(findings[0].is_guess());
        assert_eq!(findings[0].code(), "grid_rays_from_inside");
        let text = explain(&findings, PictureKind::Image);
        assert!(
            text.starts_with(
                "No fault in raycast's library reproduces this picture within the suite's rule. \
                 A guess: raycast's render of this line with this fault planted comes nearest, \
                 0.612% of pixels off: it accounts for 98.1% of the pixels that differ from the \
                 reference, so the same mistake, in part of its cases or with another \
                 difference beside it, is likely. \
                 \"My grid walk starts only"
            ),
            "{text}"
        );
        assert!(text.contains(" The pixels suggest too: "), "{text}");
        // Never taken for a match: the verdict and a merge keep it a guess.
        assert_eq!(fault_matches(&findings), Vec::<&FaultMatch>::new());
        assert_eq!(findings[0].json()["kind"], "near");
        assert_eq!(
            Finding::from_json(&findings[0].json()),
            Some(Finding::Near(near))
        );
    }

    #[test]
    fn a_guess_about_a_depth_or_normals_picture_speaks_of_that_picture() {
        let background = [Finding::Diagnosis(Diagnosis::BACKGROUND)];
        // The shaded picture's advice would send the student the wrong way here.
        let shaded = explain(&background, PictureKind::Image);
        assert!(
            shaded.contains("must take the scene's background colour"),
            "{shaded}"
        );
        for kind in [PictureKind::Depth, PictureKind::Normals] {
            let text = explain(&background, kind);
            assert!(
                text.contains("are black in the depth and normals pictures"),
                "{text}"
            );
            assert!(text.starts_with("No fault in raycast's library"), "{text}");
        }
        let curve = explain(&[Finding::Diagnosis(Diagnosis::GAMMA)], PictureKind::Depth);
        assert!(curve.contains("(TMAX - t) / (TMAX - TMIN)"), "{curve}");
        // Facts of the run read the same for every picture.
        let crash = explain(&[Finding::Diagnosis(Diagnosis::CRASH)], PictureKind::Depth);
        assert_eq!(crash, Diagnosis::CRASH.explanation());
    }
}
