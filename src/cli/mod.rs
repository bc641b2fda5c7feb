//! The program: the course's command line (`raycast -input scene.txt -size 200 200 -output
//! out.tga ...`, every option of assignments 1 to 7, and raycast's own), the run it asks for,
//! the exit statuses, and `raycast completions SHELL`.

mod check;
mod class;
mod completions;
#[cfg(windows)]
mod console_close;
mod grades;
mod progress;
mod words;

use std::ffi::OsString;
use std::io::{IsTerminal, Read, Write};
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use crate::job::{Command, Options, parse_args, usage};

use crate::check::faults::{LineScene, Plant, plant_for};
use crate::error::Error;
use crate::job::{is_stdio, render_to_files, reserve_outputs, same_file, stats};
use crate::scene::{LoadStats, Loaded, Scene};

/// Runs the program on its arguments (without the program name); returns the exit status:
/// 0 done, 1 the scene or a file is at fault, 2 the command line is.
pub fn run(args: Vec<OsString>) -> ExitCode {
    if let Err(message) = crate::simd::Path::requested() {
        say(std::io::stderr(), &format!("raycast: {message}"));
        return ExitCode::from(2);
    }
    match args.first().and_then(|a| a.to_str()) {
        Some("check") => return check::run_check(args[1..].to_vec()),
        // A line's supervisor, started by check: not an option a user gives.
        Some(crate::check::SUPERVISE) => {
            let request = args.get(1).map(|a| a.to_string_lossy().into_owned());
            return crate::check::supervise(&request.unwrap_or_default());
        }
        Some("diff") => return check::run_diff(args[1..].to_vec()),
        _ => {}
    }
    if args.first().is_some_and(|a| a == "completions") {
        return match args.get(1).and_then(|a| a.to_str()) {
            Some(shell) if args.len() == 2 => match completions::script(shell) {
                Some(script) => {
                    say(std::io::stdout(), &script);
                    ExitCode::SUCCESS
                }
                None => refuse(&format!(
                    "completions: unknown shell '{shell}': bash, zsh, fish or powershell"
                )),
            },
            _ => refuse("completions needs one shell: bash, zsh, fish or powershell"),
        };
    }
    match parse_args(args) {
        Ok(Command::Help) => {
            say(std::io::stdout(), &usage());
            ExitCode::SUCCESS
        }
        Ok(Command::Version) => {
            let version = concat!(
                "raycast ",
                env!("CARGO_PKG_VERSION"),
                " (",
                env!("RAYCAST_COMMIT"),
                ")"
            );
            say(std::io::stdout(), version);
            ExitCode::SUCCESS
        }
        Ok(Command::Render(options)) => {
            let preview = &options.preview;
            if !preview.gui && (preview.port.is_some() || preview.no_browser) {
                return refuse("-port and -no-browser serve -gui's preview: add -gui");
            }
            let live = preview.gui && (preview.port.is_some() || std::io::stdin().is_terminal());
            if preview.gui && !live {
                say(
                    std::io::stderr(),
                    "raycast: -gui: standard input is not a terminal, so no preview is served \
                     (add -port N to serve one); the images are written as without -gui",
                );
            }
            if live && options.outputs().iter().any(|(_, path)| is_stdio(path)) {
                return refuse(
                    "-gui prints the preview's address on standard output: write the images to \
                     files, not -",
                );
            }
            let result = if live {
                crate::preview::serve(&options, &mut std::io::stdout(), || execute(&options))
            } else {
                execute(&options)
            };
            match result {
                Ok(()) => ExitCode::SUCCESS,
                Err(error) => {
                    say(std::io::stderr(), &error.to_string());
                    ExitCode::from(1)
                }
            }
        }
        Err(message) => refuse(&message),
    }
}

/// A command line that cannot be run: the message and where the usage is, on stderr, exit
/// status 2.
fn refuse(message: &str) -> ExitCode {
    refuse_with_hint(message, "raycast -help")
}

/// The message, then one line naming the help to read (as cargo and git do: the whole usage
/// would scroll the message away), exit status 2.
pub(crate) fn refuse_with_hint(message: &str, help: &str) -> ExitCode {
    say(
        std::io::stderr(),
        &format!("raycast: {message}\nhint: '{help}' lists every option"),
    );
    ExitCode::from(2)
}

/// Writes a line, unlike `println!` without panicking (exit status 101) when the reader has
/// gone, as in `raycast -help | head -1`: the exit status must stay the one documented.
fn say(mut to: impl Write, text: &str) {
    let _ = writeln!(to, "{text}");
}

/// Runs the whole job (loading and tree building too, not only the render) on `-threads` threads.
fn execute(options: &Options) -> Result<(), Error> {
    match options.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| Error::Refused(format!("raycast: cannot start {n} threads: {e}")))?
            .install(|| execute_on_current_pool(options)),
        None => execute_on_current_pool(options),
    }
}

