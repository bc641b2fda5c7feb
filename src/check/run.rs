//! Running a renderer that is not trusted: in a folder of its own, with the scene files as
//! read-only copies, its images sent to a scratch folder, and a time limit.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A run: how it ended, the end of what the renderer said on stderr, and how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Ran {
    /// How it ended.
    pub ending: Ending,
    /// The last 64 KiB of its stderr.
    pub stderr: String,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ending {
    /// It exited with status 0.
    Success,
    /// It exited with another status, or was killed by a signal.
    Failed {
        /// The exit status; `None` for a signal.
        status: Option<i32>,
    },
    /// It outlasted the time limit and was killed.
    TimedOut(Duration),
    /// It could not be started at all.
    NotStarted(String),
}

/// Copies every file of `scenes` into `into`, read-only: the renderer may read them, not
/// change them, and never touches the suite itself.
pub fn copy_scenes(scenes: &Path, into: &Path) -> Result<(), String> {
    std::fs::create_dir_all(into).map_err(|e| format!("{}: {e}", into.display()))?;
    for entry in std::fs::read_dir(scenes).map_err(|e| format!("{}: {e}", scenes.display()))? {
        let entry = entry.map_err(|e| format!("{}: {e}", scenes.display()))?;
        let path = entry.path();
        if path.is_dir() {
            continue;
        }
        let target = into.join(entry.file_name());
        std::fs::copy(&path, &target).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut permissions = std::fs::metadata(&target)
            .map_err(|e| format!("{}: {e}", target.display()))?
            .permissions();
        permissions.set_readonly(true);
        std::fs::set_permissions(&target, permissions)
            .map_err(|e| format!("{}: {e}", target.display()))?;
    }
    Ok(())
}

/// A writable folder for one run, holding links to the read-only scene copies (so the
/// renderer may write files of its own beside them without touching the inputs).
pub fn work_folder(scenes: &Path, work: &Path) -> Result<(), String> {
    std::fs::create_dir_all(work).map_err(|e| format!("{}: {e}", work.display()))?;
    for entry in std::fs::read_dir(scenes).map_err(|e| format!("{}: {e}", scenes.display()))? {
        let entry = entry.map_err(|e| format!("{}: {e}", scenes.display()))?;
        let link = work.join(entry.file_name());
        std::os::unix::fs::symlink(entry.path(), &link)
            .map_err(|e| format!("{}: {e}", link.display()))?;
    }
    Ok(())
}

/// Runs `program` (its first word the executable, the rest its own arguments) with `args` in
/// `work`, for at most `limit`. The program runs in a process group of its own, so that a
/// time-out ends whatever it started too.
pub fn run(program: &[String], args: &[String], work: &Path, limit: Duration) -> Ran {
    let start = Instant::now();
    let (ending, stderr) = run_to_end(program, args, work, limit);
    Ran {
        ending,
        stderr,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The last this many bytes of a renderer's stderr are kept: its error message comes last.
const STDERR_TAIL: usize = 64 * 1024;

fn run_to_end(
    program: &[String],
    args: &[String],
    work: &Path,
    limit: Duration,
) -> (Ending, String) {
    use std::os::unix::process::CommandExt;
    let Some((executable, own)) = program.split_first() else {
        return (
            Ending::NotStarted("no renderer given".into()),
            String::new(),
        );
    };
    let child = Command::new(resolve(executable))
        .args(own)
        .args(args)
        .current_dir(work)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn();
    let mut child = match child {
        Ok(child) => child,
        Err(e) => {
            return (
                Ending::NotStarted(format!("{executable}: {e}")),
                String::new(),
            );
        }
    };
    // Read stderr as it comes, so a chatty renderer never blocks on a full pipe; kept where
    // the wait below can take what there is when the deadline comes, even if something the
    // renderer started still holds the pipe open.
    let tail = std::sync::Arc::new(std::sync::Mutex::new(Vec::<u8>::new()));
    let (ended, pipe_closed) = std::sync::mpsc::channel::<()>();
    if let Some(mut pipe) = child.stderr.take() {
        let tail = tail.clone();
        std::thread::spawn(move || {
            use std::io::Read;
            let mut chunk = [0u8; 8192];
            while let Ok(n) = pipe.read(&mut chunk) {
                if n == 0 {
                    break;
                }
                let Ok(mut tail) = tail.lock() else { break };
                tail.extend_from_slice(&chunk[..n]);
                if tail.len() > 2 * STDERR_TAIL {
                    let drop = tail.len() - STDERR_TAIL;
                    tail.drain(..drop);
                }
            }
            let _ = ended.send(());
        });
    }
    let said = || {
        let tail = tail.lock().map(|t| t.clone()).unwrap_or_default();
        let keep = tail.len().saturating_sub(STDERR_TAIL);
        String::from_utf8_lossy(&tail[keep..]).into_owned()
    };
    let start = Instant::now();
    let group = child.id();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() >= limit => break None,
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => return (Ending::NotStarted(e.to_string()), String::new()),
        }
    };
    // Whatever the renderer left running in its group ends with it, on time or not.
    kill_group(group);
    let Some(status) = status else {
        let _ = child.kill();
        let _ = child.wait();
        return (Ending::TimedOut(limit), String::new());
    };
    // One deadline for everything: stderr is read until its end or the line's time is up.
    let left = limit.saturating_sub(start.elapsed());
    let _ = pipe_closed.recv_timeout(left.max(Duration::from_millis(50)));
    let stderr = said();
    if status.success() {
        (Ending::Success, stderr)
    } else {
        (
            Ending::Failed {
                status: status.code(),
            },
            stderr,
        )
    }
}

/// Kills process group `group`: the renderer and anything it started that stayed in its
/// group. `--` before the group's negative id, which some `kill`s would otherwise read as an
/// option (and one reading of it, -1, is every process the user may signal).
fn kill_group(group: u32) {
    if group > 1 {
        let _ = Command::new("kill")
            .args(["-s", "KILL", "--", &format!("-{group}")])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }
}

/// A renderer named by a relative path (`./raytracer`) runs from the work folder, so it is made
/// absolute first; a bare name is looked up on the PATH as usual.
/// Whether the renderer's program can run at all: found (on `PATH` for a bare name), a file,
/// executable. Asked once before any line, so that a wrong path is one clear error, not a
/// crash on every line.
pub fn check_program(program: &[String]) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    let Some(executable) = program.first() else {
        return Err("--renderer is empty: which program should be graded?".into());
    };
    let path = if executable.contains('/') {
        resolve(executable)
    } else {
        let on_path = std::env::var_os("PATH")
            .map(|p| {
                std::env::split_paths(&p)
                    .map(|d| d.join(executable))
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default();
        match on_path.into_iter().find(|p| p.is_file()) {
            Some(found) => found,
            None => {
                return Err(format!(
                    "--renderer: '{executable}' is not a program on PATH (give its path, such \
                     as ./{executable})"
                ));
            }
        }
    };
    let metadata = std::fs::metadata(&path)
        .map_err(|e| format!("--renderer: '{}' cannot be run: {e}", path.display()))?;
    if !metadata.is_file() {
        return Err(format!("--renderer: '{}' is not a file", path.display()));
    }
    if metadata.permissions().mode() & 0o111 == 0 {
        return Err(format!(
            "--renderer: '{}' is not executable (chmod +x it, or name its interpreter: \
             --renderer \"python3 {}\")",
            path.display(),
            executable
        ));
    }
    Ok(())
}

fn resolve(executable: &str) -> PathBuf {
    let path = Path::new(executable);
    if path.components().count() > 1 && path.is_relative() {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    } else {
        path.to_path_buf()
    }
}
