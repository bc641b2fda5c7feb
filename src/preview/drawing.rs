//! The scene as the course's OpenGL preview draws it, ready for the page: triangles in world
//! space with the normal OpenGL would light each vertex with, grouped by material, and the
//! camera, lights and materials as the staff's `glInit` and `glSetMaterial` set them.
//!
//! The staff's viewer sends each object's vertices through its Transform's matrix and its
//! normals through that matrix's inverse transpose (`GL_NORMALIZE` on). The view matrix that
//! `gluLookAt` adds is a rotation and a translation, under which OpenGL's lighting (done in eye
//! space) gives the same colours as in world space; so the page gets world-space triangles and
//! lights them in world space.

use std::path::Path;

use glam::{DMat3, DMat4, DVec3, Vec3};
use serde_json::{Value, json};

use crate::error::Error;
use crate::parse::description::{
    CameraSpec, LightSpec, MaterialSpec, PlacedObject, Projection, SceneDescription, Shape,
};
use crate::parse::obj::parse_obj;
use crate::scene::find_mesh;

/// A sphere's steps around its axis (θ) and from pole to pole (φ) when the line gives no
/// `-tessellation`: the course names no default; these draw a smooth enough sphere at the
/// course's 200 × 200 pixels.
pub const DEFAULT_TESSELLATION: (u32, u32) = (20, 10);

/// Half the side of the square the staff's viewer draws a plane as (the handout: "big should
/// probably be < 10^6"); far past the far clipping plane, 40 units from the eye.
pub const PLANE_HALF_SIDE: f64 = 1e4;

/// OpenGL's lights: the staff's viewer skips the ninth and later with a warning.
pub const MAX_LIGHTS: usize = 8;

/// How the preview tessellates spheres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tessellation {
    /// Steps around the axis, and from pole to pole.
    pub steps: (u32, u32),
    /// A normal per vertex (`-gouraud`) instead of one per face.
    pub gouraud: bool,
}

/// What the page draws.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawing {
    /// Every vertex as twelve little-endian f32, in world space: position, the normal it is lit
    /// with, and the light reaching its front and its back (Σ colour × max(N·L, 0) over the
    /// lights); three a triangle, wound as the scene winds it (which says which side the eye
    /// sees), the triangles of each batch together.
    pub vertices: Vec<u8>,
    /// The scene's description for the page: camera, background, lights, materials, batches.
    pub meta: Value,
    /// How many triangles the scene draws as.
    pub triangles: usize,
}

/// One vertex: position, the normal it is lit with, and the light reaching its front and its
/// back.
type Vertex = [Vec3; 4];

/// The lights as OpenGL's sum sees them: toward the light (unit, for a directional one) or the
/// light's position, and the colour.
#[derive(Clone, Copy)]
enum GlLight {
    Directional(Vec3, Vec3),
    Point(Vec3, Vec3),
}

impl GlLight {
    fn new(light: &LightSpec) -> GlLight {
        match light {
            LightSpec::Directional { direction, colour } => {
                GlLight::Directional(-direction.normalize_or_zero(), *colour)
            }
            LightSpec::Point {
                position, colour, ..
            } => GlLight::Point(*position, *colour),
        }
    }

    /// The light's diffuse part at `position` for a unit normal `n`: colour × max(N·L, 0).
    /// None of it depends on the camera, so it is summed once here rather than at every frame
    /// (only the highlight, which depends on where the eye is, is left to the page).
    fn irradiance(&self, position: Vec3, n: Vec3) -> Vec3 {
        let (to_light, colour) = match *self {
            GlLight::Directional(to_light, colour) => (to_light, colour),
            GlLight::Point(at, colour) => ((at - position).normalize_or_zero(), colour),
        };
        colour * n.dot(to_light).max(0.0)
    }
}

