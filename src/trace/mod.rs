//! The ray tracer of assignment 4: the closest hit, shaded by every light (each behind a shadow
//! ray under `-shadows`), plus what the mirror and glass rays it spawns bring back.
//!
//! The course writes this as a recursive `traceRay`. Colour is linear in what each ray brings
//! back, so here the ray tree is walked with an explicit list of pending rays, each carrying
//! the product of the reflective and transparent colours on its way from the camera: the same
//! sum, in bounded native stack however large `-bounces` is, and with the list reused from ray
//! to ray instead of allocated for each.
//!
//! A packet of camera rays is shaded together under `-shadows`: its hits' shadow rays toward
//! each light are cast as a packet (`shadow_batch.rs`), with the same sums as ray by ray.

mod shadow_batch;

use glam::Vec3A;

use std::ops::ControlFlow;

use shadow_batch::ShadowBatch;

use crate::accel::{Hit, PACKET, Tallies};
use crate::camera::Camera;
use crate::geometry::Ray;
use crate::scene::{Highlight, Illumination, Light, Scene, SpecularFalloff, Surface, Texture};
use crate::variant::Exact;

/// Which of the scene's lights a light's term is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LightPlace {
    /// Its place in the file's order, from 0.
    pub index: usize,
    /// How many lights the scene has.
    pub of: usize,
}

/// How rays are traced and shaded: the seam where a render may trace as a student's tracer
/// would (check's fault library; see [`crate::variant`]). The defaults are the course's.
pub trait TraceSeam: Copy + Send + Sync {
    /// The least t a camera ray's hit may have.
    #[inline(always)]
    fn camera_t_min(&self, camera: &Camera) -> f32 {
        camera.t_min()
    }

    /// The hit as the tracer takes it from the search of `ray` from `t_min` on (its t, normal
    /// and material), or none.
    #[inline(always)]
    fn found(&self, _scene: &Scene, _ray: &Ray, _t_min: f32, hit: Option<Hit>) -> Option<Hit> {
        hit
    }

    /// Weighs `surface`'s textures at `point`.
    #[inline(always)]
    fn weigh(&self, surface: &mut Surface<'_>, point: Vec3A) {
        surface.weigh(point, Texture::weight);
    }

    /// How a shadow ray's light comes through glass: `None`, the course's required answer,
    /// keeps every shadow opaque; the handout's optional transparent shadows are one of
    /// [`ThroughGlass`]'s ways.
    #[inline(always)]
    fn shadow_through_glass(&self) -> Option<ThroughGlass> {
        None
    }

    /// What a back face shows: black, or shaded as seen from its other side (`-shade_back`).
    #[inline(always)]
    fn back_face(&self, shade_back: bool) -> BackFace {
        if shade_back {
            BackFace::Shaded
        } else {
            BackFace::Black
        }
    }

    /// The ambient term of a hit: the scene's ambient light times the diffuse colour, with
    /// `lights` lights in the scene.
    #[inline(always)]
    fn ambient(&self, term: Vec3A, _lights: usize) -> Vec3A {
        term
    }

    /// The colour the ambient light is multiplied by at a hit on `surface` (its diffuse colour
    /// there).
    #[inline(always)]
    fn ambient_diffuse(&self, surface: &Surface<'_>) -> Vec3A {
        surface.diffuse()
    }

    /// What a hit's own terms (ambient, and each light's diffuse and specular) are multiplied
    /// by on `surface`, before its mirror and glass rays add theirs.
    #[inline(always)]
    fn local_weight(&self, _surface: &Surface<'_>) -> Vec3A {
        Vec3A::ONE
    }

    /// How many of the scene's `lights` lights the loop over them visits, from the first.
    #[inline(always)]
    fn lights_visited(&self, lights: usize) -> usize {
        lights
    }

    /// The light `light` sends to `point` (its direction, colour and distance).
    #[inline(always)]
    fn illuminate(&self, light: &Light, point: Vec3A) -> Option<Illumination> {
        light.illuminate(point)
    }

