//! Faults of the rays a hit spawns: shadow rays' range, the mirror direction, the index of
//! refraction, and the limits on recursion.

use glam::Vec3A;

use super::{Candidate, Fault, LineScene, Planted};

/// How a student's tracer makes shadow, mirror and glass rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RayFault {
    /// Shadow and secondary rays start with no offset: surfaces shadow and reflect themselves.
    NoOffset,
    /// Only these rays start with no offset: shadow rays (`secondary` false), or mirror and
    /// glass rays; the others leave as the course's do.
    NoOffsetFor {
        /// Mirror and glass rays, not shadow rays.
        secondary: bool,
    },
    /// Shadow rays toward a point light go on past the light.
    PastLight,
    /// Shadow rays cast away from the light, along the way its light travels: for every
    /// light, or for point lights alone.
    ShadowReversed {
        /// Only the shadow rays of point lights.
        points_only: bool,
    },
    /// The limits tested after the ray's intersection: mirror and glass rays one bounce past
    /// `-bounces` (and, with `weight_too`, below `-weight`) still cast, bringing the background
    /// where they meet nothing.
    LimitsTestedLate {
        /// `-weight` tested late too.
        weight_too: bool,
    },
    /// The colours of a hit's mirror and glass rays added inside the loop over the lights:
    /// once for each light.
    SecondaryPerLight,
    /// No shadow ray ever meets anything: every light reaches every point.
    NoShadows,
    /// No mirror or glass ray traced (`-bounces` never read), or (`glass_only`) no glass ray.
    SecondaryMissing {
        /// Only the glass rays left out.
        glass_only: bool,
    },
    /// The mirror direction with the wrong sign: d + 2(d·n)n.
    MirrorSign,
    /// η_t / η_i where η_i / η_t is meant (the ratio inverted).
    InvertedIndex,
    /// The same ratio whichever way the ray crosses: 1 / index, or (`index_over_one`) index.
    RatioUnturned {
        /// index / 1, not 1 / index.
        index_over_one: bool,
    },
    /// One bounce more or fewer than `-bounces` (the signed difference).
    Bounces(i32),
    /// `-weight` ignored: every mirror and glass ray is traced.
    NoCutoff,
    /// A refracted ray traced even on total internal reflection, in the way of this form.
    PastCriticalAngle(CriticalAngle),
    /// An allowed answer (check/choices.rs): shadow and secondary rays ignore hits nearer than
    /// this fixed t (the course's "epsilon"), instead of raycast's clearance scaled to the hit.
    FixedStart(f32),
    /// Shadow and secondary rays start this far off the surface along its normal (check's fit
    /// of the offset), not by raycast's clearance scaled to the hit.
    NormalOffset(f32),
    /// An allowed answer: a hit exactly at the light's distance blocks it (t ≤ distance, not
    /// t < distance).
    ShadowToLight,
    /// An allowed answer: this cut-off weight where the line gives `-bounces` but no `-weight`.
    DefaultWeight(f32),
    /// Every glass refracts as if its index were this (check's fit of the index).
    IndexAs(f32),
    /// Mirror and glass rays cut off at this weight whatever `-weight` says (check's fit).
    CutoffAt(f32),
    /// What a mirror ray (or, with `transparent`, a glass ray) brings back added whole, not
    /// multiplied by the material's colour for it.
    ColourIgnored {
        /// Glass rays', not mirror rays'.
        transparent: bool,
    },
    /// What a mirror ray (or, with `transparent`, a glass ray) brings back multiplied by the
    /// material's specular colour, not its colour for the ray.
    SpecularCarried {
        /// Glass rays', not mirror rays'.
        transparent: bool,
    },
    /// Snell's formula written otherwise than the course's, in the way of this form.
    Snell(SnellForm),
    /// The mirror direction as normalize(d + β (d·n) n), β being this (check's fit; the
    /// course's is −2).
    MirrorFactor(f32),
    /// What a mirror ray (or, with `transparent`, a glass ray) brings back multiplied by the
    /// material's colour for it raised to this power (check's fit; the course's is 1, and 0 is
    /// the colour left out).
    ColourPower {
        /// Glass rays', not mirror rays'.
        transparent: bool,
        /// The power.
        power: f32,
    },
    /// Shadow rays toward a point light stop at another t than the light's distance.
    ShadowReach(ShadowReach),
    /// These mirror or glass rays, where they meet nothing, bring back black, not the
    /// background.
    MissesBlack(Secondary),
    /// A surface that reflects or refracts shows what its rays bring back instead of its own
    /// terms: those left out (`weighed` false), or weighed by one minus its reflective and
    /// transparent colours.
    LocalReplaced {
        /// Weighed by 1 − reflective − transparent (at least 0), not left out.
        weighed: bool,
    },
    /// Glass lets light through to what it shadows, in this way: an allowed answer (the
    /// handout's optional transparent shadows), or, `Whole`, the fault `shadow_skips_glass`.
    ThroughGlass(crate::trace::ThroughGlass),
}