/// The drawing of `description` (whose meshes are read again from disk).
pub fn draw(description: &SceneDescription, tessellation: Tessellation) -> Result<Drawing, Error> {
    let mut by_material: Vec<Vec<Vertex>> = vec![Vec::new(); description.materials.len()];
    let lights: Vec<GlLight> = description
        .lights
        .iter()
        .take(MAX_LIGHTS)
        .map(GlLight::new)
        .collect();
    for object in &description.objects {
        let matrix = object
            .transform
            .map_or(DMat4::IDENTITY, |t| description.transforms[t as usize]);
        let place = Placement::new(matrix, &lights);
        let out = &mut by_material[object.material as usize];
        match &object.shape {
            Shape::Sphere { center, radius } => {
                sphere(*center, *radius, tessellation, &place, out);
            }
            Shape::Plane { normal, offset } => plane(*normal, *offset, &place, out),
            Shape::Triangle { vertices } => triangle(vertices, &place, out),
            Shape::Mesh { file } => mesh(&description.path, object, file, &place, out)?,
        }
    }
    let mut vertices = Vec::new();
    let mut batches = Vec::new();
    let mut first = 0;
    for (material, list) in by_material.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        for vertex in list {
            for v in vertex.iter().flat_map(|v| v.to_array()) {
                vertices.extend_from_slice(&v.to_le_bytes());
            }
        }
        batches.push(json!({ "material": material, "first": first, "count": list.len() }));
        first += list.len();
    }
    let triangles = first / 3;
    let meta = json!({
        "name": description.path.file_name().map(|n| n.to_string_lossy().into_owned()),
        "triangles": triangles,
        "camera": camera_json(&description.camera),
        "background": description.background.to_array(),
        "ambient": description.ambient.to_array(),
        "lights": description.lights.iter().take(MAX_LIGHTS).map(light_json).collect::<Vec<_>>(),
        "lights_skipped": description.lights.len().saturating_sub(MAX_LIGHTS),
        "materials": (0..description.materials.len())
            .map(|m| material_json(description, m))
            .collect::<Vec<_>>(),
        "batches": batches,
    });
    Ok(Drawing {
        vertices,
        meta,
        triangles,
    })
}

/// The camera as the page starts from: the file's, with `up` as written (the staff's
/// `gluLookAt` takes the file's up and makes it perpendicular itself).
pub fn camera_json(camera: &CameraSpec) -> Value {
    let (kind, size, angle) = match camera.projection {
        Projection::Orthographic { size } => ("orthographic", Some(size), None),
        Projection::Perspective { angle } => ("perspective", None, Some(angle)),
    };
    json!({
        "kind": kind,
        "center": camera.center.to_array(),
        "direction": camera.direction.to_array(),
        "up": camera.up.to_array(),
        "size": size,
        "angle": angle,
    })
}

/// A light as the staff's `Light::glInit` places it: a directional light at infinity toward
/// where its light comes from (w = 0, the direction unit length), a point light at its position (w = 1), the colour as
/// both diffuse and specular, no ambient and no attenuation (the staff's code sets none, so
/// OpenGL's default of none applies).
fn light_json(light: &LightSpec) -> Value {
    match light {
        LightSpec::Directional { direction, colour } => json!({
            // Unit, as the staff's constructor made it: the page need not normalise it again.
            "position": (-direction.normalize_or_zero()).extend(0.0).to_array(),
            "colour": colour.to_array(),
        }),
        LightSpec::Point {
            position, colour, ..
        } => json!({
            "position": [position.x, position.y, position.z, 1.0],
            "colour": colour.to_array(),
        }),
    }
}

/// Material `m` as the staff's `glSetMaterial` sets it: the diffuse colour also as the ambient
/// one, the exponent clamped to OpenGL's [0, 128]. A texture is drawn as its first material
/// (the handout's `CheckerBoard::glSetMaterial`; the course says nothing of the others, which
/// are drawn the same way). Mirrors and glass show their diffuse colour and highlight: the
/// preview traces no rays.
fn material_json(description: &SceneDescription, mut m: usize) -> Value {
    loop {
        match &description.materials[m] {
            MaterialSpec::Phong(phong) => {
                return json!({
                    "diffuse": phong.diffuse.to_array(),
                    "specular": phong.specular.to_array(),
                    "exponent": phong.exponent.clamp(0.0, 128.0),
                });
            }
            MaterialSpec::Texture(texture) => m = texture.materials[0] as usize,
        }
    }
}

