//! The fault library: mistakes students make in the course's ray tracer, each a small, explicit
//! change to how raycast renders (through the seams of [`crate::variant`]), with a name, a
//! sentence in a student's words, the assignment it belongs to, and what to look for in the
//! code. `check` renders a failing line under the faults that can change it and names the one
//! whose picture matches the student's.
//!
//! A fault is one entry of [`FAULTS`], defined in the file of its family (camera, intersection,
//! shading, rays, samples, pictures), with the function that lists the renders to try on a line
//! (several where the fault has a parameter to fit: a corner, an angle, a limit).

mod camera;
mod intersection;
mod pictures;
mod rays;
mod samples;
mod shading;
mod textures;

use glam::Vec3A;

use crate::accel::Hit;
use crate::camera::{Camera, CameraSeam};
use crate::geometry::Ray;
use crate::job::Options;
use crate::parse::description::SceneDescription;
use crate::sample::{Filter, SampleSeam, Sampler};
use crate::scene::{Highlight, Illumination, Light, Scene, SpecularFalloff, Surface, Texture};
use crate::shade::PictureSeam;
use crate::trace::{BackFace, LightPlace, TraceSeam};

pub use camera::{CameraFault, Exchange, Mapping, RayForm};
pub use intersection::{HitFault, length_from, normal_length, normal_stretch};
pub(crate) use intersection::{has_triangles, lengths_change};
pub use pictures::PictureFault;
pub use rays::{CriticalAngle, RayFault, Secondary};
pub(crate) use rays::{bounces, glass_index, has_material, has_tinted_material};
pub use samples::{SampleFault, gaussian_radius};
pub use shading::{Attenuation, Cosine, LightGrey, ShadingFault};
pub use textures::TextureFault;
pub(crate) use textures::shows_veins;

/// One mistake a student's tracer may make.
#[derive(Debug)]
pub struct Fault {
    /// The stable name reports carry (snake_case).
    pub name: &'static str,
    /// The assignment whose code holds it.
    pub assignment: u8,
    /// What the code does, in a student's words.
    pub sentence: &'static str,
    /// Where to look in the code, and what it should do instead.
    pub look_for: &'static str,
    /// The renders to try on a line: none where the fault cannot change its pictures.
    pub candidates: fn(&LineScene) -> Vec<Candidate>,
}

impl PartialEq for Fault {
    fn eq(&self, other: &Fault) -> bool {
        self.name == other.name
    }
}

/// A line of a suite as the simulation sees it: its command line understood, the scene as the
/// file describes it, and the scene built.
pub struct LineScene {
    /// The command line.
    pub options: Options,
    /// The scene file, as parsed.
    pub description: SceneDescription,
    /// The scene, ready to render (with the line's grid, if it asks for one).
    pub scene: Scene,
}

impl LineScene {
    /// Whether the line makes the shaded picture.
    pub fn has_image(&self) -> bool {
        self.options.output.is_some()
    }

    /// Whether the line makes a depth or normals picture.
    pub fn has_depth_or_normals(&self) -> bool {
        self.options.depth.is_some() || self.options.normals.is_some()
    }

    /// Whether the line makes a picture traced from its rays: shaded, depth or normals.
    pub fn has_traced_picture(&self) -> bool {
        self.has_image() || self.has_depth_or_normals()
    }
}

/// One render to try: a fault planted, with its parameters fitted to this value.
#[derive(Debug, Clone, Copy)]
pub struct Candidate {
    /// The fault as planted.
    pub planted: Planted,
    /// The fitted parameter, if the fault has one: its name and value.
    pub parameter: Option<(&'static str, f64)>,
}

impl Candidate {
    /// A fault without a parameter.
    pub fn plain(planted: Planted) -> Candidate {
        Candidate {
            planted,
            parameter: None,
        }
    }

    /// A fault with a parameter fitted to `value`.
    pub fn with(planted: Planted, name: &'static str, value: f64) -> Candidate {
        Candidate {
            planted,
            parameter: Some((name, value)),
        }
    }