/// Which of a hit's secondary rays a fault changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Secondary {
    /// Mirror and glass rays alike.
    Both,
    /// Mirror rays alone.
    Mirror,
    /// Glass rays alone.
    Glass,
}

impl Secondary {
    /// Whether a mirror ray (or, with `transparent`, a glass ray) is one of these.
    fn includes(self, transparent: bool) -> bool {
        match self {
            Secondary::Both => true,
            Secondary::Mirror => !transparent,
            Secondary::Glass => transparent,
        }
    }
}

/// Where a student's shadow ray toward a point light stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowReach {
    /// At t = 1 along a unit direction: one unit from the point, short of a light further off.
    One,
    /// At t = the light's distance along the unnormalised direction to it: the distance
    /// squared, past a light further than one unit.
    Squared,
}

/// How a student's Snell's formula differs from the course's,
/// T = [η (N·I) − √(1 − η² (1 − (N·I)²))] N − η I with I = −d and N facing the ray; written
/// with c = −N·d, T = η d + (η c − √k) N.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SnellForm {
    /// Leaving the object, N is the surface's outward normal, not turned to face the ray.
    OutwardNormal,
    /// The signs of T = η d + (η c − √k) N's three terms, each bit one flipped: 1 the η d
    /// term's, 2 the η c term's, 4 the root's (3 is the course's formula with I = d, not −d).
    Signs(u8),
}

/// Every sign of Snell's formula's terms that a student's may have wrong, one pattern a form.
const SNELL_SIGNS: [u8; 7] = [1, 2, 3, 4, 5, 6, 7];

/// What a student's refraction does where the square root's argument is negative.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CriticalAngle {
    /// Takes it as 0: the ray leaves along the surface.
    Grazing,
    /// Takes its absolute value.
    Absolute,
    /// Keeps the ray's direction, unbent.
    Straight,
    /// Takes the root of the negative number as it comes: a direction of NaNs, which meets
    /// nothing, so the background shows through the glass.
    NotANumber,
    /// Sends the glass ray along the mirror direction instead.
    Mirrored,
}

impl RayFault {
    pub(super) fn shadow_end(&self, distance: f32) -> Option<f32> {
        // A directional light is infinitely far: every form reaches it.
        match self {
            RayFault::PastLight => Some(f32::MAX),
            // A range that ends before it begins: nothing is ever in it.
            RayFault::NoShadows => Some(-1.0),
            RayFault::ShadowToLight => Some(distance),
            RayFault::ShadowReach(ShadowReach::One) if distance.is_finite() => Some(1.0),
            RayFault::ShadowReach(ShadowReach::Squared) if distance.is_finite() => {
                Some(distance * distance)
            }
            _ => None,
        }
    }

    /// The least t of a ray leaving a surface of unit `normal` along `direction`: 0, for no
    /// offset; the fixed epsilon; as far as takes the ray `offset` off the surface.
    pub(super) fn start_t(&self, direction: Vec3A, normal: Vec3A) -> Option<f32> {
        match *self {
            RayFault::NoOffset | RayFault::NoOffsetFor { secondary: false } => Some(0.0),
            RayFault::FixedStart(epsilon) => Some(epsilon),
            RayFault::NormalOffset(offset) => {
                Some(crate::trace::start_t(offset, direction, normal))
            }
            _ => None,
        }
    }

    /// [`RayFault::start_t`] for a mirror or glass ray leaving a hit of `clearance`.
    pub(super) fn secondary_start_t(
        &self,
        clearance: f32,
        direction: Vec3A,
        normal: Vec3A,
    ) -> Option<f32> {
        match *self {
            RayFault::NoOffsetFor { secondary: true } => Some(0.0),
            RayFault::NoOffsetFor { secondary: false } => {
                Some(crate::trace::start_t(clearance, direction, normal))
            }
            _ => self.start_t(direction, normal),
        }
    }

    pub(super) fn through_glass(&self) -> Option<crate::trace::ThroughGlass> {
        match *self {
            RayFault::ThroughGlass(through) => Some(through),
            _ => None,
        }
    }

    pub(super) fn bounces(&self, bounces: u32) -> u32 {
        match *self {
            RayFault::Bounces(by) => bounces.saturating_add_signed(by),
            RayFault::SecondaryMissing { glass_only: false } => 0,
            _ => bounces,
        }
    }

