//! `-inspect X Y`: everything that made one pixel's colour, for a student to compare with their
//! own tracer step by step (the course's ray-tree view, in text or JSON): the camera ray, every
//! surface it crosses, the hit with its normal before and after its Transform, each light's
//! direction, shadow ray and diffuse and specular terms, and the tree of mirror and glass rays
//! with their weights, down to the colour before and after clamping.

use glam::Vec3A;
use serde_json::{Value, json};

use crate::accel::{Hit, Item};
use crate::camera::pixel_to_screen;
use crate::geometry::{Ray, intersect_plane, intersect_sphere, intersect_triangle};
use crate::scene::{Highlight, Light, Scene, Surface};
use crate::shade::to_rgb;
use crate::trace::{
    Scratch, TraceSettings, Tracer, clearance, crossing_ratio, reflect, refract, shadow_end,
    spawned, start_t, worth_tracing,
};

/// What one pixel's camera ray met and made.
pub fn inspect(scene: &Scene, trace: TraceSettings, size: (u32, u32), pixel: (u32, u32)) -> Value {
    let (width, height) = size;
    let (x, y) = pixel;
    let (u, v) = pixel_to_screen(x, y, width, height);
    let ray = scene.camera.ray(u, v);
    let t_min = scene.camera.t_min();
    let tracer = Tracer::new(scene, trace);
    let mut scratch = Scratch::default();
    let hit = scene.world.intersect(&ray, t_min);
    let colour = match &hit {
        Some(hit) => tracer.colour(&ray, Some(hit), &mut scratch),
        None => scene.background,
    };
    json!({
        "pixel": [x, y],
        "image": [width, height],
        "camera_ray": ray_json(&ray),
        "crossings": crossings(scene, &ray, t_min),
        "tree": node(scene, &trace, Branch {
            kind: "camera",
            ray,
            t_min,
            bounces_left: trace.bounces,
            weight: 1.0,
            throughput: Vec3A::ONE,
        }),
        "colour": vec3(colour),
        "bytes": to_rgb(colour),
    })
}

fn vec3(v: Vec3A) -> Value {
    json!([v.x, v.y, v.z])
}

fn ray_json(ray: &Ray) -> Value {
    json!({ "origin": vec3(ray.origin), "direction": vec3(ray.direction) })
}

/// Every surface the ray crosses at t ≥ t_min, nearest first.
fn crossings(scene: &Scene, ray: &Ray, t_min: f32) -> Value {
    let world = &scene.world;
    let mut found: Vec<(f32, String)> = Vec::new();
    for (i, (plane, material)) in world.planes.iter().enumerate() {
        if let Some(t) = intersect_plane(ray, plane, t_min, f32::INFINITY) {
            found.push((t, format!("plane {i} (material {material})")));
        }
    }
    for (i, item) in world.items.iter().enumerate() {
        let local = world.ray_into(item, ray);
        match *item {
            Item::Sphere {
                sphere, material, ..
            } => {
                let mut from = t_min;
                while let Some(t) = intersect_sphere(&local, &sphere, from, f32::INFINITY) {
                    found.push((t, format!("sphere {i} (material {material})")));
                    from = t.next_up();
                    if found.len() > 10_000 {
                        break;
                    }
                }
            }
            Item::Mesh { mesh, material, .. } => {
                for (k, triangle) in world.meshes[mesh as usize].triangles().iter().enumerate() {
                    if let Some(t) = intersect_triangle(&local, triangle, t_min, f32::INFINITY) {
                        let material = if material == Item::PER_TRIANGLE {
                            world.loose_materials[k]
                        } else {
                            material
                        };
                        found.push((
                            t,
                            format!("triangle {k} of mesh item {i} (material {material})"),
                        ));
                    }
                }
            }
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    Value::Array(
        found
            .into_iter()
            .map(|(t, what)| json!({ "t": t, "surface": what }))
            .collect(),
    )
}

/// One ray of the tree before it is followed: what kind it is, where it goes, and what it
/// carries.
#[derive(Debug, Clone, Copy)]
struct Branch<'a> {
    kind: &'a str,
    ray: Ray,
    t_min: f32,
    bounces_left: u32,
    weight: f32,
    throughput: Vec3A,
}

/// Where a ray of the tree hit, as shading sees it: the material there, and the normal turned
/// toward the ray.
struct HitSite<'a> {
    surface: Surface<'a>,
    point: Vec3A,
    normal: Vec3A,
    /// The ray hit the surface's back.
    inside: bool,
}