    /// One light's term (diffuse plus specular) at a hit whose normal, turned toward the ray,
    /// is `normal`, the light lying along `to_light`; `shade(n, f, h)` is the term for a
    /// normal `n`, a highlight's fall-off `f` and its formula `h`, `falloff` the line's, and
    /// `place` the light's among the scene's.
    #[inline(always)]
    fn light(
        &self,
        shade: impl Fn(Vec3A, SpecularFalloff, Highlight) -> Vec3A,
        normal: Vec3A,
        _to_light: Vec3A,
        falloff: SpecularFalloff,
        _place: LightPlace,
    ) -> Vec3A {
        shade(normal, falloff, Highlight::Course)
    }

    /// The t past which a hit no longer blocks a shadow ray toward a light `distance` away.
    #[inline(always)]
    fn shadow_end(&self, distance: f32) -> f32 {
        shadow_end(distance)
    }

    /// The direction of the shadow ray toward the light that sends `light` to the point.
    #[inline(always)]
    fn shadow_direction(&self, light: &Illumination) -> Vec3A {
        light.to_light
    }

    /// The least t of a shadow, mirror or glass ray leaving a surface of unit `normal` along
    /// `direction`, given the hit's [`clearance`]: far enough that it does not find the surface
    /// it leaves.
    #[inline(always)]
    fn start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        start_t(clearance, direction, normal)
    }

    /// [`TraceSeam::start_t`] for a mirror or glass ray (a tracer may start its shadow rays
    /// one way and its secondary rays another).
    #[inline(always)]
    fn secondary_start_t(&self, clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
        self.start_t(clearance, direction, normal)
    }

    /// How many times a camera ray may be reflected or refracted, given `-bounces`.
    #[inline(always)]
    fn bounces(&self, bounces: u32) -> u32 {
        bounces
    }

    /// Which mirror and glass rays past the course's limits are still cast, each bringing the
    /// background where it meets nothing and nothing where it meets something (a tracer that
    /// tests its limits after the ray's intersection): `None`, the course's, casts none;
    /// `Some(false)` those one bounce past `-bounces`; `Some(true)` those below `-weight` too.
    #[inline(always)]
    fn cast_past_limits(&self) -> Option<bool> {
        None
    }

    /// The weight of a mirror or glass ray spawned with `colour` (the material's reflective
    /// or transparent colour) from a ray of `weight`.
    #[inline(always)]
    fn ray_weight(&self, weight: f32, colour: Vec3A) -> f32 {
        ray_weight(weight, colour)
    }

    /// The weight below which no mirror or glass ray is traced, given `-weight`.
    #[inline(always)]
    fn cutoff_weight(&self, weight: f32) -> f32 {
        weight
    }

    /// What the colour a mirror ray (or, with `transparent`, a glass ray) brings back is
    /// multiplied by, the material's reflective (or transparent) colour being `colour`; its
    /// other colours are `surface`'s, and the scene's lights are `lights` (a tracer that adds
    /// the ray's colour inside its loop over them), asked for only by a seam that needs them.
    #[inline(always)]
    fn carried(
        &self,
        colour: Vec3A,
        _transparent: bool,
        _surface: &Surface<'_>,
        _lights: usize,
    ) -> Vec3A {
        colour
    }

    /// What a mirror ray (or, with `transparent`, a glass ray) that meets nothing brings back,
    /// the scene's background being `background`.
    #[inline(always)]
    fn escaped(&self, background: Vec3A, _transparent: bool) -> Vec3A {
        background
    }

    /// The mirror direction of unit `direction` about unit `normal`.
    #[inline(always)]
    fn reflect(&self, direction: Vec3A, normal: Vec3A) -> Vec3A {
        reflect(direction, normal)
    }

    /// η_i / η_t for a ray crossing a surface of `index` (`inside`: from behind it).
    #[inline(always)]
    fn crossing_ratio(&self, index: f32, inside: bool) -> f32 {
        crossing_ratio(index, inside)
    }

    /// The refracted direction of unit `direction` through unit `normal` (facing against it)
    /// with `ratio` = η_i / η_t, the ray `inside` the object (leaving it) or not; `None` on
    /// total internal reflection.
    #[inline(always)]
    fn refract(&self, direction: Vec3A, normal: Vec3A, ratio: f32, inside: bool) -> Option<Vec3A> {
        let _ = inside;
        refract(direction, normal, ratio)
    }
}

impl TraceSeam for Exact {}

