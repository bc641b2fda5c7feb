//! Faults of shading: back faces, the ambient term, the light terms.

use glam::Vec3A;

use super::{Candidate, Fault, LineScene, Planted};
use crate::parse::description::{LightSpec, MaterialSpec};
use crate::scene::{
    Highlight, HighlightColour, HighlightForm, Illumination, Light, SpecularFalloff,
};
use crate::trace::{BackFace, LightPlace};

/// The one brightness a student's tracer gives a light in place of its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightGrey {
    /// White at full strength, whatever the colour and, for a point light, the distance.
    White,
    /// The brightest channel of the colour as it arrives.
    Brightest,
    /// The mean of the colour's channels as it arrives.
    Mean,
}

impl LightGrey {
    /// The light's colour as it arrives, as the student's tracer has it.
    pub(super) fn colour(self, arriving: Vec3A) -> Vec3A {
        match self {
            LightGrey::White => Vec3A::ONE,
            LightGrey::Brightest => Vec3A::splat(arriving.max_element()),
            LightGrey::Mean => Vec3A::splat(arriving.element_sum() / 3.0),
        }
    }
}

/// How a student's tracer shades a hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShadingFault {
    /// `-shade_back` ignored: back faces black even when asked to shade them.
    ShadeBackIgnored,
    /// Back faces shaded (the normal turned toward the ray) without `-shade_back`.
    BackFacesLit,
    /// Back faces shaded with their normal not turned toward the ray, `-shade_back` or not.
    BackFacesUnturned,
    /// Each light's N·L taken as |N·L|: lit from behind too.
    AbsoluteCosine,
    /// The ambient term added once for each light.
    AmbientPerLight,
    /// No ambient term.
    AmbientMissing,
    /// The ambient light added as it is, not times the surface's diffuse colour.
    AmbientUncoloured,
    /// Back faces that should be black show the ambient term.
    AmbientOnBackFaces,
    /// Each light's term multiplied by N·L once more.
    CosineTwice,
    /// Highlights faded by N·L without `-specular_fix`, or cut with it.
    SpecularFixSwapped,
    /// The highlight worked out by another formula.
    Highlight(Highlight),
    /// A point light's attenuation worked out another way.
    Attenuation(Attenuation),
    /// The loop over the lights stopped early: before the last (form 0), or after the first
    /// (form 1).
    LightsSkipped(u8),
    /// Each directional light's direction taken as the way toward the light.
    DirectionReversed,
    /// The way toward a point light, `position - point`, never normalised: in the shading,
    /// and for the shadow ray (tested to t = 1, the light).
    PointVectorUnnormalised,
    /// The highlight of one of the scene's lights alone, the first or (`true`) the last: the
    /// others' specular terms left out.
    HighlightOneLight(bool),
    /// Each light's colour left out of the shading: every light white (with a point light's
    /// dimming, which the course's light folds into its colour), or a grey as bright as the
    /// colour's brightest channel or its channels' mean.
    LightColourIgnored(LightGrey),
    /// Each light's diffuse term with N·L as it is: a light behind the surface takes its
    /// light away.
    SignedCosine,
    /// The terms weighed by numbers check's shading fit found.
    Weighed {
        /// What the ambient term is multiplied by.
        ambient: f32,
        /// The power of each light's N·L (its term is multiplied by N·L `power - 1` more times).
        power: f32,
        /// How each light's N·L is taken where the light is behind the surface.
        cosine: Cosine,
        /// A point light's colour at distance d divided by these terms' x + y·d + z·d², not
        /// by the file's c + l·d + q·d².
        divisor: Option<[f32; 3]>,
        /// The highlight's form.
        highlight: HighlightForm,
    },
}

/// How a student's tracer takes each light's N·L where the light is behind the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cosine {
    /// The course's max(N·L, 0): that light brings nothing.
    Clamped,
    /// |N·L|: lit as if from in front.
    Absolute,
    /// N·L as it is: its diffuse term is taken away from the rest.
    Signed,
}