/// One ray of the tree, what it hit, what each light gave there, and the rays it spawned.
fn node(scene: &Scene, trace: &TraceSettings, branch: Branch) -> Value {
    let Branch { ray, weight, .. } = branch;
    let mut out = json!({
        "kind": branch.kind,
        "ray": ray_json(&ray),
        "weight": weight,
        "throughput": vec3(branch.throughput),
    });
    let Some(hit) = scene.world.intersect(&ray, branch.t_min) else {
        out["hit"] = Value::Null;
        out["colour"] = vec3(scene.background);
        out["note"] = json!("no hit: the background colour");
        return out;
    };
    let inside = ray.direction.dot(hit.normal) > 0.0;
    let point = ray.at(hit.t);
    out["hit"] = json!({
        "t": hit.t,
        "point": vec3(point),
        "material": hit.material,
        "object_normal": vec3(object_normal(scene, &ray, &hit)),
        "world_normal": vec3(hit.normal),
        "back_face": inside,
    });
    if inside && !trace.shade_back {
        out["colour"] = vec3(Vec3A::ZERO);
        out["note"] = json!("a back face without -shade_back: black, and no further rays");
        return out;
    }
    let at = HitSite {
        surface: scene.materials.at(hit.material, point),
        point,
        normal: if inside { -hit.normal } else { hit.normal },
        inside,
    };
    let ambient = scene.ambient * at.surface.diffuse();
    let (local, lights) = light_terms(scene, trace, &ray, &at, ambient);
    out["ambient"] = vec3(ambient);
    out["lights"] = Value::Array(lights);
    out["local"] = vec3(local);
    let (children, colour) = if branch.bounces_left > 0 {
        children(scene, trace, &branch, &at, local)
    } else {
        (Vec::new(), local)
    };
    out["children"] = Value::Array(children);
    out["colour"] = vec3(colour);
    out
}

/// Each light's terms at `point`, with its shadow ray's verdict; and the colour shaded there:
/// `ambient` plus each light's light, added in the tracer's order (so the sums round alike).
fn light_terms(
    scene: &Scene,
    trace: &TraceSettings,
    ray: &Ray,
    at: &HitSite,
    ambient: Vec3A,
) -> (Vec3A, Vec<Value>) {
    let HitSite {
        surface,
        point,
        normal,
        ..
    } = at;
    let (point, normal) = (*point, *normal);
    let mut lit = ambient;
    let mut lights = Vec::new();
    for (i, light) in scene.lights.iter().enumerate() {
        let kind = match light {
            Light::Directional { .. } => "directional",
            Light::Point { .. } => "point",
        };
        let Some(light) = light.illuminate(point) else {
            lights.push(json!({ "light": i, "kind": kind, "note": "the point is at the light" }));
            continue;
        };
        let shaded = surface.shade(
            normal,
            ray.direction,
            light.to_light,
            light.colour,
            trace.specular,
            Highlight::Course,
        );
        let n_dot_l = normal.dot(light.to_light);
        let diffuse = surface.diffuse() * n_dot_l.max(0.0) * light.colour;
        let shadow = if !trace.shadows {
            "not asked for (no -shadows)"
        } else if shaded == Vec3A::ZERO {
            "not sent: the light adds nothing here"
        } else {
            // As the tracer sends it: clear of the surface, to just short of the light.
            let near = start_t(clearance(point, ray.origin), light.to_light, normal);
            let far = shadow_end(light.distance);
            if scene
                .world
                .occluded(&Ray::new(point, light.to_light), near, far)
            {
                "blocked"
            } else {
                "clear"
            }
        };
        let adds = if shadow == "blocked" {
            Vec3A::ZERO
        } else {
            shaded
        };
        lit += adds;
        lights.push(json!({
            "light": i,
            "kind": kind,
            "to_light": vec3(light.to_light),
            "distance": if light.distance.is_finite() { json!(light.distance) } else { json!("infinite") },
            "colour_arriving": vec3(light.colour),
            "n_dot_l": n_dot_l,
            "shadow_ray": shadow,
            "diffuse": vec3(diffuse),
            "specular": vec3(shaded - diffuse),
            "adds": vec3(adds),
        }));
    }
    (lit, lights)
}

