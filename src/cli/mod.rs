//! The program: the course's command line (`raycast -input scene.txt -size 200 200 -output
//! out.tga ...`, every option of assignments 1 to 7, and raycast's own), the run it asks for,
//! the exit statuses, and `raycast completions SHELL`.

mod check;
mod completions;
mod options;

use std::ffi::OsString;
use std::io::{IsTerminal, Read, Write};
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

pub use options::{
    Command, Group, MAX_FILM_SAMPLES, MAX_FILTER_REACH, MAX_SAMPLES, MAX_THREADS, OPTIONS,
    OptionSpec, Options, is_stdio, parse_args, usage,
};

use crate::error::Error;
use crate::image_io::{self, PendingOutputs};
use crate::render::{RenderSettings, render};
use crate::sample;
use crate::scene::Scene;
use options::same_file;

/// Runs the program on its arguments (without the program name); returns the exit status:
/// 0 done, 1 the scene or a file is at fault, 2 the command line is.
pub fn run(args: Vec<OsString>) -> ExitCode {
    match args.first().and_then(|a| a.to_str()) {
        Some("check") => return check::run_check(args[1..].to_vec()),
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
                    "completions: unknown shell '{shell}': bash, zsh or fish"
                )),
            },
            _ => refuse("completions needs one shell: bash, zsh or fish"),
        };
    }
    match parse_args(args) {
        Ok(Command::Help) => {
            say(std::io::stdout(), &usage());
            ExitCode::SUCCESS
        }
        Ok(Command::Version) => {
            let version = concat!("raycast ", env!("CARGO_PKG_VERSION"));
            say(std::io::stdout(), version);
            ExitCode::SUCCESS
        }
        Ok(Command::Render(options)) => {
            if options.preview {
                say(
                    std::io::stderr(),
                    "raycast: -gui, -tessellation and -gouraud drive the course's OpenGL preview, \
                     which raycast does not have; they are ignored (the image is the same)",
                );
            }
            match execute(&options) {
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

/// A command line that cannot be run: the message and the usage on stderr, exit status 2.
fn refuse(message: &str) -> ExitCode {
    say(
        std::io::stderr(),
        &format!("raycast: {message}\n\n{}", usage()),
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
    let paths: Vec<&Path> = outputs.iter().map(|&(_, p)| p).collect();
    let files: Vec<&Path> = paths.iter().copied().filter(|p| !is_stdio(p)).collect();
    // Before any work: a folder that is missing or unwritable fails the run now.
    let pending = PendingOutputs::reserve(&files)?;

    let (mut scene, mut load) = load_scene(&options.input)?;
    if let Some(pixel) = options.inspect {
        let account = crate::inspect::inspect(
            &scene,
            options.trace,
            (options.width, options.height),
            pixel,
        );
        let text = if options.json {
            serde_json::to_string_pretty(&account).unwrap_or_default()
        } else {
            crate::inspect::to_text(&account)
        };
        // Beside an image on standard output, the account goes to stderr.
        if paths.iter().any(|p| is_stdio(p)) {
            say(std::io::stderr(), text.trim_end());
        } else {
            say(std::io::stdout(), text.trim_end());
        }
    }
    if outputs.is_empty() {
        return Ok(());
    }
    for &(flag, path) in &outputs {
        if let Some(mesh) = load.mesh_files.iter().find(|m| same_file(path, m)) {
            return Err(Error::Refused(format!(
                "raycast: {flag} '{}' would overwrite the mesh file '{}' that the scene reads",
                path.display(),
                mesh.display()
            )));
        }
    }
    if let Some([nx, ny, nz]) = options.grid {
        let start = Instant::now();
        scene
            .world
            .use_grid(glam::UVec3::new(nx, ny, nz))
            .map_err(|e| Error::Refused(format!("{}: {e}", options.input.display())))?;
        load.build += start.elapsed();
    }

    let settings = RenderSettings {
        width: options.width,
        height: options.height,
        // The samples picture shows the samples' colours.
        colour: options.output.is_some() || options.render_samples.is_some(),
        normals: options.normals.is_some(),
        depth: options.depth.as_ref().map(|&(near, far, _)| (near, far)),
        trace: options.trace,
        sampling: options.sampling,
        keep_film: options.render_samples.is_some(),
        progress: std::io::stderr().is_terminal(),
    };
    // Only the filter picture asked for: nothing to trace.
    let traced = options.output.is_some()
        || options.normals.is_some()
        || options.depth.is_some()
        || options.render_samples.is_some();
    let render_start = Instant::now();
    let mut rendered = if traced {
        render(&scene, &settings)
    } else {
        crate::render::Rendered::default()
    };
    let threads = rayon::current_num_threads();
    let render_time = render_start.elapsed();

    let write_start = Instant::now();
    let samples_picture = options.render_samples.as_ref().map(|&(_, zoom)| {
        let film = rendered.film.take().expect("kept for -render_samples");
        sample::render_samples_picture(&film, zoom)
    });
    let filter_picture = options.render_filter.as_ref().map(|&(_, zoom)| {
        sample::render_filter_picture(options.width, options.height, options.sampling.filter, zoom)
    });
    if options.output.is_none() {
        rendered.colour = None;
    }
    let images = [
        &rendered.colour,
        &rendered.normals,
        &rendered.depth,
        &samples_picture,
        &filter_picture,
    ];
    let mut contents = Vec::new();
    let mut to_stdout = None;
    for (image, path) in images.into_iter().flatten().zip(&paths) {
        let format = options
            .format_of(path)
            .expect("checked when parsing the command line");
        let encoded = image_io::encode_parts(image, format);
        if is_stdio(path) {
            to_stdout = Some(encoded);
        } else {
            contents.push(encoded);
        }
    }
    pending.commit(&contents)?;
    if let Some(encoded) = to_stdout {
        let mut out = std::io::stdout().lock();
        encoded
            .write_to(&mut out)
            .and_then(|()| out.flush())
            .map_err(|e| Error::Write {
                path: "standard output".into(),
                message: e.to_string(),
            })?;
    }
    let write_time = write_start.elapsed();

    if options.stats {
        // Beside an image on standard output, the course's block goes to stderr.
        if paths.iter().any(|p| is_stdio(p)) {
            print_course_statistics(
                std::io::stderr(),
                options,
                &scene,
                &rendered.rays,
                render_time,
            );
        } else {
            print_course_statistics(
                std::io::stdout(),
                options,
                &scene,
                &rendered.rays,
                render_time,
            );
        }
        let w = load.world;
        let rays = rendered.rays;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let mb = |bytes: usize| bytes as f64 / (1 << 20) as f64;
        // Not eprintln!: a closed or full stderr must not turn into a panic (exit status 101).
        let mut err = std::io::stderr().lock();
        let _ = writeln!(err, "raycast: parse and load  {:9.2} ms", ms(load.parse));
        let _ = writeln!(err, "raycast: build BVH       {:9.2} ms", ms(load.build));
        let _ = writeln!(
            err,
            "raycast: render          {:9.2} ms  ({} rays on {threads} thread{}, {:.2} M rays/s)",
            ms(render_time),
            rays.primary + rays.secondary + rays.shadow,
            if threads == 1 { "" } else { "s" },
            (rays.primary + rays.secondary + rays.shadow) as f64 / render_time.as_secs_f64() / 1e6
        );
        let _ = writeln!(
            err,
            "raycast: rays: {} primary, {} reflected or refracted, {} shadow",
            rays.primary, rays.secondary, rays.shadow
        );
        let _ = writeln!(err, "raycast: write images    {:9.2} ms", ms(write_time));
        let _ = writeln!(
            err,
            "raycast: scene: {} triangles stored ({} placed) in {} mesh{}, {} instance{}, {} sphere{}, {} plane{}",
            w.triangles,
            w.triangles_placed,
            w.meshes,
            if w.meshes == 1 { "" } else { "es" },
            w.instances,
            if w.instances == 1 { "" } else { "s" },
            w.spheres,
            if w.spheres == 1 { "" } else { "s" },
            w.planes,
            if w.planes == 1 { "" } else { "s" },
        );
        let _ = writeln!(
            err,
            "raycast: memory: geometry {:.2} MiB, acceleration {:.2} MiB ({} BVH nodes)",
            mb(w.geometry_bytes),
            mb(w.acceleration_bytes),
            w.nodes
        );
    }
    Ok(())
}

/// The course's `RayTracingStats::PrintStatistics`, line for line: the render's time in whole
/// seconds (at least 1), the image, the scene's box and the grid, then the rays cast (camera,
/// mirror and glass rays are the course's "non-shadow" rays), the primitives tested and the grid
/// cells entered, and their rates.
fn print_course_statistics(
    to: impl Write,
    options: &Options,
    scene: &Scene,
    rays: &crate::trace::RayCounts,
    render_time: std::time::Duration,
) {
    let seconds = render_time.as_secs().max(1);
    let non_shadow = rays.primary + rays.secondary;
    let all = non_shadow + rays.shadow;
    let pixels = u64::from(options.width) * u64::from(options.height);
    // As the course's floats: no rays at all give nan.
    let per = |count: u64, of: u64| count as f32 / of as f32;
    let bounds = match scene.world.bounds() {
        Some(b) => format!(
            "{:.6} {:.6} {:.6}  -> {:.6} {:.6} {:.6}",
            b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
        ),
        None => "NULL".to_string(),
    };
    let cells = match options.grid {
        Some([x, y, z]) => format!(
            "{} ({x}x{y}x{z})",
            u64::from(x) * u64::from(y) * u64::from(z)
        ),
        None => "NULL".to_string(),
    };
    let stars = "*".repeat(44);
    let text = format!(
        "{stars}
RAY TRACING STATISTICS
  total time                 {}:{:02}:{:02}
  num pixels                 {pixels} ({}x{})
  scene bounds               {bounds}
  num grid cells             {cells}
  num non-shadow rays        {non_shadow}
  num shadow rays            {}
  total intersections        {}
  total cells traversed      {}
  rays per second            {:.1}
  rays per pixel             {:.1}
  intersections per ray      {:.1}
  cells traversed per ray    {:.1}
{stars}",
        seconds / 3600,
        (seconds / 60) % 60,
        seconds % 60,
        options.width,
        options.height,
        rays.shadow,
        rays.tallies.intersections,
        rays.tallies.cells,
        per(all, seconds),
        per(all, pixels),
        per(rays.tallies.intersections, all),
        per(rays.tallies.cells, all),
    );
    say(to, &text);
}

/// Reads the scene from its file, or from standard input for `-`.
fn load_scene(input: &Path) -> Result<(Scene, crate::scene::LoadStats), Error> {
    if !is_stdio(input) {
        return Scene::load(input);
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
    let (scene, mut load) = Scene::from_description(&description)?;
    load.parse += start.elapsed() - load.parse - load.build;
    Ok((scene, load))
}