    /// One render for each form a fault takes, its `form` parameter numbering them from 0 in
    /// the order the fault's sentence lists them.
    pub fn forms(forms: impl IntoIterator<Item = Planted>) -> Vec<Candidate> {
        forms
            .into_iter()
            .enumerate()
            .map(|(form, planted)| Candidate::with(planted, "form", form as f64))
            .collect()
    }

    /// [`Candidate::forms`], numbered over every form, then only those whose `shows` is true
    /// kept: the forms that can draw another picture of the line than the course's, and than
    /// each other's.
    pub fn forms_shown<const N: usize>(forms: [Planted; N], shows: [bool; N]) -> Vec<Candidate> {
        Candidate::forms(forms)
            .into_iter()
            .zip(shows)
            .filter(|&(_, shows)| shows)
            .map(|(candidate, _)| candidate)
            .collect()
    }
}

/// A fault as planted in a render: which seam it changes, and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Planted {
    /// Camera rays made another way.
    Camera(CameraFault),
    /// Hits taken another way.
    Hit(HitFault),
    /// Shading done another way.
    Shading(ShadingFault),
    /// Pictures made another way.
    Picture(PictureFault),
    /// Shadow, mirror and glass rays made another way.
    Ray(RayFault),
    /// Samples placed or filtered another way.
    Sample(SampleFault),
    /// Textures weighed another way.
    Texture(TextureFault),
}

/// Every fault the library knows, in the order they are tried and listed among equals.
pub static FAULTS: &[Fault] = &[
    camera::PIXEL_CORNER,
    camera::PIXEL_SPAN_MINUS_ONE,
    camera::FLIP_VERTICAL,
    camera::FLIP_HORIZONTAL,
    camera::PIXELS_TRANSPOSED,
    camera::FIELD_OF_VIEW,
    camera::EQUAL_ANGLE_RAYS,
    camera::CAMERA_BASIS,
    pictures::CHANNEL_SWAP,
    intersection::T_MIN_IGNORED,
    intersection::T_LIMIT,
    shading::SHADE_BACK_IGNORED,
    // Before back_faces_lit: where back faces show the ambient term alone, the ambient term
    // added before the test that blacks them out is the likelier mistake than a normal never
    // turned, which draws the same where every light is behind the back faces.
    shading::AMBIENT_ON_BACK_FACES,
    shading::BACK_FACES_LIT,
    shading::SHADE_BACK_ABS,
    shading::DIFFUSE_UNCLAMPED,
    shading::AMBIENT_PER_LIGHT,
    shading::AMBIENT_MISSING,
    shading::AMBIENT_UNCOLOURED,
    shading::COSINE_TWICE,
    pictures::NO_CLAMP,
    intersection::DEPTH_TMIN,
    pictures::DEPTH_CLAMP,
    pictures::PICTURE_BACKGROUND,
    pictures::NORMALS_SIGNED,
    shading::SPECULAR_FIX,
    shading::SPECULAR_UNCLAMPED,
    shading::HALF_VECTOR,
    // After half_vector: where a highlight vector that points away from the eye puts the
    // highlight nowhere, the two draw the same picture, and the vector is the commoner mistake
    // (a student who writes the term at all); where it puts a highlight somewhere, the
    // student's other pictures tell them apart.
    shading::SPECULAR_MISSING,
    shading::SPECULAR_COLOUR,
    shading::LIGHT_COLOUR_IGNORED,
    shading::ATTENUATION,
    // Before lights_skipped: where a directional light shines only on what the eye cannot see,
    // the two draw the same, and its direction's sign is the commoner mistake.
    shading::LIGHT_DIRECTION,
    shading::LIGHTS_SKIPPED,
    shading::LIGHT_VECTOR,
    shading::HIGHLIGHT_ONE_LIGHT,
    rays::SHADOW_ACNE,
    rays::SHADOW_PAST_LIGHT,
    rays::SHADOW_DIRECTION,
    rays::SHADOWS_MISSING,
    rays::SHADOW_REACH,
    rays::SHADOW_SKIPS_GLASS,
    rays::REFLECTION_DIRECTION,
    rays::REFRACTION_INDEX,
    rays::TOTAL_INTERNAL_REFLECTION,
    rays::REFRACTION_FORMULA,
    rays::BOUNCES_OFF_BY_ONE,
    rays::BOUNCES_UNCOUNTED,
    rays::WEIGHT_CUTOFF,
    rays::LIMITS_TESTED_LATE,
    rays::SECONDARY_RAYS_MISSING,
    rays::SECONDARY_COLOUR,
    rays::SECONDARY_PER_LIGHT,
    rays::SECONDARY_BACKGROUND,
    rays::SHADING_REPLACED,
    samples::JITTER_WHOLE_PIXEL,
    samples::UNIFORM_CORNERS,
    samples::FILTER_RADIUS,
    samples::FILTER_WEIGHTS,
    samples::FILTER_SHAPE,
    samples::FILTER_NEIGHBOURS,
    samples::FILTER_CENTRE,
    textures::CHECKER_TRUNCATION,
    textures::TEXTURE_TRANSFORM,
    textures::NOISE_CONSTANTS,
    textures::TEXTURE_BLEND_SWAPPED,
    textures::TEXTURE_AMBIENT,
    pictures::DEPTH_RANGE,
    intersection::NORMAL_TRANSFORM,
    intersection::NORMAL_LENGTH,
    intersection::OBJECT_SPACE_T,
    intersection::TRIANGLE_EPSILON,
    intersection::PLANE_OFFSET_SIGN,
    intersection::TRIANGLE_WINDING,
    intersection::TRIANGLE_NORMAL_LENGTH,
    intersection::SPHERE_NORMAL_LENGTH,
    intersection::SPHERE_ROOT,
    intersection::RAY_TRANSFORM,
    intersection::GRID_FIRST_HIT,
    intersection::GRID_MARCH,
    intersection::GRID_TRANSFORMED_BOX,
    intersection::GRID_CELLS_MISSED,
    intersection::GRID_RAYS_FROM_INSIDE,
    intersection::GRID_PLANES,
];