/// The mirror and glass rays a hit spawns, each followed; and the hit's colour: `local` plus
/// what they bring back, weighted by the surface's reflective and transparent colours, added in
/// the tracer's order.
fn children(
    scene: &Scene,
    trace: &TraceSettings,
    parent: &Branch,
    at: &HitSite,
    local: Vec3A,
) -> (Vec<Value>, Vec3A) {
    let HitSite {
        surface,
        point,
        normal,
        inside,
    } = at;
    let (point, normal, inside) = (*point, *normal, *inside);
    let unit = parent.ray.direction.normalize();
    let mut children = Vec::new();
    let mut total = local;
    let mut spawn = |kind: &str, colour: Vec3A, new_direction: Option<Vec3A>| {
        let (weight, throughput) = spawned(parent.weight, parent.throughput, colour);
        let Some(new_direction) = new_direction else {
            children.push(json!({ "kind": kind, "note": "total internal reflection: none" }));
            return;
        };
        if !worth_tracing(trace.cutoff_weight, weight, throughput) {
            children.push(json!({
                "kind": kind, "weight": weight, "note": "below the -weight cut-off: not traced"
            }));
            return;
        }
        let branch = Branch {
            kind,
            ray: Ray::new(point, new_direction),
            t_min: start_t(clearance(point, parent.ray.origin), new_direction, normal),
            bounces_left: parent.bounces_left - 1,
            weight,
            throughput,
        };
        let child = node(scene, trace, branch);
        let seen: Vec<f32> = serde_json::from_value(child["colour"].clone()).unwrap_or_default();
        if seen.len() == 3 {
            total += colour * Vec3A::new(seen[0], seen[1], seen[2]);
        }
        children.push(child);
    };
    let reflective = surface.reflective();
    if reflective != Vec3A::ZERO {
        spawn("reflected", reflective, Some(reflect(unit, normal)));
    }
    let transparent = surface.transparent();
    if transparent != Vec3A::ZERO {
        let index = surface.index_of_refraction();
        spawn(
            "refracted",
            transparent,
            refract(unit, normal, crossing_ratio(index, inside)),
        );
    }
    (children, total)
}

/// The hit's normal in its object's own space, before its Transform.
fn object_normal(scene: &Scene, ray: &Ray, hit: &Hit) -> Vec3A {
    let world = &scene.world;
    let point = ray.at(hit.t);
    for item in &world.items {
        let local = world.ray_into(item, ray);
        match *item {
            Item::Sphere { sphere, .. } => {
                if intersect_sphere(&local, &sphere, hit.t, hit.t).is_some() {
                    return sphere.normal_at(local.at(hit.t)).normalize_or_zero();
                }
            }
            Item::Mesh { mesh, .. } => {
                let mesh = &world.meshes[mesh as usize];
                for (k, triangle) in mesh.triangles().iter().enumerate() {
                    if intersect_triangle(&local, triangle, hit.t, hit.t).is_some() {
                        return mesh.normal(k as u32).normalize_or_zero();
                    }
                }
            }
        }
    }
    // A plane is stored in world space: its normal is the same in both.
    let _ = point;
    hit.normal
}

/// A JSON number as the single-precision value the tracer computed, in its fewest digits
/// (9.000156, not the 9.000156402587891 of its widening to double); anything else as JSON.
fn number(value: &Value) -> String {
    match value.as_f64() {
        Some(f) if value.is_f64() => (f as f32).to_string(),
        _ => value.to_string(),
    }
}

