//! The tracer's tests: its formulas by hand, and scenes traced.

use std::path::Path;

use super::*;
use crate::parse::parse_scene;

fn close(a: Vec3A, b: Vec3A) -> bool {
    (a - b).abs().max_element() < 1e-6
}

#[test]
fn reflection_by_hand() {
    let d = Vec3A::new(1.0, -1.0, 0.0).normalize();
    assert!(close(
        reflect(d, Vec3A::Y),
        Vec3A::new(1.0, 1.0, 0.0).normalize()
    ));
    // The same mirror seen from below: the normal's side does not matter.
    assert!(close(
        reflect(d, -Vec3A::Y),
        Vec3A::new(1.0, 1.0, 0.0).normalize()
    ));
    // Head on, straight back.
    assert!(close(reflect(-Vec3A::Z, Vec3A::Z), Vec3A::Z));
}

#[test]
fn refraction_into_glass_by_hand() {
    // 45° into index 1.5: sin θt = sin 45° / 1.5 = 0.4714, cos θt = 0.8819.
    let d = Vec3A::new(1.0, -1.0, 0.0).normalize();
    let t = refract(d, Vec3A::Y, 1.0 / 1.5).unwrap();
    assert!(close(t, Vec3A::new(0.471_404_5, -0.881_917_1, 0.0)), "{t}");
    // Index 1 bends nothing.
    assert!(close(refract(d, Vec3A::Y, 1.0).unwrap(), d));
    // Head on goes straight through.
    assert!(close(
        refract(-Vec3A::Y, Vec3A::Y, 1.0 / 1.5).unwrap(),
        -Vec3A::Y
    ));
}

#[test]
fn refraction_out_of_glass_and_total_internal_reflection() {
    // Inside index 1.5, the normal turned to face the ray: 20° leaves with
    // sin θt = 1.5 sin 20° = 0.513030 (Snell), cos θt = 0.858371.
    let angle = 20f32.to_radians();
    let d = Vec3A::new(angle.sin(), angle.cos(), 0.0);
    let t = refract(d, -Vec3A::Y, 1.5).unwrap();
    assert!(close(t, Vec3A::new(0.513_030_2, 0.858_370_5, 0.0)), "{t}");
    // The critical angle is asin(1/1.5) = 41.81°: 45° stays inside.
    let d = Vec3A::new(1.0, 1.0, 0.0).normalize();
    assert_eq!(refract(d, -Vec3A::Y, 1.5), None);
    // Just under it, out at nearly 90°.
    let angle = 41.8f32.to_radians();
    let d = Vec3A::new(angle.sin(), angle.cos(), 0.0);
    let t = refract(d, -Vec3A::Y, 1.5).unwrap();
    assert!(t.y > 0.0 && t.y < 0.03, "{t}");
}

#[test]
fn shadow_range_stops_short_of_the_light() {
    let far = shadow_end(5.0);
    assert!(far < 5.0 && far > 4.9999);
    assert_eq!(shadow_end(f32::INFINITY), f32::MAX);
}

#[test]
fn rays_clear_their_surface_by_a_share_of_its_size() {
    // 2^-16 of the largest coordinate, straight off the surface: 1000 → 1000/65536.
    let t = start_t(
        clearance(Vec3A::new(1000.0, -3.0, 2.0), Vec3A::ZERO),
        Vec3A::Y,
        Vec3A::Y,
    );
    assert_eq!(t, 1000.0 / 65536.0);
    // Scaled down a million times, the clearance is too.
    let small = start_t(
        clearance(Vec3A::new(1e-3, -3e-6, 2e-6), Vec3A::ZERO),
        Vec3A::Y,
        Vec3A::Y,
    );
    assert_eq!(small, 1e-3 / 65536.0);
    // Found by a ray from farther away, the point's error is that far's: so is the step;
    // at 60° from the normal the ray runs twice as far to clear it.
    let leaning = Vec3A::new(3f32.sqrt() / 2.0, 0.5, 0.0);
    let far = start_t(
        clearance(Vec3A::ZERO, Vec3A::new(0.0, 0.0, -8.0)),
        leaning,
        Vec3A::Y,
    );
    assert!((far - 2.0 * 8.0 / 65536.0).abs() < 1e-9, "{far}");
    // Along the surface, capped at 64 clearances.
    assert_eq!(
        start_t(clearance(Vec3A::X, Vec3A::ZERO), Vec3A::X, Vec3A::Y),
        64.0 / 65536.0
    );
}