    pub(super) fn cutoff_weight(&self, weight: f32) -> f32 {
        match self {
            RayFault::NoCutoff => 0.0,
            RayFault::DefaultWeight(default) if weight == 0.0 => *default,
            RayFault::CutoffAt(cutoff) => *cutoff,
            _ => weight,
        }
    }

    /// What a mirror (or glass) ray's colour is multiplied by, where not the material's
    /// `colour` for it.
    pub(super) fn carried(
        &self,
        colour: Vec3A,
        transparent: bool,
        surface: &crate::scene::Surface<'_>,
    ) -> Option<Vec3A> {
        match *self {
            RayFault::ColourIgnored { transparent: which } if which == transparent => {
                Some(Vec3A::ONE)
            }
            RayFault::SpecularCarried { transparent: which } if which == transparent => {
                Some(surface.specular())
            }
            RayFault::SecondaryMissing { glass_only: true } if transparent => Some(Vec3A::ZERO),
            RayFault::ColourPower {
                transparent: which,
                power,
            } if which == transparent => Some(colour.powf(power)),
            _ => None,
        }
    }

    /// What a hit's own terms are multiplied by on `surface`, where not 1.
    pub(super) fn local_weight(&self, surface: &crate::scene::Surface<'_>) -> Option<Vec3A> {
        let RayFault::LocalReplaced { weighed } = *self else {
            return None;
        };
        let (reflective, transparent) = (surface.reflective(), surface.transparent());
        if reflective == Vec3A::ZERO && transparent == Vec3A::ZERO {
            return None;
        }
        Some(if weighed {
            (Vec3A::ONE - reflective - transparent).max(Vec3A::ZERO)
        } else {
            Vec3A::ZERO
        })
    }

    /// What a mirror (or glass) ray that meets nothing brings back, where not the background.
    pub(super) fn escaped(&self, transparent: bool) -> Option<Vec3A> {
        match *self {
            RayFault::MissesBlack(which) if which.includes(transparent) => Some(Vec3A::ZERO),
            _ => None,
        }
    }

    pub(super) fn reflect(&self, direction: Vec3A, normal: Vec3A) -> Option<Vec3A> {
        match *self {
            RayFault::MirrorSign => Some(direction + 2.0 * direction.dot(normal) * normal),
            RayFault::MirrorFactor(factor) => {
                Some((direction + factor * direction.dot(normal) * normal).normalize())
            }
            _ => None,
        }
    }

    pub(super) fn refract(
        &self,
        direction: Vec3A,
        normal: Vec3A,
        ratio: f32,
        inside: bool,
    ) -> Option<Vec3A> {
        // Either form leaves the radicand, so total internal reflection, as it was.
        match *self {
            RayFault::Snell(SnellForm::OutwardNormal) if inside => {
                return crate::trace::refract(direction, -normal, ratio);
            }
            RayFault::Snell(SnellForm::Signs(flipped)) => {
                let k = crate::trace::refraction_radicand(direction, normal, ratio);
                if k < 0.0 {
                    return None;
                }
                let sign = |bit: u8| if flipped & bit == 0 { 1.0 } else { -1.0 };
                let c = -normal.dot(direction);
                let t = sign(1) * ratio * direction
                    + (sign(2) * ratio * c - sign(4) * k.sqrt()) * normal;
                return t.try_normalize();
            }
            _ => {}
        }
        let RayFault::PastCriticalAngle(way) = *self else {
            return None;
        };
        let k = crate::trace::refraction_radicand(direction, normal, ratio);
        if k >= 0.0 {
            return None;
        }
        let root = match way {
            CriticalAngle::Grazing => 0.0,
            CriticalAngle::Absolute => (-k).sqrt(),
            CriticalAngle::Straight => return Some(direction),
            CriticalAngle::NotANumber => return Some(Vec3A::NAN),
            CriticalAngle::Mirrored => return Some(crate::trace::reflect(direction, normal)),
        };
        Some(crate::trace::refracted(direction, normal, ratio, root))
    }

    pub(super) fn crossing_ratio(&self, index: f32, inside: bool) -> Option<f32> {
        match self {
            RayFault::InvertedIndex => Some(1.0 / crate::trace::crossing_ratio(index, inside)),
            RayFault::RatioUnturned { index_over_one } => {
                Some(if *index_over_one { index } else { 1.0 / index })
            }
            RayFault::IndexAs(instead) => Some(crate::trace::crossing_ratio(*instead, inside)),
            _ => None,
        }
    }
}

fn only(fault: RayFault) -> Vec<Candidate> {
    vec![Candidate::plain(Planted::Ray(fault))]
}

