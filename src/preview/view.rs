//! The view the page shows, traced by raycast itself: 'r' renders it as the command line would
//! (every option of the line, the camera where the mouse left it) and writes the line's images;
//! 't' traces one pixel's ray tree, as `-inspect X Y -json` prints it.

use std::path::Path;

use std::ops::ControlFlow;

use serde_json::{Value, json};

use crate::error::Error;
use crate::geometry::Ray;
use crate::image_io::{self, ImageFormat};
use crate::job::stats::print_course_statistics;
use crate::job::{Options, render_pictures_counted, reserve_outputs, write_pictures};
use crate::parse::description::{CameraSpec, Projection};
use crate::parse::parse_camera;
use crate::render::{Exact, RenderCounter};
use crate::scene::Scene;
use crate::trace::{clearance, grid_palette, shadow_end, start_t};

/// A camera in the scene file's syntax (as `GET /api/camera` gives it), read as the scene
/// parser reads one.
pub fn camera_of(text: &str) -> Result<CameraSpec, Error> {
    Ok(parse_camera(Path::new("the page's camera"), text)?)
}

/// `camera` in the scene file's syntax, its numbers as Rust writes them (each reads back as
/// the same f32).
pub fn camera_text(camera: &CameraSpec) -> String {
    let triple = |v: glam::Vec3| format!("{} {} {}", v.x, v.y, v.z);
    let (kind, last) = match camera.projection {
        Projection::Orthographic { size } => ("OrthographicCamera", format!("size {size}")),
        Projection::Perspective { angle } => ("PerspectiveCamera", format!("angle {angle}")),
    };
    format!(
        "{kind} {{\n    center {}\n    direction {}\n    up {}\n    {last}\n}}\n",
        triple(camera.center),
        triple(camera.direction),
        triple(camera.up)
    )
}

/// The line's scene as the page sees it: with `camera` (the scene file's syntax) in place of
/// the file's, and the line's grid.
pub fn scene_at(options: &Options, camera: Option<&str>) -> Result<Scene, Error> {
    let mut description = crate::parse::read_scene(&options.input)?;
    if let Some(camera) = camera {
        description.camera = camera_of(camera)?;
    }
    let mut scene = Scene::from_description(&description)?;
    if let Some([nx, ny, nz]) = options.grid {
        scene
            .world
            .use_grid(glam::UVec3::new(nx, ny, nz))
            .map_err(|e| Error::Refused(format!("{}: {e}", options.input.display())))?;
    }
    Ok(scene)
}

/// What 'r' made: the first picture of the line as PNG (for the page), how long it took, and
/// the course's statistics when the line asks for them.
pub struct Rendered {
    /// The line's first picture (the image, or else the normals or the depth), as PNG.
    pub png: Vec<u8>,
    /// Seconds from reading the scene to the files in place.
    pub seconds: f64,
    /// The course's `-stats` block, as the command line prints it, with `-stats`.
    pub stats: Option<String>,
}

/// 'r': renders the line with `camera` and writes its images as the command line would; the
/// render's progress goes to `counter`.
pub fn render_view(
    options: &Options,
    camera: Option<&str>,
    counter: Option<&'static RenderCounter>,
) -> Result<Rendered, Error> {
    let start = std::time::Instant::now();
    let pending = reserve_outputs(options)?;
    let scene = scene_at(options, camera)?;
    let render_start = std::time::Instant::now();
    let rendered = render_pictures_counted(options, &scene, Exact, counter);
    let stats = options.stats.then(|| {
        let mut text = Vec::new();
        print_course_statistics(
            &mut text,
            options,
            &scene,
            &rendered.rays,
            render_start.elapsed(),
        );
        String::from_utf8_lossy(&text).into_owned()
    });
    let pictures = rendered.pictures;
    let png = pictures
        .first()
        .map(|p| image_io::encode(p, ImageFormat::Png))
        .unwrap_or_default();
    write_pictures(options, pictures, pending)?;
    Ok(Rendered {
        png,
        seconds: start.elapsed().as_secs_f64(),
        stats,
    })
}

/// 't': pixel (x, y) of the view with `camera` (counted as `-inspect` counts them, from the
/// lower left), as `-inspect X Y -json` prints it, or as its text when `text`.
pub fn ray_tree(
    options: &Options,
    camera: Option<&str>,
    (x, y): (u32, u32),
    text: bool,
) -> Result<String, Error> {
    if x >= options.width || y >= options.height {
        return Err(Error::Refused(format!(
            "pixel ({x}, {y}) is outside the {}x{} image",
            options.width, options.height
        )));
    }
    let scene = scene_at(options, camera)?;
    let account = crate::inspect::inspect(
        &scene,
        options.trace,
        (options.width, options.height),
        (x, y),
    );
    // Word for word what the command line prints: trimmed, one newline.
    let body = if text {
        crate::inspect::to_text(&account)
    } else {
        serde_json::to_string_pretty(&account).unwrap_or_default()
    };
    Ok(format!("{}\n", body.trim_end()))
}

