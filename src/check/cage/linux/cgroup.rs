//! A line's own control groups: its memory (`--memory`) and its number of processes counted over
//! all the line's processes together, not per process or per user. The supervisor makes them
//! beside its own groups and moves itself in before it forks the line's init, so the init, the
//! renderer and all they start are in them from their first instruction. Where the kernel does
//! not let check make them (an ordinary user without a delegated subtree, a container without
//! the controllers) the line runs without, under the per-process limits, and the report says
//! why.
//!
//! Two layouts: cgroup v2 (one hierarchy; `memory.max`, `pids.max`, `memory.events`), and v1's
//! separate `memory` and `pids` hierarchies (`memory.limit_in_bytes`, `pids.max`,
//! `memory.oom_control`), as a hybrid system mounts them.

use std::path::{Path, PathBuf};

use super::Limits;

const ROOT: &str = "/sys/fs/cgroup";

/// How the single-threaded supervisor moves itself between v1 groups: its own thread ("0" is the
/// writer) through `tasks`, which the kernel does without the lock on every thread group that
/// a move through `cgroup.procs` takes; that lock waits for an RCU grace period, about 10 ms a
/// move on a machine busy with the lines before (four moves a line). Its children are born in
/// the group of the thread that forks them.
const V1_MOVE: (&str, &str) = ("tasks", "0");

/// The line's groups, with the supervisor in them.
#[derive(Debug)]
pub struct LineGroup {
    /// Each group's folder and the folder of the group the supervisor came from.
    groups: Vec<(PathBuf, PathBuf)>,
    /// The file that counts the line's kills for memory, and whether it is v2's.
    memory_events: Option<(PathBuf, bool)>,
    /// Whether the groups are v2's (one hierarchy), not v1's.
    v2: bool,
}

/// Where this process's group of `controller` is (v1), or its one group (v2, `None`).
fn own_group(controller: Option<&str>) -> Option<PathBuf> {
    let text = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    text.lines().find_map(|line| {
        let mut fields = line.splitn(3, ':');
        let (_, controllers, path) = (fields.next()?, fields.next()?, fields.next()?);
        let path = path.trim_start_matches('/');
        match controller {
            None if controllers.is_empty() => Some(Path::new(ROOT).join(path)),
            Some(name) if controllers.split(',').any(|c| c == name) => {
                Some(Path::new(ROOT).join(name).join(path))
            }
            _ => None,
        }
    })
}

fn write(path: &Path, value: impl std::fmt::Display) -> Result<(), String> {
    std::fs::write(path, value.to_string()).map_err(|e| format!("{}: {e}", path.display()))
}

impl LineGroup {
    /// Makes the line's groups, sets `limits` on them (the process count with room for the
    /// supervisor and the init), and moves this process in.
    pub fn join(limits: &Limits) -> Result<LineGroup, String> {
        let me = std::process::id();
        let name = format!("raycast-line-{me}");
        let processes = limits.processes + 2;
        let pure_v2 = Path::new(ROOT).join("cgroup.controllers").is_file();
        let mut made = LineGroup {
            groups: Vec::new(),
            memory_events: None,
            v2: pure_v2,
        };
        let attempt = if pure_v2 {
            made.join_v2(&name, limits.memory, processes, me)
        } else {
            made.join_v1(&name, limits.memory, processes)
        };
        match attempt {
            Ok(()) => Ok(made),
            Err(why) => {
                made.leave();
                Err(why)
            }
        }
    }

    fn join_v2(&mut self, name: &str, memory: u64, processes: u64, me: u32) -> Result<(), String> {
        let parent = own_group(None).ok_or("no cgroup v2 group of its own")?;
        let group = parent.join(name);
        std::fs::create_dir(&group).map_err(|e| format!("{}: {e}", group.display()))?;
        self.groups.push((group.clone(), parent));
        write(&group.join("memory.max"), memory)?;
        write(&group.join("pids.max"), processes)?;
        write(&group.join("cgroup.procs"), me)?;
        self.memory_events = Some((group.join("memory.events"), true));
        Ok(())
    }

    fn join_v1(&mut self, name: &str, memory: u64, processes: u64) -> Result<(), String> {
        for (controller, limit_file, limit) in [
            ("memory", "memory.limit_in_bytes", memory),
            ("pids", "pids.max", processes),
        ] {
            let parent = own_group(Some(controller))
                .ok_or_else(|| format!("no cgroup v1 {controller} hierarchy"))?;
            let group = parent.join(name);
            std::fs::create_dir(&group).map_err(|e| format!("{}: {e}", group.display()))?;
            self.groups.push((group.clone(), parent));
            write(&group.join(limit_file), limit)?;
            write(&group.join(V1_MOVE.0), V1_MOVE.1)?;
        }
        let memory = &self.groups[0].0;
        // Swap counted too, where the kernel accounts for it.
        let _ = write(
            &memory.join("memory.memsw.limit_in_bytes"),
            memory_limit(memory),
        );
        self.memory_events = Some((memory.join("memory.oom_control"), false));
        Ok(())
    }

    /// Whether the kernel killed a process of the line for its memory.
    pub fn ran_out_of_memory(&self) -> bool {
        let Some((events, _)) = &self.memory_events else {
            return false;
        };
        // v2's memory.events and v1's memory.oom_control both say "oom_kill N".
        std::fs::read_to_string(events)
            .ok()
            .and_then(|text| {
                text.lines().find_map(|line| {
                    line.strip_prefix("oom_kill ")
                        .and_then(|n| n.trim().parse::<u64>().ok())
                })
            })
            .is_some_and(|kills| kills > 0)
    }

    /// Moves this process back where it came from, ends whatever is left in the groups, and
    /// removes them.
    pub fn leave(self) {
        let me = std::process::id();
        for (group, parent) in self.groups.iter().rev() {
            let _ = match self.v2 {
                true => write(&parent.join("cgroup.procs"), me),
                false => write(&parent.join(V1_MOVE.0), V1_MOVE.1),
            };
            for _ in 0..50 {
                let left: Vec<i32> = std::fs::read_to_string(group.join("cgroup.procs"))
                    .unwrap_or_default()
                    .lines()
                    .filter_map(|pid| pid.trim().parse().ok())
                    .collect();
                for pid in &left {
                    if let Some(pid) = rustix::process::Pid::from_raw(*pid) {
                        let _ = rustix::process::kill_process(pid, rustix::process::Signal::KILL);
                    }
                }
                if std::fs::remove_dir(group).is_ok() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
        }
    }
}

/// The memory limit set on a v1 group, for its swap limit (which may not be below it).
fn memory_limit(group: &Path) -> String {
    std::fs::read_to_string(group.join("memory.limit_in_bytes"))
        .map(|text| text.trim().to_string())
        .unwrap_or_default()
}
