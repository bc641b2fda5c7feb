//! A line's supervisor reports to check on its stdout, as one JSON object: how the renderer's
//! run ended and what confined it. One format for every system's supervisor.

use std::time::Duration;

use super::{Confinement, Ending};

/// A supervisor's whole life on Linux and macOS: `request` is the JSON check passed, `run`
/// runs it; the report goes to stdout, the renderer's stderr and stdout to the supervisor's
/// stderr.
#[cfg(unix)]
pub(super) fn serve(
    request: &str,
    run: impl FnOnce(&super::Request) -> (Ending, Confinement),
) -> std::process::ExitCode {
    let (ending, cage) = match super::Request::from_json(request) {
        Ok(request) => run(&request),
        Err(why) => (Ending::NotStarted(why), Confinement::default()),
    };
    write(&ending, &cage);
    std::process::ExitCode::SUCCESS
}

/// The report of a supervisor whose renderer ended as `ending`, caged by `cage`: one line.
pub(super) fn write(ending: &Ending, cage: &Confinement) {
    let report = serde_json::json!({ "ending": ending_json(ending), "cage": cage.json() });
    println!("{report}");
}

/// An ending as a supervisor's report writes it.
pub(super) fn ending_json(ending: &Ending) -> serde_json::Value {
    match ending {
        Ending::Success => serde_json::json!({ "exited": 0 }),
        Ending::Failed { status } => serde_json::json!({ "exited": status }),
        Ending::Signaled { signal } => serde_json::json!({ "signal": signal }),
        Ending::TimedOut(limit) => serde_json::json!({ "timed_out_ms": limit.as_millis() as u64 }),
        Ending::Interrupted => serde_json::json!({ "interrupted": true }),
        Ending::DeadlineCame => serde_json::json!({ "deadline_came": true }),
        Ending::OverBudget(budget) => {
            serde_json::json!({ "over_budget_ms": budget.as_millis() as u64 })
        }
        Ending::BudgetRanOut { budget, after } => serde_json::json!({
            "budget_ran_out_ms": budget.as_millis() as u64,
            "after_ms": after.as_millis() as u64,
        }),
        Ending::NotStarted(why) => serde_json::json!({ "not_started": why }),
    }
}

/// The ending a supervisor's report gives.
pub(super) fn ending_of(value: &serde_json::Value) -> Ending {
    if let Some(code) = value["exited"].as_i64() {
        return match code {
            0 => Ending::Success,
            _ => Ending::Failed {
                status: code as i32,
            },
        };
    }
    if let Some(signal) = value["signal"].as_i64() {
        return Ending::Signaled {
            signal: signal as i32,
        };
    }
    if let Some(ms) = value["timed_out_ms"].as_u64() {
        return Ending::TimedOut(Duration::from_millis(ms));
    }
    if value["interrupted"].as_bool() == Some(true) {
        return Ending::Interrupted;
    }
    if value["deadline_came"].as_bool() == Some(true) {
        return Ending::DeadlineCame;
    }
    if let Some(ms) = value["over_budget_ms"].as_u64() {
        return Ending::OverBudget(Duration::from_millis(ms));
    }
    if let Some(ms) = value["budget_ran_out_ms"].as_u64() {
        return Ending::BudgetRanOut {
            budget: Duration::from_millis(ms),
            after: Duration::from_millis(value["after_ms"].as_u64().unwrap_or(0)),
        };
    }
    Ending::NotStarted(
        value["not_started"]
            .as_str()
            .unwrap_or("its supervisor's report made no sense")
            .to_string(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_ending_reads_back_as_it_was_written() {
        for ending in [
            Ending::Success,
            Ending::Failed { status: 3 },
            Ending::Signaled { signal: 11 },
            Ending::TimedOut(Duration::from_millis(1500)),
            Ending::Interrupted,
            Ending::DeadlineCame,
            Ending::OverBudget(Duration::from_secs(90)),
            Ending::BudgetRanOut {
                budget: Duration::from_secs(90),
                after: Duration::from_millis(29_989),
            },
            Ending::NotStarted("no such file".into()),
        ] {
            assert_eq!(ending_of(&ending_json(&ending)), ending);
        }
    }
}
