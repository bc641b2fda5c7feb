//! The tracer's forms: the nearest hit, back faces, lights, shadows, mirrors, glass and the
//! recursion.

use std::ops::ControlFlow;

use raycast::Scene;
use raycast::Vec3A;
use raycast::accel::Grid;
use raycast::accel::grid::{Extent, Primitive};
use raycast::accel::{Carry, Hit, Struck};
use raycast::camera::Camera;
use raycast::geometry::Aabb;
use raycast::geometry::{Ray, Sphere};
use raycast::glam::{Mat4, Vec3};
use raycast::parse::description::Projection;
use raycast::scene::{
    Highlight, HighlightAt, Illumination, Light, SpecularFalloff, Surface, Texture,
};
use raycast::trace::{BackFace, LightPlace, ThroughGlass, TraceSeam};

use crate::Form;
use crate::highlight::{keep_specular, unlit_highlight};
use crate::textures::{
    checker, marble_along_y, marble_in_turns, noise_blended_the_other_way,
    noise_from_second_octave, noise_octaves_unweighed, noise_unmapped,
};

impl TraceSeam for Form {
    fn camera_t_min(&self, camera: &Camera) -> f32 {
        match (self, camera.projection()) {
            (Form::HitsBehindTheEye, Projection::Perspective { .. }) => f32::NEG_INFINITY,
            (Form::OrthographicFromZero, Projection::Orthographic { .. }) => 0.0,
            _ => camera.t_min(),
        }
    }

    fn shadow_through_glass(&self) -> Option<ThroughGlass> {
        // The student's shadow rays ask their own grid, as their camera rays do.
        match self {
            Form::GridBoxOfTwoCorners
            | Form::GridBoxInItsOwnSpace
            | Form::GridSphereCentresInside
            | Form::GridCellsUpperLeftOut
            | Form::GridOriginCellLeftOut
            | Form::GridOriginInsideLeftOut
            | Form::GridOriginInSlabsLeftOut
            | Form::GridStepNotAbsolute
            | Form::GridUpperFaceAlways
            | Form::SphereMinusRootOnly
            | Form::SpherePlusRootOnly
            | Form::DirectionCarriedAsPoint
            | Form::RaysByTheMatrix => Some(ThroughGlass::Opaque),
            _ => None,
        }
    }

    fn back_face(&self, shade_back: bool) -> BackFace {
        match self {
            Form::BackFacesAlwaysBlack => BackFace::Black,
            Form::NormalsNeverTurned => BackFace::Unturned,
            Form::BackFacesAlwaysShaded => BackFace::Shaded,
            Form::BackFacesAmbient if !shade_back => BackFace::Ambient,
            _ if shade_back => BackFace::Shaded,
            _ => BackFace::Black,
        }
    }

    fn ray_weight(&self, weight: f32, colour: Vec3A) -> f32 {
        match self {
            Form::WeightByMeanChannel => weight * colour.element_sum() / 3.0,
            Form::WeightByGreatestChannel => weight * colour.max_element(),
            _ => raycast::trace::ray_weight(weight, colour),
        }
    }

    fn cutoff_weight(&self, weight: f32) -> f32 {
        match self {
            Form::EveryRayTraced => 0.0,
            _ => weight,
        }
    }

