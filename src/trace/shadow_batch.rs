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