/// How a student's tracer dims a point light with distance d, the file giving c, l and q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Attenuation {
    /// Not at all.
    Ignored,
    /// 1 / (c + l·d + q·d): the quadratic term without its square.
    NotSquared,
    /// 1 / (q + l·d + c·d²): the terms read in the wrong order.
    Reversed,
    /// 1 / (x + y·d + z·d²), whatever the file says (check's shading fit).
    Divisor([f32; 3]),
}

impl Attenuation {
    const ALL: [Attenuation; 3] = [
        Attenuation::Ignored,
        Attenuation::NotSquared,
        Attenuation::Reversed,
    ];

    /// What the light's colour is divided by at distance `d`.
    fn divisor(&self, [c, l, q]: [f32; 3], d: f32) -> f32 {
        match self {
            Attenuation::Ignored => 1.0,
            Attenuation::NotSquared => c + l * d + q * d,
            Attenuation::Reversed => q + l * d + c * d * d,
            Attenuation::Divisor([x, y, z]) => (x + y * d + z * d * d).max(f32::MIN_POSITIVE),
        }
    }

    /// The light `light` sends to `point`, dimmed this way.
    pub(super) fn illuminate(&self, light: &Light, point: Vec3A) -> Option<Illumination> {
        let course = light.illuminate(point)?;
        Some(match *light {
            Light::Point {
                colour,
                attenuation,
                ..
            } => Illumination {
                colour: colour / self.divisor(attenuation, course.distance),
                ..course
            },
            Light::Directional { .. } => course,
        })
    }

    /// Whether some distance dims the light differently than the course's divisor does.
    fn differs(&self, [c, l, q]: [f32; 3]) -> bool {
        match self {
            Attenuation::Ignored => [c, l, q] != [1.0, 0.0, 0.0],
            Attenuation::NotSquared => q != 0.0,
            Attenuation::Reversed => c != q,
            Attenuation::Divisor(terms) => *terms != [c, l, q],
        }
    }
}

impl ShadingFault {
    pub(super) fn back_face(&self, shade_back: bool, face: BackFace) -> BackFace {
        match self {
            ShadingFault::ShadeBackIgnored => BackFace::Black,
            ShadingFault::BackFacesLit if !shade_back => BackFace::Shaded,
            ShadingFault::BackFacesUnturned => BackFace::Unturned,
            ShadingFault::AmbientOnBackFaces if face == BackFace::Black => BackFace::Ambient,
            _ => face,
        }
    }

    pub(super) fn lights_visited(&self, lights: usize) -> usize {
        match self {
            ShadingFault::LightsSkipped(0) => lights.saturating_sub(1),
            ShadingFault::LightsSkipped(_) => lights.min(1),
            _ => lights,
        }
    }