    fn shadow_end(&self, distance: f32) -> f32 {
        match self {
            Form::ShadowToInfinity => f32::INFINITY,
            Form::ShadowRayOfNoLength => 0.0,
            Form::ShadowToDistanceSquared if distance.is_finite() => distance * distance,
            Form::ShadowToOneMinusEpsilon | Form::PointDirectionUnnormalised
                if distance.is_finite() =>
            {
                1.0 - 1e-4
            }
            _ => raycast::trace::shadow_end(distance),
        }
    }

    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        match self {
            Form::MarbleInTurns => surface.weigh(point, marble_in_turns),
            Form::MarbleAlongY => surface.weigh(point, marble_along_y),
            Form::NoiseFromSecondOctave => surface.weigh(point, noise_from_second_octave),
            Form::NoiseOctavesUnweighed => surface.weigh(point, noise_octaves_unweighed),
            Form::NoiseUnmapped => surface.weigh(point, noise_unmapped),
            Form::NoiseBlendedTheOtherWay => surface.weigh(point, noise_blended_the_other_way),
            Form::TextureMatrixInverted => {
                surface.weigh(point, |texture, point| {
                    let inverse = texture.to_texture.inverse();
                    texture
                        .pattern
                        .weight(inverse.transform_point3(point.as_dvec3()))
                });
            }
            Form::TextureMatrixIgnored => {
                surface.weigh(point, |texture, point| {
                    texture.pattern.weight(point.as_dvec3())
                });
            }
            Form::CheckerFmod => surface.weigh(point, |texture, point| {
                checker(texture, point, |x| f64::from(x % 2.0 < 1.0))
            }),
            Form::CheckerAbsolute => surface.weigh(point, |texture, point| {
                checker(texture, point, |x| 1.0 - x.abs().floor().rem_euclid(2.0))
            }),
            Form::HighlightWithoutLightColour => {
                surface.weigh(point, Texture::weight);
                keep_specular(surface);
            }
            _ => surface.weigh(point, Texture::weight),
        }
    }

    fn illuminate(&self, light: &Light, point: Vec3A) -> Option<Illumination> {
        let lit = light.illuminate(point)?;
        match (self, light) {
            (Form::InverseSquareLight, Light::Point { colour, .. }) => Some(Illumination {
                colour: *colour / (lit.distance * lit.distance),
                ..lit
            }),
            (
                Form::AttenuationReversed,
                Light::Point {
                    colour,
                    attenuation: [c, l, q],
                    ..
                },
            ) => Some(Illumination {
                colour: *colour / (q + l * lit.distance + c * lit.distance * lit.distance),
                ..lit
            }),
            (Form::DirectionalNotNegated, Light::Directional { .. }) => Some(Illumination {
                to_light: -lit.to_light,
                ..lit
            }),
            (
                Form::PointDirectionUnnormalised | Form::PointVectorToDistance,
                Light::Point { .. },
            ) => Some(Illumination {
                to_light: lit.to_light * lit.distance,
                ..lit
            }),
            (Form::LightAsBrightestChannel, _) => Some(Illumination {
                colour: Vec3A::splat(lit.colour.max_element()),
                ..lit
            }),
            (Form::LightColourLeftOut, _) => Some(Illumination {
                colour: Vec3A::new(1.0, 1.0, 1.0),
                ..lit
            }),
            _ => Some(lit),
        }
    }

    fn start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        match self {
            Form::TinyNormalOffset => 1e-7 / direction.dot(normal).abs(),
            Form::AbsoluteEpsilonAlongRay => 1e-6,
            Form::ShadowsFromZero => 0.0,
            _ => raycast::trace::start_t(clearance, direction, normal),
        }
    }

    fn secondary_start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        match self {
            Form::SecondaryFromZero => 0.0,
            Form::ShadowsFromZero => raycast::trace::start_t(clearance, direction, normal),
            _ => self.start_t(clearance, direction, normal),
        }
    }

    fn cast_past_limits(&self) -> Option<bool> {
        match self {
            Form::BouncesTestedAfterTheHit => Some(false),
            Form::LimitsTestedAfterTheHit => Some(true),
            _ => None,
        }
    }

    fn shadow_direction(&self, light: &Illumination) -> Vec3A {
        match self {
            Form::ShadowFromTheLight => -light.to_light,
            // (A directional light is infinitely far.)
            Form::PointShadowFromTheLight if light.distance.is_finite() => -light.to_light,
            _ => light.to_light,
        }
    }

    fn bounces(&self, bounces: u32) -> u32 {
        match self {
            Form::DepthCountedFromOne => bounces.saturating_sub(1),
            Form::OneBounceMore => bounces + 1,
            Form::BouncesNeverCounted => u32::MAX,
            _ => bounces,
        }
    }

    fn lights_visited(&self, lights: usize) -> usize {
        match self {
            Form::LightLoopShort => lights.saturating_sub(1),
            Form::FirstLightOnly => lights.min(1),
            _ => lights,
        }
    }

    fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        match self {
            Form::AmbientInLoopCosineSquared | Form::AmbientInLoopNeverClamped => {
                (0..lights).map(|_| term).sum()
            }
            Form::AmbientOnlyWithoutLights if lights > 0 => Vec3A::ZERO,
            Form::AmbientTimesLights => term * lights.max(1) as f32,
            _ => term,
        }
    }

    fn light(
        &self,
        shade: impl Fn(Vec3A, SpecularFalloff, Highlight) -> Vec3A,
        normal: Vec3A,
        to_light: Vec3A,
        falloff: SpecularFalloff,
        place: LightPlace,
    ) -> Vec3A {
        // (The highlight worked out once, after the loop, for lights[0]: inside the loop the
        // other lights bring their diffuse terms alone.)
        let highlighted = match self {
            Form::HighlightFirstLightOnly => place.index == 0,
            Form::SpecularLeftOut => false,
            Form::HighlightAfterTheLoop => place.index + 1 == place.of,
            _ => true,
        };
        if !highlighted {
            return shade(normal, falloff, Highlight::Own(|_| 0.0));
        }
        if let Form::HighlightWithoutLightColour = self {
            return unlit_highlight(shade, normal, falloff);
        }
        if let Form::NormalTurnedToTheLight = self {
            let towards = if normal.dot(to_light) < 0.0 {
                -normal
            } else {
                normal
            };
            return shade(towards, falloff, Highlight::Course);
        }
        let own = match self {
            Form::HighlightUngated => Some(highlight_ungated as fn(&HighlightAt) -> f32),
            Form::HighlightAbsolute => Some(highlight_absolute as fn(&HighlightAt) -> f32),
            Form::HalfVectorHalved => Some(half_vector_halved as fn(&HighlightAt) -> f32),
            Form::MirrorAgainstTheRay => Some(mirror_against_the_ray as fn(&HighlightAt) -> f32),
            Form::HighlightTimesCosine => Some(highlight_times_cosine as fn(&HighlightAt) -> f32),
            _ => None,
        };
        if let Some(own) = own {
            return shade(normal, falloff, Highlight::Own(own));
        }
        if let Form::DiffuseAbsolute = self
            && normal.dot(to_light) < 0.0
        {
            // The diffuse term alone, from the other side: no highlight there.
            return shade(-normal, falloff, Highlight::Own(|_| 0.0));
        }
        if let Form::DiffuseNeverClamped | Form::AmbientInLoopNeverClamped = self
            && normal.dot(to_light) < 0.0
        {
            // kd * light * N.L below zero: the term from the other side, negated.
            return -shade(-normal, falloff, Highlight::Own(|_| 0.0));
        }
        if let Form::SpecularAlwaysFaded = self {
            return shade(normal, SpecularFalloff::Fade, Highlight::Course);
        }
        let shaded = shade(normal, falloff, Highlight::Course);
        match self {
            Form::AmbientInLoopCosineSquared => {
                shaded * normal.dot(to_light).max(0.0).powi(2)
                    / normal.dot(to_light).max(f32::MIN_POSITIVE)
            }
            Form::LightScaledByCosine => shaded * normal.dot(to_light).max(0.0),
            _ => shaded,
        }
    }

    fn carried(
        &self,
        colour: Vec3A,
        transparent: bool,
        _surface: &Surface<'_>,
        lights: usize,
    ) -> Vec3A {
        match self {
            Form::MirrorColourTwice if !transparent => colour * colour,
            Form::GlassColourIgnored if transparent => Vec3A::ONE,
            Form::GlassNeverTraced if transparent => Vec3A::ZERO,
            Form::MirrorsInTheLightLoop => colour * lights as f32,
            _ => colour,
        }
    }

    fn ambient_diffuse(&self, surface: &Surface<'_>) -> Vec3A {
        match self {
            Form::TextureAmbientBlack if surface.is_textured() => Vec3A::ZERO,
            Form::TextureAmbientFirstMaterial => surface.side_diffuse(false),
            Form::AmbientLightAlone => Vec3A::ONE,
            _ => surface.diffuse(),
        }
    }

    fn local_weight(&self, surface: &Surface<'_>) -> Vec3A {
        let secondary = surface.reflective() + surface.transparent();
        match self {
            Form::MirrorOrShading if secondary != Vec3A::ZERO => Vec3A::ZERO,
            Form::ShadingMixedWithMirror => (Vec3A::ONE - secondary).max(Vec3A::ZERO),
            _ => Vec3A::ONE,
        }
    }

    fn escaped(&self, background: Vec3A, transparent: bool) -> Vec3A {
        match self {
            Form::MissesAddNothing => Vec3A::ZERO,
            Form::MirrorMissAddsNothing if !transparent => Vec3A::ZERO,
            _ => background,
        }
    }

    fn crossing_ratio(&self, index: f32, inside: bool) -> f32 {
        match self {
            Form::RatioNeverFlipped => 1.0 / index,
            Form::RatioIndexBothWays => index,
            _ => raycast::trace::crossing_ratio(index, inside),
        }
    }

    fn reflect(&self, direction: Vec3A, normal: Vec3A) -> Vec3A {
        match self {
            Form::ReflectViewVector => return 2.0 * normal.dot(direction) * normal - direction,
            Form::ReflectWithoutTwo => {
                return (direction - direction.dot(normal) * normal).normalize();
            }
            _ => {}
        }
        let Form::DoublePrecision = self else {
            return raycast::trace::reflect(direction, normal);
        };
        let (d, n) = (direction.as_dvec3(), normal.as_dvec3());
        Vec3A::from((d - 2.0 * d.dot(n) * n).as_vec3())
    }

    fn refract(&self, direction: Vec3A, normal: Vec3A, ratio: f32, inside: bool) -> Option<Vec3A> {
        let heckbert = |n: Vec3A, c1: f32| {
            let c2 = 1.0 - ratio * ratio * (1.0 - c1 * c1);
            (c2 >= 0.0).then(|| (ratio * direction + (ratio * c1 - c2.sqrt()) * n).normalize())
        };
        match self {
            Form::HeckbertOutwardNormal => {
                let outward = if inside { -normal } else { normal };
                return heckbert(outward, -outward.dot(direction));
            }
            Form::HeckbertCosineSign => return heckbert(normal, normal.dot(direction)),
            Form::TotalInternalNan => {
                return raycast::trace::refract(direction, normal, ratio)
                    .or(Some(Vec3A::splat(f32::NAN)));
            }
            Form::TotalInternalMirror => {
                return raycast::trace::refract(direction, normal, ratio)
                    .or_else(|| Some(raycast::trace::reflect(direction, normal)));
            }
            _ => {}
        }
        let Form::DoublePrecision = self else {
            return raycast::trace::refract(direction, normal, ratio);
        };
        let (incoming, n, ratio) = (-direction.as_dvec3(), normal.as_dvec3(), f64::from(ratio));
        let cos_in = n.dot(incoming);
        let k = 1.0 - ratio * ratio * (1.0 - cos_in * cos_in);
        (k >= 0.0).then(|| {
            let t = (ratio * cos_in - k.sqrt()) * n - ratio * incoming;
            Vec3A::from(t.normalize().as_vec3())
        })
    }

    fn found(&self, scene: &Scene, ray: &Ray, t_min: f32, hit: Option<Hit>) -> Option<Hit> {
        // (A plane, or an object carried another way, met where the course's rays meet
        // nothing.)
        match self {
            Form::PlanePlusOffset => return plane_plus_offset(scene, ray, t_min),
            Form::DirectionCarriedAsPoint => {
                return scene
                    .world
                    .intersect_carried(ray, t_min, Carry::DirectionAsPoint);
            }
            Form::RaysByTheMatrix => {
                return scene.world.intersect_carried(ray, t_min, Carry::ByMatrix);
            }
            _ => {}
        }
        let hit = hit?;
        match self {
            Form::FarthestFifty if hit.t * ray.direction.length() > 50.0 => return None,
            Form::SphereMinusRootOnly | Form::SpherePlusRootOnly => {
                let sign = if matches!(self, Form::SpherePlusRootOnly) {
                    1.0
                } else {
                    -1.0
                };
                return scene.world.intersect_spheres_by(
                    ray,
                    t_min,
                    |local, sphere, t_min, t_max| {
                        textbook_sphere_root(local, sphere, sign)
                            .filter(|t| (t_min..=t_max).contains(t))
                    },
                );
            }
            Form::MollerTrumboreEdges | Form::MollerTrumboreDeterminant => {
                let (edge, determinant) = match self {
                    Form::MollerTrumboreEdges => (5e-3, 0.0),
                    _ => (0.0, 1e-5),
                };
                return scene
                    .world
                    .intersect_accepting(ray, t_min, |local, corners| {
                        moller_trumbore(local, corners, edge, determinant)
                    });
            }
            Form::GridOriginInSlabsLeftOut => {
                let Some(grid) = scene.world.grid() else {
                    return Some(hit);
                };
                let (low, high) = (grid.bounds().min, grid.bounds().max);
                let (mut near, mut far) = (f32::NEG_INFINITY, f32::INFINITY);
                for axis in 0..3 {
                    let across = 1.0 / ray.direction[axis];
                    let (a, b) = (
                        (low[axis] - ray.origin[axis]) * across,
                        (high[axis] - ray.origin[axis]) * across,
                    );
                    near = near.max(a.min(b));
                    far = far.min(a.max(b));
                }
                return if near < 0.0 && far > 0.0 {
                    scene.world.plane_hit(ray, t_min)
                } else {
                    Some(hit)
                };
            }
            Form::GridOriginCellLeftOut | Form::GridOriginInsideLeftOut => {
                let Some(grid) = scene.world.grid() else {
                    return Some(hit);
                };
                let (low, high) = (grid.bounds().min, grid.bounds().max);
                let inside = if let Form::GridOriginCellLeftOut = self {
                    // The cell the origin falls in: one of the grid's where the origin is
                    // inside, and then the march (written for rays from outside) is skipped.
                    let cells = grid.cells().as_vec3a();
                    let at = (ray.origin - low) / (high - low) * cells;
                    (0..3).all(|axis| at[axis] >= 0.0 && at[axis].floor() < cells[axis])
                } else {
                    (0..3)
                        .all(|axis| low[axis] <= ray.origin[axis] && ray.origin[axis] <= high[axis])
                };
                return if inside {
                    scene.world.plane_hit(ray, t_min)
                } else {
                    Some(hit)
                };
            }
            Form::GridBoxOfTwoCorners | Form::GridBoxInItsOwnSpace => {
                let own_space = matches!(self, Form::GridBoxInItsOwnSpace);
                return walk_own_grid(scene, own_grid(scene, own_space), ray, t_min)
                    .unwrap_or(Some(hit));
            }
            Form::GridSphereCentresInside | Form::GridCellsUpperLeftOut => {
                return walk_own_grid(scene, listed_grid(scene, self), ray, t_min)
                    .unwrap_or(Some(hit));
            }
            Form::GridStepNotAbsolute | Form::GridUpperFaceAlways => {
                return own_march(scene, ray, t_min, self).unwrap_or(Some(hit));
            }
            Form::GridTrustsFirstHit | Form::GridMailbox => {
                return walk_grid(scene, ray, t_min, matches!(self, Form::GridMailbox))
                    .unwrap_or(Some(hit));
            }
            Form::ObjectTMultipliedBack => {
                return scene.world.intersect_stretched_t(ray, t_min, 2.0);
            }
            Form::CrossProductReversed
            | Form::EdgesFromTheMiddleCorner
            | Form::TriangleNormalUnnormalised
            | Form::LastCornerNormalUnnormalised => {
                let Some((
                    again,
                    Struck::Triangle {
                        corners: [a, b, c],
                        transformed,
                    },
                )) = scene.world.intersect_noting(ray, t_min)
                else {
                    return Some(hit);
                };
                let course = (b - a).cross(c - a);
                // The student's normal, as a factor of the course's unit one (a Transform
                // normalises the normal it carries).
                let factor = match self {
                    Form::TriangleNormalUnnormalised | Form::LastCornerNormalUnnormalised
                        if transformed =>
                    {
                        1.0
                    }
                    Form::TriangleNormalUnnormalised => course.length(),
                    Form::LastCornerNormalUnnormalised => (a - c).cross(b - c).length(),
                    Form::CrossProductReversed => (c - a).cross(b - a).dot(course).signum(),
                    _ => (a - b).cross(c - b).dot(course).signum(),
                };
                return Some(Hit {
                    normal: again.normal * factor,
                    ..again
                });
            }
            Form::GridWithoutPlanes | Form::PlanesInGridCells => {
                let clipped = matches!(self, Form::PlanesInGridCells);
                return walk_grid_planes(scene, ray, t_min, clipped).unwrap_or(Some(hit));
            }
            Form::NearestWithinTwenty if hit.t * ray.direction.length() > 20.0 => return None,
            Form::SphereNormalNotDivided => {
                let radius = match scene.world.intersect_noting(ray, t_min) {
                    Some((
                        _,
                        Struck::Sphere {
                            radius,
                            transformed: false,
                        },
                    )) => radius,
                    _ => 1.0,
                };
                return Some(Hit {
                    normal: hit.normal * radius,
                    ..hit
                });
            }
            Form::NormalByInverse | Form::NormalByTranspose => {
                let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, t_min)
                else {
                    return Some(hit);
                };
                let matrix = match self {
                    Form::NormalByInverse => transform.world_to_object.matrix3,
                    _ => transform.object_to_world.matrix3.transpose(),
                };
                let normal = matrix * object_normal;
                return Some(Hit {
                    normal: normal.normalize(),
                    ..hit
                });
            }
            Form::DepthNearDropsHits(near) if hit.t * ray.direction.length() < *near => {
                return None;
            }
            Form::DepthNearAsStart(near) if hit.t * ray.direction.length() < *near => {
                return scene.world.intersect(ray, near / ray.direction.length());
            }
            Form::NormalByObjectMatrix => {
                let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, t_min)
                else {
                    return Some(hit);
                };
                let normal = transform.object_to_world.transform_vector3a(object_normal);
                return Some(Hit {
                    normal: normal.normalize(),
                    ..hit
                });
            }
            Form::NormalNotRenormalised => {
                let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, t_min)
                else {
                    return Some(hit);
                };
                let normal = transform.normal_to_world * object_normal.normalize();
                let facing = if normal.dot(hit.normal) < 0.0 {
                    -normal
                } else {
                    normal
                };
                return Some(Hit {
                    normal: facing,
                    ..hit
                });
            }
            Form::NormalFourVector => {}
            _ => return Some(hit),
        }
        let Some((object_normal, Some(transform))) = scene.world.normal_origin(ray, t_min) else {
            return Some(hit);
        };
        let object_normal = object_normal.normalize();
        // The inverse's transpose, as a 4×4 matrix, times (n, 0): its fourth row is the
        // inverse's translation.
        let inverse = Mat4::from(transform.world_to_object);
        let carried = inverse.transpose() * object_normal.extend(0.0);
        Some(Hit {
            normal: Vec3A::from(carried.normalize().truncate()),
            ..hit
        })
    }
}