/// How light comes through the glass between a point and a light, in the handout's optional
/// transparent shadows ("the attenuation depends on the distance traveled in the transparent
/// object"; it gives no formula), or as a student's mistake lets it: an opaque object still
/// blocks it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThroughGlass {
    /// Not at all, as the course's shadows, but found by the tracer's own search for the
    /// nearest hit (its seam): check's faults of that search reach the shadow rays too.
    Opaque,
    /// Whole, as if the glass were not there: check's fault `shadow_skips_glass`, no answer.
    Whole,
    /// Times the transparent colour at each glass surface the shadow ray crosses.
    EachSurface,
    /// Times the transparent colour once for each glass object, where the ray enters it.
    EachObject,
    /// Times the transparent colour raised to the distance the ray travels inside each glass
    /// object.
    ByDistance,
}

/// The most glass surfaces a shadow ray is followed through: past it the light is taken as
/// blocked (the course's scenes cross at most a few).
const MAX_GLASS_CROSSINGS: u32 = 64;

/// What a ray that meets a surface from behind shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BackFace {
    /// Black, and no further rays (the course without `-shade_back`).
    Black,
    /// Shaded as seen from the other side, the normal turned toward the ray.
    Shaded,
    /// The ambient term alone.
    Ambient,
    /// Shaded with the normal as found, facing away from the ray (a tracer that never turns
    /// it).
    Unturned,
}

/// How far a shadow, mirror or glass ray must clear the surface it leaves, relative to the
/// largest coordinate of the hit point and of the ray that found it (see [`clearance`]).
pub const RELATIVE_OFFSET: f32 = 1.0 / 65536.0;
/// A mirror or glass ray whose colour counts for less than this in every channel of the pixel
/// is not traced: it could not move the pixel by a 256th of a level unless what it saw were
/// brighter than white. The course's weight cut-off stops far earlier in its scenes; this one
/// ends what the weight cannot, such as two perfect mirrors facing each other (whose colour's
/// magnitude, √3, never lets the weight fall).
pub const NEGLIGIBLE_THROUGHPUT: f32 = 1.0 / 65536.0;
/// The most mirror and glass rays one camera ray may spawn: the course's deepest scene (four
/// bounces of glass that both reflects and refracts) needs 62, `-bounces 10` at most 2,046.
/// Past this the ray tree is cut, so that even `-bounces 1000000` between mirrors ends.
pub const MAX_RAYS_PER_CAMERA_RAY: u32 = 1 << 14;

/// How rays are traced: the course's assignment-2 to -4 switches.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TraceSettings {
    /// Shade back faces as seen from their other side (otherwise they are black).
    pub shade_back: bool,
    /// Send a shadow ray toward each light.
    pub shadows: bool,
    /// How many times a ray may be reflected or refracted; 0 traces camera rays only.
    pub bounces: u32,
    /// Mirror and glass rays whose weight falls below this are not traced.
    pub cutoff_weight: f32,
    /// How highlights end where the light grazes the surface (`-specular_fix` fades them).
    pub specular: SpecularFalloff,
    /// Count primitives tested and grid cells entered (for the course's `-stats`).
    pub tally: bool,
    /// Show the grid's occupied cells as opaque cubes instead of the scene (`-visualize_grid`).
    pub visualize_grid: bool,
}

/// Rays cast, for `-stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays.
    pub primary: u64,
    /// Reflected and refracted rays.
    pub secondary: u64,
    /// Rays toward lights, under `-shadows`: one for each light that adds to a lit point.
    pub shadow: u64,
    /// Primitives tested and grid cells entered, when counted.
    pub tallies: Tallies,
}

impl std::ops::Add for RayCounts {
    type Output = RayCounts;
    fn add(self, other: RayCounts) -> RayCounts {
        RayCounts {
            primary: self.primary + other.primary,
            secondary: self.secondary + other.secondary,
            shadow: self.shadow + other.shadow,
            tallies: Tallies {
                intersections: self.tallies.intersections + other.tallies.intersections,
                cells: self.tallies.cells + other.tallies.cells,
            },
        }
    }
}