fn scene(text: &str) -> Scene {
    let description = parse_scene(Path::new("t.txt"), text).unwrap();
    Scene::from_description(&description).unwrap()
}

const MIRRORS: &str = "
    OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
    Background { color 0.5 0.25 1 ambientLight 1 1 1 }
    Materials { numMaterials 2
        Material { diffuseColor 0.1 0.2 0.3 reflectiveColor 0.5 0.5 0.5 }
        Material { diffuseColor 0.4 0 0 } }
    Group { numObjects 2
        MaterialIndex 0 Plane { normal 0 0 1 offset 0 }
        MaterialIndex 1 Plane { normal 0 0 -1 offset -20 } }";

#[test]
fn bounces_and_the_weight_cut_off() {
    // A camera ray meets a mirror (diffuse 0.1 0.2 0.3, reflective 0.5 grey); the reflected
    // ray meets a red wall behind the camera. |0.5 0.5 0.5| = 0.866.
    let scene = scene(MIRRORS);
    let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
    let colour = |bounces, cutoff_weight| {
        let settings = TraceSettings {
            bounces,
            cutoff_weight,
            ..TraceSettings::default()
        };
        let mut scratch = Scratch::default();
        let c = Tracer::new(&scene, settings).trace(&ray, 0.0, &mut scratch);
        (c, scratch.counts.secondary)
    };
    let mirror = Vec3A::new(0.1, 0.2, 0.3);
    let wall = Vec3A::new(0.4, 0.0, 0.0);
    assert_eq!(colour(0, 0.0), (mirror, 0));
    assert_eq!(colour(1, 0.0), (mirror + 0.5 * wall, 1));
    // At or under 0.866 the reflection is traced, above it not.
    assert_eq!(colour(1, 0.866).1, 1);
    assert_eq!(colour(1, 0.867), (mirror, 0));
    // More bounces change nothing: the wall does not reflect.
    assert_eq!(colour(5, 0.0), (mirror + 0.5 * wall, 1));
}

#[test]
fn a_mirror_ray_that_escapes_brings_the_background() {
    let scene = scene(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
         Background { color 0.5 0.25 1 ambientLight 1 1 1 }
         Materials { numMaterials 1 Material { diffuseColor 0 0 0 reflectiveColor 1 0.5 0 } }
         Group { numObjects 1 MaterialIndex 0 Plane { normal 0 0 1 offset 0 } }",
    );
    let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
    let settings = TraceSettings {
        bounces: 1,
        ..TraceSettings::default()
    };
    let c = Tracer::new(&scene, settings).trace(&ray, 0.0, &mut Scratch::default());
    assert_eq!(c, Vec3A::new(0.5, 0.125, 0.0));
}

#[test]
fn what_an_escaped_mirror_ray_brings_is_the_seams_and_a_camera_miss_stays_the_background() {
    #[derive(Clone, Copy)]
    struct Black;
    impl TraceSeam for Black {
        fn escaped(&self, _background: Vec3A, _transparent: bool) -> Vec3A {
            Vec3A::ZERO
        }
    }
    let scene = scene(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
         Background { color 0.5 0.25 1 ambientLight 1 1 1 }
         Materials { numMaterials 1 Material { diffuseColor 0.25 0 0 reflectiveColor 1 0.5 0 } }
         Group { numObjects 1 MaterialIndex 0 Plane { normal 0 0 1 offset 0 } }",
    );
    let settings = TraceSettings {
        bounces: 1,
        ..TraceSettings::default()
    };
    let tracer = Tracer::with_variant(&scene, settings, Black);
    let mut scratch = Scratch::default();
    let down = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
    assert_eq!(
        tracer.camera_ray(&down, true, &mut scratch).0,
        Vec3A::new(0.25, 0.0, 0.0)
    );
    let along = Ray::new(Vec3A::new(0.0, 0.0, 10.0), Vec3A::X);
    assert_eq!(
        tracer.camera_ray(&along, true, &mut scratch).0,
        Vec3A::new(0.5, 0.25, 1.0)
    );
}