fn highlight_ungated(at: &HighlightAt) -> f32 {
    let half = (at.to_light + at.to_eye).normalize();
    at.normal.dot(half).max(0.0).powf(at.exponent)
}

fn highlight_absolute(at: &HighlightAt) -> f32 {
    let half = (at.to_light + at.to_eye).normalize();
    at.normal.dot(half).abs().powf(at.exponent)
}

fn highlight_times_cosine(at: &HighlightAt) -> f32 {
    let half = (at.to_light + at.to_eye).normalize();
    let cosine = at.normal.dot(at.to_light).max(0.0);
    at.normal.dot(half).max(0.0).powf(at.exponent) * cosine
}

fn half_vector_halved(at: &HighlightAt) -> f32 {
    if at.normal.dot(at.to_light) < 0.0 {
        return 0.0;
    }
    let half = (at.to_light + at.to_eye) / 2.0;
    at.normal.dot(half).max(0.0).powf(at.exponent)
}

fn mirror_against_the_ray(at: &HighlightAt) -> f32 {
    let n_dot_l = at.normal.dot(at.to_light);
    if n_dot_l < 0.0 {
        return 0.0;
    }
    let mirrored = 2.0 * n_dot_l * at.normal - at.to_light;
    mirrored.dot(-at.to_eye).max(0.0).powf(at.exponent)
}

