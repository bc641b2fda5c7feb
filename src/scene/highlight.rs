//! A highlight's strength: the course's Blinn-Torrance term, k_s max(N·H, 0)^q with
//! H = normalize(L + V), and the family of ways a student's tracer writes it otherwise (check's
//! fault library plants some, and its shading fit searches the whole family).

use glam::Vec3A;

/// How a highlight is worked out.
#[derive(Debug, Clone, Copy, Default)]
pub enum Highlight {
    /// k_s max(N·H, 0)^q with H = normalize(L + V), V toward the eye, where N·L ≥ 0.
    #[default]
    Course,
    /// (N·H)^q with N·H not clamped at 0, and worked out where the light is behind the surface
    /// too (a negative base with a fractional exponent gives no highlight).
    Unclamped,
    /// H made from the ray's own direction, which points away from the eye: normalize(L + d).
    HalfFromRay,
    /// H = L + V, not made unit length.
    HalfNotUnit,
    /// Phong's mirror term (R·V)^q, R the light's direction mirrored about N, instead of
    /// Blinn's (N·H)^q.
    Mirror,
    /// No highlight at all: the specular term never added.
    Absent,
    /// Any member of the family (check's shading fit finds one).
    Formed(HighlightForm),
    /// A highlight's strength (before k_s, the light's colour and `-specular_fix`'s fade) as a
    /// tracer of one's own works it out, where the light is behind the surface too: so that a
    /// test can write a mistake in a form the family does not have.
    Own(fn(&HighlightAt) -> f32),
}

impl PartialEq for Highlight {
    fn eq(&self, other: &Highlight) -> bool {
        match (self, other) {
            (Highlight::Own(mine), Highlight::Own(theirs)) => std::ptr::fn_addr_eq(*mine, *theirs),
            (Highlight::Formed(mine), Highlight::Formed(theirs)) => mine == theirs,
            _ => std::mem::discriminant(self) == std::mem::discriminant(other),
        }
    }
}

/// What a highlight is worked out from at a hit.
#[derive(Debug, Clone, Copy)]
pub struct HighlightAt {
    /// The unit normal, on the eye's side of the surface.
    pub normal: Vec3A,
    /// Unit, toward the light.
    pub to_light: Vec3A,
    /// Unit, toward the eye (minus the ray's direction).
    pub to_eye: Vec3A,
    /// The material's exponent q.
    pub exponent: f32,
}

/// How the base of a highlight's power is kept from going below 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HighlightBase {
    /// max(base, 0): the course's.
    #[default]
    Clamped,
    /// |base|.
    Absolute,
    /// Not at all: a negative base to a fractional power is no number, and no highlight.
    Whole,
}

/// Which colour a highlight's strength multiplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HighlightColour {
    /// The material's `specularColor`: the course's.
    #[default]
    Specular,
    /// The material's diffuse colour.
    Diffuse,
    /// White: the light's colour alone.
    White,
    /// The material's `specularColor`, but not times the light's colour: every light's
    /// highlight as a white light's at full strength.
    Unlit,
}

impl HighlightColour {
    /// Every colour, the course's first.
    pub const ALL: [HighlightColour; 4] = [
        HighlightColour::Specular,
        HighlightColour::Diffuse,
        HighlightColour::White,
        HighlightColour::Unlit,
    ];

    /// The other colours, in the order of `specular_colour`'s forms.
    pub const OTHERS: [HighlightColour; 3] = [
        HighlightColour::Diffuse,
        HighlightColour::White,
        HighlightColour::Unlit,
    ];

    /// The colour it takes on a material of these `diffuse` and `specular` colours.
    #[inline]
    pub fn of(self, diffuse: Vec3A, specular: Vec3A) -> Vec3A {
        match self {
            HighlightColour::Specular | HighlightColour::Unlit => specular,
            HighlightColour::Diffuse => diffuse,
            HighlightColour::White => Vec3A::ONE,
        }
    }

    /// Whether the highlight is multiplied by the light's colour, as the course's is.
    #[inline]
    pub fn lit(self) -> bool {
        self != HighlightColour::Unlit
    }