/// A tracer's seams as check's faults set them, one at a time.
#[derive(Clone, Copy, Default)]
struct Seams {
    past_limits: Option<bool>,
    secondary_times: Option<f32>,
    shadow_reversed: bool,
}

impl TraceSeam for Seams {
    fn cast_past_limits(&self) -> Option<bool> {
        self.past_limits
    }

    fn carried(
        &self,
        colour: Vec3A,
        _transparent: bool,
        _surface: &Surface<'_>,
        _lights: usize,
    ) -> Vec3A {
        colour * self.secondary_times.unwrap_or(1.0)
    }

    fn shadow_direction(&self, light: &Illumination) -> Vec3A {
        if self.shadow_reversed {
            -light.to_light
        } else {
            light.to_light
        }
    }
}

#[test]
fn rays_past_the_limits_bring_the_background_or_nothing() {
    let trace = |text: &str, bounces, cutoff_weight, past_limits| {
        let scene = scene(text);
        let settings = TraceSettings {
            bounces,
            cutoff_weight,
            ..TraceSettings::default()
        };
        let seams = Seams {
            past_limits,
            ..Seams::default()
        };
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
        Tracer::with_variant(&scene, settings, seams).trace(&ray, 0.0, &mut Scratch::default())
    };
    // A mirror under the open sky (reflective 1 0.5 0, |c| = 1.118): a ray one bounce past
    // -bounces 0 brings the background, 0.5 0.25 1, times the mirror's colour.
    let sky = "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
         Background { color 0.5 0.25 1 ambientLight 1 1 1 }
         Materials { numMaterials 1 Material { diffuseColor 0 0 0 reflectiveColor 1 0.5 0 } }
         Group { numObjects 1 MaterialIndex 0 Plane { normal 0 0 1 offset 0 } }";
    let background = Vec3A::new(0.5, 0.125, 0.0);
    assert_eq!(trace(sky, 0, 0.0, None), Vec3A::ZERO);
    assert_eq!(trace(sky, 0, 0.0, Some(false)), background);
    // Below -weight: cast only where the weight is tested late too.
    assert_eq!(trace(sky, 1, 2.0, Some(false)), Vec3A::ZERO);
    assert_eq!(trace(sky, 1, 2.0, Some(true)), background);
    // A ray past the limit that meets something (the red wall behind the camera) brings
    // nothing: the mirror's own colour alone.
    assert_eq!(
        trace(MIRRORS, 0, 0.0, Some(false)),
        Vec3A::new(0.1, 0.2, 0.3)
    );
}

#[test]
fn the_mirror_counted_per_light_and_the_shadow_ray_turned_around() {
    // The mirror's reflection of the red wall, counted three times.
    let scene_of_mirrors = scene(MIRRORS);
    let settings = TraceSettings {
        bounces: 1,
        ..TraceSettings::default()
    };
    let thrice = Seams {
        secondary_times: Some(3.0),
        ..Seams::default()
    };
    let down = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
    let c = Tracer::with_variant(&scene_of_mirrors, settings, thrice).trace(
        &down,
        0.0,
        &mut Scratch::default(),
    );
    assert!(
        (c - Vec3A::new(0.7, 0.2, 0.3)).abs().max_element() < 1e-6,
        "{c}"
    );
    // A white floor under a ball, lit from straight above: the point under the ball is in
    // its shadow, unless the shadow ray looks down, away from the light.
    let shadowed = scene(
        "OrthographicCamera { center 0 10 0 direction 0 -1 0 up 0 0 1 size 2 }
         Lights { numLights 1 DirectionalLight { direction 0 -1 0 color 1 1 1 } }
         Background { color 0 0 0 ambientLight 0 0 0 }
         Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }
         Group { numObjects 2 MaterialIndex 0
             Plane { normal 0 1 0 offset 0 }
             Sphere { center 0 2 0 radius 1 } }",
    );
    let settings = TraceSettings {
        shadows: true,
        ..TraceSettings::default()
    };
    let under = Ray::new(Vec3A::new(0.0, 0.5, 5.0), Vec3A::new(0.0, -0.5, -5.0));
    let lit = |shadow_reversed| {
        let seams = Seams {
            shadow_reversed,
            ..Seams::default()
        };
        Tracer::with_variant(&shadowed, settings, seams).trace(&under, 0.0, &mut Scratch::default())
    };
    assert_eq!(lit(false), Vec3A::ZERO);
    assert_eq!(lit(true), Vec3A::ONE);
}