    pub(crate) fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        match self {
            ShadingFault::AmbientPerLight => term * lights as f32,
            ShadingFault::AmbientMissing => Vec3A::ZERO,
            ShadingFault::Weighed { ambient, .. } => term * ambient,
            _ => term,
        }
    }

    pub(super) fn attenuation(&self) -> Option<Attenuation> {
        match *self {
            ShadingFault::Attenuation(way) => Some(way),
            ShadingFault::Weighed { divisor, .. } => divisor.map(Attenuation::Divisor),
            _ => None,
        }
    }

    /// One light's term as the student's shading makes it: the light along `to_light`, at
    /// `place` among the scene's.
    pub(crate) fn light(
        &self,
        shade: &dyn Fn(Vec3A, SpecularFalloff, Highlight) -> Vec3A,
        normal: Vec3A,
        (to_light, place): (Vec3A, LightPlace),
        falloff: SpecularFalloff,
        highlight: Highlight,
    ) -> Vec3A {
        match *self {
            ShadingFault::HighlightOneLight(last) => {
                let lit = if last { place.of - 1 } else { 0 };
                match place.index == lit {
                    true => shade(normal, falloff, highlight),
                    false => shade(normal, falloff, Highlight::Own(|_| 0.0)),
                }
            }
            ShadingFault::AbsoluteCosine if normal.dot(to_light) < 0.0 => {
                shade(-normal, falloff, highlight)
            }
            ShadingFault::SignedCosine if normal.dot(to_light) < 0.0 => {
                shade(normal, falloff, highlight) - shade(-normal, falloff, Highlight::Absent)
            }
            ShadingFault::CosineTwice => {
                shade(normal, falloff, highlight) * normal.dot(to_light).max(0.0)
            }
            ShadingFault::SpecularFixSwapped => shade(
                normal,
                match falloff {
                    SpecularFalloff::Cut => SpecularFalloff::Fade,
                    SpecularFalloff::Fade => SpecularFalloff::Cut,
                },
                highlight,
            ),
            ShadingFault::Highlight(student) => shade(normal, falloff, student),
            ShadingFault::Weighed {
                power,
                cosine: form_of_cosine,
                highlight: form,
                ..
            } => {
                let highlight = if form == HighlightForm::default() {
                    highlight
                } else {
                    Highlight::Formed(form)
                };
                let cosine = normal.dot(to_light);
                let more_cosines = |shaded: Vec3A, cosine: f32| {
                    if power == 1.0 {
                        shaded
                    } else {
                        shaded * cosine.powf(power - 1.0)
                    }
                };
                match form_of_cosine {
                    Cosine::Absolute if cosine < 0.0 => {
                        more_cosines(shade(-normal, falloff, highlight), -cosine)
                    }
                    // The diffuse term from the other side, taken away (its highlight is the
                    // front's, which its own gate decides).
                    Cosine::Signed if cosine < 0.0 => {
                        shade(normal, falloff, highlight)
                            - more_cosines(shade(-normal, falloff, Highlight::Absent), -cosine)
                    }
                    _ => more_cosines(shade(normal, falloff, highlight), cosine.max(0.0)),
                }
            }
            _ => shade(normal, falloff, highlight),
        }
    }
}

fn only(fault: ShadingFault) -> Vec<Candidate> {
    vec![Candidate::plain(Planted::Shading(fault))]
}