/// What one thread keeps between rays: the pending-ray list (so that no ray allocates) and its
/// counts.
#[derive(Debug, Default)]
pub struct Scratch {
    pending: Vec<Pending>,
    /// A packet's camera hits' shadow rays, put off to be cast together.
    batch: ShadowBatch,
    /// The rays cast with this scratch; the pixel loop sums those of every band at the end.
    pub counts: RayCounts,
}

/// A mirror or glass ray still to trace.
#[derive(Debug, Clone, Copy)]
struct Pending {
    ray: Ray,
    /// The least t of a hit: past the surface the ray leaves.
    t_min: f32,
    branch: Branch,
    /// A glass ray, not a mirror ray.
    transparent: bool,
    /// Cast past the limits (see [`TraceSeam::cast_past_limits`]): it brings the background
    /// or nothing.
    past_limits: bool,
}

/// Where a ray stands in the ray tree.
#[derive(Debug, Clone, Copy)]
struct Branch {
    bounces_left: u32,
    /// The course's weight: the product of the magnitudes of the colours on the way here.
    weight: f32,
    /// The product of the colours it was reflected or refracted by: what its colour counts for
    /// in the pixel.
    throughput: Vec3A,
}

/// Traces rays through one scene with one set of switches, as the course does (or, for
/// `check`, as variant `V` does).
#[derive(Debug, Clone, Copy)]
pub struct Tracer<'a, V = Exact> {
    scene: &'a Scene,
    settings: TraceSettings,
    variant: V,
}

impl<'a> Tracer<'a> {
    /// Traces through `scene` under `settings`; cheap to make, as it only borrows the scene.
    pub fn new(scene: &'a Scene, settings: TraceSettings) -> Self {
        Tracer::with_variant(scene, settings, Exact)
    }
}

impl<'a, V: TraceSeam> Tracer<'a, V> {
    /// [`Tracer::new`], tracing as `variant` does.
    pub fn with_variant(scene: &'a Scene, settings: TraceSettings, variant: V) -> Self {
        Tracer {
            scene,
            settings,
            variant,
        }
    }

    /// The scene it traces through (the pixel loop takes the camera from it).
    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// The colour seen along `ray` from its own start (the course's `traceRay` with weight 1 and
    /// every bounce left).
    pub fn trace(&self, ray: &Ray, t_min: f32, scratch: &mut Scratch) -> Vec3A {
        let hit = self.intersect(ray, t_min, scratch);
        self.colour(ray, hit.as_ref(), scratch)
    }

    /// A camera ray: what it hits (for the normal and depth pictures) and, if `colour`, the
    /// colour it sees; under `-visualize_grid`, the grid's first occupied cell instead.
    #[inline]
    pub fn camera_ray(
        &self,
        ray: &Ray,
        colour: bool,
        scratch: &mut Scratch,
    ) -> (Vec3A, Option<Hit>) {
        scratch.counts.primary += 1;
        let t_min = self.variant.camera_t_min(&self.scene.camera);
        if self.settings.visualize_grid {
            return self.grid_cell(ray, t_min, scratch);
        }
        let hit = self.intersect(ray, t_min, scratch);
        (self.seen(ray, hit.as_ref(), colour, scratch), hit)
    }

    /// [`Tracer::camera_ray`] for up to [`PACKET`] rays (a packet: a square of pixels), which search
    /// the scene together: `each(i, seen, hit)` gets ray i's results, the same as it alone
    /// would get.
    pub fn camera_rays(
        &self,
        rays: &[Ray],
        colour: bool,
        scratch: &mut Scratch,
        mut each: impl FnMut(usize, Vec3A, Option<Hit>),
    ) {
        if self.settings.visualize_grid {
            for (i, ray) in rays.iter().enumerate() {
                let (seen, hit) = self.camera_ray(ray, colour, scratch);
                each(i, seen, hit);
            }
            return;
        }
        scratch.counts.primary += rays.len() as u64;
        let t_min = self.variant.camera_t_min(&self.scene.camera);
        let world = &self.scene.world;
        let mut hits = [None; PACKET];
        let hits = &mut hits[..rays.len()];
        if self.settings.tally {
            world.intersect_packet_with(rays, t_min, hits, &mut scratch.counts.tallies);
        } else {
            world.intersect_packet_with(rays, t_min, hits, &mut ());
        }
        if colour && self.settings.shadows {
            for (hit, ray) in hits.iter_mut().zip(rays) {
                *hit = self.variant.found(self.scene, ray, t_min, *hit);
            }
            return self.shade_packet(rays, hits, scratch, each);
        }
        for (i, (ray, &hit)) in rays.iter().zip(hits.iter()).enumerate() {
            let hit = self.variant.found(self.scene, ray, t_min, hit);
            each(i, self.seen(ray, hit.as_ref(), colour, scratch), hit);
        }
    }

