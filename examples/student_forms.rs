//! A student's tracer with one mistake written in a form of its own: not the way check's fault
//! library plants it, so that check's tests can show a fit naming what no list holds.
//!
//! ```sh
//! cargo run --release --example student_forms -- FORM -input scene.txt -size 200 200 -output out.tga
//! ```
//!
//! FORM is one of the names in [`Form::named`]; the rest is the course's command line.

use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use raycast::Scene;
use raycast::accel::Hit;
use raycast::camera::{Camera, CameraSeam, film_to_screen};
use raycast::geometry::Ray;
use raycast::glam::Mat4;
use raycast::glam::Vec2;
use raycast::job::{Command, parse_args, render_to_files, reserve_outputs};
use raycast::parse::description::Pattern;
use raycast::parse::description::Projection;
use raycast::parse::read_scene;
use raycast::sample::{Filter, ONE_BELOW, SampleSeam, Sampler};
use raycast::scene::perlin::{noise as perlin_noise, octave_noise};
use raycast::scene::{Highlight, Illumination, Light, SpecularFalloff, Surface, Texture};
use raycast::shade::PictureSeam;
use raycast::trace::{BackFace, TraceSeam};
use raycast::{UVec3, Vec3A};

/// Each mistake, as a student might have written it.
#[derive(Debug, Clone, Copy)]
enum Form {
    /// Perspective rays at equal angle steps, a tangent per axis:
    /// `direction + tan((u - 0.5) * angle) * horizontal + tan((v - 0.5) * angle) * up`.
    TangentPerAxis,
    /// The up vector made orthogonal to the direction (`up - (up . d) d`) and never normalised.
    UpOrthogonalNotNormalised(Vec3A),
    /// The horizontal vector `direction x up` never normalised (the up vector made from it is).
    HorizontalNotNormalised(Vec3A),
    /// The screen built from the file's direction as written, not normalised.
    RawDirection(Vec3A),
    /// Half a pixel added to the row but not to the column.
    LeftEdge,
    /// The depth picture's grey counted from the picture's nearest hit, over the command line's
    /// range: `1 - (t - nearest) / (TMAX - TMIN)`.
    DepthFromNearest(f32),
    /// A Transform's normal carried as the 4-vector (n, 0) by the whole inverse transpose and
    /// normalised with its fourth component, whose first three are then the normal: shortened
    /// wherever the translation leans on it.
    NormalFourVector,
    /// Two mistakes of the shading sum at once: the ambient term inside the loop over the
    /// lights, and each light's diffuse term written `kd * light * pow(max(N.L, 0), 2)`.
    AmbientInLoopCosineSquared,
    /// Shadow, mirror and glass rays started at `point + 1e-7 * normal`: the t of that point
    /// along the ray, `1e-7 / |d.n|`.
    TinyNormalOffset,
    /// Each filter's reach (the box's and the tent's radius, the Gaussian's sigma) half a
    /// pixel more than the command line says.
    FilterHalfPixelWider,
    /// Marble's veins as `sin(2 pi frequency x + amplitude noise)`: the file's frequency taken
    /// as turns per unit, not radians.
    MarbleInTurns,
    /// A point light dimmed as light falls off in the world, `colour / (d * d)`, whatever the
    /// file's attenuation says.
    InverseSquareLight,
    /// Snell's law in Heckbert's form, `c1 = -n.d`, `c2 = sqrt(1 - eta^2 (1 - c1^2))`,
    /// `t = eta d + (eta c1 - c2) n`, with n the surface's outward normal on both sides: never
    /// turned when the ray leaves the glass.
    HeckbertOutwardNormal,
    /// The same form with the normal turned to the ray, but `c1 = n.d`: the cosine's minus
    /// forgotten.
    HeckbertCosineSign,
    /// The shadow ray toward a point light made with a unit direction and tested for hits
    /// with `t < 1 - epsilon`, as for the unnormalised direction `light - point`.
    ShadowToOneMinusEpsilon,
    /// The mirror direction as the textbook's `2 (N.V) N - V`, with V the ray's own direction
    /// where the formula means the direction back toward the eye.
    ReflectViewVector,
    /// The mirror direction `d - (d.n) n`, normalised: the 2 forgotten.
    ReflectWithoutTwo,
    /// Snell's ratio `1 / index` on both sides of the glass: never turned when the ray leaves.
    RatioNeverFlipped,
    /// Snell's ratio `index / 1` on both sides of the glass.
    RatioIndexBothWays,
    /// Past the critical angle the square root of a negative number: a direction of NaNs,
    /// which finds nothing and brings back the background.
    TotalInternalNan,
    /// Past the critical angle the glass ray is sent along the mirror direction instead,
    /// weighed by the transparent colour.
    TotalInternalMirror,
    /// The mirror ray's colour weighed by the reflective colour twice (once where the ray is
    /// made, once where its colour is added).
    MirrorColourTwice,
    /// The checkerboard's cells counted with C's `fmod(x, 2) < 1` per axis, which is true for
    /// every negative coordinate.
    CheckerFmod,
    /// The checkerboard's cells counted from `floor(|x|)`: mirrored about each axis.
    CheckerAbsolute,
    /// Uniform samples spread from edge to edge of the pixel, `a / (s - 1)`.
    UniformEdgeToEdge,
    /// The attenuation's three numbers read in the other order: `1 / (q + l d + c d^2)`.
    AttenuationReversed,
    /// Shadow, mirror and glass rays started `1e-6` along themselves, however large the
    /// scene's coordinates.
    AbsoluteEpsilonAlongRay,
    /// The Gaussian written `exp(-d^2 / (2 sigma))`: the file's sigma taken as the variance.
    GaussianVarianceAsSigma,
    /// Rows counted from the top of the picture where the camera counts from the bottom.
    RowsFromTheTop,
    /// The horizontal vector made as `up x direction`, the cross product's order reversed.
    HorizontalReversed,
    /// Columns spread over `width - 1`, `i / (width - 1)`; rows through their centres.
    ColumnsOverWidthMinusOne,
    /// Rays through each pixel's upper-right corner, `(i + 1) / width`.
    FarCorner,
    /// The perspective screen as wide as the angle in radians at distance 1, not
    /// `2 tan(angle / 2)`.
    ScreenAsWideAsTheAngle,
    /// The depth picture's grey counted from the command line's near end to the picture's
    /// farthest hit.
    DepthToFarthest(f32),
    /// The normals picture as `(n + 1) / 2`, the way normal maps are stored.
    NormalsHalfPlusHalf,
    /// Each light's colour scaled by `N.L` where it arrives, before the diffuse and specular
    /// terms (which take `N.L` again).
    LightScaledByCosine,
    /// The recursion's depth counted from 1, so `-bounces N` traces N - 1 levels.
    DepthCountedFromOne,
    /// The noise's octaves summed from the second, `noise(2^i p) / 2^i` for i = 1 to octaves.
    NoiseFromSecondOctave,
    /// The picture's bytes written blue, green, red into a writer that takes red first.
    BlueGreenRed,
    /// Bytes made with a cast to `unsigned char` and no clamp: past 255 they wrap.
    BytesWrap,
    /// The normals picture's colour `max(n, 0)` per component: the negative ones black.
    NormalsClampedAtZero,
    /// The depth and normals pictures' misses in the scene's background colour.
    MissesInBackground,
    /// Back faces black, `-shade_back` or not.
    BackFacesAlwaysBlack,
    /// Back faces shaded from their other side, `-shade_back` or not.
    BackFacesAlwaysShaded,
    /// Without `-shade_back`, back faces given the ambient term before the test that blacks
    /// them out.
    BackFacesAmbient,
    /// The ambient term added only in a scene without lights.
    AmbientOnlyWithoutLights,
    /// The ambient term times the number of lights (at least one).
    AmbientTimesLights,
    /// Each light's terms with the normal turned toward the light: lit from both sides.
    NormalTurnedToTheLight,
    /// Shadow rays toward point lights tested to infinity.
    ShadowToInfinity,
    /// `-weight` never read: every mirror and glass ray traced.
    EveryRayTraced,
    /// Jittered samples anywhere in the pixel, from a generator of the student's own.
    JitterAnywhere,
    /// The filter's weighted sum divided by the number of samples it weighed.
    WeightsOverCount,
    /// The perspective camera's rays take hits from minus infinity on: behind the eye too.
    HitsBehindTheEye,
    /// Textures evaluated at the world point, the texture's own Transform never applied.
    TextureMatrixIgnored,
    /// A Transform's normal carried by the object's own matrix, then normalised.
    NormalByObjectMatrix,
    /// The nearest hit searched from t = 50 down: farther surfaces lost.
    FarthestFifty,
    /// Camera rays started at the depth picture's near end (the command line's TMIN), as if
    /// it bounded the search: what is nearer is cut away.
    DepthNearAsStart(f32),
    /// The depth picture's grey cast to `unsigned char` unclamped: past either end it wraps.
    DepthWraps,
    /// The highlight faded by `N.L` whether or not the line asks for `-specular_fix`.
    SpecularAlwaysFaded,
    /// The recursion's test `depth <= bounces` with the depth counted from 0: a level more.
    OneBounceMore,
    /// Uniform samples at the upper-right corners of the grid's cells, `(a + 1) / s`.
    UniformUpperCorners,
    /// The filter's weighted sum divided by the pixel's own number of samples.
    WeightsOverPixelSamples,
    /// The texture's point taken through the inverse of its Transform.
    TextureMatrixInverted,
    /// Shadow rays toward point lights made with the unnormalised `light - point` and tested
    /// up to t = the light's distance: the distance squared along a unit direction.
    ShadowToDistanceSquared,
    /// The orthographic camera's rays take hits from t = 0 on: nothing behind its centre.
    OrthographicFromZero,
    /// A Transform's normal carried by the inverse transpose and never made unit again.
    NormalNotRenormalised,
    /// Perspective rays turned up or down by `y a`, then left or right by `x a`:
    /// `cos(x a) cos(y a) d + sin(x a) h + cos(x a) sin(y a) up`.
    SphericalRays,
    /// The view's v counted from the top, `1 - (j + 0.5) / height`.
    VFromTheTop,
    /// The view's u mirrored, `1 - (i + 0.5) / width`.
    UMirrored,
    /// What a glass ray brings back added whole, not times the transparent colour.
    GlassColourIgnored,
    /// No mistake: a correct tracer whose camera rays, mirror and glass directions are worked
    /// out in double precision (`Vec3d`), each then rounded to float.
    DoublePrecision,
}