pub(super) const SHADE_BACK_IGNORED: Fault = Fault {
    name: "shade_back_ignored",
    assignment: 2,
    sentence: "I ignore -shade_back: back faces stay black even when the line asks to shade them \
               (form 0), or are shaded with their normal facing away from the ray (form 1).",
    look_for: "Where a hit's normal faces away from the ray: with -shade_back, turn the normal \
               around and shade as usual; only without it is the pixel black.",
    candidates: |line: &LineScene| {
        if line.options.trace.shade_back && line.has_image() {
            Candidate::forms(
                [
                    ShadingFault::ShadeBackIgnored,
                    ShadingFault::BackFacesUnturned,
                ]
                .map(Planted::Shading),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const BACK_FACES_LIT: Fault = Fault {
    name: "back_faces_lit",
    assignment: 2,
    sentence: "I shade back faces even without -shade_back (form 0: the normal turned toward the \
               ray; 1: not turned).",
    look_for: "Where a hit's normal faces away from the ray: without -shade_back the pixel is \
               black (and nothing more is traced from it).",
    candidates: |line: &LineScene| {
        if !line.options.trace.shade_back && line.has_image() {
            Candidate::forms(
                [ShadingFault::BackFacesLit, ShadingFault::BackFacesUnturned].map(Planted::Shading),
            )
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

pub(super) const DIFFUSE_UNCLAMPED: Fault = Fault {
    name: "diffuse_unclamped",
    assignment: 2,
    sentence: "I take each light's N·L as it is, never clamped at 0: a light behind the surface \
               takes its light away from the ambient term and the other lights.",
    look_for: "The diffuse term: k_d × light × max(N·L, 0); a light behind the surface brings \
               nothing (it does not subtract).",
    candidates: |line: &LineScene| {
        // Taken away from something: the ambient term or another light.
        let description = &line.description;
        let something_lit = description.ambient != glam::Vec3::ZERO || description.lights.len() > 1;
        if line.has_image() && !line.scene.lights.is_empty() && something_lit {
            only(ShadingFault::SignedCosine)
        } else {
            Vec::new()
        }
    },
};

pub(super) const AMBIENT_UNCOLOURED: Fault = Fault {
    name: "ambient_uncoloured",
    assignment: 2,
    sentence: "I add the ambient light as it is, not multiplied by the surface's diffuse \
               colour: every object gets the same grey wash.",
    look_for: "The shading sum starts with ambient light × the material's diffuse colour (at \
               the point, for a texture), component by component.",
    candidates: |line: &LineScene| {
        let description = &line.description;
        // (Without lights, the course's pictures are flat colours, no sum of terms.)
        let lit = !line.scene.lights.is_empty();
        if line.has_image() && lit && description.ambient != glam::Vec3::ZERO {
            only(ShadingFault::AmbientUncoloured)
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
        MaterialSpec::Phong(p) => p.specular != glam::Vec3::ZERO,
        MaterialSpec::Texture(_) => false,
    })
}

/// Whether the line's picture shows highlights.
fn highlights_show(line: &LineScene) -> bool {
    line.has_image() && has_highlights(line) && !line.scene.lights.is_empty()
}

pub(super) const HIGHLIGHT_ONE_LIGHT: Fault = Fault {
    name: "highlight_one_light",
    assignment: 3,
    sentence: "My highlight comes from one light alone: the specular term is worked out once, \
               outside the loop over the lights, for the first light (form 0) or the last, \
               where the loop left its index (form 1).",
    look_for: "The loop over the lights: each light's specular term, like its diffuse term, is \
               added inside it, with that light's direction and colour.",
    candidates: |line: &LineScene| {
        if highlights_show(line) && line.scene.lights.len() > 1 {
            Candidate::forms(
                [false, true].map(|last| Planted::Shading(ShadingFault::HighlightOneLight(last))),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const SPECULAR_FIX: Fault = Fault {
    name: "specular_fix",
    assignment: 3,
    sentence: "My highlights fade by N·L where the line does not ask for -specular_fix (or do not \
               fade where it does).",
    look_for: "The specular term: without -specular_fix it is cut where N·L < 0 and not faded; \
               with it, multiplied by N·L (the handout's fix).",
    candidates: |line: &LineScene| {
        if highlights_show(line) {
            only(ShadingFault::SpecularFixSwapped)
        } else {
            Vec::new()
        }
    },
};

pub(super) const SPECULAR_UNCLAMPED: Fault = Fault {
    name: "specular_unclamped",
    assignment: 3,
    sentence: "My highlight is (N·H)^q without clamping N·H at 0, worked out even where the light \
               is behind the surface.",
    look_for: "The specular term: max(N·H, 0)^q, and none at all where N·L < 0 (clamp the \
               specular term as the diffuse one is clamped).",
    candidates: |line: &LineScene| {
        if highlights_show(line) {
            only(ShadingFault::Highlight(Highlight::Unclamped))
        } else {
            Vec::new()
        }
    },
};

pub(super) const HALF_VECTOR: Fault = Fault {
    name: "half_vector",
    assignment: 3,
    sentence: "My highlight's half vector is not normalize(L + V) with V pointing toward the eye \
               (form 0: V taken as the ray's direction; 1: L + V not normalised; 2: Phong's \
               (R·V)^q instead of (N·H)^q).",
    look_for: "The specular term: H = normalize(L + V), L toward the light and V toward the \
               eye (minus the ray's direction), both unit; then k_s (N·H)^q.",
    candidates: |line: &LineScene| {
        if !highlights_show(line) {
            return Vec::new();
        }
        Candidate::forms(
            [
                Highlight::HalfFromRay,
                Highlight::HalfNotUnit,
                Highlight::Mirror,
            ]
            .map(|h| Planted::Shading(ShadingFault::Highlight(h))),
        )
    },
};

pub(super) const SPECULAR_MISSING: Fault = Fault {
    name: "specular_missing",
    assignment: 3,
    sentence: "No object shows a highlight: my shading never adds the specular term, or works it \
               out as nothing wherever the eye looks (V taken along the ray, away from the eye, \
               puts every highlight out of sight).",
    look_for: "The specular term, for each light: k_s (N·H)^q times the light's colour, with \
               H = normalize(L + V), L toward the light and V toward the eye (minus the ray's \
               direction).",
    candidates: |line: &LineScene| {
        if highlights_show(line) {
            only(ShadingFault::Highlight(Highlight::Absent))
        } else {
            Vec::new()
        }
    },
};

pub(super) const SPECULAR_COLOUR: Fault = Fault {
    name: "specular_colour",
    assignment: 3,
    sentence: "My highlight takes the wrong colour: the material's diffuse colour (form 0), or \
               white, the light's colour alone (form 1), not its specularColor; or its \
               specularColor not times the light's colour (form 2: k_s (N·H)^q added as it is, \
               so a dim, coloured or distant light makes a full highlight).",
    look_for: "The specular term: k_s (N·H)^q times the light's colour (the `col` \
               getIllumination returns, a point light's dimming in it), k_s being the \
               material's specularColor.",
    candidates: |line: &LineScene| {
        if !highlights_show(line) {
            return Vec::new();
        }
        // A form shows only where a material with a highlight takes another colour with it.
        // Form 2 only where a light is not white at full strength.
        let unlit_shows = line.scene.lights.iter().any(|light| match light {
            Light::Directional { colour, .. } => *colour != Vec3A::ONE,
            Light::Point {
                colour,
                attenuation,
                ..
            } => *colour != Vec3A::ONE || *attenuation != [1.0, 0.0, 0.0],
        });
        let shows = |colour: HighlightColour| {
            line.description.materials.iter().any(|m| match m {
                MaterialSpec::Phong(p) if p.specular != glam::Vec3::ZERO => {
                    let specular = p.specular.into();
                    colour.of(p.diffuse.into(), specular) != specular
                        || (!colour.lit() && unlit_shows)
                }
                _ => false,
            })
        };
        HighlightColour::OTHERS
            .into_iter()
            .filter(|&colour| shows(colour))
            .filter_map(|colour| {
                let planted =
                    Planted::Shading(ShadingFault::Highlight(Highlight::Formed(HighlightForm {
                        colour,
                        ..HighlightForm::default()
                    })));
                Some(Candidate::with(planted, "form", colour.form()? as f64))
            })
            .collect()
    },
};

pub(super) const LIGHT_COLOUR_IGNORED: Fault = Fault {
    name: "light_colour_ignored",
    assignment: 2,
    sentence: "My shading leaves out the light's colour (the `col` getIllumination returns): \
               every light shines white at full strength, coloured or dim, near or far (form 0), \
               or grey, as bright as its colour's brightest channel (form 1) or the mean of its \
               channels (form 2).",
    look_for: "Each light's diffuse (and, from assignment 3, specular) term is multiplied by the \
               colour getIllumination returns for the point, which holds a point light's \
               attenuation too.",
    candidates: |line: &LineScene| {
        let shows = line.description.lights.iter().any(|light| match light {
            LightSpec::Directional { colour, .. } => *colour != glam::Vec3::ONE,
            LightSpec::Point {
                colour,
                attenuation,
                ..
            } => *colour != glam::Vec3::ONE || *attenuation != [1.0, 0.0, 0.0],
        });
        if line.has_image() && shows {
            Candidate::forms(
                [LightGrey::White, LightGrey::Brightest, LightGrey::Mean]
                    .map(|grey| Planted::Shading(ShadingFault::LightColourIgnored(grey))),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const ATTENUATION: Fault = Fault {
    name: "attenuation",
    assignment: 4,
    sentence: "My point lights dim with distance the wrong way (form 0: not at all; 1: q·d \
               where q·d² is meant; 2: the constant and quadratic terms swapped).",
    look_for: "A point light's colour at distance d is divided by c + l·d + q·d², with c, l \
               and q in the order the file gives them after `attenuation`.",
    candidates: |line: &LineScene| {
        if !line.has_image() {
            return Vec::new();
        }
        let terms: Vec<[f32; 3]> = line
            .description
            .lights
            .iter()
            .filter_map(|l| match l {
                LightSpec::Point { attenuation, .. } => Some(*attenuation),
                LightSpec::Directional { .. } => None,
            })
            .collect();
        Candidate::forms_shown(
            Attenuation::ALL.map(|way| Planted::Shading(ShadingFault::Attenuation(way))),
            Attenuation::ALL.map(|way| terms.iter().any(|t| way.differs(*t))),
        )
    },
};

/// Whether the line has a shaded picture and a light of the kind `of` says.
fn shines(line: &LineScene, of: impl Fn(&Light) -> bool) -> bool {
    line.has_image() && line.scene.lights.iter().any(of)
}

pub(super) const LIGHT_DIRECTION: Fault = Fault {
    name: "light_direction",
    assignment: 2,
    sentence: "My directional lights shine from the wrong side: I take the file's direction, the \
               way the light travels, as the way toward the light.",
    look_for: "DirectionalLight::getIllumination: the direction toward the light is minus the \
               file's direction (normalised), for the shading and for the shadow ray alike.",
    candidates: |line: &LineScene| {
        if shines(line, |light| matches!(light, Light::Directional { .. })) {
            only(ShadingFault::DirectionReversed)
        } else {
            Vec::new()
        }
    },
};

pub(super) const LIGHT_VECTOR: Fault = Fault {
    name: "light_vector",
    assignment: 4,
    sentence: "My shading takes the vector toward a point light, its position minus the point, \
               without normalising it: N·L, and the highlight's half vector, grow with the \
               light's distance.",
    look_for: "PointLight::getIllumination: the direction toward the light is (position - p) \
               normalised; the distance, for the attenuation and the shadow ray's end, is the \
               length before it is normalised.",
    candidates: |line: &LineScene| {
        if shines(line, |light| matches!(light, Light::Point { .. })) {
            only(ShadingFault::PointVectorUnnormalised)
        } else {
            Vec::new()
        }
    },
};

pub(super) const LIGHTS_SKIPPED: Fault = Fault {
    name: "lights_skipped",
    assignment: 2,
    sentence: "My loop over the lights stops early: the last light never shades (form 0: i < n - \
               1), or only the first one does (form 1).",
    look_for: "The loop over the scene's lights: for (i = 0; i < numLights; i++), each light's \
               diffuse and specular terms added.",
    candidates: |line: &LineScene| {
        let lights = line.scene.lights.len();
        if !line.has_image() || lights == 0 {
            return Vec::new();
        }
        // With two lights, only the first is the same as all but the last.
        let forms: &[u8] = if lights >= 3 { &[0, 1] } else { &[0] };
        Candidate::forms(
            forms
                .iter()
                .map(|&form| Planted::Shading(ShadingFault::LightsSkipped(form))),
        )
    },
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attenuation_divisors_by_hand() {
        let terms = [1.0, 0.5, 0.25];
        // The course's at d = 2: 1 + 1 + 1 = 3.
        assert_eq!(Attenuation::Ignored.divisor(terms, 2.0), 1.0);
        assert_eq!(Attenuation::NotSquared.divisor(terms, 2.0), 2.5);
        assert_eq!(Attenuation::Reversed.divisor(terms, 2.0), 5.25);
        assert!(!Attenuation::Ignored.differs([1.0, 0.0, 0.0]));
        assert!(!Attenuation::NotSquared.differs([1.0, 0.5, 0.0]));
        assert!(!Attenuation::Reversed.differs([0.5, 1.0, 0.5]));
        // A point light of colour 3 at distance 2 (c = 1, l = 0.5, q = 0.25).
        let light = Light::Point {
            position: Vec3A::new(0.0, 2.0, 0.0),
            colour: Vec3A::splat(3.0),
            attenuation: terms,
        };
        let course = light.illuminate(Vec3A::ZERO).unwrap();
        assert_eq!(course.colour, Vec3A::ONE);
        let lit = Attenuation::NotSquared
            .illuminate(&light, Vec3A::ZERO)
            .unwrap();
        assert_eq!(lit.colour, Vec3A::splat(1.2));
        assert_eq!((lit.to_light, lit.distance), (Vec3A::Y, 2.0));
    }
}