    /// What a camera ray that hit `hit` sees: its colour if `colour` is asked for, else black.
    /// A miss is the background straight away (the tracer's bookkeeping cost a ray that hits
    /// nothing a tenth of its time).
    #[inline(always)]
    fn seen(&self, ray: &Ray, hit: Option<&Hit>, colour: bool, scratch: &mut Scratch) -> Vec3A {
        match hit {
            _ if !colour => Vec3A::ZERO,
            None => self.scene.background,
            Some(hit) => self.colour(ray, Some(hit), scratch),
        }
    }

    /// The nearest hit, counted when `-stats` asks.
    #[inline(always)]
    fn intersect(&self, ray: &Ray, t_min: f32, scratch: &mut Scratch) -> Option<Hit> {
        let world = &self.scene.world;
        let hit = if self.settings.tally {
            world.intersect_with(ray, t_min, &mut scratch.counts.tallies)
        } else {
            world.intersect(ray, t_min)
        };
        self.variant.found(self.scene, ray, t_min, hit)
    }

    /// How much of a light reaches the shadow ray's origin through the glass on the way, in
    /// the way `through` (the handout's optional transparent shadows): nothing past an opaque
    /// surface.
    fn through_glass(
        &self,
        shadow: &Ray,
        near: f32,
        far: f32,
        through: ThroughGlass,
        scratch: &mut Scratch,
    ) -> Vec3A {
        let mut light = Vec3A::ONE;
        let mut from = near;
        let mut entered = None;
        for _ in 0..MAX_GLASS_CROSSINGS {
            let Some(hit) = self.intersect(shadow, from, scratch).filter(|h| h.t < far) else {
                return light;
            };
            if through == ThroughGlass::Opaque {
                return Vec3A::ZERO;
            }
            let point = shadow.at(hit.t);
            let mut surface = Surface::unweighed(&self.scene.materials, hit.material);
            self.variant.weigh(&mut surface, point);
            let transparent = surface.transparent();
            if transparent == Vec3A::ZERO {
                return Vec3A::ZERO;
            }
            let entering = shadow.direction.dot(hit.normal) < 0.0;
            match through {
                ThroughGlass::EachSurface => light *= transparent,
                ThroughGlass::EachObject if entering => light *= transparent,
                ThroughGlass::ByDistance if entering => entered = Some(hit.t),
                ThroughGlass::ByDistance => {
                    // Left without being seen to enter: the ray started inside.
                    let inside = hit.t - entered.take().unwrap_or(0.0);
                    light *= transparent.powf(inside * shadow.direction.length());
                }
                ThroughGlass::EachObject | ThroughGlass::Whole | ThroughGlass::Opaque => {}
            }
            from = hit.t + clearance(point, shadow.origin);
        }
        Vec3A::ZERO
    }

