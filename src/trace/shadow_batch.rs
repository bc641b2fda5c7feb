//! The shadow rays of a packet of camera rays, cast together.
//!
//! Under `-shadows`, shading a hit asks one shadow ray for each light that adds to it. A
//! packet's camera rays hit points close together, so their shadow rays toward one light run
//! nearly alike (exactly alike toward a directional light) and can walk the trees as a packet,
//! as the camera rays did. So each camera hit is shaded with the lights behind shadow rays left
//! out and those rays put off; once every one is answered, each light not blocked is added, in
//! the lights' order, as the ray-by-ray shading adds it: the same sum, the same bits. The
//! mirror and glass rays a hit spawns wait, in their order, until its sum is whole.

use arrayvec::ArrayVec;
use glam::Vec3A;

use super::{Pending, Scratch, TraceSeam, Tracer};
use crate::accel::{Hit, PACKET};
use crate::geometry::Ray;

/// A shadow ray put off: which camera ray's hit asked it, toward which light, over what range,
/// and what the light adds there unless it is blocked.
#[derive(Debug, Clone, Copy)]
struct Deferred {
    camera_ray: usize,
    light: usize,
    ray: Ray,
    near: f32,
    far: f32,
    shaded: Vec3A,
    blocked: bool,
}

/// A packet's shadow rays and spawned rays, kept in the thread's scratch so that no packet
/// allocates.
#[derive(Debug, Default)]
pub(super) struct ShadowBatch {
    /// Camera ray by camera ray, each's lights in order.
    deferred: Vec<Deferred>,
    /// `deferred`'s indices, light by light.
    by_light: Vec<u32>,
    /// The mirror and glass rays each hit spawned, camera ray by camera ray.
    spawned: Vec<Pending>,
}

impl ShadowBatch {
    /// Puts off the shadow ray that camera ray `camera_ray`'s hit sends toward light `light`,
    /// which adds `shaded` unless something lies on `ray` within [near, far].
    pub(super) fn defer(
        &mut self,
        camera_ray: usize,
        light: usize,
        ray: Ray,
        near: f32,
        far: f32,
        shaded: Vec3A,
    ) {
        self.deferred.push(Deferred {
            camera_ray,
            light,
            ray,
            near,
            far,
            shaded,
            blocked: false,
        });
    }
}