    /// Its form of `specular_colour` (none for the course's).
    pub fn form(self) -> Option<usize> {
        HighlightColour::OTHERS.iter().position(|&c| c == self)
    }
}

/// One member of the family of highlights: each field's default is the course's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HighlightForm {
    /// V along the ray's own direction (away from the eye), not toward the eye.
    pub view_along_ray: bool,
    /// Phong's (R·V)^q, R the light's direction mirrored about N, not Blinn's (N·H)^q.
    pub mirror: bool,
    /// H = L + V not divided by its length.
    pub half_not_unit: bool,
    /// What H is multiplied by once made (1/2: the mean of L and V).
    pub half_scale: f32,
    /// How the base is kept from below 0.
    pub base: HighlightBase,
    /// Worked out where the light is behind the surface (N·L < 0) too.
    pub ungated: bool,
    /// No highlight at all, whatever the rest says: the specular term never added.
    pub absent: bool,
    /// The colour the strength multiplies (on a material with a highlight).
    pub colour: HighlightColour,
}

impl Default for HighlightForm {
    fn default() -> HighlightForm {
        HighlightForm {
            view_along_ray: false,
            mirror: false,
            half_not_unit: false,
            half_scale: 1.0,
            base: HighlightBase::Clamped,
            ungated: false,
            absent: false,
            colour: HighlightColour::Specular,
        }
    }
}

impl HighlightForm {
    /// The strength (k_s's multiplier) at `at`.
    #[inline]
    pub fn strength(&self, at: &HighlightAt) -> f32 {
        if self.absent {
            return 0.0;
        }
        let view = if self.view_along_ray {
            -at.to_eye
        } else {
            at.to_eye
        };
        let base = if self.mirror {
            let mirrored = 2.0 * at.normal.dot(at.to_light) * at.normal - at.to_light;
            mirrored.dot(view)
        } else {
            let half = at.to_light + view;
            let half = if self.half_not_unit {
                half
            } else {
                half.normalize_or_zero()
            };
            at.normal.dot(half) * self.half_scale
        };
        let term = match self.base {
            HighlightBase::Clamped => base.max(0.0).powf(at.exponent),
            HighlightBase::Absolute => base.abs().powf(at.exponent),
            HighlightBase::Whole => base.powf(at.exponent),
        };
        if term.is_nan() { 0.0 } else { term }
    }
}

impl Highlight {
    /// Whether there is no highlight where the light is behind the surface (N·L < 0).
    #[inline]
    pub fn gated(&self) -> bool {
        match self {
            Highlight::Own(_) => false,
            Highlight::Course => true,
            other => !other.form().is_some_and(|form| form.ungated),
        }
    }

    /// The member of the family this is (none for a tracer's own).
    pub fn form(&self) -> Option<HighlightForm> {
        let course = HighlightForm::default();
        Some(match *self {
            Highlight::Course => course,
            Highlight::Unclamped => HighlightForm {
                base: HighlightBase::Whole,
                ungated: true,
                ..course
            },
            Highlight::HalfFromRay => HighlightForm {
                view_along_ray: true,
                ..course
            },
            Highlight::HalfNotUnit => HighlightForm {
                half_not_unit: true,
                ..course
            },
            Highlight::Mirror => HighlightForm {
                mirror: true,
                ..course
            },
            Highlight::Absent => HighlightForm {
                absent: true,
                ..course
            },
            Highlight::Formed(form) => form,
            Highlight::Own(_) => return None,
        })
    }

    /// The colour the strength multiplies on a material with a highlight.
    #[inline]
    pub fn colour(&self) -> HighlightColour {
        match self {
            Highlight::Formed(form) => form.colour,
            _ => HighlightColour::Specular,
        }
    }

    /// The strength (k_s's multiplier) at `at`, where the highlight is worked out at all.
    #[inline]
    pub fn strength(&self, at: &HighlightAt) -> f32 {
        match self {
            // The course's, on every shaded hit: the family's most general form not asked.
            Highlight::Course => {
                let half = (at.to_light + at.to_eye).normalize_or_zero();
                at.normal.dot(half).max(0.0).powf(at.exponent)
            }
            Highlight::Own(strength) => strength(at),
            other => other.form().map_or(0.0, |form| form.strength(at)),
        }
    }
}
