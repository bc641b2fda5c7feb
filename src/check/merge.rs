//! Joining the reports of one renderer's shards (`--shard K/N` over the suite's lines) into the
//! report one run makes: each picture read back from its shard's `summary.json`, its findings
//! put back in the order simulation found them, its pictures copied, and the verdict made anew
//! over all of them.

use std::path::{Path, PathBuf};

use super::vary::{VARIED_FOLDER, Variation};
use serde_json::Value;

use super::{
    Checked, Confinement, Finding, Graded, Group, PictureKind, Pictures, Rule, Staging, Status,
    WorstPixel, finding, renderer_verdict, unique_names,
};

/// A picture as its shard's `summary.json` wrote it; its findings in simulation's order.
fn graded_of(value: &Value) -> Option<Graded> {
    let status = match value["status"].as_str()? {
        "pass" => Status::Pass,
        "fail" => Status::Fail,
        _ => Status::Error,
    };
    let mut findings = value["diagnoses"]
        .as_array()?
        .iter()
        .map(Finding::from_json)
        .collect::<Option<Vec<_>>>()?;
    let picture = PictureKind::of_option(value["picture"].as_str()?)?;
    let mut explanation = value["explanation"].as_str()?.to_string();
    let moved_from = value["verdict_moved_from"].as_u64().map(|k| k as usize);
    if let Some(k) = moved_from.filter(|&k| k < findings.len()) {
        let first = findings.remove(0);
        findings.insert(k, first);
        explanation = finding::explain(&findings, picture);
    }
    let name = value["name"].as_str()?;
    let file = |kind: &str| value["pictures"][kind].as_str().map(String::from);
    Some(Graded {
        // The `#2` of a repeated name is the merged run's to give.
        name: name.split('#').next().unwrap_or(name).to_string(),
        command: value["command"].as_str()?.to_string(),
        status,
        bad_fraction: value["bad_fraction"].as_f64(),
        findings,
        explanation,
        actual: None,
        reference: None,
        stderr: value["stderr"].as_str()?.to_string(),
        seconds: value["seconds"].as_f64()?,
        against_raycast: value["reference"] == "raycast" || value["reference"] == "raycast_seeds",
        by_chance: value["reference"] == "raycast_seeds",
        picture,
        worst_pixel: value["worst_pixel"].as_object().and_then(|w| {
            Some(WorstPixel {
                x: w.get("x")?.as_u64()? as u32,
                y: w.get("y")?.as_u64()? as u32,
                difference: w.get("difference")?.as_u64()? as u8,
                ray_tree: w.get("ray_tree")?.as_str()?.to_string(),
            })
        }),
        pictures: Pictures {
            actual: file("actual"),
            reference: file("reference"),
            diff: file("diff"),
        },
        points: value["points"].as_f64()?,
        line: (
            value["line"].as_u64()? as usize,
            value["output"].as_u64()? as usize,
        ),
        moved_from: None,
        located: super::Located::from_json(&value["where"]),
        accepted: super::choices::Acceptance::from_json(&value["accepted"]),
    })
}

/// Reads the shards in `shards`, copies their pictures into `staging`, and makes the report's
/// contents: every picture in the suite's order, the verdict over all of them, the rule.
pub fn merge(staging: Staging, shards: &[PathBuf]) -> Result<(Checked, Vec<Group>, Rule), String> {
    let mut graded: Vec<Graded> = Vec::new();
    let mut rule: Option<Rule> = None;
    let (mut partial, mut confinement, mut cage_note) = (false, None, None);
    let mut seconds = 0.0;
    let mut no_cage = false;
    let mut variation: Option<Variation> = None;
    for (k, shard) in shards.iter().enumerate() {
        let summary: Value = std::fs::read_to_string(shard.join("summary.json"))
            .ok()
            .and_then(|text| serde_json::from_str(&text).ok())
            .ok_or_else(|| format!("{}: no report of raycast check there", shard.display()))?;
        let shard_rule = Rule {
            tolerance: summary["rule"]["tolerance"].as_u64().unwrap_or(2) as u8,
            max_bad: summary["rule"]["max_bad"].as_f64().unwrap_or(0.001),
        };
        if rule.is_some_and(|r| r != shard_rule) {
            return Err(format!(
                "{}: graded by another rule than the shards before it",
                shard.display()
            ));
        }
        rule = Some(shard_rule);
        let shard_variation = Variation::from_json(&summary["varied"]);
        if k == 0 {
            if let Some(varied) = &shard_variation {
                varied.copy_scenes(&shard.join(VARIED_FOLDER), staging.path())?;
            }
            variation = shard_variation;
        } else if variation.as_ref().map(|v| v.seed) != shard_variation.map(|v| v.seed) {
            return Err(format!(
                "{}: graded on other scenes (--vary) than the shards before it",
                shard.display()
            ));
        }
        partial |= summary["partial"] == true;
        no_cage |= summary["cage"]["no_cage"] == true;
        // Shards ran one after another or on other machines: their times add up.
        seconds += summary["seconds"].as_f64().unwrap_or(0.0);
        if confinement.is_none() {
            confinement = Confinement::from_json(&summary["cage"]);
            cage_note = summary["cage"]["note"].as_str().map(String::from);
        }
        for image in summary["images"].as_array().into_iter().flatten() {
            let g = graded_of(image).ok_or_else(|| {
                format!(
                    "{}: a picture this raycast cannot read back (made by another version?)",
                    shard.display()
                )
            })?;
            if graded.iter().any(|other| other.line == g.line) {
                return Err(format!(
                    "line {} is in two shards ({} is one): were they made with the same suite?",
                    g.line.0 + 1,
                    shard.display()
                ));
            }
            for file in [&g.pictures.actual, &g.pictures.reference, &g.pictures.diff]
                .into_iter()
                .flatten()
            {
                std::fs::copy(shard.join(file), staging.path().join(file))
                    .map_err(|e| format!("{}: {e}", shard.join(file).display()))?;
            }
            graded.push(g);
        }
    }
    graded.sort_by_key(|g| g.line);
    unique_names(&mut graded);
    let groups = renderer_verdict(&mut graded);
    let checked = Checked {
        graded,
        confinement,
        cage_note,
        cleanup: None,
        no_cage,
        partial,
        staging: Some(staging),
        build: None,
        seconds,
        variation,
    };
    Ok((checked, groups, rule.unwrap_or(Rule::COURSE)))
}

/// Whether `dir` holds the report of a class (`--class`), rather than of one renderer.
pub fn is_class(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<Value>(&text).ok())
        .is_some_and(|summary| summary["class"] == true)
}
