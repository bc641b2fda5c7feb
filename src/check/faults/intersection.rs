//! Faults of the search for the nearest hit: the range of t it accepts.

use super::{Candidate, Fault, LineScene, Planted};
use crate::accel::Hit;
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::parse::description::Projection;
use crate::scene::Scene;

/// How a student's tracer takes the nearest hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HitFault {
    /// Camera rays accept hits from this t on (the course: the orthographic camera sees behind
    /// its centre, the perspective camera only in front of its eye).
    CameraTMin(f32),
    /// Hits farther than this distance are lost (a finite "infinity").
    Limit(f32),
    /// Hits nearer than this distance are skipped, for every picture (the depth picture's
    /// near end used as the rays' t_min).
    Nearer(f32),
    /// Normals carried into the world by the object's matrix, not its inverse transpose.
    NormalByMatrix,
    /// Normals carried by the inverse transpose but not made unit length again.
    NormalNotUnit,
}

impl HitFault {
    pub(super) fn camera_t_min(&self, _camera: &Camera) -> Option<f32> {
        match *self {
            HitFault::CameraTMin(t) => Some(t),
            _ => None,
        }
    }

    pub(super) fn found(&self, scene: &Scene, ray: &Ray, hit: Option<Hit>) -> Option<Hit> {
        // Distances along the ray as a student's unit-direction ray would measure them.
        let length = ray.direction.length();
        match *self {
            HitFault::CameraTMin(_) => hit,
            HitFault::Limit(limit) => hit.filter(|h| h.t * length <= limit),
            HitFault::Nearer(near) => match hit {
                Some(h) if h.t * length < near => scene.world.intersect(ray, near / length),
                other => other,
            },
            HitFault::NormalByMatrix | HitFault::NormalNotUnit => {
                let hit = hit?;
                let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, hit.t)
                else {
                    return Some(hit);
                };
                let object_normal = object_normal.normalize_or_zero();
                let normal = if *self == HitFault::NormalByMatrix {
                    transform
                        .object_to_world
                        .transform_vector3a(object_normal)
                        .normalize_or_zero()
                } else {
                    transform.normal_to_world * object_normal
                };
                Some(Hit {
                    normal: if normal == glam::Vec3A::ZERO {
                        hit.normal
                    } else {
                        normal
                    },
                    ..hit
                })
            }
        }
    }
}

/// Whether the line's scene places something under a Transform, and the line shows normals
/// (in the normals picture, or in shading with lights).
fn transformed_normals_show(line: &LineScene) -> bool {
    let placed = line
        .description
        .objects
        .iter()
        .any(|o| o.transform.is_some());
    let shows =
        line.options.normals.is_some() || (line.has_image() && !line.scene.lights.is_empty());
    placed && shows
}

pub(super) const NORMAL_TRANSFORM: Fault = Fault {
    name: "normal_transform",
    assignment: 2,
    sentence: "I carry normals into the world with the object's matrix, not with the transpose \
               of its inverse.",
    look_for: "The normal of a transformed object: n_world = (M^-1)^T n_object, then normalised; \
               M itself tilts normals of scaled or sheared objects.",
    candidates: |line: &LineScene| {
        if transformed_normals_show(line) {
            vec![Candidate::plain(Planted::Hit(HitFault::NormalByMatrix))]
        } else {
            Vec::new()
        }
    },
};

pub(super) const NORMAL_LENGTH: Fault = Fault {
    name: "normal_length",
    assignment: 2,
    sentence: "My normals are not unit length after a Transform.",
    look_for: "After carrying a normal into the world by the inverse transpose, normalise it \
               again: a scale changes its length.",
    candidates: |line: &LineScene| {
        if transformed_normals_show(line) {
            vec![Candidate::plain(Planted::Hit(HitFault::NormalNotUnit))]
        } else {
            Vec::new()
        }
    },
};

fn t_min_ignored(line: &LineScene) -> Vec<Candidate> {
    // The other of the two choices: hits behind a perspective camera's eye accepted, or an
    // orthographic camera that sees nothing behind its centre.
    let t_min = match line.description.camera.projection {
        Projection::Perspective { .. } => f32::NEG_INFINITY,
        Projection::Orthographic { .. } => 0.0,
    };
    vec![Candidate::with(
        Planted::Hit(HitFault::CameraTMin(t_min)),
        "t_min",
        f64::from(t_min),
    )]
}

pub(super) const T_MIN_IGNORED: Fault = Fault {
    name: "t_min_ignored",
    assignment: 1,
    sentence: "My camera rays take hits on the wrong side of their start: behind a perspective \
               camera's eye, or none behind an orthographic camera's centre.",
    look_for: "The tmin a camera ray passes to intersect: 0 for the perspective camera (only \
               what is in front of the eye), -infinity for the orthographic camera.",
    candidates: t_min_ignored,
};

fn t_limit(line: &LineScene) -> Vec<Candidate> {
    if !line.has_image() && !line.has_depth_or_normals() {
        return Vec::new();
    }
    [1.0f32, 10.0, 100.0, 1000.0]
        .into_iter()
        .map(|limit| {
            Candidate::with(
                Planted::Hit(HitFault::Limit(limit)),
                "limit",
                f64::from(limit),
            )
        })
        .collect()
}

pub(super) const T_LIMIT: Fault = Fault {
    name: "t_limit",
    assignment: 1,
    sentence: "My nearest-hit search starts from a finite \"infinity\", so far surfaces are lost.",
    look_for: "The initial t of the hit record: start from a value larger than any hit (such as \
               FLT_MAX or infinity), not from 1 or 1000.",
    candidates: t_limit,
};

fn depth_tmin(line: &LineScene) -> Vec<Candidate> {
    match line.options.depth {
        Some((near, _, _)) if near > 0.0 => vec![Candidate::with(
            Planted::Hit(HitFault::Nearer(near)),
            "t_min",
            f64::from(near),
        )],
        _ => Vec::new(),
    }
}

pub(super) const DEPTH_TMIN: Fault = Fault {
    name: "depth_tmin",
    assignment: 2,
    sentence: "My rays start at the depth picture's near end, so what is nearer is cut away.",
    look_for: "The depth range only maps t to grey: the rays still start at the camera's own \
               tmin, and t nearer than -depth's TMIN is white, not skipped.",
    candidates: depth_tmin,
};