impl Form {
    fn named(
        name: &str,
        file_up: Vec3A,
        file_direction: Vec3A,
        (nearest, farthest): (f32, f32),
        depth_near: f32,
    ) -> Option<Form> {
        Some(match name {
            "tangent_per_axis" => Form::TangentPerAxis,
            "up_orthogonal_not_normalised" => Form::UpOrthogonalNotNormalised(file_up),
            "horizontal_not_normalised" => Form::HorizontalNotNormalised(file_up),
            "raw_direction" => Form::RawDirection(file_direction),
            "left_edge" => Form::LeftEdge,
            "depth_from_nearest" => Form::DepthFromNearest(nearest),
            "normal_four_vector" => Form::NormalFourVector,
            "ambient_in_loop_cosine_squared" => Form::AmbientInLoopCosineSquared,
            "tiny_normal_offset" => Form::TinyNormalOffset,
            "filter_half_pixel_wider" => Form::FilterHalfPixelWider,
            "marble_in_turns" => Form::MarbleInTurns,
            "inverse_square_light" => Form::InverseSquareLight,
            "double_precision" => Form::DoublePrecision,
            "heckbert_outward_normal" => Form::HeckbertOutwardNormal,
            "heckbert_cosine_sign" => Form::HeckbertCosineSign,
            "shadow_to_one_minus_epsilon" => Form::ShadowToOneMinusEpsilon,
            "reflect_view_vector" => Form::ReflectViewVector,
            "reflect_without_two" => Form::ReflectWithoutTwo,
            "ratio_never_flipped" => Form::RatioNeverFlipped,
            "ratio_index_both_ways" => Form::RatioIndexBothWays,
            "total_internal_nan" => Form::TotalInternalNan,
            "total_internal_mirror" => Form::TotalInternalMirror,
            "mirror_colour_twice" => Form::MirrorColourTwice,
            "checker_fmod" => Form::CheckerFmod,
            "checker_absolute" => Form::CheckerAbsolute,
            "uniform_edge_to_edge" => Form::UniformEdgeToEdge,
            "attenuation_reversed" => Form::AttenuationReversed,
            "absolute_epsilon_along_ray" => Form::AbsoluteEpsilonAlongRay,
            "gaussian_variance_as_sigma" => Form::GaussianVarianceAsSigma,
            "rows_from_the_top" => Form::RowsFromTheTop,
            "orthographic_from_zero" => Form::OrthographicFromZero,
            "normal_not_renormalised" => Form::NormalNotRenormalised,
            "spherical_rays" => Form::SphericalRays,
            "v_from_the_top" => Form::VFromTheTop,
            "u_mirrored" => Form::UMirrored,
            "glass_colour_ignored" => Form::GlassColourIgnored,
            "depth_near_as_start" => Form::DepthNearAsStart(depth_near),
            "depth_wraps" => Form::DepthWraps,
            "specular_always_faded" => Form::SpecularAlwaysFaded,
            "one_bounce_more" => Form::OneBounceMore,
            "uniform_upper_corners" => Form::UniformUpperCorners,
            "weights_over_pixel_samples" => Form::WeightsOverPixelSamples,
            "texture_matrix_inverted" => Form::TextureMatrixInverted,
            "shadow_to_distance_squared" => Form::ShadowToDistanceSquared,
            "blue_green_red" => Form::BlueGreenRed,
            "bytes_wrap" => Form::BytesWrap,
            "normals_clamped_at_zero" => Form::NormalsClampedAtZero,
            "misses_in_background" => Form::MissesInBackground,
            "back_faces_always_black" => Form::BackFacesAlwaysBlack,
            "back_faces_always_shaded" => Form::BackFacesAlwaysShaded,
            "back_faces_ambient" => Form::BackFacesAmbient,
            "ambient_only_without_lights" => Form::AmbientOnlyWithoutLights,
            "ambient_times_lights" => Form::AmbientTimesLights,
            "normal_turned_to_the_light" => Form::NormalTurnedToTheLight,
            "shadow_to_infinity" => Form::ShadowToInfinity,
            "every_ray_traced" => Form::EveryRayTraced,
            "jitter_anywhere" => Form::JitterAnywhere,
            "weights_over_count" => Form::WeightsOverCount,
            "hits_behind_the_eye" => Form::HitsBehindTheEye,
            "texture_matrix_ignored" => Form::TextureMatrixIgnored,
            "normal_by_object_matrix" => Form::NormalByObjectMatrix,
            "farthest_fifty" => Form::FarthestFifty,
            "horizontal_reversed" => Form::HorizontalReversed,
            "columns_over_width_minus_one" => Form::ColumnsOverWidthMinusOne,
            "far_corner" => Form::FarCorner,
            "screen_as_wide_as_the_angle" => Form::ScreenAsWideAsTheAngle,
            "depth_to_farthest" => Form::DepthToFarthest(farthest),
            "normals_half_plus_half" => Form::NormalsHalfPlusHalf,
            "light_scaled_by_cosine" => Form::LightScaledByCosine,
            "depth_counted_from_one" => Form::DepthCountedFromOne,
            "noise_from_second_octave" => Form::NoiseFromSecondOctave,
            _ => return None,
        })
    }

