//! Materials as shading uses them. Every question takes the world-space hit point: the course's
//! assignment 6 adds solid textures, which choose between two earlier materials by that point
//! (and blend their shaded colours); they will join [`Material`] as variants without changing
//! what the tracer asks.

use glam::Vec3A;

use super::model;

/// A material of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    Phong(Phong),
}

/// Blinn-Phong shading plus the mirror and glass terms of assignment 4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    pub diffuse: Vec3A,
    pub specular: Vec3A,
    pub exponent: f32,
    pub reflective: Vec3A,
    pub transparent: Vec3A,
    pub index_of_refraction: f32,
}

/// How the specular highlight fades where the light comes from behind the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpecularFalloff {
    /// The course's default: no highlight at all once N·L is negative, so wide lobes end in a
    /// hard edge at grazing light.
    #[default]
    Cut,
    /// The handout's optional fix (`-specular_fix`): the highlight multiplied by N·L, so it
    /// fades to nothing as the light reaches grazing.
    Fade,
}

impl Material {
    pub fn new(spec: &model::Material) -> Material {
        Material::Phong(Phong {
            diffuse: spec.diffuse.into(),
            specular: spec.specular.into(),
            exponent: spec.exponent,
            reflective: spec.reflective.into(),
            transparent: spec.transparent.into(),
            index_of_refraction: spec.index_of_refraction,
        })
    }

    /// The colour that ambient light is multiplied by.
    #[inline]
    pub fn diffuse_at(&self, _point: Vec3A) -> Vec3A {
        match self {
            Material::Phong(phong) => phong.diffuse,
        }
    }

    /// The light of one light source reflected toward the eye (the course's `Material::Shade`).
    /// `normal` and `to_light` are unit length, `normal` on the eye's side of the surface;
    /// `view` is the direction the eye looks along, of any length.
    #[inline]
    pub fn shade(
        &self,
        _point: Vec3A,
        normal: Vec3A,
        view: Vec3A,
        to_light: Vec3A,
        light: Vec3A,
        falloff: SpecularFalloff,
    ) -> Vec3A {
        match self {
            Material::Phong(phong) => phong.shade(normal, view, to_light, light, falloff),
        }
    }

    #[inline]
    pub fn reflective_at(&self, _point: Vec3A) -> Vec3A {
        match self {
            Material::Phong(phong) => phong.reflective,
        }
    }

    #[inline]
    pub fn transparent_at(&self, _point: Vec3A) -> Vec3A {
        match self {
            Material::Phong(phong) => phong.transparent,
        }
    }

    #[inline]
    pub fn index_of_refraction_at(&self, _point: Vec3A) -> f32 {
        match self {
            Material::Phong(phong) => phong.index_of_refraction,
        }
    }
}

impl Phong {
    /// Diffuse plus Blinn-Torrance specular, k_s (N·H)^q with H = normalize(L + V), as OpenGL
    /// and the course's lecture have it; no distance term (point lights attenuate their colour).
    /// `view` is the direction the eye looks along, of any length: it is normalised only for a
    /// highlight, which most of the course's materials do not have.
    #[inline]
    pub fn shade(
        &self,
        normal: Vec3A,
        view: Vec3A,
        to_light: Vec3A,
        light: Vec3A,
        falloff: SpecularFalloff,
    ) -> Vec3A {
        let n_dot_l = normal.dot(to_light);
        let mut colour = self.diffuse * n_dot_l.max(0.0);
        if self.specular != Vec3A::ZERO && n_dot_l >= 0.0 {
            let to_eye = -view.normalize();
            let half = (to_light + to_eye).normalize_or_zero();
            let mut highlight = normal.dot(half).max(0.0).powf(self.exponent);
            if falloff == SpecularFalloff::Fade {
                highlight *= n_dot_l;
            }
            colour += self.specular * highlight;
        }
        colour * light
    }
}