/// Whether any material of the line's scene reflects (or, with `transparent`, refracts) with a
/// colour other than white: there a colour left out changes the picture.
pub(crate) fn has_tinted_material(line: &LineScene, transparent: bool) -> bool {
    material_colours(line, transparent).any(|colour| colour != glam::Vec3::ONE)
}

/// Whether a Phong material of the line that reflects (or, with `transparent`, refracts) has
/// a specular colour other than its colour for that ray.
fn specular_differs(line: &LineScene, transparent: bool) -> bool {
    line.description.materials.iter().any(|m| match m {
        crate::parse::description::MaterialSpec::Phong(p) => {
            let colour = if transparent {
                p.transparent
            } else {
                p.reflective
            };
            colour != glam::Vec3::ZERO && colour != p.specular
        }
        crate::parse::description::MaterialSpec::Texture(_) => false,
    })
}

/// The reflective (or, with `transparent`, transparent) colours of the line's Phong materials
/// that reflect (or refract).
fn material_colours(line: &LineScene, transparent: bool) -> impl Iterator<Item = glam::Vec3> + '_ {
    line.description
        .materials
        .iter()
        .filter_map(move |m| match m {
            crate::parse::description::MaterialSpec::Phong(p) => Some(if transparent {
                p.transparent
            } else {
                p.reflective
            }),
            crate::parse::description::MaterialSpec::Texture(_) => None,
        })
        .filter(|&colour| colour != glam::Vec3::ZERO)
}

/// The index of refraction of the line's glass, where it shows glass and all of it has one.
pub(crate) fn glass_index(line: &LineScene) -> Option<f32> {
    let mut indices = line.description.materials.iter().filter_map(|m| match m {
        crate::parse::description::MaterialSpec::Phong(p) if p.transparent != glam::Vec3::ZERO => {
            Some(p.index_of_refraction)
        }
        _ => None,
    });
    let first = indices.next()?;
    (bounces(line) && indices.all(|index| index == first)).then_some(first)
}

/// Whether the line traces mirror or glass rays.
pub(crate) fn bounces(line: &LineScene) -> bool {
    line.options.trace.bounces > 0 && line.has_image()
}

/// Whether any material of the line's scene reflects, or (with `transparent`) refracts.
pub(crate) fn has_material(line: &LineScene, transparent: bool) -> bool {
    material_colours(line, transparent).next().is_some()
}

pub(super) const SHADOW_ACNE: Fault = Fault {
    name: "shadow_acne",
    assignment: 4,
    sentence: "My shadow, mirror and glass rays start exactly on the surface, which then shadows \
               and reflects itself in speckles (form 0: all of them; form 1: the shadow rays \
               alone; form 2: the mirror and glass rays alone).",
    look_for: "Where a shadow or secondary ray is made: start it a little off the surface (by \
               a distance that grows with the point's coordinates), or ignore hits nearer than \
               a small epsilon (the course's 1e-4); the same for shadow, mirror and glass rays.",
    candidates: |line: &LineScene| {
        let shadows = line.has_image() && line.options.trace.shadows;
        let secondary = bounces(line) && (has_material(line, false) || has_material(line, true));
        // Where a line casts one kind of ray, its form draws what form 0 draws.
        Candidate::forms_shown(
            [
                RayFault::NoOffset,
                RayFault::NoOffsetFor { secondary: false },
                RayFault::NoOffsetFor { secondary: true },
            ]
            .map(Planted::Ray),
            [
                line.has_image() && (line.options.trace.shadows || line.options.trace.bounces > 0),
                shadows && secondary,
                shadows && secondary,
            ],
        )
    },
};

pub(super) const SHADOW_REACH: Fault = Fault {
    name: "shadow_reach",
    assignment: 4,
    sentence: "My shadow rays toward a point light stop at the wrong t (form 0: t = 1 along a \
               unit direction, so only what lies within one unit of the point shadows it; 1: \
               t = the light's distance along the unnormalised direction to the light, so they \
               reach the distance squared).",
    look_for: "The shadow ray's tmax toward a point light: with a unit direction, the distance \
               to the light; with the direction light - point left unnormalised, 1.",
    candidates: |line: &LineScene| {
        if line.has_image() && line.options.trace.shadows && has_point_light(line) {
            Candidate::forms(
                [ShadowReach::One, ShadowReach::Squared]
                    .map(|reach| Planted::Ray(RayFault::ShadowReach(reach))),
            )
        } else {
            Vec::new()
        }
    },
};

/// Whether the line's scene has a point light.
fn has_point_light(line: &LineScene) -> bool {
    line.description
        .lights
        .iter()
        .any(|l| matches!(l, crate::parse::description::LightSpec::Point { .. }))
}

