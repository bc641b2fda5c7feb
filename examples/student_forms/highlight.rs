//! A highlight worked out by the student's own Blinn term, beside the library's shading: the
//! material's specular colour kept as the hit is weighed, the hit's vectors read as the
//! library's shading hands them to a highlight of one's own.

use std::cell::Cell;

use raycast::Vec3A;
use raycast::scene::{Highlight, HighlightAt, SpecularFalloff, Surface};

thread_local! {
    /// The specular colour of the surface being shaded on this thread.
    static SPECULAR: Cell<Vec3A> = const { Cell::new(Vec3A::ZERO) };
    /// The vectors of the light being shaded, as the shading last handed them over.
    static SEEN: Cell<Option<HighlightAt>> = const { Cell::new(None) };
}

/// Keeps the specular colour of `surface`, once weighed, for [`unlit_highlight`].
pub(crate) fn keep_specular(surface: &Surface<'_>) {
    SPECULAR.set(surface.specular());
}

/// `kd * light * N.L + ks * (N.H)^q`: the highlight added as it is, never times the light's
/// colour. `shade` is the library's shading of the light (its highlight given by the closure).
pub(crate) fn unlit_highlight(
    shade: impl Fn(Vec3A, SpecularFalloff, Highlight) -> Vec3A,
    normal: Vec3A,
    falloff: SpecularFalloff,
) -> Vec3A {
    SEEN.set(None);
    // The diffuse term alone, the vectors read on the way.
    let diffuse = shade(
        normal,
        falloff,
        Highlight::Own(|at| {
            SEEN.set(Some(*at));
            0.0
        }),
    );
    let Some(at) = SEEN.get() else {
        return diffuse;
    };
    let n_dot_l = at.normal.dot(at.to_light);
    if n_dot_l < 0.0 {
        return diffuse;
    }
    let half = (at.to_light + at.to_eye).normalize();
    let mut strength = at.normal.dot(half).max(0.0).powf(at.exponent);
    if falloff == SpecularFalloff::Fade {
        strength *= n_dot_l;
    }
    diffuse + SPECULAR.get() * strength
}