/// Whether Moller and Trumbore's test takes the hit of `ray` on the triangle of `corners`,
/// refusing a hit within `edge` of an edge in u, v or their sum, or a determinant below
/// `determinant` in magnitude.
fn moller_trumbore(ray: &Ray, corners: &[Vec3; 3], edge: f32, determinant: f32) -> bool {
    let [a, b, c] = corners.map(Vec3A::from);
    let (e1, e2) = (b - a, c - a);
    let p = ray.direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < determinant || det == 0.0 {
        return false;
    }
    let s = ray.origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = ray.direction.dot(q) / det;
    u >= edge && v >= edge && u + v <= 1.0 - edge
}

/// The nearest hit of `ray` from `t_min` on through the scene's grid, walked as the student
/// wrote it: the walk ends at the first cell with any hit (`mailbox` false), or tests each
/// object once and keeps a hit only within the cell that tested it (`mailbox`). `None` where
/// the line has no grid.
fn walk_grid(scene: &Scene, ray: &Ray, t_min: f32, mailbox: bool) -> Option<Option<Hit>> {
    let grid = scene.world.grid()?;
    let plane = scene.world.plane_hit(ray, t_min);
    let beyond = plane.map_or(f32::INFINITY, |h| h.t);
    let mut nearest: Option<(f32, Primitive)> = None;
    let mut tested: Vec<Primitive> = Vec::new();
    grid.walk(ray, t_min, beyond, |cell| {
        for p in cell.primitives {
            if mailbox {
                if tested.contains(p) {
                    continue;
                }
                tested.push(*p);
            }
            let reach = nearest.map_or(beyond, |(t, _)| t);
            let reach = if mailbox {
                reach.min(cell.t_exit)
            } else {
                reach
            };
            if let Some(t) = scene.world.primitive_t(p, ray, t_min, reach) {
                nearest = Some((t, *p));
            }
        }
        let done = match nearest {
            Some((t, _)) if mailbox => t <= cell.t_exit,
            found => found.is_some(),
        };
        if done {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    Some(match nearest {
        Some((t, p)) if t < beyond => Some(scene.world.primitive_hit(ray, t, &p)),
        _ => plane,
    })
}

/// The student's own 3D-DDA through the course's grid, with its mistake (`form`): cell by
/// cell from where the ray enters the grid's box, stopping at the first cell whose nearest hit
/// lies within it; the nearer of that and the planes' hit. `None` without a grid.
fn own_march(scene: &Scene, ray: &Ray, t_min: f32, form: &Form) -> Option<Option<Hit>> {
    let grid = scene.world.grid()?;
    let plane = scene.world.plane_hit(ray, t_min);
    let beyond = plane.map_or(f32::INFINITY, |h| h.t);
    let (low, high) = (grid.bounds().min, grid.bounds().max);
    let cells = grid.cells();
    let (mut enter, mut leave) = (t_min, beyond);
    for axis in 0..3 {
        let a = (low[axis] - ray.origin[axis]) / ray.direction[axis];
        let b = (high[axis] - ray.origin[axis]) / ray.direction[axis];
        if a.is_nan() || b.is_nan() {
            continue;
        }
        enter = enter.max(a.min(b));
        leave = leave.min(a.max(b));
    }
    if enter > leave {
        return Some(plane);
    }
    let start = ray.origin + ray.direction * enter;
    let mut index = [0i64; 3];
    let mut step = [0i64; 3];
    let mut next = [f32::INFINITY; 3];
    let mut delta = [f32::INFINITY; 3];
    for axis in 0..3 {
        let size = (high[axis] - low[axis]) / cells[axis] as f32;
        let last = i64::from(cells[axis]) - 1;
        let i = (((start[axis] - low[axis]) / size).floor() as i64).clamp(0, last);
        index[axis] = i;
        let d = ray.direction[axis];
        if d == 0.0 {
            continue;
        }
        step[axis] = if d > 0.0 { 1 } else { -1 };
        let face = if d > 0.0 || matches!(form, Form::GridUpperFaceAlways) {
            i + 1
        } else {
            i
        };
        next[axis] = (low[axis] + face as f32 * size - ray.origin[axis]) / d;
        delta[axis] = if matches!(form, Form::GridStepNotAbsolute) {
            size / d
        } else {
            (size / d).abs()
        };
    }
    let mut nearest: Option<(f32, Primitive)> = None;
    loop {
        let axis = if next[0] < next[1] && next[0] < next[2] {
            0
        } else if next[1] < next[2] {
            1
        } else {
            2
        };
        let here = raycast::UVec3::new(index[0] as u32, index[1] as u32, index[2] as u32);
        for p in grid.primitives(here) {
            let reach = nearest.map_or(beyond, |(t, _)| t);
            if let Some(t) = scene.world.primitive_t(p, ray, t_min, reach) {
                nearest = Some((t, *p));
            }
        }
        let exit = next[axis].min(leave);
        if nearest.is_some_and(|(t, _)| t <= exit) || next[axis] > leave {
            break;
        }
        index[axis] += step[axis];
        if index[axis] < 0 || index[axis] >= i64::from(cells[axis]) {
            break;
        }
        next[axis] += delta[axis];
    }
    Some(match nearest {
        Some((t, p)) if t < beyond => Some(scene.world.primitive_hit(ray, t, &p)),
        _ => plane,
    })
}

/// The student's own grid, of the course's cells, built once: an object under a Transform is
/// entered by its box's lowest and highest corners carried by the matrix and sorted per axis
/// (`own_space` false), or by the box its own space gives it (`own_space`).
fn own_grid(scene: &Scene, own_space: bool) -> Option<&'static Grid> {
    static GRID: std::sync::OnceLock<Option<Grid>> = std::sync::OnceLock::new();
    GRID.get_or_init(|| {
        let cells = scene.world.grid()?.cells();
        let entered: Vec<(Primitive, Extent)> = scene
            .world
            .grid_primitives()
            .map(|(primitive, own_box, transform)| {
                let entered = match transform {
                    Some(t) if !own_space => {
                        let low = t.object_to_world.transform_point3a(own_box.min);
                        let high = t.object_to_world.transform_point3a(own_box.max);
                        Aabb {
                            min: low.min(high),
                            max: low.max(high),
                        }
                    }
                    _ => own_box,
                };
                (primitive, Extent::Box(entered))
            })
            .collect();
        let scene_box = entered.iter().fold(Aabb::EMPTY, |around, (_, extent)| {
            let Extent::Box(b) = extent else {
                return around;
            };
            around.union(*b)
        });
        Grid::build(scene_box, cells, &entered).ok()
    })
    .as_ref()
}

/// The nearest hit through the student's own `grid`, walked as the course walks, the planes
/// tested beside it. `None` without a grid.
fn walk_own_grid(scene: &Scene, grid: Option<&Grid>, ray: &Ray, t_min: f32) -> Option<Option<Hit>> {
    let plane = scene.world.plane_hit(ray, t_min);
    Some(march(scene, grid?, ray, t_min, plane))
}

/// The student's own lists over the course's cells, built once, each object entered in the
/// cells the form's loop picks: one entry of a cell's own box (shrunk a little) per cell, so
/// that the course's grid keeps exactly those lists.
fn listed_grid(scene: &Scene, form: &Form) -> Option<&'static Grid> {
    static GRID: std::sync::OnceLock<Option<Grid>> = std::sync::OnceLock::new();
    GRID.get_or_init(|| {
        let course = scene.world.grid()?;
        let (cells, low) = (course.cells(), course.bounds().min);
        let size = (course.bounds().max - low) / cells.as_vec3a();
        let cell_of = |p: Vec3A| {
            let at = ((p - low) / size).floor();
            [0, 1, 2].map(|axis| at[axis].clamp(0.0, (cells[axis] - 1) as f32) as u32)
        };
        let upper_left_out = matches!(form, Form::GridCellsUpperLeftOut);
        let mut entries = Vec::new();
        for (primitive, own_box, transform) in scene.world.grid_primitives() {
            let sphere = scene
                .world
                .primitive_sphere(&primitive)
                .filter(|_| transform.is_none());
            let b = match transform {
                None => own_box,
                Some(t) => {
                    let corners = (0..8).map(|c| {
                        let pick = |bit, lo: f32, hi: f32| if c & bit == 0 { lo } else { hi };
                        t.object_to_world.transform_point3a(Vec3A::new(
                            pick(1, own_box.min.x, own_box.max.x),
                            pick(2, own_box.min.y, own_box.max.y),
                            pick(4, own_box.min.z, own_box.max.z),
                        ))
                    });
                    corners.fold(Aabb::EMPTY, |b, p| b.union(Aabb { min: p, max: p }))
                }
            };
            let (from, to) = (cell_of(b.min), cell_of(b.max));
            let end = |axis: usize| {
                if upper_left_out {
                    to[axis]
                } else {
                    to[axis] + 1
                }
            };
            for z in from[2]..end(2) {
                for y in from[1]..end(1) {
                    for x in from[0]..end(0) {
                        let corner = low + Vec3A::new(x as f32, y as f32, z as f32) * size;
                        let centre = corner + 0.5 * size;
                        if let Some((c, r)) = sphere
                            && !upper_left_out
                            && (centre - c).length() >= r
                        {
                            continue;
                        }
                        let inset = 0.25 * size;
                        let cell = Aabb {
                            min: corner + inset,
                            max: corner + size - inset,
                        };
                        entries.push((primitive, Extent::Box(cell)));
                    }
                }
            }
        }
        Grid::build(course.bounds(), cells, &entries).ok()
    })
    .as_ref()
}

/// A grid walk whose planes are in no cell (never tested), or in the cells they cross
/// (`clipped`: a plane's hit counts only inside the grid's box). `None` without a grid.
fn walk_grid_planes(scene: &Scene, ray: &Ray, t_min: f32, clipped: bool) -> Option<Option<Hit>> {
    let grid = scene.world.grid()?;
    let plane = scene.world.plane_hit(ray, t_min).filter(|hit| {
        let (low, high) = (grid.bounds().min, grid.bounds().max);
        let point = ray.origin + ray.direction * hit.t;
        clipped && (0..3).all(|axis| low[axis] <= point[axis] && point[axis] <= high[axis])
    });
    Some(march(scene, grid, ray, t_min, plane))
}

/// The nearer of `plane` and the hit the student's march through `grid` finds: cell by cell,
/// stopping at the first cell whose nearest hit lies within it.
fn march(scene: &Scene, grid: &Grid, ray: &Ray, t_min: f32, plane: Option<Hit>) -> Option<Hit> {
    let beyond = plane.map_or(f32::INFINITY, |h| h.t);
    let mut nearest: Option<(f32, Primitive)> = None;
    grid.walk(ray, t_min, beyond, |cell| {
        for p in cell.primitives {
            let reach = nearest.map_or(beyond, |(t, _)| t);
            if let Some(t) = scene.world.primitive_t(p, ray, t_min, reach) {
                nearest = Some((t, *p));
            }
        }
        match nearest {
            Some((t, _)) if t <= cell.t_exit => ControlFlow::Break(()),
            _ => ControlFlow::Continue(()),
        }
    });
    match nearest {
        Some((t, p)) if t < beyond => Some(scene.world.primitive_hit(ray, t, &p)),
        _ => plane,
    }
}

/// The nearest hit with the planes by the student's own equation, n·P + d = 0, and everything
/// else as the course's.
fn plane_plus_offset(scene: &Scene, ray: &Ray, t_min: f32) -> Option<Hit> {
    let mut nearest = scene
        .world
        .intersect_planes_by(ray, t_min, |_, _, _, _| None);
    for &(plane, material) in scene.world.planes() {
        let (n, d) = (plane.normal, plane.offset);
        let t = -(d + n.dot(ray.origin)) / n.dot(ray.direction);
        if t.is_finite() && t >= t_min && nearest.is_none_or(|h| t < h.t) {
            nearest = Some(Hit {
                t,
                normal: n,
                material,
            });
        }
    }
    nearest
}

/// One root of the sphere's quadratic, as the textbook writes it: `(-b ± sqrt(b² - 4ac)) / 2a`.
fn textbook_sphere_root(ray: &Ray, sphere: &Sphere, sign: f32) -> Option<f32> {
    let oc = ray.origin - sphere.center;
    let a = ray.direction.dot(ray.direction);
    let b = 2.0 * oc.dot(ray.direction);
    let c = oc.dot(oc) - sphere.radius * sphere.radius;
    let discriminant = b * b - 4.0 * a * c;
    (discriminant >= 0.0).then(|| (-b + sign * discriminant.sqrt()) / (2.0 * a))
}