    #[inline(always)]
    fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, scratch: &mut Scratch) -> bool {
        let world = &self.scene.world;
        if self.settings.tally {
            world.occluded_with(ray, t_min, t_max, &mut scratch.counts.tallies)
        } else {
            world.occluded(ray, t_min, t_max)
        }
    }

    /// `-visualize_grid`: the first cell along the ray that lists a primitive, as an opaque
    /// cube coloured by how many it lists ([`grid_palette`]), lit by the scene's lights (no
    /// shadows) with the normal of the face the ray came in by.
    fn grid_cell(&self, ray: &Ray, t_min: f32, scratch: &mut Scratch) -> (Vec3A, Option<Hit>) {
        let scene = self.scene;
        let Some(grid) = scene.world.grid() else {
            return (scene.background, None);
        };
        let mut found = None;
        grid.walk(ray, t_min, f32::INFINITY, |cell| {
            scratch.counts.tallies.cells += u64::from(self.settings.tally);
            if cell.primitives.is_empty() {
                return ControlFlow::Continue(());
            }
            let mut normal = Vec3A::ZERO;
            normal[cell.entered_axis] = cell.entered_sign;
            found = Some((cell.t_enter, normal, cell.primitives.len()));
            ControlFlow::Break(())
        });
        let Some((t, normal, count)) = found else {
            return (scene.background, None);
        };
        let point = ray.at(t);
        let colour = grid_palette(count);
        let mut seen = scene.ambient * colour;
        for light in &scene.lights {
            if let Some(light) = light.illuminate(point) {
                seen += colour * normal.dot(light.to_light).max(0.0) * light.colour;
            }
        }
        let hit = Hit {
            t,
            normal,
            material: 0,
        };
        (seen, Some(hit))
    }

    /// The colour seen along `ray`, given what it hits (the camera's rays are cast by the
    /// caller, which also wants the hit for the normal and depth pictures). Unclamped.
    pub fn colour(&self, ray: &Ray, hit: Option<&Hit>, scratch: &mut Scratch) -> Vec3A {
        let colour = self.visit(ray, self.camera_branch(), hit, scratch, None);
        self.follow_pending(colour, scratch)
    }

    /// A camera ray's place in the ray tree: every bounce left, weight 1.
    fn camera_branch(&self) -> Branch {
        Branch {
            bounces_left: self.variant.bounces(self.settings.bounces),
            weight: 1.0,
            throughput: Vec3A::ONE,
        }
    }

    /// `colour` plus what the pending mirror and glass rays (and those they spawn) bring back.
    /// Most camera rays leave none: they return at once, without the call into the rest,
    /// whose frame is kilobytes (the shading inlined), set up and taken down on every hit.
    #[inline(always)]
    fn follow_pending(&self, colour: Vec3A, scratch: &mut Scratch) -> Vec3A {
        if scratch.pending.is_empty() {
            return colour;
        }
        self.follow_each_pending(colour, scratch)
    }

    #[inline(never)]
    fn follow_each_pending(&self, mut colour: Vec3A, scratch: &mut Scratch) -> Vec3A {
        let mut traced = 0;
        while let Some(next) = scratch.pending.pop() {
            traced += 1;
            if traced > MAX_RAYS_PER_CAMERA_RAY {
                scratch.pending.clear();
                break;
            }
            scratch.counts.secondary += 1;
            let seen = match self.intersect(&next.ray, next.t_min, scratch) {
                None => self
                    .variant
                    .escaped(self.scene.background, next.transparent),
                Some(_) if next.past_limits => Vec3A::ZERO,
                Some(hit) => self.visit(&next.ray, next.branch, Some(&hit), scratch, None),
            };
            colour += next.branch.throughput * seen;
        }
        colour
    }

    /// The light `ray` brings back from `hit` itself (ambient, then each light), queueing the
    /// mirror and glass rays it spawns. With `defer`, the number of a camera ray in its packet,
    /// the lights behind shadow rays are left out and their shadow rays put in the packet's
    /// batch (see [`Tracer::shade_packet`]).
    #[inline(always)]
    fn visit(
        &self,
        ray: &Ray,
        branch: Branch,
        hit: Option<&Hit>,
        scratch: &mut Scratch,
        defer: Option<usize>,
    ) -> Vec3A {
        let scene = self.scene;
        let Some(hit) = hit else {
            return scene.background;
        };
        let direction = ray.direction;
        let inside = direction.dot(hit.normal) > 0.0;
        let point = ray.at(hit.t);
        let mut turned = inside;
        if inside {
            match self.variant.back_face(self.settings.shade_back) {
                BackFace::Shaded => {}
                BackFace::Unturned => turned = false,
                BackFace::Black => return Vec3A::ZERO,
                BackFace::Ambient => {
                    let mut surface = Surface::unweighed(&scene.materials, hit.material);
                    self.variant.weigh(&mut surface, point);
                    let diffuse = self.variant.ambient_diffuse(&surface);
                    return self
                        .variant
                        .ambient(scene.ambient * diffuse, scene.lights.len());
                }
            }
        }
        let normal = if turned { -hit.normal } else { hit.normal };
        let mut surface = Surface::unweighed(&scene.materials, hit.material);
        self.variant.weigh(&mut surface, point);
        // How far the rays this hit sends must clear its surface: once for all of them.
        let clearance = clearance(point, ray.origin);
        let local = self.variant.local_weight(&surface);
        let mut colour = local
            * self.variant.ambient(
                scene.ambient * self.variant.ambient_diffuse(&surface),
                scene.lights.len(),
            );
        let visited = self.variant.lights_visited(scene.lights.len());
        for (light_index, light) in scene.lights.iter().enumerate().take(visited) {
            let Some(light) = self.variant.illuminate(light, point) else {
                continue;
            };
            let shaded = self.variant.light(
                |normal, falloff, highlight| {
                    let to_light = light.to_light;
                    surface.shade(
                        normal,
                        direction,
                        to_light,
                        light.colour,
                        falloff,
                        highlight,
                    )
                },
                normal,
                light.to_light,
                self.settings.specular,
                LightPlace {
                    index: light_index,
                    of: scene.lights.len(),
                },
            ) * local;
            if self.settings.shadows {
                // A light that adds nothing here needs no shadow ray.
                if shaded == Vec3A::ZERO {
                    continue;
                }
                scratch.counts.shadow += 1;
                let shadow = Ray::new(point, self.variant.shadow_direction(&light));
                let near = self.variant.start_t(clearance, light.to_light, normal);
                let far = self.variant.shadow_end(light.distance);
                if let Some(through) = self.variant.shadow_through_glass() {
                    colour += shaded * self.through_glass(&shadow, near, far, through, scratch);
                    continue;
                }
                if let Some(camera_ray) = defer {
                    scratch
                        .batch
                        .defer(camera_ray, light_index, shadow, near, far, shaded);
                    continue;
                }
                if self.occluded(&shadow, near, far, scratch) {
                    continue;
                }
            }
            colour += shaded;
        }
        let past_limits = self.variant.cast_past_limits();
        if branch.bounces_left > 0 || past_limits.is_some() {
            let unit = direction.normalize();
            let mut spawn = |colour: Vec3A, transparent: bool, direction: Vec3A| {
                let weight = self.variant.ray_weight(branch.weight, colour);
                let carried =
                    self.variant
                        .carried(colour, transparent, &surface, scene.lights.len());
                let throughput = branch.throughput * carried;
                let cutoff = self.variant.cutoff_weight(self.settings.cutoff_weight);
                let worth = worth_tracing(cutoff, weight, throughput);
                let within = branch.bounces_left > 0 && worth;
                let past = !within && past_limits.is_some_and(|weight_too| worth || weight_too);
                if within || past {
                    scratch.pending.push(Pending {
                        ray: Ray::new(point, direction),
                        t_min: self.variant.secondary_start_t(clearance, direction, normal),
                        branch: Branch {
                            bounces_left: branch.bounces_left.saturating_sub(1),
                            weight,
                            throughput,
                        },
                        transparent,
                        past_limits: past,
                    });
                }
            };
            let reflective = surface.reflective();
            if reflective != Vec3A::ZERO {
                spawn(reflective, false, self.variant.reflect(unit, normal));
            }
            let transparent = surface.transparent();
            if transparent != Vec3A::ZERO {
                // Outside is air (index 1); which side the ray is on says which way it crosses.
                let index = surface.index_of_refraction();
                let ratio = self.variant.crossing_ratio(index, inside);
                if let Some(refracted) = self.variant.refract(unit, normal, ratio, inside) {
                    spawn(transparent, true, refracted);
                }
            }
        }
        colour
    }
}

