//! Faults of shading: back faces, the ambient term, the light terms.

use glam::Vec3A;

use super::{Candidate, Fault, LineScene, Planted};
use crate::scene::SpecularFalloff;
use crate::trace::BackFace;

/// How a student's tracer shades a hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadingFault {
    /// `-shade_back` ignored: back faces black even when asked to shade them.
    ShadeBackIgnored,
    /// Back faces shaded (the normal turned toward the ray) without `-shade_back`.
    BackFacesLit,
    /// Each light's N·L taken as |N·L|: lit from behind too.
    AbsoluteCosine,
    /// The ambient term added once for each light.
    AmbientPerLight,
    /// No ambient term.
    AmbientMissing,
    /// Back faces that should be black show the ambient term.
    AmbientOnBackFaces,
    /// Each light's term multiplied by N·L once more.
    CosineTwice,
    /// Highlights faded by N·L without `-specular_fix`, or cut with it.
    SpecularFixSwapped,
}

impl ShadingFault {
    pub(super) fn back_face(&self, shade_back: bool, face: BackFace) -> BackFace {
        match self {
            ShadingFault::ShadeBackIgnored => BackFace::Black,
            ShadingFault::BackFacesLit if !shade_back => BackFace::Shaded,
            ShadingFault::AmbientOnBackFaces if face == BackFace::Black => BackFace::Ambient,
            _ => face,
        }
    }

    pub(super) fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        match self {
            ShadingFault::AmbientPerLight => term * lights as f32,
            ShadingFault::AmbientMissing => Vec3A::ZERO,
            _ => term,
        }
    }

    pub(super) fn light(
        &self,
        shade: &dyn Fn(Vec3A, SpecularFalloff) -> Vec3A,
        normal: Vec3A,
        to_light: Vec3A,
        falloff: SpecularFalloff,
    ) -> Vec3A {
        match self {
            ShadingFault::AbsoluteCosine if normal.dot(to_light) < 0.0 => shade(-normal, falloff),
            ShadingFault::CosineTwice => shade(normal, falloff) * normal.dot(to_light).max(0.0),
            ShadingFault::SpecularFixSwapped => shade(
                normal,
                match falloff {
                    SpecularFalloff::Cut => SpecularFalloff::Fade,
                    SpecularFalloff::Fade => SpecularFalloff::Cut,
                },
            ),
            _ => shade(normal, falloff),
        }
    }
}

fn only(fault: ShadingFault) -> Vec<Candidate> {
    vec![Candidate::plain(Planted::Shading(fault))]
}

pub(super) const SHADE_BACK_IGNORED: Fault = Fault {
    name: "shade_back_ignored",
    assignment: 2,
    sentence: "I ignore -shade_back: back faces stay black even when the line asks to shade them.",
    look_for: "Where a hit's normal faces away from the ray: with -shade_back, turn the normal \
               around and shade as usual; only without it is the pixel black.",
    candidates: |line: &LineScene| {
        if line.options.trace.shade_back && line.has_image() {
            only(ShadingFault::ShadeBackIgnored)
        } else {
            Vec::new()
        }
    },
};

pub(super) const BACK_FACES_LIT: Fault = Fault {
    name: "back_faces_lit",
    assignment: 2,
    sentence: "I shade back faces even without -shade_back.",
    look_for: "Where a hit's normal faces away from the ray: without -shade_back the pixel is \
               black (and nothing more is traced from it).",
    candidates: |line: &LineScene| {
        if !line.options.trace.shade_back && line.has_image() {
            only(ShadingFault::BackFacesLit)
        } else {
            Vec::new()
        }
    },
};

pub(super) const SHADE_BACK_ABS: Fault = Fault {
    name: "shade_back_abs",
    assignment: 2,
    sentence: "I take |N·L| for each light instead of turning the normal toward the viewer, so \
               surfaces are lit from behind too.",
    look_for: "The diffuse term: max(N·L, 0) with the normal turned toward the ray (for \
               -shade_back); |N·L| lights a surface from both sides.",
    candidates: |line: &LineScene| {
        if line.has_image() && !line.scene.lights.is_empty() {
            only(ShadingFault::AbsoluteCosine)
        } else {
            Vec::new()
        }
    },
};

pub(super) const AMBIENT_PER_LIGHT: Fault = Fault {
    name: "ambient_per_light",
    assignment: 2,
    sentence: "I add the ambient term inside the loop over the lights, once per light.",
    look_for: "The shading sum: ambient × diffuse once, then Σ over the lights of their terms; \
               the ambient term belongs outside the loop.",
    candidates: |line: &LineScene| {
        if line.has_image() && line.scene.lights.len() != 1 {
            only(ShadingFault::AmbientPerLight)
        } else {
            Vec::new()
        }
    },
};

pub(super) const AMBIENT_MISSING: Fault = Fault {
    name: "ambient_missing",
    assignment: 2,
    sentence: "I leave out the ambient term.",
    look_for: "The shading sum starts with ambient light × the diffuse colour (a scene without \
               lights has white ambient light, showing objects in their flat colour).",
    candidates: |line: &LineScene| {
        if line.has_image() && line.scene.ambient != Vec3A::ZERO {
            only(ShadingFault::AmbientMissing)
        } else {
            Vec::new()
        }
    },
};

pub(super) const AMBIENT_ON_BACK_FACES: Fault = Fault {
    name: "ambient_on_back_faces",
    assignment: 2,
    sentence: "Back faces that should be black show the ambient term.",
    look_for: "Without -shade_back a back face is black: return black before adding the \
               ambient term, not after.",
    candidates: |line: &LineScene| {
        if !line.options.trace.shade_back && line.has_image() {
            only(ShadingFault::AmbientOnBackFaces)
        } else {
            Vec::new()
        }
    },
};

pub(super) const COSINE_TWICE: Fault = Fault {
    name: "cosine_twice",
    assignment: 2,
    sentence: "I multiply each light's term by N·L twice.",
    look_for: "The diffuse term is diffuse × light colour × max(N·L, 0), N·L once (and the \
               light's colour is not itself scaled by N·L).",
    candidates: |line: &LineScene| {
        if line.has_image() && !line.scene.lights.is_empty() {
            only(ShadingFault::CosineTwice)
        } else {
            Vec::new()
        }
    },
};

/// Whether any material of the line's scene has a highlight.
fn has_highlights(line: &LineScene) -> bool {
    line.description.materials.iter().any(|m| match m {
        crate::parse::description::MaterialSpec::Phong(p) => p.specular != glam::Vec3::ZERO,
        crate::parse::description::MaterialSpec::Texture(_) => false,
    })
}

pub(super) const SPECULAR_FIX: Fault = Fault {
    name: "specular_fix",
    assignment: 3,
    sentence: "My highlights fade by N·L where the line does not ask for -specular_fix (or do not \
               fade where it does).",
    look_for: "The specular term: without -specular_fix it is cut where N·L < 0 and not faded; \
               with it, multiplied by N·L (the handout's fix).",
    candidates: |line: &LineScene| {
        if line.has_image() && has_highlights(line) && !line.scene.lights.is_empty() {
            only(ShadingFault::SpecularFixSwapped)
        } else {
            Vec::new()
        }
    },
};