/// A JSON vector as `(x, y, z)` to four places; anything else as JSON.
fn show(value: &Value) -> String {
    match value.as_array() {
        Some(a) => format!(
            "({})",
            a.iter()
                .map(|x| x
                    .as_f64()
                    .map_or_else(|| x.to_string(), |f| format!("{f:.4}")))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        None => value.to_string(),
    }
}

/// The inspection as text, for the terminal.
pub fn to_text(inspection: &Value) -> String {
    let mut text = String::new();
    text.push_str(&format!(
        "pixel ({}, {}) of {}x{} (x from the left, y from the bottom)\n",
        inspection["pixel"][0],
        inspection["pixel"][1],
        inspection["image"][0],
        inspection["image"][1]
    ));
    text.push_str(&format!(
        "camera ray: from {} along {}\n",
        show(&inspection["camera_ray"]["origin"]),
        show(&inspection["camera_ray"]["direction"])
    ));
    text.push_str("surfaces along the ray, nearest first:\n");
    let crossings = inspection["crossings"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    if crossings.is_empty() {
        text.push_str("  none\n");
    }
    for c in &crossings {
        text.push_str(&format!(
            "  t = {:<12} {}\n",
            number(&c["t"]),
            c["surface"].as_str().unwrap_or("")
        ));
    }
    tree_text(&inspection["tree"], 0, &mut text);
    text.push_str(&format!(
        "colour {} unclamped, {} as bytes\n",
        show(&inspection["colour"]),
        inspection["bytes"]
    ));
    text
}

/// One ray of the tree and, indented below it, the rays it spawned.
fn tree_text(node: &Value, depth: usize, text: &mut String) {
    let pad = "  ".repeat(depth);
    text.push_str(&format!(
        "{pad}{} ray, weight {}, throughput {}\n",
        node["kind"].as_str().unwrap_or("?"),
        number(&node["weight"]),
        show(&node["throughput"])
    ));
    if let Some(note) = node["note"].as_str() {
        text.push_str(&format!("{pad}  {note}\n"));
    }
    if node["hit"].is_object() {
        let hit = &node["hit"];
        text.push_str(&format!(
            "{pad}  hit at t = {} point {} material {}{}\n",
            number(&hit["t"]),
            show(&hit["point"]),
            hit["material"],
            if hit["back_face"] == true {
                " (back face)"
            } else {
                ""
            }
        ));
        text.push_str(&format!(
            "{pad}  normal: {} in the object's space, {} in the world\n",
            show(&hit["object_normal"]),
            show(&hit["world_normal"])
        ));
    }
    if !node["ambient"].is_null() {
        text.push_str(&format!("{pad}  ambient {}\n", show(&node["ambient"])));
    }
    for light in node["lights"].as_array().into_iter().flatten() {
        if let Some(note) = light["note"].as_str() {
            text.push_str(&format!("{pad}  light {}: {note}\n", light["light"]));
            continue;
        }
        let shadow_ray = light["shadow_ray"].as_str().unwrap_or("");
        // A blocked light's terms are what it would add if it were clear; "shaded here" then
        // leaves them out, and the line says so first.
        let terms = if shadow_ray == "blocked" {
            format!(
                "blocked: adds 0 (if it were clear: diffuse {}, specular {})",
                show(&light["diffuse"]),
                show(&light["specular"])
            )
        } else {
            format!(
                "{shadow_ray}, diffuse {}, specular {}",
                show(&light["diffuse"]),
                show(&light["specular"])
            )
        };
        text.push_str(&format!(
            "{pad}  light {} ({}): toward it {}, N.L {}, shadow ray {terms}\n",
            light["light"],
            light["kind"].as_str().unwrap_or(""),
            show(&light["to_light"]),
            number(&light["n_dot_l"]),
        ));
    }
    if !node["local"].is_null() {
        text.push_str(&format!("{pad}  shaded here {}\n", show(&node["local"])));
    }
    for child in node["children"].as_array().into_iter().flatten() {
        tree_text(child, depth + 1, text);
    }
    text.push_str(&format!("{pad}  = {}\n", show(&node["colour"])));
}