/// The fault of `name`.
pub fn fault(name: &str) -> Option<&'static Fault> {
    FAULTS.iter().find(|f| f.name == name)
}

/// The plant `-fault` asks for: `NAME` (the fault's first render for the line), `NAME:K` (its
/// K-th, from 0, where it has several: corners, angles, limits), or two of these joined by `,`.
/// `None` where no fault named can change the line's pictures (a fault of back faces on a line
/// without any, say): the line renders as the course's.
pub fn plant_for(spec: &str, line: &LineScene) -> Result<Option<Plant>, String> {
    let one = |part: &str| -> Result<Option<Planted>, String> {
        let (name, index) = match part.split_once(':') {
            Some((name, k)) => {
                let k = k.parse::<usize>().map_err(|_| {
                    format!("-fault {part}: expected a render number after ':', found '{k}'")
                })?;
                (name, k)
            }
            None => (part, 0),
        };
        let fault = fault(name).ok_or_else(|| {
            let names: Vec<&str> = FAULTS.iter().map(|f| f.name).collect();
            format!(
                "-fault: unknown fault '{name}' (one of {})",
                names.join(", ")
            )
        })?;
        let candidates = (fault.candidates)(line);
        match (candidates.get(index), candidates.len()) {
            (Some(candidate), _) => Ok(Some(candidate.planted)),
            (None, 0) => Ok(None),
            (None, n) => Err(format!(
                "-fault {part}: the fault has {n} renders for this line (0 to {})",
                n - 1
            )),
        }
    };
    let (first, second) = match spec.split_once(',') {
        Some((first, second)) => (one(first)?, one(second)?),
        None => (one(spec)?, None),
    };
    Ok(match (first, second) {
        (Some(a), Some(b)) => Some(Plant::two(a, b)),
        (Some(one), None) | (None, Some(one)) => Some(Plant::one(one)),
        (None, None) => None,
    })
}

/// One or two faults planted in one render; each seam applies them in turn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plant {
    first: Planted,
    second: Option<Planted>,
}

impl Plant {
    /// One fault.
    pub fn one(fault: Planted) -> Plant {
        Plant {
            first: fault,
            second: None,
        }
    }

    /// Two faults at once.
    pub fn two(first: Planted, second: Planted) -> Plant {
        Plant {
            first,
            second: Some(second),
        }
    }

    /// The first fault planted.
    pub fn first(&self) -> Planted {
        self.first
    }