/// 'g': the line's grid (`-grid`): its box, its cells, and each occupied cell with how many
/// primitives it lists and its colour (as `-visualize_grid` colours it); `null` without a grid.
pub fn grid(options: &Options) -> Result<Value, Error> {
    let scene = scene_at(options, None)?;
    let Some(grid) = scene.world.grid() else {
        return Ok(Value::Null);
    };
    let n = grid.cells();
    let mut occupied = Vec::new();
    for k in 0..n.z {
        for j in 0..n.y {
            for i in 0..n.x {
                let count = grid.count(glam::UVec3::new(i, j, k));
                if count > 0 {
                    let colour = grid_palette(count as usize);
                    occupied.push(json!([i, j, k, count, [colour.x, colour.y, colour.z]]));
                }
            }
        }
    }
    let bounds = grid.bounds();
    Ok(json!({
        "min": [bounds.min.x, bounds.min.y, bounds.min.z],
        "max": [bounds.max.x, bounds.max.y, bounds.max.z],
        "cells": [n.x, n.y, n.z],
        "occupied": occupied,
    }))
}

/// The cells the rays of pixel (x, y)'s ray tree walk through the grid, as the course's grid
/// search walks them (the 3D-DDA, up to the cell where the ray's hit lies): the camera ray
/// first, then each ray it spawns, shadow rays included, each cell with the axis and sign of the
/// face it was entered by.
pub fn grid_walk(
    options: &Options,
    camera: Option<&str>,
    pixel: (u32, u32),
) -> Result<Value, Error> {
    let scene = scene_at(options, camera)?;
    let Some(grid) = scene.world.grid() else {
        return Ok(Value::Null);
    };
    let account = crate::inspect::inspect(
        &scene,
        options.trace,
        (options.width, options.height),
        pixel,
    );
    let mut rays = Vec::new();
    let walk = |kind: &str, ray: Ray, t_min: f32, t_max: f32, rays: &mut Vec<Value>| {
        let mut cells = Vec::new();
        grid.walk(&ray, t_min, t_max, |cell| {
            cells.push(json!([
                cell.index.x,
                cell.index.y,
                cell.index.z,
                cell.entered_axis,
                cell.entered_sign
            ]));
            if cell.t_exit >= t_max {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        rays.push(json!({ "kind": kind, "cells": cells }));
    };
    let vec3 = |v: &Value| {
        let f = |k: usize| v[k].as_f64().unwrap_or(0.0) as f32;
        glam::Vec3A::new(f(0), f(1), f(2))
    };
    // Each ray with its least t: the camera's, or for a mirror or glass ray the tracer's
    // clearance of the surface it leaves.
    let mut pending = vec![(account["tree"].clone(), scene.camera.t_min())];
    while let Some((node, t_min)) = pending.pop() {
        if node["ray"].is_null() {
            continue;
        }
        let ray = Ray::new(
            vec3(&node["ray"]["origin"]),
            vec3(&node["ray"]["direction"]),
        );
        let t_hit = node["hit"]["t"]
            .as_f64()
            .map_or(f32::INFINITY, |t| t as f32);
        let kind = node["kind"].as_str().unwrap_or("ray").to_string();
        walk(&kind, ray, t_min, t_hit, &mut rays);
        let point = vec3(&node["hit"]["point"]);
        let facing = vec3(&node["hit"]["world_normal"]);
        let normal = if node["hit"]["back_face"] == true {
            -facing
        } else {
            facing
        };
        let clearance = clearance(point, ray.origin);
        if let Some(lights) = node["lights"].as_array() {
            for light in lights {
                if !matches!(light["shadow_ray"].as_str(), Some("blocked" | "clear")) {
                    continue;
                }
                let distance = light["distance"]
                    .as_f64()
                    .map_or(f32::INFINITY, |d| d as f32);
                let to_light = vec3(&light["to_light"]);
                let near = start_t(clearance, to_light, normal);
                let far = shadow_end(distance);
                let shadow = Ray::new(point, to_light);
                // A blocked shadow ray's walk ends at the blocker's cell.
                let blocker = scene.world.intersect(&shadow, near).map(|h| h.t);
                let end = blocker.filter(|&t| t <= far).unwrap_or(far);
                walk("shadow", shadow, near, end, &mut rays);
            }
        }
        if let Some(children) = node["children"].as_array() {
            for child in children.iter().rev() {
                let direction = vec3(&child["ray"]["direction"]);
                let t_min = start_t(clearance, direction, normal);
                pending.push((child.clone(), t_min));
            }
        }
    }
    Ok(json!({ "pixel": [pixel.0, pixel.1], "rays": rays }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_camera_written_reads_back_the_same() {
        let text = "PerspectiveCamera { center -0.367659 0.288879 0.266634 \
                    direction 0.717496 -0.394623 -0.573997 up 0 1 0.1 angle 30.5 }";
        let camera = camera_of(text).unwrap();
        assert_eq!(camera_of(&camera_text(&camera)).unwrap(), camera);
        let orthographic =
            camera_of("OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2.5 }")
                .unwrap();
        assert_eq!(
            camera_text(&orthographic),
            "OrthographicCamera {\n    center 0 0 10\n    direction 0 0 -1\n    up 0 1 0\n    size 2.5\n}\n"
        );
        assert!(camera_of("PerspectiveCamera { center 0 0 }").is_err());
    }
}