#[test]
fn glass_without_shade_back_is_dark_inside() {
    // A clear glass slab seen head on in front of a white wall: the glass ray meets the
    // slab's back face from inside, which is black unless back faces are shaded.
    let scene = scene(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
         Background { color 0 0 0 ambientLight 1 1 1 }
         Materials { numMaterials 2
             Material { diffuseColor 0 0 0 transparentColor 0.5 0.5 0.5 indexOfRefraction 1.5 }
             Material { diffuseColor 1 1 1 } }
         Group { numObjects 3
             MaterialIndex 0
             Triangle { vertex0 -5 -5 1 vertex1 5 -5 1 vertex2 0 5 1 }
             Triangle { vertex0 -5 -5 -1 vertex1 0 5 -1 vertex2 5 -5 -1 }
             MaterialIndex 1 Plane { normal 0 0 1 offset -5 } }",
    );
    let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
    let colour = |shade_back| {
        let settings = TraceSettings {
            shade_back,
            bounces: 5,
            ..TraceSettings::default()
        };
        Tracer::new(&scene, settings).trace(&ray, 0.0, &mut Scratch::default())
    };
    assert_eq!(colour(false), Vec3A::ZERO);
    // In, out, and onto the wall: 0.5 · 0.5 · white.
    assert_eq!(colour(true), Vec3A::splat(0.25));
}