pub(super) const SHADOW_PAST_LIGHT: Fault = Fault {
    name: "shadow_past_light",
    assignment: 4,
    sentence: "My shadow rays toward a point light go on past the light, so things behind it \
               cast shadows.",
    look_for: "The shadow ray's tmax toward a point light: the distance to the light, not \
               infinity.",
    candidates: |line: &LineScene| {
        if line.has_image() && line.options.trace.shadows && has_point_light(line) {
            only(RayFault::PastLight)
        } else {
            Vec::new()
        }
    },
};

pub(super) const SHADOW_DIRECTION: Fault = Fault {
    name: "shadow_direction",
    assignment: 4,
    sentence: "My shadow rays go away from the light, along the way its light travels (from the \
               light to the point, or a directional light's direction as the file gives it): \
               what lies behind the point casts the shadows, and a lit side shadows itself \
               (form 0: for every light; form 1: for point lights alone).",
    look_for: "The shadow ray starts at the point and heads toward the light: the same unit \
               vector L as the diffuse term's (for a directional light, minus its direction).",
    candidates: |line: &LineScene| {
        if !line.has_image() || !line.options.trace.shadows || line.scene.lights.is_empty() {
            return Vec::new();
        }
        // For point lights alone differs from every light only where both kinds shine.
        let directional = line
            .description
            .lights
            .iter()
            .any(|l| matches!(l, crate::parse::description::LightSpec::Directional { .. }));
        Candidate::forms_shown(
            [false, true].map(|points_only| Planted::Ray(RayFault::ShadowReversed { points_only })),
            [true, directional && has_point_light(line)],
        )
    },
};

pub(super) const SECONDARY_PER_LIGHT: Fault = Fault {
    name: "secondary_per_light",
    assignment: 4,
    sentence: "I add the mirror's and the glass's rays inside the loop over the lights: their \
               colours count once for each light (and not at all in a scene without lights).",
    look_for: "The loop over the lights holds each light's shadow test and its diffuse and \
               specular terms alone; the reflected and refracted colours are added once, after \
               it.",
    candidates: |line: &LineScene| {
        let secondary = has_material(line, false) || has_material(line, true);
        if bounces(line) && secondary && line.scene.lights.len() != 1 {
            only(RayFault::SecondaryPerLight)
        } else {
            Vec::new()
        }
    },
};

pub(super) const SHADOWS_MISSING: Fault = Fault {
    name: "shadows_missing",
    assignment: 4,
    sentence: "My tracer casts no shadows: under -shadows every light still reaches every point \
               (the shadow rays are never cast, or never meet anything, or -shadows is never \
               read).",
    look_for: "Under -shadows, for each light: cast a ray from the point (a little off the \
               surface) toward the light, and leave the light's diffuse and specular terms out \
               where that ray meets anything before the light.",
    candidates: |line: &LineScene| {
        if line.has_image() && line.options.trace.shadows && !line.description.lights.is_empty() {
            only(RayFault::NoShadows)
        } else {
            Vec::new()
        }
    },
};

pub(super) const SHADOW_SKIPS_GLASS: Fault = Fault {
    name: "shadow_skips_glass",
    assignment: 4,
    sentence: "My shadow rays pass through glass as if it were not there, so glass casts no \
               shadow.",
    look_for: "The shadow test: every object between the point and the light blocks it, \
               glass too (the course's shadows are opaque; the handout's optional transparent \
               shadows let through the light times the glass's transparent colour, never all \
               of it).",
    candidates: |line: &LineScene| {
        if line.has_image() && line.options.trace.shadows && has_material(line, true) {
            only(RayFault::ThroughGlass(crate::trace::ThroughGlass::Whole))
        } else {
            Vec::new()
        }
    },
};

pub(super) const REFLECTION_DIRECTION: Fault = Fault {
    name: "reflection_direction",
    assignment: 4,
    sentence: "My mirror rays go the wrong way: d + 2(d·n)n instead of d - 2(d·n)n.",
    look_for: "The mirror direction: R = d - 2(d·n)n, with d the incoming unit direction and n \
               the unit normal.",
    candidates: |line: &LineScene| {
        if bounces(line) && has_material(line, false) {
            only(RayFault::MirrorSign)
        } else {
            Vec::new()
        }
    },
};