/// An object's Transform (points by the matrix, normals by its inverse transpose), and the
/// scene's lights.
struct Placement<'a> {
    matrix: DMat4,
    normals: DMat3,
    lights: &'a [GlLight],
}

impl<'a> Placement<'a> {
    fn new(matrix: DMat4, lights: &'a [GlLight]) -> Placement<'a> {
        Placement {
            matrix,
            normals: DMat3::from_mat4(matrix).inverse().transpose(),
            lights,
        }
    }

    /// Triangle (a, b, c) in the world, each corner lit with its normal.
    fn triangle(&self, corners: [DVec3; 3], normals: [DVec3; 3], out: &mut Vec<Vertex>) {
        for (p, n) in corners.iter().zip(normals) {
            let position = self.matrix.transform_point3(*p).as_vec3();
            let normal = (self.normals * n).normalize_or_zero().as_vec3();
            let light = |n: Vec3| self.lights.iter().map(|l| l.irradiance(position, n)).sum();
            out.push([position, normal, light(normal), light(-normal)]);
        }
    }
}

/// A triangle of the handout's `paint`: the normal from the cross product of its edges.
fn triangle(corners: &[Vec3; 3], place: &Placement, out: &mut Vec<Vertex>) {
    let [a, b, c] = corners.map(|v| v.as_dvec3());
    let normal = (b - a).cross(c - a);
    place.triangle([a, b, c], [normal; 3], out);
}

/// The handout's plane: a square `PLANE_HALF_SIDE` across each way about the world origin's
/// projection onto it, in the basis b1 = v × n, b2 = n × b1 (v the x axis, or the y axis for a
/// plane across x).
fn plane(normal: Vec3, offset: f32, place: &Placement, out: &mut Vec<Vertex>) {
    let n = normal.as_dvec3();
    let origin = n * f64::from(offset);
    let v = if n.x.abs() > 0.999_999 {
        DVec3::Y
    } else {
        DVec3::X
    };
    let b1 = v.cross(n).normalize();
    let b2 = n.cross(b1);
    let big = PLANE_HALF_SIDE;
    let corner = |s: f64, t: f64| origin + b1 * (s * big) + b2 * (t * big);
    let [p0, p1, p2, p3] = [
        corner(-1.0, -1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ];
    place.triangle([p0, p1, p2], [n; 3], out);
    place.triangle([p0, p2, p3], [n; 3], out);
}

/// The sphere as the staff's viewer draws it: poles on the object's y axis, θ from the x
/// axis toward +z in `steps.0` steps, φ from −90° to 90° in `steps.1`, each cell a quad split
/// along the diagonal from (θk, φj) to (θk+1, φj+1); flat, each quad lit by its plane's normal
/// (the remaining triangle's at the poles), or with `-gouraud` by the sphere's true normal at
/// each vertex.
fn sphere(
    center: Vec3,
    radius: f32,
    tessellation: Tessellation,
    place: &Placement,
    out: &mut Vec<Vertex>,
) {
    let (around, up) = tessellation.steps;
    let (center, radius) = (center.as_dvec3(), f64::from(radius));
    let unit = |k: u32, j: u32| {
        let theta = std::f64::consts::TAU * f64::from(k) / f64::from(around);
        let phi =
            -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(j) / f64::from(up);
        DVec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin())
    };
    for j in 0..up {
        for k in 0..around {
            let corners = [
                unit(k, j),
                unit(k + 1, j),
                unit(k + 1, j + 1),
                unit(k, j + 1),
            ];
            let at = corners.map(|u| center + u * radius);
            // Seen from outside, (k, j), (k+1, j+1), (k+1, j) runs counter-clockwise.
            let triangles = [[0, 2, 1], [0, 3, 2]];
            let flat = quad_normal(&at);
            for t in triangles {
                let normals = match tessellation.gouraud {
                    true => t.map(|i| corners[i]),
                    false => [flat; 3],
                };
                place.triangle(t.map(|i| at[i]), normals, out);
            }
        }
    }
}

/// The outward normal of a planar quad (a, b, c, d), corners counter-clockwise seen from
/// inside the sphere (θ, then φ, rising); where two corners meet at a pole, that of the
/// triangle the others make.
fn quad_normal(at: &[DVec3; 4]) -> DVec3 {
    let [a, b, c, d] = *at;
    let n = (c - a).cross(d - b);
    // (c − a) × (d − b) points inward for this order.
    -n
}

/// A mesh file's triangles, each lit by its face's normal.
fn mesh(
    scene: &Path,
    object: &PlacedObject,
    file: &str,
    place: &Placement,
    out: &mut Vec<Vertex>,
) -> Result<(), Error> {
    let found = find_mesh(scene, file, object.span)?;
    let bytes = std::fs::read(&found).map_err(|source| Error::Read {
        path: found.clone(),
        source,
    })?;
    let obj = parse_obj(&found, &bytes)?;
    for t in &obj.triangles {
        triangle(&t.map(|i| obj.positions[i as usize]), place, out);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_normals_point_out_even_at_the_poles() {
        let flat = Tessellation {
            steps: (4, 2),
            gouraud: false,
        };
        let mut out = Vec::new();
        sphere(
            Vec3::ZERO,
            1.0,
            flat,
            &Placement::new(DMat4::IDENTITY, &[]),
            &mut out,
        );
        // 4 × 2 quads, two triangles each.
        assert_eq!(out.len(), 4 * 2 * 6);
        for [position, normal, ..] in &out {
            assert!(normal.dot(*position) > 0.0, "{normal} at {position}");
            assert!((normal.length() - 1.0).abs() < 1e-6);
        }
        // Wound counter-clockwise seen from outside.
        for t in out.chunks(3) {
            let face = (t[1][0] - t[0][0]).cross(t[2][0] - t[0][0]);
            assert!(face.dot(t[0][0] + t[1][0] + t[2][0]) > 0.0);
        }
        // The first quad (θ 0 to 90°, φ −90° to 0): its corners (0, −1, 0), (1, 0, 0) and
        // (0, 0, 1) span the plane x − y + z = 1, whose outward normal is (1, −1, 1)/√3.
        let third = 1.0 / 3f32.sqrt();
        assert!((out[0][1] - Vec3::new(third, -third, third)).length() < 1e-6);
    }

    #[test]
    fn normals_go_through_the_inverse_transpose() {
        // A triangle in the z = 0 plane, squashed along x: the normal stays +z; sheared so that
        // z grows with x (the plane z = x), the normal tilts against the shear.
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let mut out = Vec::new();
        let squash = DMat4::from_scale(DVec3::new(0.5, 1.0, 1.0));
        triangle(&corners, &Placement::new(squash, &[]), &mut out);
        assert_eq!(out[1][..2], [Vec3::new(0.5, 0.0, 0.0), Vec3::Z]);
        let shear = DMat4::from_cols_array(&[
            1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        out.clear();
        triangle(&corners, &Placement::new(shear, &[]), &mut out);
        let tilted = Vec3::new(-1.0, 0.0, 1.0).normalize();
        assert!((out[0][1] - tilted).length() < 1e-6, "{}", out[0][1]);
    }

    #[test]
    fn a_plane_is_a_big_square_about_the_origins_projection() {
        let mut out = Vec::new();
        plane(
            Vec3::Y,
            -2.0,
            &Placement::new(DMat4::IDENTITY, &[]),
            &mut out,
        );
        assert_eq!(out.len(), 6);
        for [position, normal, ..] in &out {
            assert_eq!(position.y, -2.0);
            assert_eq!(position.x.abs(), PLANE_HALF_SIDE as f32);
            assert_eq!(*normal, Vec3::Y);
        }
        // Wound counter-clockwise seen from above: its front faces up.
        for t in out.chunks(3) {
            assert!((t[1][0] - t[0][0]).cross(t[2][0] - t[0][0]).y > 0.0);
        }
    }
}