    /// The student's frame: direction, horizontal and up, each as their code makes it.
    fn frame(&self, camera: &Camera) -> (Vec3A, Vec3A, Vec3A) {
        let (direction, horizontal, up) = camera.frame();
        match *self {
            Form::UpOrthogonalNotNormalised(file_up) => (
                direction,
                horizontal,
                file_up - file_up.dot(direction) * direction,
            ),
            Form::HorizontalNotNormalised(file_up) => {
                let long = direction.cross(file_up);
                (direction, long, long.normalize().cross(direction))
            }
            Form::RawDirection(raw) => (raw, horizontal, up),
            Form::HorizontalReversed => (direction, -horizontal, up),
            _ => (direction, horizontal, up),
        }
    }
}

impl CameraSeam for Form {
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        match self {
            Form::LeftEdge => film_to_screen(i as f32, j as f32 + 0.5, width, height),
            Form::RowsFromTheTop => {
                film_to_screen(i as f32 + 0.5, (height - 1 - j) as f32 + 0.5, width, height)
            }
            Form::ColumnsOverWidthMinusOne => {
                let across = width as f32 / (width.max(2) - 1) as f32;
                film_to_screen(i as f32 * across, j as f32 + 0.5, width, height)
            }
            Form::FarCorner => film_to_screen(i as f32 + 1.0, j as f32 + 1.0, width, height),
            Form::VFromTheTop | Form::UMirrored => {
                let (u, v) = film_to_screen(i as f32 + 0.5, j as f32 + 0.5, width, height);
                match self {
                    Form::VFromTheTop => (u, 1.0 - v),
                    _ => (1.0 - u, v),
                }
            }
            _ => film_to_screen(i as f32 + 0.5, j as f32 + 0.5, width, height),
        }
    }

    fn ray(&self, camera: &Camera, u: f32, v: f32) -> Ray {
        let (x, y) = (u - 0.5, v - 0.5);
        let (direction, horizontal, up) = self.frame(camera);
        match (camera.projection(), self) {
            (Projection::Perspective { angle }, Form::DoublePrecision) => {
                let (x, y) = (f64::from(u) - 0.5, f64::from(v) - 0.5);
                let screen = 2.0 * (f64::from(angle).to_radians() / 2.0).tan();
                let through = direction.as_dvec3()
                    + (x * screen) * horizontal.as_dvec3()
                    + (y * screen) * up.as_dvec3();
                Ray::new(camera.center(), Vec3A::from(through.normalize().as_vec3()))
            }
            (Projection::Perspective { angle }, Form::SphericalRays) => {
                let angle = angle.to_radians();
                let (ax, ay) = (x * angle, y * angle);
                let tilted = ay.cos() * direction + ay.sin() * up;
                let through = ax.cos() * tilted + ax.sin() * horizontal;
                Ray::new(camera.center(), through)
            }
            (Projection::Perspective { angle }, Form::TangentPerAxis) => {
                let angle = angle.to_radians();
                let through = direction + (x * angle).tan() * horizontal + (y * angle).tan() * up;
                Ray::new(camera.center(), through)
            }
            (Projection::Perspective { angle }, _) => {
                let screen = match self {
                    Form::ScreenAsWideAsTheAngle => angle.to_radians(),
                    _ => 2.0 * (angle.to_radians() / 2.0).tan(),
                };
                let through = direction + (x * screen) * horizontal + (y * screen) * up;
                Ray::new(camera.center(), through)
            }
            (Projection::Orthographic { size }, _) => Ray::new(
                camera.center() + (x * size) * horizontal + (y * size) * up,
                direction.normalize(),
            ),
        }
    }
}