pub(super) const REFRACTION_INDEX: Fault = Fault {
    name: "refraction_index",
    assignment: 4,
    sentence: "My glass bends rays as glass of another index would: the ratio of the indices \
               η_i / η_t wrong on one side of the glass or both (form 0: inverted both ways; 1: \
               1 / index both ways, not turned when the ray leaves; 2: index both ways), or the \
               index taken as the number given.",
    look_for: "Snell's ratio η_i / η_t: entering glass from air it is 1 / index, leaving it, \
               index / 1; tell the two apart by the sign of d·n.",
    candidates: |line: &LineScene| {
        if bounces(line) && has_material(line, true) {
            Candidate::forms(
                [
                    RayFault::InvertedIndex,
                    RayFault::RatioUnturned {
                        index_over_one: false,
                    },
                    RayFault::RatioUnturned {
                        index_over_one: true,
                    },
                ]
                .map(Planted::Ray),
            )
        } else {
            Vec::new()
        }
    },
};

pub(super) const TOTAL_INTERNAL_REFLECTION: Fault = Fault {
    name: "total_internal_reflection",
    assignment: 4,
    sentence: "Past the critical angle I still trace a refracted ray (form 0: along the surface, \
               taking the square root of 0; 1: the root of the absolute value; 2: the ray \
               unbent; 3: the root of the negative number, a ray of NaNs that shows the \
               background; 4: the ray sent along the mirror direction).",
    look_for: "The refraction: where 1 - η²(1 - (N·I)²) is negative the light is totally \
               reflected inside: trace no refracted ray there (the mirror ray, if the material \
               reflects, is traced as usual).",
    candidates: |line: &LineScene| {
        if !(bounces(line) && has_material(line, true)) {
            return Vec::new();
        }
        Candidate::forms(
            [
                CriticalAngle::Grazing,
                CriticalAngle::Absolute,
                CriticalAngle::Straight,
                CriticalAngle::NotANumber,
                CriticalAngle::Mirrored,
            ]
            .map(|way| Planted::Ray(RayFault::PastCriticalAngle(way))),
        )
    },
};

pub(super) const REFRACTION_FORMULA: Fault = Fault {
    name: "refraction_formula",
    assignment: 4,
    sentence: "My Snell's formula is not T = η d + (η c − √k) N with c = −N·d (form 0: \
               leaving the glass, N is the surface's outward normal, not turned to face the \
               ray; forms 1 to 7: a sign of its terms flipped, 1 the η d term's, 2 the η c \
               term's, 4 the root's, and their sums, 3 being the course's formula with I = d \
               where I = −d is meant).",
    look_for: "The refraction: T = [η (N·I) − √(1 − η² (1 − (N·I)²))] N − η I, with I = −d \
               pointing back along the incoming ray and N the normal on the ray's side (turn it \
               when the ray leaves the object: d·N > 0).",
    candidates: |line: &LineScene| {
        if !(bounces(line) && has_material(line, true)) {
            return Vec::new();
        }
        Candidate::forms(
            std::iter::once(SnellForm::OutwardNormal)
                .chain(SNELL_SIGNS.map(SnellForm::Signs))
                .map(|form| Planted::Ray(RayFault::Snell(form))),
        )
    },
};

pub(super) const BOUNCES_UNCOUNTED: Fault = Fault {
    name: "bounces_uncounted",
    assignment: 4,
    sentence: "My recursion never counts its bounces (each mirror and glass ray is traced with \
               the depth it was spawned at): only -weight, or a ray's leaving the scene, stops \
               it.",
    look_for: "traceRay: pass bounces + 1 to the traceRay of each mirror and glass ray, and stop \
               once it passes -bounces.",
    candidates: |line: &LineScene| {
        // Without a cut-off weight such a recursion ends only where its rays leave the scene.
        // (A ray trapped between surfaces whose colours are 1 or longer, so that its weight
        // never shrinks, is cut where the tracer cuts every ray tree, at
        // MAX_RAYS_PER_CAMERA_RAY; the student's program would not end: no picture matches.)
        let secondary = has_material(line, false) || has_material(line, true);
        if line.has_image() && secondary && line.options.trace.cutoff_weight > 0.0 {
            only(RayFault::Bounces(i32::MAX))
        } else {
            Vec::new()
        }
    },
};

pub(super) const BOUNCES_OFF_BY_ONE: Fault = Fault {
    name: "bounces_off_by_one",
    assignment: 4,
    sentence: "My recursion stops one bounce too early or too late.",
    look_for: "The recursion's test: -bounces N traces N levels of mirror and glass rays after \
               the camera ray (stop when the depth passes N, not at N - 1 or N + 1).",
    candidates: |line: &LineScene| {
        if line.has_image() && (has_material(line, false) || has_material(line, true)) {
            let mut candidates = vec![Candidate::with(
                Planted::Ray(RayFault::Bounces(1)),
                "bounces",
                1.0,
            )];
            if line.options.trace.bounces > 0 {
                candidates.push(Candidate::with(
                    Planted::Ray(RayFault::Bounces(-1)),
                    "bounces",
                    -1.0,
                ));
            }
            candidates
        } else {
            Vec::new()
        }
    },
};

