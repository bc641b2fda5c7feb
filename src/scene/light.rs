//! Lights as shading uses them, each answering one question: how much light reaches a point,
//! from which direction, and from how far (the course's `Light::getIllumination`).

use glam::Vec3A;

use crate::parse::description::LightSpec;

/// A light of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// The same direction and colour everywhere, infinitely far away.
    Directional {
        /// Unit vector toward the light: the opposite of the way its light travels.
        to_light: Vec3A,
        /// The colour that arrives everywhere, not clamped.
        colour: Vec3A,
    },
    /// Light from a point, dimmed with distance d by 1 / (c + l·d + q·d²).
    Point {
        /// Where the light is, in world space.
        position: Vec3A,
        /// The colour at the light itself, before attenuation; not clamped.
        colour: Vec3A,
        /// The constant, linear and quadratic terms c, l and q.
        attenuation: [f32; 3],
    },
}

/// The light one light sends to one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Illumination {
    /// Unit vector from the point toward the light.
    pub to_light: Vec3A,
    /// The light's colour as it arrives, attenuation applied.
    pub colour: Vec3A,
    /// How far the light is, in world units: infinite for a directional light.
    pub distance: f32,
}

impl Light {
    /// A light as the file gives it, in the form shading uses: a directional light turned to
    /// point toward the light.
    pub fn new(spec: &LightSpec) -> Light {
        match *spec {
            LightSpec::Directional { direction, colour } => Light::Directional {
                to_light: -Vec3A::from(direction).normalize(),
                colour: colour.into(),
            },
            LightSpec::Point {
                position,
                colour,
                attenuation,
            } => Light::Point {
                position: position.into(),
                colour: colour.into(),
                attenuation,
            },
        }
    }

    /// The light reaching `point`; `None` only for a point light at the point itself, which has
    /// no direction to come from.
    #[inline]
    pub fn illuminate(&self, point: Vec3A) -> Option<Illumination> {
        match *self {
            Light::Directional { to_light, colour } => Some(Illumination {
                to_light,
                colour,
                distance: f32::INFINITY,
            }),
            Light::Point {
                position,
                colour,
                attenuation: [c, l, q],
            } => {
                let offset = position - point;
                let distance = offset.length();
                if distance == 0.0 {
                    return None;
                }
                // As the course's PointLight: no term is negative (the parser refuses that), so
                // its clamp at 0 never applies.
                let attenuation = 1.0 / (c + l * distance + q * distance * distance);
                Some(Illumination {
                    to_light: offset / distance,
                    colour: colour * attenuation,
                    distance,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point_light(attenuation: [f32; 3]) -> Light {
        Light::Point {
            position: Vec3A::new(0.0, 4.0, 0.0),
            colour: Vec3A::new(0.8, 0.4, 1.0),
            attenuation,
        }
    }

    #[test]
    fn directional_light_is_the_same_everywhere() {
        let light = Light::new(&LightSpec::Directional {
            direction: glam::Vec3::new(0.0, -2.0, 0.0),
            colour: glam::Vec3::new(0.5, 0.5, 0.5),
        });
        for point in [Vec3A::ZERO, Vec3A::new(1e6, -3.0, 7.0)] {
            let i = light.illuminate(point).unwrap();
            assert_eq!(i.to_light, Vec3A::Y);
            assert_eq!(i.colour, Vec3A::splat(0.5));
            assert_eq!(i.distance, f32::INFINITY);
        }
    }

    #[test]
    fn point_light_attenuation_by_hand() {
        // The point is 4 units below the light.
        let at = |attenuation| point_light(attenuation).illuminate(Vec3A::ZERO).unwrap();
        let constant = at([1.0, 0.0, 0.0]);
        assert_eq!(constant.to_light, Vec3A::Y);
        assert_eq!(constant.distance, 4.0);
        assert_eq!(constant.colour, Vec3A::new(0.8, 0.4, 1.0));
        // 1 / (0.2·4) = 1.25
        assert_eq!(at([0.0, 0.2, 0.0]).colour, Vec3A::new(0.8, 0.4, 1.0) * 1.25);
        // 1 / (0.05·16) = 1.25
        assert_eq!(
            at([0.0, 0.0, 0.05]).colour,
            Vec3A::new(0.8, 0.4, 1.0) * 1.25
        );
        // 1 / (1 + 0.5·4 + 0.25·16) = 1/7
        let mixed = at([1.0, 0.5, 0.25]).colour;
        assert!(
            (mixed - Vec3A::new(0.8, 0.4, 1.0) / 7.0)
                .abs()
                .max_element()
                < 1e-7
        );
    }

    #[test]
    fn point_light_direction_is_unit_toward_the_light() {
        let i = point_light([1.0, 0.0, 0.0])
            .illuminate(Vec3A::new(3.0, 0.0, 0.0))
            .unwrap();
        assert_eq!(i.distance, 5.0);
        assert!((i.to_light - Vec3A::new(-0.6, 0.8, 0.0)).length() < 1e-7);
    }

    #[test]
    fn a_point_at_the_light_gets_nothing() {
        assert_eq!(
            point_light([0.0, 0.0, 1.0]).illuminate(Vec3A::new(0.0, 4.0, 0.0)),
            None
        );
    }
}
