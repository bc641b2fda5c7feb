//! The pictures' forms: bytes, misses, normals' colours and depth greys.

use std::sync::atomic::Ordering;

use raycast::Vec3A;
use raycast::accel::Hit;
use raycast::shade::PictureSeam;

use crate::{Form, ROUNDED};

impl PictureSeam for Form {
    fn to_rgb(&self, colour: Vec3A) -> [u8; 3] {
        let half = if ROUNDED.load(Ordering::Relaxed) {
            0.5
        } else {
            0.0
        };
        let byte = |value: f32| match self {
            Form::BytesWrap => (value * 255.0 + half) as i32 as u8,
            Form::ClampBeforeScaling => (value.clamp(0.0, 255.0) * 255.0 + half) as i32 as u8,
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
            Form::DepthClampBeforeScaling => {
                let raw = 1.0 - (t - t_near) / (t_far - t_near);
                f32::from((raw.clamp(0.0, 255.0) * 255.0) as i32 as u8) / 255.0
            }
            Form::DepthToFarthest(farthest) => {
                (1.0 - (t - t_near) / (farthest - t_near)).clamp(0.0, 1.0)
            }
            _ => raycast::shade::depth_grey(t, t_near, t_far),
        }
    }
}