pub(super) const WEIGHT_CUTOFF: Fault = Fault {
    name: "weight_cutoff",
    assignment: 4,
    sentence: "I cut mirror and glass rays off at another weight than -weight says: at none, \
               every ray traced however little it adds (where no weight is given), or at the \
               weight given.",
    look_for: "Before tracing a mirror or glass ray: its weight (the product of the colours' \
               magnitudes on the way) must be at least -weight.",
    candidates: |line: &LineScene| {
        if bounces(line) && line.options.trace.cutoff_weight > 0.0 {
            only(RayFault::NoCutoff)
        } else {
            Vec::new()
        }
    },
};

pub(super) const LIMITS_TESTED_LATE: Fault = Fault {
    name: "limits_tested_late",
    assignment: 4,
    sentence: "My traceRay tests -bounces (form 1: and -weight) only after the ray's \
               intersection: a mirror or glass ray past the limit is still cast, and brings the \
               background where it meets nothing (black where it meets something).",
    look_for: "traceRay: test the limits before the intersection (or do not cast the ray): a \
               ray past -bounces or below -weight brings nothing, black, whether or not it \
               would meet anything.",
    candidates: |line: &LineScene| {
        let secondary = has_material(line, false) || has_material(line, true);
        if !line.has_image() || !secondary {
            return Vec::new();
        }
        Candidate::forms_shown(
            [false, true].map(|weight_too| Planted::Ray(RayFault::LimitsTestedLate { weight_too })),
            [true, line.options.trace.cutoff_weight > 0.0],
        )
    },
};

pub(super) const SECONDARY_RAYS_MISSING: Fault = Fault {
    name: "secondary_rays_missing",
    assignment: 4,
    sentence: "My tracer traces no mirror or glass rays (form 0: -bounces is never read, or the \
               recursion never starts), or no glass rays (form 1: refraction left out): what \
               they would bring back is missing.",
    look_for: "traceRay: while bounces are left, add reflectiveColor × traceRay(the mirror ray) \
               and transparentColor × traceRay(the refracted ray), each with one bounce fewer.",
    candidates: |line: &LineScene| {
        if !bounces(line) {
            return Vec::new();
        }
        Candidate::forms_shown(
            [false, true].map(|glass_only| Planted::Ray(RayFault::SecondaryMissing { glass_only })),
            [
                has_material(line, false) || has_material(line, true),
                has_material(line, true),
            ],
        )
    },
};

pub(super) const SECONDARY_COLOUR: Fault = Fault {
    name: "secondary_colour",
    assignment: 4,
    sentence: "I add what my mirror rays (form 0) or glass rays (form 1) bring back whole, not \
               multiplied by the material's reflective or transparent colour; or multiplied by \
               its specular colour instead (mirror rays: form 2; glass rays: form 3).",
    look_for: "Where a mirror or glass ray's colour is added to the hit's: colour += \
               reflectiveColor × traceRay(mirror ray), and transparentColor × traceRay(glass \
               ray).",
    candidates: |line: &LineScene| {
        if !bounces(line) {
            return Vec::new();
        }
        Candidate::forms_shown(
            [
                RayFault::ColourIgnored { transparent: false },
                RayFault::ColourIgnored { transparent: true },
                RayFault::SpecularCarried { transparent: false },
                RayFault::SpecularCarried { transparent: true },
            ]
            .map(Planted::Ray),
            [
                has_tinted_material(line, false),
                has_tinted_material(line, true),
                specular_differs(line, false),
                specular_differs(line, true),
            ],
        )
    },
};

pub(super) const SECONDARY_BACKGROUND: Fault = Fault {
    name: "secondary_background",
    assignment: 4,
    sentence: "My mirror and glass rays that meet nothing bring back black, not the background \
               colour (form 0: both; form 1: mirror rays alone; form 2: glass rays alone): only \
               the camera's rays see the background.",
    look_for: "traceRay: a ray that hits nothing returns the background colour, whether it is \
               the camera's ray or a mirror or glass ray (one function for all of them, or the \
               same test in each).",
    candidates: |line: &LineScene| {
        if !bounces(line) || line.description.background == glam::Vec3::ZERO {
            return Vec::new();
        }
        let (mirrors, glass) = (has_material(line, false), has_material(line, true));
        // With one kind of secondary ray, its form draws what form 0 draws.
        Candidate::forms_shown(
            [Secondary::Both, Secondary::Mirror, Secondary::Glass]
                .map(|which| Planted::Ray(RayFault::MissesBlack(which))),
            [mirrors || glass, mirrors && glass, mirrors && glass],
        )
    },
};