#[test]
fn shadow_ray_epsilon_and_light_distance() {
    // A floor lit by a point light at (3, 0, 2) and a dim directional light from straight
    // above; a small sphere halfway to the point light, off the camera ray, can block it.
    let floor = |blocker: &str| {
        // A blocker may bring a material of its own: "Material { ... } MaterialIndex 1 ...".
        let (glass, blocker) = match blocker.split_once(" MaterialIndex") {
            Some((material, rest)) => (material, format!("MaterialIndex{rest}")),
            None => ("", blocker.to_string()),
        };
        let materials = if glass.is_empty() { 1 } else { 2 };
        scene(&format!(
            "OrthographicCamera {{ center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }}
             Background {{ color 0 0 0 ambientLight 0 0 0 }}
             Lights {{ numLights 2 PointLight {{ position 3 0 2 color 0.5 0.5 0.5 }}
                 DirectionalLight {{ direction 0 0 -1 color 0.1 0.2 0.3 }} }}
             Materials {{ numMaterials {materials} Material {{ diffuseColor 1 1 1 }} {glass} }}
             Group {{ numObjects 2 MaterialIndex 0 Plane {{ normal 0 0 1 offset 0 }}
                 {blocker} }}"
        ))
    };
    let floor_point = |scene: &Scene, shadows| {
        let settings = TraceSettings {
            shadows,
            ..TraceSettings::default()
        };
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
        let mut scratch = Scratch::default();
        let c = Tracer::new(scene, settings).trace(&ray, 0.0, &mut scratch);
        (c, scratch.counts.shadow)
    };
    // N·L = 2/√13 for the point light, 1 for the directional one.
    let point_share = Vec3A::splat(0.5 * 2.0 / 13f32.sqrt());
    let directional_share = Vec3A::new(0.1, 0.2, 0.3);
    let open = floor("Sphere { center 1.5 3 1 radius 0.1 }");
    let blocked = floor("Sphere { center 1.5 0 1 radius 0.1 }");
    let (lit, rays) = floor_point(&open, true);
    assert!(close(lit, point_share + directional_share), "{lit}");
    assert_eq!(rays, 2);
    let (shadowed, rays) = floor_point(&blocked, true);
    assert_eq!(rays, 2);
    // Exactly the blocked light's share is missing.
    assert!(close(lit - shadowed, point_share), "{shadowed}");
    // Without -shadows, no shadow rays and no shadow.
    assert_eq!(floor_point(&blocked, false), (lit, 0));
    // Glass casts the same, opaque shadow (the course's rule).
    let glass = floor(
        "Material { diffuseColor 0 0 0 transparentColor 1 1 1 indexOfRefraction 1 }
         MaterialIndex 1 Sphere { center 1.5 0 1 radius 0.1 }",
    );
    let (through_glass, _) = floor_point(&glass, true);
    assert!(close(through_glass, shadowed), "{through_glass}");
    // The handout's optional transparent shadows: glass of colour 0.5 and of 0.2 units
    // across the ray lets through 0.25 at two surfaces, 0.5 for one object, 0.5^0.2
    // by the distance; an opaque sphere still nothing.
    #[derive(Clone, Copy)]
    struct Through(ThroughGlass);
    impl TraceSeam for Through {
        fn shadow_through_glass(&self) -> Option<ThroughGlass> {
            Some(self.0)
        }
    }
    let tinted = floor(
        "Material { diffuseColor 0 0 0 transparentColor 0.5 0.5 0.5 indexOfRefraction 1 }
         MaterialIndex 1 Sphere { center 1.5 0 1 radius 0.1 }",
    );
    let through = |scene: &Scene, way| {
        let settings = TraceSettings {
            shadows: true,
            ..TraceSettings::default()
        };
        let ray = Ray::new(Vec3A::new(0.0, 0.0, 10.0), -Vec3A::Z);
        Tracer::with_variant(scene, settings, Through(way)).trace(
            &ray,
            0.0,
            &mut Scratch::default(),
        )
    };
    for (way, share) in [
        (ThroughGlass::EachSurface, 0.25),
        (ThroughGlass::EachObject, 0.5),
        (ThroughGlass::ByDistance, 0.5f32.powf(0.2)),
    ] {
        let lit = through(&tinted, way);
        assert!(close(lit, shadowed + point_share * share), "{way:?}: {lit}");
        assert!(close(through(&blocked, way), shadowed), "{way:?}");
    }

    let blocked = scene(
        "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 2 }
         Background { color 0 0 0 ambientLight 0 0 0 }
         Lights { numLights 1 PointLight { position 0 0 2 color 0.5 0.5 0.5 } }
         Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }
         Group { numObjects 1 MaterialIndex 0 Plane { normal 0 0 1 offset 0 } }",
    );
    let world = &blocked.world;
    // From a point on the floor found by a camera ray from 10 above, toward the light:
    // the floor does not block, nor does it from a hair below it.
    let near = start_t(
        clearance(Vec3A::ZERO, Vec3A::new(0.0, 0.0, 10.0)),
        Vec3A::Z,
        Vec3A::Z,
    );
    let far = shadow_end(2.0);
    let up = Ray::new(Vec3A::ZERO, Vec3A::Z);
    assert!(!world.occluded(&up, near, far));
    let under = Ray::new(Vec3A::new(0.0, 0.0, -1e-6), Vec3A::Z);
    assert!(!world.occluded(&under, near, far));
    // Below the clearance (10/65536), it does.
    let deeper = Ray::new(Vec3A::new(0.0, 0.0, -2e-4), Vec3A::Z);
    assert!(world.occluded(&deeper, near, far));
    // A surface beyond the light does not block: the light at distance 2 from a point 3
    // below the plane... the plane is at t = 3, past the light.
    let below = Ray::new(Vec3A::new(0.0, 0.0, -3.0), Vec3A::Z);
    let (near, far) = (0.0, shadow_end(2.0));
    assert!(!world.occluded(&below, near, far));
    let (near, far) = (0.0, shadow_end(3.5));
    assert!(world.occluded(&below, near, far));
    // Exactly at the light's distance: open end, no block.
    let (near, far) = (0.0, shadow_end(3.0));
    assert!(!world.occluded(&below, near, far));
}