    // By reference: a planted camera holds a whole camera, and the seams ask for their faults
    // once a ray or more, so copying each `Planted` showed as a tenth of a simulation's time.
    fn each(&self) -> impl Iterator<Item = &Planted> + '_ {
        std::iter::once(&self.first).chain(&self.second)
    }

    fn cameras(&self) -> impl Iterator<Item = &CameraFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Camera(c) => Some(c),
            _ => None,
        })
    }

    fn hits(&self) -> impl Iterator<Item = HitFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Hit(h) => Some(*h),
            _ => None,
        })
    }

    fn shadings(&self) -> impl Iterator<Item = ShadingFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Shading(s) => Some(*s),
            _ => None,
        })
    }

    fn rays(&self) -> impl Iterator<Item = RayFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Ray(r) => Some(*r),
            _ => None,
        })
    }

    /// Whether it places `sampler`'s samples otherwise than raycast does: its pictures of a
    /// line drawn by chance are spread otherwise too.
    pub fn places_samples(&self, sampler: Sampler) -> bool {
        self.samples().any(|s| s.places(sampler))
    }

    fn samples(&self) -> impl Iterator<Item = SampleFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Sample(s) => Some(*s),
            _ => None,
        })
    }

    fn textures(&self) -> impl Iterator<Item = TextureFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Texture(t) => Some(*t),
            _ => None,
        })
    }

    fn pictures(&self) -> impl Iterator<Item = PictureFault> + '_ {
        self.each().filter_map(|p| match p {
            Planted::Picture(p) => Some(*p),
            _ => None,
        })
    }
}

impl CameraSeam for Plant {
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        let (i, j) = self
            .cameras()
            .fold((i, j), |(i, j), c| c.pixel(i, j, width, height));
        let (x, y) = self
            .cameras()
            .find_map(|c| c.film_point(i, j, width, height))
            .unwrap_or((i as f32 + 0.5, j as f32 + 0.5));
        self.film_to_screen(x, y, width, height)
    }

    fn ray(&self, camera: &Camera, u: f32, v: f32) -> Ray {
        self.cameras()
            .find_map(|c| c.ray(u, v))
            .unwrap_or_else(|| camera.ray(u, v))
    }
}

impl TraceSeam for Plant {
    fn camera_t_min(&self, camera: &Camera) -> f32 {
        self.hits()
            .find_map(|h| h.camera_t_min(camera))
            .unwrap_or_else(|| camera.t_min())
    }

