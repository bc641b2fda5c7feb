//! A student's tracer with one mistake written in a form of its own: not the way check's fault
//! library plants it, so that check's tests can show a fit naming what no list holds.
//!
//! ```sh
//! cargo run --release --example student_forms -- FORM -input scene.txt -size 200 200 -output out.tga
//! ```
//!
//! FORM is one of the names in [`Form::named`]; the rest is the course's command line.

use std::process::ExitCode;

use raycast::Scene;
use raycast::accel::Hit;
use raycast::camera::{Camera, CameraSeam, film_to_screen};
use raycast::geometry::Ray;
use raycast::glam::Mat4;
use raycast::job::{Command, parse_args, render_to_files, reserve_outputs};
use raycast::parse::description::Pattern;
use raycast::parse::description::Projection;
use raycast::parse::read_scene;
use raycast::sample::{Filter, SampleSeam};
use raycast::scene::perlin::octave_noise;
use raycast::scene::{Highlight, Illumination, Light, SpecularFalloff, Surface, Texture};
use raycast::shade::PictureSeam;
use raycast::trace::TraceSeam;
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
    /// No mistake: a correct tracer whose camera rays, mirror and glass directions are worked
    /// out in double precision (`Vec3d`), each then rounded to float.
    DoublePrecision,
}

impl Form {
    fn named(name: &str, file_up: Vec3A, file_direction: Vec3A, nearest: f32) -> Option<Form> {
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
            _ => (direction, horizontal, up),
        }
    }
}

impl CameraSeam for Form {
    fn pixel_to_screen(&self, i: u32, j: u32, width: u32, height: u32) -> (f32, f32) {
        match self {
            Form::LeftEdge => film_to_screen(i as f32, j as f32 + 0.5, width, height),
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
            (Projection::Perspective { angle }, Form::TangentPerAxis) => {
                let angle = angle.to_radians();
                let through = direction + (x * angle).tan() * horizontal + (y * angle).tan() * up;
                Ray::new(camera.center(), through)
            }
            (Projection::Perspective { angle }, _) => {
                let screen = 2.0 * (angle.to_radians() / 2.0).tan();
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
    fn shadow_end(&self, distance: f32) -> f32 {
        match self {
            Form::ShadowToOneMinusEpsilon if distance.is_finite() => 1.0 - 1e-4,
            _ => raycast::trace::shadow_end(distance),
        }
    }

    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        match self {
            Form::MarbleInTurns => surface.weigh(point, marble_in_turns),
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
            _ => Some(lit),
        }
    }

    fn start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        match self {
            Form::TinyNormalOffset => 1e-7 / direction.dot(normal).abs(),
            _ => raycast::trace::start_t(clearance, direction, normal),
        }
    }

    fn ambient(&self, term: Vec3A, lights: usize) -> Vec3A {
        match self {
            Form::AmbientInLoopCosineSquared => (0..lights).map(|_| term).sum(),
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
        let shaded = shade(normal, falloff, Highlight::Course);
        match self {
            Form::AmbientInLoopCosineSquared => {
                shaded * normal.dot(to_light).max(0.0).powi(2)
                    / normal.dot(to_light).max(f32::MIN_POSITIVE)
            }
            _ => shaded,
        }
    }

    fn reflect(&self, direction: Vec3A, normal: Vec3A) -> Vec3A {
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
        let Form::NormalFourVector = self else {
            return Some(hit);
        };
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
    fn depth_grey(&self, t: f32, t_near: f32, t_far: f32) -> f32 {
        match *self {
            Form::DepthFromNearest(nearest) => {
                (1.0 - (t - nearest) / (t_far - t_near)).clamp(0.0, 1.0)
            }
            _ => raycast::shade::depth_grey(t, t_near, t_far),
        }
    }
}
impl SampleSeam for Form {
    fn filter(&self, filter: Filter) -> Filter {
        match (self, filter) {
            (Form::FilterHalfPixelWider, Filter::Box(r)) => Filter::Box(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Tent(r)) => Filter::Tent(r + 0.5),
            (Form::FilterHalfPixelWider, Filter::Gaussian(s)) => Filter::Gaussian(s + 0.5),
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

fn run(args: Vec<String>) -> Result<(), String> {
    let (form, course) = args
        .split_first()
        .ok_or("usage: student_forms FORM RAYTRACER-ARGUMENTS...")?;
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
    let nearest = nearest_hit(&scene, options.width, options.height);
    let form = Form::named(form, camera.up.into(), raw_direction, nearest)
        .ok_or_else(|| format!("unknown form '{form}'"))?;
    let pending = reserve_outputs(&options).map_err(|e| e.to_string())?;
    render_to_files(&options, &scene, form, pending).map_err(|e| e.to_string())?;
    Ok(())
}

/// The distance of the nearest hit of the rays through the pixels' centres.
fn nearest_hit(scene: &Scene, width: u32, height: u32) -> f32 {
    let camera = &scene.camera;
    let mut nearest = f32::INFINITY;
    for j in 0..height {
        for i in 0..width {
            let (u, v) = raycast::camera::pixel_to_screen(i, j, width, height);
            let ray = camera.ray(u, v);
            if let Some(hit) = scene.world.intersect(&ray, camera.t_min()) {
                nearest = nearest.min(hit.t * ray.direction.length());
            }
        }
    }
    nearest
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
