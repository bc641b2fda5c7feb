//! A line's supervisor: raycast started as `raycast __supervise REQUEST`. It stays
//! single-threaded (so that the renderer's process can be prepared between fork and exec), puts
//! itself in a new network namespace where the kernel lets it, becomes the subreaper of
//! everything the renderer starts, runs the renderer confined, and reports how it ended on its
//! stdout, as one JSON object, once nothing the renderer started is left.

// Preparing the renderer between fork and exec (`pre_exec`) needs an unsafe block.
#![allow(unsafe_code)]

use std::os::fd::AsFd;
use std::os::unix::process::CommandExt;
use std::process::{Command, ExitCode, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rustix::process::{Pid, Signal, WaitOptions};

use super::{Confinement, Ending, Request, confine, reap};

/// The supervisor's whole life: `request` is the JSON check passed. Its report goes to stdout;
/// the renderer's stderr and stdout go to the supervisor's stderr.
pub fn supervise(request: &str) -> ExitCode {
    let (ending, cage) = match Request::from_json(request) {
        Ok(request) => run(&request),
        Err(why) => (Ending::NotStarted(why), Confinement::default()),
    };
    let report = serde_json::json!({ "ending": ending_json(&ending), "cage": cage.json() });
    println!("{report}");
    ExitCode::SUCCESS
}

fn run(request: &Request) -> (Ending, Confinement) {
    let parent = rustix::process::getppid();
    // Asked to stop (check interrupted) or hung up on: the renderer's tree ends first.
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGHUP,
    ] {
        let _ = signal_hook::flag::register(signal, stop.clone());
    }
    let mut cage = Confinement {
        user: match request.user {
            Some((uid, _)) => format!("uid {uid}"),
            None => "check's own user".to_string(),
        },
        ..Confinement::default()
    };
    cage.landlock = confine::landlock_state(request);
    let namespaces = confine::enter_namespaces();
    cage.network_namespace = namespaces.network;
    cage.subreaper = rustix::process::set_child_subreaper(Some(rustix::process::getpid())).is_ok();
    let Some((program, own)) = request.command.split_first() else {
        return (Ending::NotStarted("no renderer given".into()), cage);
    };
    let said = match std::io::stderr().as_fd().try_clone_to_owned() {
        Ok(fd) => Stdio::from(fd),
        Err(_) => Stdio::null(),
    };
    let mut command = Command::new(program);
    command
        .args(own)
        .current_dir(&request.work)
        .env_clear()
        .envs(confine::environment(request))
        .stdin(Stdio::null())
        .stdout(said)
        .stderr(Stdio::inherit());
    if let Some((uid, gid)) = request.user {
        command.uid(uid).gid(gid);
    }
    // The renderer's own process count: another user's, or a user namespace's.
    let counted = request.user.is_some() || namespaces.user;
    let prepare = confine::in_child(request, counted);
    // SAFETY: the closure runs in the forked child before exec. The supervisor is
    // single-threaded (signal-hook's handlers need no thread), so no lock is held by another
    // thread at the fork, and what the closure does (prctl, setrlimit, Landlock's system calls
    // and its small allocations) is safe there.
    unsafe {
        command.pre_exec(prepare);
    }
    let start = Instant::now();
    let child = match command.spawn() {
        Ok(child) => child,
        Err(e) => {
            return (Ending::NotStarted(format!("{program}: {e}")), cage);
        }
    };
    let renderer = Pid::from_raw(child.id() as i32);
    // The renderer's status is taken below with wait() (waitpid(-1): any child, whatever its
    // process group; rustix's waitpid(None) is waitpid(0), the caller's group only, which
    // missed setsid orphans), which also reaps the orphans the supervisor adopts; `child` is
    // never waited on.
    drop(child);
    let ending = loop {
        match rustix::process::wait(WaitOptions::NOHANG) {
            Ok(Some((pid, status))) if Some(pid) == renderer => {
                break match (status.exit_status(), status.terminating_signal()) {
                    (Some(0), _) => Ending::Success,
                    (Some(code), _) => Ending::Failed { status: code },
                    (None, Some(signal)) => Ending::Signaled { signal },
                    (None, None) => Ending::Failed { status: -1 },
                };
            }
            Ok(Some(_)) => continue,
            Ok(None) => {}
            Err(e) => break Ending::NotStarted(format!("its supervisor lost it: {e}")),
        }
        if stop.load(Ordering::Relaxed) || rustix::process::getppid() != parent {
            break Ending::Interrupted;
        }
        if start.elapsed() >= request.limit {
            break Ending::TimedOut(request.limit);
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    if let Some(renderer) = renderer {
        let _ = rustix::process::kill_process(renderer, Signal::KILL);
    }
    reap::end_descendants();
    (ending, cage)
}

fn ending_json(ending: &Ending) -> serde_json::Value {
    match ending {
        Ending::Success => serde_json::json!({ "exited": 0 }),
        Ending::Failed { status } => serde_json::json!({ "exited": status }),
        Ending::Signaled { signal } => serde_json::json!({ "signal": signal }),
        Ending::TimedOut(limit) => serde_json::json!({ "timed_out_ms": limit.as_millis() as u64 }),
        Ending::Interrupted => serde_json::json!({ "interrupted": true }),
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