/// `-visualize_grid`'s colours by the number of primitives a cell lists: white for one, then
/// purple, blue, cyan, green, yellow and orange, and red for eight or more (the handout's
/// example runs from white through purple to red and leaves the scale free).
pub fn grid_palette(count: usize) -> Vec3A {
    const PALETTE: [[f32; 3]; 8] = [
        [1.0, 1.0, 1.0],
        [0.75, 0.35, 1.0],
        [0.3, 0.35, 1.0],
        [0.2, 0.85, 0.95],
        [0.3, 0.9, 0.3],
        [1.0, 0.95, 0.25],
        [1.0, 0.6, 0.15],
        [1.0, 0.15, 0.1],
    ];
    Vec3A::from(PALETTE[count.clamp(1, 8) - 1])
}

/// The course's weight and the colour product of a mirror or glass ray spawned with `colour`
/// from a ray of `weight` and `throughput`.
#[inline]
pub fn spawned(weight: f32, throughput: Vec3A, colour: Vec3A) -> (f32, Vec3A) {
    (ray_weight(weight, colour), throughput * colour)
}

/// The course's weight of a mirror or glass ray spawned with `colour` from a ray of `weight`:
/// the product of the colours' magnitudes on the way.
#[inline]
pub fn ray_weight(weight: f32, colour: Vec3A) -> f32 {
    weight * colour.length()
}

