//! `-stats`: the course's statistics block, and raycast's own time and size for each phase.

use std::io::Write;
use std::time::Duration;

use super::Options;
use crate::scene::{LoadStats, Scene};
use crate::trace::RayCounts;

/// How long each phase of a run took, and on how many threads.
pub struct PhaseTimes {
    /// Reading the scene and building its trees.
    pub load: LoadStats,
    /// The render.
    pub render: Duration,
    /// Encoding and writing the images.
    pub write: Duration,
    /// The threads the render ran on.
    pub threads: usize,
}

/// Writes a line, ignoring a reader that has gone (as `raycast ... -stats | head -1`).
fn say(mut to: impl Write, text: &str) {
    let _ = writeln!(to, "{text}");
}

/// The course's `RayTracingStats::PrintStatistics`, line for line: the render's time in whole
/// seconds (at least 1), the image, the scene's box and the grid, then the rays cast (camera,
/// mirror and glass rays are the course's "non-shadow" rays), the primitives tested and the grid
/// cells entered, and their rates.
pub fn print_course_statistics(
    to: impl Write,
    options: &Options,
    scene: &Scene,
    rays: &RayCounts,
    render_time: Duration,
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

/// raycast's own figures, on stderr: each phase's time, the rays, what the scene holds and the
/// memory its geometry and trees take.
pub fn print_phase_times(to: impl Write, times: &PhaseTimes, rays: &RayCounts) {
    let PhaseTimes {
        load,
        render,
        write,
        threads,
    } = times;
    let w = &load.world;
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let mb = |bytes: usize| bytes as f64 / (1 << 20) as f64;
    let plural = |n: usize, one: &'static str, many: &'static str| if n == 1 { one } else { many };
    let all = rays.primary + rays.secondary + rays.shadow;
    // Under -grid the rays search the course's grid: the phase and the memory name it.
    let (structure, trees) = match w.grid_cells {
        Some([x, y, z]) => (
            "grid",
            format!("grid of {x}x{y}x{z} cells; {} BVH nodes", w.nodes),
        ),
        None => ("BVH ", format!("{} BVH nodes", w.nodes)),
    };
    let text = format!(
        "raycast: parse and load  {:9.2} ms
raycast: build {structure}      {:9.2} ms
raycast: render          {:9.2} ms  ({all} rays on {threads} thread{}, {:.2} M rays/s, {} kernels)
raycast: rays: {} primary, {} reflected or refracted, {} shadow
raycast: write images    {:9.2} ms
raycast: scene: {} triangles stored ({} placed) in {} mesh{}, {} instance{}, {} sphere{}, {} plane{}
raycast: memory: geometry {:.2} MiB, acceleration {:.2} MiB ({trees})",
        ms(load.parse),
        ms(load.build),
        ms(*render),
        plural(*threads, "", "s"),
        all as f64 / render.as_secs_f64() / 1e6,
        crate::simd::Path::chosen().name(),
        rays.primary,
        rays.secondary,
        rays.shadow,
        ms(*write),
        w.triangles,
        w.triangles_placed,
        w.meshes,
        plural(w.meshes, "", "es"),
        w.instances,
        plural(w.instances, "", "s"),
        w.spheres,
        plural(w.spheres, "", "s"),
        w.planes,
        plural(w.planes, "", "s"),
        mb(w.geometry_bytes),
        mb(w.acceleration_bytes),
    );
    // Not eprintln!: a closed or full stderr must not turn into a panic (exit status 101).
    say(to, &text);
}