    fn found(&self, scene: &Scene, ray: &Ray, t_min: f32, hit: Option<Hit>) -> Option<Hit> {
        self.hits()
            .fold(hit, |hit, h| h.found(scene, ray, t_min, hit))
    }

    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        let mut textures = self.textures();
        match (textures.next(), textures.next()) {
            (Some(fault), None) => surface.weigh(point, |t, p| fault.weight(t, p)),
            // Two (a scene of Noise and Marble, each weighed otherwise): each texture as the
            // first weighs it where that changes its weight, else as the second does.
            (Some(first), Some(second)) => surface.weigh(point, |t, p| {
                let weight = first.weight(t, p);
                if weight == t.weight(p) {
                    second.weight(t, p)
                } else {
                    weight
                }
            }),
            _ => surface.weigh(point, Texture::weight),
        }
    }

    fn back_face(&self, shade_back: bool) -> BackFace {
        let course = if shade_back {
            BackFace::Shaded
        } else {
            BackFace::Black
        };
        self.shadings()
            .fold(course, |face, s| s.back_face(shade_back, face))
    }

    fn lights_visited(&self, lights: usize) -> usize {
        self.shadings()
            .fold(lights, |lights, s| s.lights_visited(lights))
    }

    fn ambient_diffuse(&self, surface: &Surface<'_>) -> Vec3A {
        if self
            .shadings()
            .any(|s| s == ShadingFault::AmbientUncoloured)
        {
            return Vec3A::ONE;
        }
        self.textures()
            .find_map(|t| t.ambient_diffuse(surface))
            .unwrap_or_else(|| surface.diffuse())
    }

    fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        self.shadings()
            .fold(term, |term, s| s.ambient(term, lights))
    }

    fn illuminate(&self, light: &Light, point: Vec3A) -> Option<Illumination> {
        let grey = self.shadings().find_map(|s| match s {
            ShadingFault::LightColourIgnored(grey) => Some(grey),
            _ => None,
        });
        let lit = match (grey, self.shadings().find_map(|s| s.attenuation())) {
            (Some(grey), _) => {
                let course = light.illuminate(point)?;
                Illumination {
                    colour: grey.colour(course.colour),
                    ..course
                }
            }
            (None, Some(way)) => way.illuminate(light, point)?,
            (None, None) => light.illuminate(point)?,
        };
        let has = |fault: ShadingFault| self.shadings().any(|s| s == fault);
        Some(match light {
            Light::Directional { .. } if has(ShadingFault::DirectionReversed) => Illumination {
                to_light: -lit.to_light,
                ..lit
            },
            Light::Point { .. } if has(ShadingFault::PointVectorUnnormalised) => Illumination {
                to_light: lit.to_light * lit.distance,
                ..lit
            },
            _ => lit,
        })
    }

    fn light(
        &self,
        shade: impl Fn(Vec3A, SpecularFalloff, Highlight) -> Vec3A,
        normal: Vec3A,
        to_light: Vec3A,
        falloff: SpecularFalloff,
        place: LightPlace,
    ) -> Vec3A {
        let course = Highlight::Course;
        let mut shadings = self.shadings();
        let which = (to_light, place);
        match (shadings.next(), shadings.next()) {
            (None, _) => shade(normal, falloff, course),
            (Some(s), None) => s.light(&shade, normal, which, falloff, course),
            (Some(first), Some(second)) => first.light(
                &|n: Vec3A, f: SpecularFalloff, h: Highlight| second.light(&shade, n, which, f, h),
                normal,
                which,
                falloff,
                course,
            ),
        }
    }

    fn shadow_end(&self, distance: f32) -> f32 {
        // Along the unnormalised way toward a point light, the light is at t = 1.
        let unnormalised = distance.is_finite()
            && self
                .shadings()
                .any(|s| s == ShadingFault::PointVectorUnnormalised);
        let distance = if unnormalised { 1.0 } else { distance };
        self.rays()
            .find_map(|r| r.shadow_end(distance))
            .unwrap_or_else(|| crate::trace::shadow_end(distance))
    }

    fn shadow_through_glass(&self) -> Option<crate::trace::ThroughGlass> {
        self.rays().find_map(|r| r.through_glass()).or_else(|| {
            self.hits()
                .any(|h| h.searches_shadows())
                .then_some(crate::trace::ThroughGlass::Opaque)
        })
    }

    fn shadow_direction(&self, light: &Illumination) -> Vec3A {
        // (A directional light is infinitely far.)
        let reversed = self.rays().any(|r| match r {
            RayFault::ShadowReversed { points_only } => !points_only || light.distance.is_finite(),
            _ => false,
        });
        if reversed {
            -light.to_light
        } else {
            light.to_light
        }
    }

    fn start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        self.rays()
            .find_map(|r| r.start_t(direction, normal))
            .unwrap_or_else(|| crate::trace::start_t(clearance, direction, normal))
    }

    fn secondary_start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        self.rays()
            .find_map(|r| r.secondary_start_t(clearance, direction, normal))
            .unwrap_or_else(|| crate::trace::start_t(clearance, direction, normal))
    }

    fn bounces(&self, bounces: u32) -> u32 {
        self.rays().fold(bounces, |b, r| r.bounces(b))
    }

    fn cutoff_weight(&self, weight: f32) -> f32 {
        self.rays().fold(weight, |w, r| r.cutoff_weight(w))
    }

    fn cast_past_limits(&self) -> Option<bool> {
        self.rays().find_map(|r| match r {
            RayFault::LimitsTestedLate { weight_too } => Some(weight_too),
            _ => None,
        })
    }

    fn carried(
        &self,
        colour: Vec3A,
        transparent: bool,
        surface: &Surface<'_>,
        lights: usize,
    ) -> Vec3A {
        let carried = self
            .rays()
            .find_map(|r| r.carried(colour, transparent, surface))
            .unwrap_or(colour);
        if self.rays().any(|r| r == RayFault::SecondaryPerLight) {
            carried * lights as f32
        } else {
            carried
        }
    }

    fn local_weight(&self, surface: &Surface<'_>) -> Vec3A {
        self.rays()
            .find_map(|r| r.local_weight(surface))
            .unwrap_or(Vec3A::ONE)
    }

    fn escaped(&self, background: Vec3A, transparent: bool) -> Vec3A {
        self.rays()
            .find_map(|r| r.escaped(transparent))
            .unwrap_or(background)
    }

    fn reflect(&self, direction: Vec3A, normal: Vec3A) -> Vec3A {
        self.rays()
            .find_map(|r| r.reflect(direction, normal))
            .unwrap_or_else(|| crate::trace::reflect(direction, normal))
    }

    fn crossing_ratio(&self, index: f32, inside: bool) -> f32 {
        self.rays()
            .find_map(|r| r.crossing_ratio(index, inside))
            .unwrap_or_else(|| crate::trace::crossing_ratio(index, inside))
    }

    fn refract(&self, direction: Vec3A, normal: Vec3A, ratio: f32, inside: bool) -> Option<Vec3A> {
        self.rays()
            .find_map(|r| r.refract(direction, normal, ratio, inside))
            .or_else(|| crate::trace::refract(direction, normal, ratio))
    }
}