impl TraceSeam for Form {
    fn camera_t_min(&self, camera: &Camera) -> f32 {
        match (self, camera.projection()) {
            (Form::HitsBehindTheEye, Projection::Perspective { .. }) => f32::NEG_INFINITY,
            (Form::OrthographicFromZero, Projection::Orthographic { .. }) => 0.0,
            _ => camera.t_min(),
        }
    }

    fn back_face(&self, shade_back: bool) -> BackFace {
        match self {
            Form::BackFacesAlwaysBlack => BackFace::Black,
            Form::BackFacesAlwaysShaded => BackFace::Shaded,
            Form::BackFacesAmbient if !shade_back => BackFace::Ambient,
            _ if shade_back => BackFace::Shaded,
            _ => BackFace::Black,
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
            Form::ShadowToDistanceSquared if distance.is_finite() => distance * distance,
            Form::ShadowToOneMinusEpsilon if distance.is_finite() => 1.0 - 1e-4,
            _ => raycast::trace::shadow_end(distance),
        }
    }

    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        match self {
            Form::MarbleInTurns => surface.weigh(point, marble_in_turns),
            Form::NoiseFromSecondOctave => surface.weigh(point, noise_from_second_octave),
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
            _ => Some(lit),
        }
    }

    fn start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        match self {
            Form::TinyNormalOffset => 1e-7 / direction.dot(normal).abs(),
            Form::AbsoluteEpsilonAlongRay => 1e-6,
            _ => raycast::trace::start_t(clearance, direction, normal),
        }
    }

    fn bounces(&self, bounces: u32) -> u32 {
        match self {
            Form::DepthCountedFromOne => bounces.saturating_sub(1),
            Form::OneBounceMore => bounces + 1,
            _ => bounces,
        }
    }

    fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        match self {
            Form::AmbientInLoopCosineSquared => (0..lights).map(|_| term).sum(),
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
    ) -> Vec3A {
        if let Form::NormalTurnedToTheLight = self {
            let towards = if normal.dot(to_light) < 0.0 {
                -normal
            } else {
                normal
            };
            return shade(towards, falloff, Highlight::Course);
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

    fn carried(&self, colour: Vec3A, transparent: bool) -> Vec3A {
        match self {
            Form::MirrorColourTwice if !transparent => colour * colour,
            Form::GlassColourIgnored if transparent => Vec3A::ONE,
            _ => colour,
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
        let hit = hit?;
        match self {
            Form::FarthestFifty if hit.t * ray.direction.length() > 50.0 => return None,
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
impl PictureSeam for Form {
    fn to_rgb(&self, colour: Vec3A) -> [u8; 3] {
        let half = if ROUNDED.load(Ordering::Relaxed) {
            0.5
        } else {
            0.0
        };
        let byte = |value: f32| match self {
            Form::BytesWrap => (value * 255.0 + half) as i32 as u8,
            _ => (value * 255.0 + half).clamp(0.0, 255.0) as u8,
        };
        let [r, g, b] = [byte(colour.x), byte(colour.y), byte(colour.z)];
        match self {
            Form::BlueGreenRed => [b, g, r],
            _ => [r, g, b],
        }
    }

    fn picture_miss(&self, background: [u8; 3]) -> Option<[u8; 3]> {
        match self {
            Form::MissesInBackground => Some(background),
            _ => None,
        }
    }

    fn normal_colour(&self, hit: &Hit) -> Vec3A {
        match self {
            Form::NormalsHalfPlusHalf => hit.normal * 0.5 + 0.5,
            Form::NormalsClampedAtZero => hit.normal.max(Vec3A::ZERO),
            _ => raycast::shade::normal_colour(hit),
        }
    }

    fn depth_grey(&self, t: f32, t_near: f32, t_far: f32) -> f32 {
        match *self {
            Form::DepthFromNearest(nearest) => {
                (1.0 - (t - nearest) / (t_far - t_near)).clamp(0.0, 1.0)
            }
            Form::DepthWraps => {
                let raw = 1.0 - (t - t_near) / (t_far - t_near);
                f32::from((raw * 255.0) as i32 as u8) / 255.0
            }
            Form::DepthToFarthest(farthest) => {
                (1.0 - (t - t_near) / (farthest - t_near)).clamp(0.0, 1.0)
            }
            _ => raycast::shade::depth_grey(t, t_near, t_far),
        }
    }
}
impl SampleSeam for Form {
    fn positions(&self, sampler: Sampler, seed: u64, pixel: u64, out: &mut [Vec2]) {
        match (self, sampler) {
            (Form::UniformEdgeToEdge, Sampler::Uniform(n)) if n > 1 => {
                let side = n.isqrt();
                let step = 1.0 / (side - 1) as f32;
                for (k, p) in out.iter_mut().enumerate() {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    *p = Vec2::new((a * step).min(ONE_BELOW), (b * step).min(ONE_BELOW));
                }
            }
            (Form::UniformUpperCorners, Sampler::Uniform(n)) => {
                let side = n.isqrt().max(1);
                for (k, p) in out.iter_mut().enumerate() {
                    let (a, b) = ((k as u32 % side) as f32, (k as u32 / side) as f32);
                    let corner = |c: f32| ((c + 1.0) / side as f32).min(ONE_BELOW);
                    *p = Vec2::new(corner(a), corner(b));
                }
            }
            (Form::JitterAnywhere, Sampler::Jittered(n)) => {
                // The student's own generator: a 64-bit LCG seeded by the pixel.
                let mut state = pixel.wrapping_mul(6_364_136_223_846_793_005) ^ 0x5DEE_CE66;
                let mut unit = move || {
                    state = state
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1_442_695_040_888_963_407);
                    ((state >> 40) as f32 / (1u64 << 24) as f32).min(ONE_BELOW)
                };
                for p in out.iter_mut().take(n as usize) {
                    let x = unit();
                    *p = Vec2::new(x, unit());
                }
            }
            _ => sampler.positions(seed, pixel, out),
        }
    }

    fn weighted_mean(&self, sum: Vec3A, total: f32, count: u32) -> Vec3A {
        match self {
            Form::WeightsOverCount => sum / count as f32,
            Form::WeightsOverPixelSamples => sum / PIXEL_SAMPLES.load(Ordering::Relaxed) as f32,
            _ => sum / total,
        }
    }

    fn filter(&self, filter: Filter) -> Filter {
        match (self, filter) {
            (Form::FilterHalfPixelWider, Filter::Box(r)) => Filter::Box(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Tent(r)) => Filter::Tent(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Gaussian(s)) => Filter::Gaussian(s + 0.5),
            (Form::GaussianVarianceAsSigma, Filter::Gaussian(s)) => Filter::Gaussian(s.sqrt()),
            _ => filter,
        }
    }
}

/// Where `point` falls between a texture's materials, Marble's frequency in turns.
fn marble_in_turns(texture: &Texture, point: Vec3A) -> f32 {
    let Pattern::Marble {
        octaves,
        frequency,
        amplitude,
    } = texture.pattern
    else {
        return texture.weight(point);
    };
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    let noise = octave_noise(p.x, p.y, p.z, octaves);
    let turns = std::f64::consts::TAU * frequency * p.x;
    (0.5 * ((turns + amplitude * noise).sin() + 1.0)) as f32
}

/// Whether the student's bytes are rounded to the nearest (`FORM+rounded`), not truncated as
/// the course's: a second, harmless difference beside the form's mistake.
static ROUNDED: AtomicBool = AtomicBool::new(false);

/// The line's samples a pixel (the student divides by it).
static PIXEL_SAMPLES: AtomicU32 = AtomicU32::new(1);

/// Where `point` falls between a texture's materials, its noise summed from the second octave.
fn noise_from_second_octave(texture: &Texture, point: Vec3A) -> f32 {
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    let noise = |octaves: u32| {
        (1..=octaves)
            .map(|i| {
                let scale = f64::from(1u32 << i);
                perlin_noise(p.x * scale, p.y * scale, p.z * scale) / scale
            })
            .sum::<f64>()
    };
    let weight = match texture.pattern {
        Pattern::Checkerboard => return texture.weight(point),
        Pattern::Noise { octaves } => 0.5 * (noise(octaves) + 1.0),
        Pattern::Marble {
            octaves,
            frequency,
            amplitude,
        } => 0.5 * ((frequency * p.x + amplitude * noise(octaves)).sin() + 1.0),
        Pattern::Wood {
            octaves,
            frequency,
            amplitude,
        } => {
            let radius = (p.x * p.x + p.z * p.z).sqrt();
            let ring = 0.5 * ((frequency * radius + amplitude * noise(octaves)).sin() + 1.0);
            ring * ring * ring
        }
    };
    weight.clamp(0.0, 1.0) as f32
}

/// A checkerboard whose cell along each axis is `cell(x)` (1 or 0), their parities added.
fn checker(texture: &Texture, point: Vec3A, cell: impl Fn(f64) -> f64) -> f32 {
    let Pattern::Checkerboard = texture.pattern else {
        return texture.weight(point);
    };
    let p = texture.to_texture.transform_point3(point.as_dvec3());
    // Cell (0, 0, 0) gives 1 on each axis, and the course's weight 0 there.
    let ones = cell(p.x) + cell(p.y) + cell(p.z);
    (1.0 - ones.rem_euclid(2.0)) as f32
}

fn run(args: Vec<String>) -> Result<(), String> {
    let (form, course) = args
        .split_first()
        .ok_or("usage: student_forms FORM[+rounded] RAYTRACER-ARGUMENTS...")?;
    let form = match form.strip_suffix("+rounded") {
        Some(form) => {
            ROUNDED.store(true, Ordering::Relaxed);
            form
        }
        None => form,
    };
    let options = match parse_args(course.iter().map(Into::into).collect())? {
        Command::Render(options) => *options,
        _ => return Err("expected a render's command line".into()),
    };
    let description = read_scene(&options.input).map_err(|e| e.to_string())?;
    let camera = description.camera;
    let raw_direction = written_direction(&options.input).unwrap_or(camera.direction.into());
    let mut scene = Scene::from_description(&description).map_err(|e| e.to_string())?;
    if let Some([x, y, z]) = options.grid {
        scene
            .world
            .use_grid(UVec3::new(x, y, z))
            .map_err(|e| e.to_string())?;
    }
    let hits = hit_range(&scene, options.width, options.height);
    let depth_near = options.depth.as_ref().map_or(0.0, |&(near, _, _)| near);
    let form = Form::named(form, camera.up.into(), raw_direction, hits, depth_near)
        .ok_or_else(|| format!("unknown form '{form}'"))?;
    PIXEL_SAMPLES.store(options.sampling.sampler.samples(), Ordering::Relaxed);
    let pending = reserve_outputs(&options).map_err(|e| e.to_string())?;
    render_to_files(&options, &scene, form, pending).map_err(|e| e.to_string())?;
    Ok(())
}

/// The distances of the nearest and the farthest hits of the rays through the pixels' centres.
fn hit_range(scene: &Scene, width: u32, height: u32) -> (f32, f32) {
    let camera = &scene.camera;
    let (mut nearest, mut farthest) = (f32::INFINITY, 0.0f32);
    for j in 0..height {
        for i in 0..width {
            let (u, v) = raycast::camera::pixel_to_screen(i, j, width, height);
            let ray = camera.ray(u, v);
            if let Some(hit) = scene.world.intersect(&ray, camera.t_min()) {
                let t = hit.t * ray.direction.length();
                nearest = nearest.min(t);
                farthest = farthest.max(t);
            }
        }
    }
    (nearest, farthest)
}

/// The camera's direction as the scene file writes it (the parser normalises it).
fn written_direction(path: &std::path::Path) -> Option<Vec3A> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut words = text
        .split_whitespace()
        .skip_while(|w| *w != "direction")
        .skip(1);
    let mut next = || words.next()?.parse::<f32>().ok();
    Some(Vec3A::new(next()?, next()?, next()?))
}

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("student_forms: {message}");
            ExitCode::FAILURE
        }
    }
}