fn execute_on_current_pool(options: &Options) -> Result<(), Error> {
    let outputs = options.outputs();
    // Before any work: a folder that is missing or unwritable fails the run now.
    let pending = reserve_outputs(options)?;
    let Loaded {
        mut scene,
        stats: mut load,
    } = load_scene(&options.input)?;
    if let Some(pixel) = options.inspect {
        print_account(options, &scene, pixel);
    }
    if outputs.is_empty() {
        return Ok(());
    }
    refuse_to_overwrite_meshes(&outputs, &load)?;
    if let Some([nx, ny, nz]) = options.grid {
        let start = Instant::now();
        scene
            .world
            .use_grid(glam::UVec3::new(nx, ny, nz))
            .map_err(|e| Error::Refused(format!("{}: {e}", options.input.display())))?;
        load.build += start.elapsed();
        load.world = scene.world.stats();
    }
    let written = match (&options.fault, &options.choose) {
        (None, None) => render_to_files(options, &scene, crate::render::Exact, pending)?,
        (fault, choose) => {
            let description = if is_stdio(&options.input) {
                return Err(Error::Refused(
                    "raycast: -fault and -choose need the scene from a file, not standard input"
                        .into(),
                ));
            } else {
                crate::parse::read_scene(&options.input)?
            };
            let line = LineScene {
                options: options.clone(),
                description,
                scene,
            };
            let refused = |e: String| Error::Refused(format!("raycast: {e}"));
            let planted = fault
                .as_deref()
                .map(|spec| plant_for(spec, &line))
                .transpose()
                .map_err(refused)?
                .flatten();
            let chosen = choose
                .as_deref()
                .map(|name| crate::check::choices::planted_for(name, &line))
                .transpose()
                .map_err(refused)?
                .flatten();
            let plant = match (planted, chosen) {
                (Some(plant), Some(answer)) => Some(Plant::two(plant.first(), answer)),
                (Some(plant), None) => Some(plant),
                (None, Some(answer)) => Some(Plant::one(answer)),
                (None, None) => None,
            };
            scene = line.scene;
            match plant {
                Some(plant) => render_to_files(options, &scene, plant, pending)?,
                None => render_to_files(options, &scene, crate::render::Exact, pending)?,
            }
        }
    };
    let times = stats::PhaseTimes {
        load,
        render: written.render,
        write: written.write,
        threads: rayon::current_num_threads(),
    };
    if options.stats {
        // Beside an image on standard output, the course's block goes to stderr.
        if options.writes_to_stdout() {
            stats::print_course_statistics(
                std::io::stderr(),
                options,
                &scene,
                &written.rays,
                written.render,
            );
        } else {
            stats::print_course_statistics(
                std::io::stdout(),
                options,
                &scene,
                &written.rays,
                written.render,
            );
        }
        stats::print_phase_times(std::io::stderr(), &times, &written.rays);
    }
    Ok(())
}

/// `-inspect X Y`: the pixel's account, as text or JSON.
fn print_account(options: &Options, scene: &Scene, pixel: (u32, u32)) {
    let account =
        crate::inspect::inspect(scene, options.trace, (options.width, options.height), pixel);
    let text = if options.json {
        serde_json::to_string_pretty(&account).unwrap_or_default()
    } else {
        crate::inspect::to_text(&account)
    };
    // Beside an image on standard output, the account goes to stderr.
    if options.writes_to_stdout() {
        say(std::io::stderr(), text.trim_end());
    } else {
        say(std::io::stdout(), text.trim_end());
    }
}

/// An output that names a mesh the scene reads would destroy the user's data.
fn refuse_to_overwrite_meshes(
    outputs: &[(&'static str, &Path)],
    load: &LoadStats,
) -> Result<(), Error> {
    for &(flag, path) in outputs {
        if let Some(mesh) = load.mesh_files.iter().find(|m| same_file(path, m)) {
            return Err(Error::Refused(format!(
                "raycast: {flag} '{}' would overwrite the mesh file '{}' that the scene reads",
                path.display(),
                mesh.display()
            )));
        }
    }
    Ok(())
}

/// Reads the scene from its file, or from standard input for `-`.
fn load_scene(input: &Path) -> Result<Loaded, Error> {
    if !is_stdio(input) {
        return Scene::load_with_stats(input);
    }
    let start = Instant::now();
    let name = Path::new("<stdin>");
    let mut bytes = Vec::new();
    std::io::stdin()
        .read_to_end(&mut bytes)
        .map_err(|source| Error::Read {
            path: name.to_path_buf(),
            source,
        })?;
    let description = crate::parse::parse_scene_bytes(name, &bytes)?;
    let mut loaded = Scene::from_description_with_stats(&description)?;
    let stats = &mut loaded.stats;
    stats.parse += start.elapsed() - stats.parse - stats.build;
    Ok(loaded)
}