impl PictureSeam for Plant {
    fn to_rgb(&self, colour: Vec3A) -> [u8; 3] {
        let bytes = self
            .pictures()
            .find_map(|p| p.bytes(colour))
            .unwrap_or_else(|| crate::shade::to_rgb(colour));
        self.pictures().fold(bytes, |bytes, p| p.rearrange(bytes))
    }

    fn normal_colour(&self, hit: &Hit) -> Vec3A {
        self.pictures()
            .find_map(|p| p.normal_colour(hit))
            .unwrap_or_else(|| crate::shade::normal_colour(hit))
    }

    fn depth_grey(&self, t: f32, t_near: f32, t_far: f32) -> f32 {
        self.pictures()
            .find_map(|p| p.depth_grey(t, t_near, t_far))
            .unwrap_or_else(|| crate::shade::depth_grey(t, t_near, t_far))
    }

    fn picture_miss(&self, background: [u8; 3]) -> Option<[u8; 3]> {
        self.pictures().find_map(|p| p.picture_miss(background))
    }
}

impl SampleSeam for Plant {
    fn positions(&self, sampler: Sampler, seed: u64, pixel: u64, out: &mut [glam::Vec2]) {
        match self.samples().find(|s| s.places(sampler)) {
            Some(fault) => fault.positions(sampler, seed, pixel, out),
            None => sampler.positions(seed, pixel, out),
        }
    }

    fn filter(&self, filter: Filter) -> Filter {
        self.samples().fold(filter, |f, s| s.filter(f))
    }

    fn neighbours(&self, reach: i64) -> (i64, i64) {
        self.samples()
            .find_map(|s| s.neighbours(reach))
            .unwrap_or((-reach, reach))
    }

    fn weight(&self, filter: Filter, x: f32, y: f32) -> f32 {
        self.samples()
            .find_map(|s| s.weight(filter, x, y))
            .unwrap_or_else(|| filter.weight(x, y))
    }

    fn weighted_mean(&self, sum: Vec3A, total: f32, count: u32) -> Vec3A {
        self.samples()
            .find_map(|s| s.weighted_mean(sum, count))
            .unwrap_or(sum / total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_distinct_snake_case_and_every_fault_explains_itself() {
        for (i, fault) in FAULTS.iter().enumerate() {
            assert!(
                fault
                    .name
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c == '_'),
                "{}",
                fault.name
            );
            assert!(
                FAULTS[..i].iter().all(|f| f.name != fault.name),
                "{} twice",
                fault.name
            );
            assert!(fault.sentence.ends_with('.'), "{}", fault.name);
            assert!(fault.look_for.ends_with('.'), "{}", fault.name);
            assert!((1..=7).contains(&fault.assignment), "{}", fault.name);
            assert_eq!(super::fault(fault.name).map(|f| f.name), Some(fault.name));
        }
    }
}