/// Whether a spawned ray is traced: its weight at least the cut-off (`-weight`), and its colour
/// able to count for something in the pixel.
#[inline]
pub fn worth_tracing(cutoff_weight: f32, weight: f32, throughput: Vec3A) -> bool {
    weight >= cutoff_weight && throughput.abs().max_element() >= NEGLIGIBLE_THROUGHPUT
}

/// η_i / η_t for a ray crossing a surface of `index`: outside is air (index 1), and which side
/// the ray is on says which way it crosses.
#[inline]
pub fn crossing_ratio(index: f32, inside: bool) -> f32 {
    if inside { index } else { 1.0 / index }
}

/// Where a shadow ray toward a light `distance` away stops: just short of the light (its least
/// t comes from [`start_t`]).
#[inline]
pub fn shadow_end(distance: f32) -> f32 {
    distance.next_down()
}

/// How far the rays leaving hit point `point` (found by a ray from `from`) must clear its
/// surface: [`RELATIVE_OFFSET`] of the largest coordinate of `point` and `from`. A computed hit
/// point (`from + t·direction`) is off its surface by a rounding error of a few ulps of those
/// coordinates, whatever the scene's scale; a fixed t (the course's 1e-4) is far too large for
/// a scene a thousandth of a unit across (shadows lost in its details) and too small for one ten
/// thousand units across (acne).
#[inline]
pub fn clearance(point: Vec3A, from: Vec3A) -> f32 {
    point.abs().max(from.abs()).max_element() * RELATIVE_OFFSET
}

/// The least t of a ray leaving a surface of unit `normal` along unit `direction` that must
/// clear it by `clearance`. The ray keeps its line (a start moved along the normal would shift
/// it sideways, which glass of index 1 shows); at grazing angles the t is capped where the ray
/// would have to run 64 times the clearance along the surface.
#[inline]
pub fn start_t(clearance: f32, direction: Vec3A, normal: Vec3A) -> f32 {
    clearance / direction.dot(normal).abs().max(1.0 / 64.0)
}

/// The mirror direction of unit `direction` about unit `normal` (either side).
#[inline]
pub fn reflect(direction: Vec3A, normal: Vec3A) -> Vec3A {
    direction - 2.0 * direction.dot(normal) * normal
}

/// The direction of unit `direction` once through a surface with unit `normal` facing against
/// it, `ratio` being the index it leaves over the index it enters (η_i / η_t); `None` on total
/// internal reflection. The course's formula: with I = −direction,
/// T = [η (N·I) − √(1 − η² (1 − (N·I)²))] N − η I.
#[inline]
pub fn refract(direction: Vec3A, normal: Vec3A, ratio: f32) -> Option<Vec3A> {
    let k = refraction_radicand(direction, normal, ratio);
    (k >= 0.0).then(|| refracted(direction, normal, ratio, k.sqrt()))
}

/// What [`refract`] takes the square root of: 1 − η² (1 − (N·I)²), negative past the critical
/// angle.
#[inline]
pub fn refraction_radicand(direction: Vec3A, normal: Vec3A, ratio: f32) -> f32 {
    let cos_in = -normal.dot(direction);
    1.0 - ratio * ratio * (1.0 - cos_in * cos_in)
}

/// The course's refracted direction, [η (N·I) − root] N − η I, with `root` in place of the
/// square root of the [`refraction_radicand`].
#[inline]
pub fn refracted(direction: Vec3A, normal: Vec3A, ratio: f32, root: f32) -> Vec3A {
    let incoming = -direction;
    let cos_in = normal.dot(incoming);
    ((ratio * cos_in - root) * normal - ratio * incoming).normalize()
}

#[cfg(test)]
mod tests;