pub(super) const SHADING_REPLACED: Fault = Fault {
    name: "shading_replaced",
    assignment: 4,
    sentence: "Where a material reflects or refracts, my tracer shows what its mirror and glass \
               rays bring back instead of the surface's own shading (form 0: the ambient, \
               diffuse and specular terms left out, an if and an else; form 1: weighed by 1 − \
               the reflective and transparent colours, a mix).",
    look_for: "traceRay: the colour of a hit is its ambient term plus each light's diffuse and \
               specular terms, and then, added to all of that, reflectiveColor × the mirror \
               ray's colour and transparentColor × the glass ray's; none of them replaces or \
               scales the others.",
    candidates: |line: &LineScene| {
        if !line.has_image() || !(has_material(line, false) || has_material(line, true)) {
            return Vec::new();
        }
        // Where reflective plus transparent is white or more, the mix leaves the shading out.
        let mixes = line.description.materials.iter().any(|m| match m {
            crate::parse::description::MaterialSpec::Phong(p) => {
                let secondary = p.reflective + p.transparent;
                secondary != glam::Vec3::ZERO && secondary.min_element() < 1.0
            }
            crate::parse::description::MaterialSpec::Texture(_) => false,
        });
        Candidate::forms_shown(
            [false, true].map(|weighed| Planted::Ray(RayFault::LocalReplaced { weighed })),
            [true, mixes],
        )
    },
};

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3A, b: Vec3A) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn refraction_past_the_critical_angle_by_hand() {
        // Inside glass of index 1.5 at 45°, past the critical angle of 41.8°: the course
        // traces nothing; k = 1 − 2.25 (1 − 0.5) = −0.125.
        let d = Vec3A::new(1.0, 1.0, 0.0).normalize();
        let refract = |way| RayFault::PastCriticalAngle(way).refract(d, -Vec3A::Y, 1.5, true);
        assert_eq!(crate::trace::refract(d, -Vec3A::Y, 1.5), None);
        // √0: 1.5 cos 45° (−Y) + 1.5 d = (1.0607, 0, 0), along the surface.
        assert!(close(refract(CriticalAngle::Grazing).unwrap(), Vec3A::X));
        // √0.125 = 0.35355: (1.06066, 0.35355, 0) made unit.
        let absolute = refract(CriticalAngle::Absolute).unwrap();
        assert!(
            close(absolute, Vec3A::new(0.948_683, 0.316_228, 0.0)),
            "{absolute}"
        );
        assert_eq!(refract(CriticalAngle::Straight), Some(d));
        // Short of the critical angle each leaves the course's ray alone.
        let head_on = RayFault::PastCriticalAngle(CriticalAngle::Straight);
        assert_eq!(head_on.refract(Vec3A::Y, -Vec3A::Y, 1.5, true), None);
    }

    #[test]
    fn snells_formula_in_the_forms_students_write_by_hand() {
        let outward = RayFault::Snell(SnellForm::OutwardNormal);
        let unnegated = RayFault::Snell(SnellForm::Signs(3));
        // Into glass of index 1.5 at 45°: sin 45° / 1.5 = 0.4714 across, cos 0.8819 down.
        let d = Vec3A::new(1.0, -1.0, 0.0).normalize();
        let (ratio, normal) = (1.0 / 1.5, Vec3A::Y);
        let right = Vec3A::new(0.471_405, -0.881_917, 0.0);
        assert!(close(
            crate::trace::refract(d, normal, ratio).unwrap(),
            right
        ));
        // Entering, the outward normal is the one facing the ray: no change.
        assert_eq!(outward.refract(d, normal, ratio, false), None);
        // I = d bends the ray the other way across.
        let across = unnegated.refract(d, normal, ratio, false).unwrap();
        assert!(
            close(across, Vec3A::new(-0.471_405, -0.881_917, 0.0)),
            "{across}"
        );
        // Out of it at 30° (the normal as the tracer turns it, −Y): out at sin 0.75 above;
        // with the outward normal (+Y), the ray turns back down into the glass.
        let d = Vec3A::new(0.5, 0.75f32.sqrt(), 0.0);
        let right = Vec3A::new(0.75, 0.4375f32.sqrt(), 0.0);
        assert!(close(
            crate::trace::refract(d, -Vec3A::Y, 1.5).unwrap(),
            right
        ));
        let back = outward.refract(d, -Vec3A::Y, 1.5, true).unwrap();
        assert!(
            close(back, Vec3A::new(0.75, -(0.4375f32.sqrt()), 0.0)),
            "{back}"
        );
    }
}