impl<V: TraceSeam> Tracer<'_, V> {
    /// The colours the camera rays `rays` see, given their hits, with their hits' shadow rays
    /// cast as packets, one light at a time: `each(i, seen, hit)` gets ray i's, the same as
    /// [`Tracer::colour`] gives.
    pub(super) fn shade_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        scratch: &mut Scratch,
        mut each: impl FnMut(usize, Vec3A, Option<Hit>),
    ) {
        scratch.batch.deferred.clear();
        scratch.batch.spawned.clear();
        let mut unshadowed = [Vec3A::ZERO; PACKET];
        let mut spawned = [(0, 0); PACKET];
        for (i, (ray, hit)) in rays.iter().zip(hits).enumerate() {
            if let Some(hit) = hit {
                unshadowed[i] = self.visit(ray, self.camera_branch(), Some(hit), scratch, Some(i));
                let start = scratch.batch.spawned.len();
                scratch.batch.spawned.append(&mut scratch.pending);
                spawned[i] = (start, scratch.batch.spawned.len());
            }
        }
        self.cast_deferred(scratch);
        let mut next = 0;
        for (i, hit) in hits.iter().enumerate() {
            let Some(hit) = hit else {
                each(i, self.scene.background, None);
                continue;
            };
            let mut colour = unshadowed[i];
            let deferred = &scratch.batch.deferred;
            while let Some(shadow) = deferred.get(next).filter(|d| d.camera_ray == i) {
                if !shadow.blocked {
                    colour += shadow.shaded;
                }
                next += 1;
            }
            let (start, end) = spawned[i];
            scratch
                .pending
                .extend_from_slice(&scratch.batch.spawned[start..end]);
            each(i, self.follow_pending(colour, scratch), Some(*hit));
        }
    }

    /// Answers every deferred shadow ray, those toward each light in packets of camera-ray
    /// order.
    fn cast_deferred(&self, scratch: &mut Scratch) {
        let Scratch { batch, counts, .. } = scratch;
        let ShadowBatch {
            deferred, by_light, ..
        } = batch;
        by_light.clear();
        by_light.extend(0..deferred.len() as u32);
        by_light.sort_unstable_by_key(|&k| (deferred[k as usize].light, k));
        let world = &self.scene.world;
        let mut start = 0;
        while start < by_light.len() {
            let light = deferred[by_light[start] as usize].light;
            let end = start
                + by_light[start..]
                    .iter()
                    .take_while(|&&k| deferred[k as usize].light == light)
                    .count();
            for packet in by_light[start..end].chunks(PACKET) {
                let shadow = |k: &u32| deferred[*k as usize];
                let rays: ArrayVec<Ray, PACKET> = packet.iter().map(|k| shadow(k).ray).collect();
                let near: ArrayVec<f32, PACKET> = packet.iter().map(|k| shadow(k).near).collect();
                let far: ArrayVec<f32, PACKET> = packet.iter().map(|k| shadow(k).far).collect();
                let mut blocked = [false; PACKET];
                let blocked = &mut blocked[..packet.len()];
                if self.settings.tally {
                    world.occluded_packet_with(&rays, &near, &far, blocked, &mut counts.tallies);
                } else {
                    world.occluded_packet_with(&rays, &near, &far, blocked, &mut ());
                }
                for (&k, &blocked) in packet.iter().zip(blocked.iter()) {
                    deferred[k as usize].blocked = blocked;
                }
            }
            start = end;
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::camera::pixel_to_screen;
    use crate::parse::parse_scene;
    use crate::scene::Scene;
    use crate::trace::TraceSettings;

    /// Two suns, a lamp, a mirror floor, glass, a mesh under a Transform and spheres, some
    /// lit from behind: every way a shadow ray can be put off, blocked or not, with mirror and
    /// glass rays waiting behind the sums.
    const SCENE: &str = "
        PerspectiveCamera { center 0 1 6 direction 0 -0.15 -1 up 0 1 0 angle 50 }
        Lights { numLights 3
            DirectionalLight { direction -0.4 -1 -0.3 color 0.6 0.6 0.6 }
            DirectionalLight { direction 0.7 -0.2 0.5 color 0.2 0.3 0.2 }
            PointLight { position 0.5 2.5 1.5 color 0.7 0.6 0.5 attenuation 1 0 0.05 } }
        Background { color 0.1 0.1 0.2 ambientLight 0.2 0.2 0.2 }
        Materials { numMaterials 4
            Material { diffuseColor 0.8 0.8 0.8 specularColor 0.5 0.5 0.5 exponent 20 }
            Material { diffuseColor 0.2 0.3 0.2 reflectiveColor 0.5 0.5 0.5 }
            Material { diffuseColor 0.1 0.1 0.1 transparentColor 0.8 0.8 0.8 indexOfRefraction 1.3 }
            Material { diffuseColor 0.9 0.4 0.2 } }
        Group { numObjects 5
            MaterialIndex 1 Plane { normal 0 1 0 offset -1 }
            MaterialIndex 0 Sphere { center -1 0 0 radius 0.8 }
            MaterialIndex 2 Sphere { center 0.8 0 0.8 radius 0.6 }
            MaterialIndex 3 Transform { Translate 0.5 0.2 -1.5 Scale 0.7 1.2 0.7
                Group { numObjects 2
                    Triangle { vertex0 -1 -1 0 vertex1 1 -1 0 vertex2 0 1 0.5 }
                    Triangle { vertex0 1 -1 0 vertex1 0 -1 -1 vertex2 0 1 0.5 } } }
            MaterialIndex 0 Triangle { vertex0 -2 -1 -2 vertex1 2 -1 -2 vertex2 0 2 -2.5 } }";

    #[test]
    fn a_packet_shaded_together_sees_what_each_ray_sees_alone() {
        let description = parse_scene(Path::new("t.txt"), SCENE).unwrap();
        let scene = Scene::from_description(&description).unwrap();
        let size = 48;
        let mut shadowed = 0;
        for shade_back in [false, true] {
            let settings = TraceSettings {
                shadows: true,
                shade_back,
                bounces: 3,
                ..TraceSettings::default()
            };
            let tracer = Tracer::new(&scene, settings);
            let (mut alone, mut together) = (Scratch::default(), Scratch::default());
            for (top, left) in
                (0..size / 8).flat_map(|r| (0..size / 8).map(move |c| (r * 8, c * 8)))
            {
                let rays: Vec<Ray> = (0..64)
                    .map(|k| {
                        let (u, v) = pixel_to_screen(left + k % 8, top + k / 8, size, size);
                        scene.camera.ray(u, v)
                    })
                    .collect();
                let mut seen = Vec::new();
                tracer.camera_rays(&rays, true, &mut together, |i, colour, hit| {
                    seen.push((i, colour.to_array().map(f32::to_bits), hit));
                });
                for (i, ray) in rays.iter().enumerate() {
                    let (colour, hit) = tracer.camera_ray(ray, true, &mut alone);
                    assert_eq!(seen[i], (i, colour.to_array().map(f32::to_bits), hit));
                }
            }
            assert_eq!(together.counts.shadow, alone.counts.shadow);
            assert_eq!(together.counts.secondary, alone.counts.secondary);
            shadowed += together.counts.shadow;
        }
        assert!(shadowed > 2000, "only {shadowed} shadow rays");
    }
}
