//! Materials as shading uses them: Phong materials and the course's solid textures, which
//! choose, or blend, between two earlier materials by where the hit point lies in texture
//! space. Every question takes the world-space point; a texture answers it by asking its two
//! materials and interpolating their answers (the handout's 11/2 update: the shaded colours
//! are interpolated, and so are the ambient, reflective and transparent terms).

use arrayvec::ArrayVec;
use glam::{DAffine3, Vec3A};

use super::highlight::{Highlight, HighlightAt};
use super::perlin::octave_noise;
use crate::parse::MAX_TEXTURE_DEPTH;
use crate::parse::description::{self, Pattern};

/// A material of the scene; a texture refers to others by their index in [`Materials`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// Shaded by its own colours.
    Phong(Phong),
    /// Shaded by two earlier materials, chosen or blended by where the point lies.
    Texture(Texture),
}

/// Blinn-Phong shading plus the mirror and glass terms of assignment 4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    /// The colour a lit surface scatters in every direction, which ambient light is also
    /// multiplied by.
    pub diffuse: Vec3A,
    /// The highlight's colour; black skips the highlight's work altogether.
    pub specular: Vec3A,
    /// How tight the highlight is: the power N·H is raised to; at least 0.
    pub exponent: f32,
    /// What the mirror ray's colour is multiplied by; black spawns no mirror ray.
    pub reflective: Vec3A,
    /// What the refracted ray's colour is multiplied by; black spawns no refracted ray.
    pub transparent: Vec3A,
    /// Relative to the air outside (index 1); which side a ray hits from says whether it
    /// enters or leaves.
    pub index_of_refraction: f32,
}

/// A solid texture between two materials listed before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texture {
    /// Which of the course's textures, with its parameters.
    pub pattern: Pattern,
    /// World space to texture space.
    pub to_texture: DAffine3,
    /// The material where the pattern is 0, and where it is 1.
    pub materials: [u32; 2],
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

/// The scene's materials, asked by index.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Materials {
    list: Vec<Material>,
}

impl Material {
    /// A material as the file gives it, in the form shading uses: colours as SIMD vectors, the
    /// texture's matrix as an affine map.
    pub fn new(spec: &description::MaterialSpec) -> Material {
        match spec {
            description::MaterialSpec::Phong(phong) => Material::Phong(Phong {
                diffuse: phong.diffuse.into(),
                specular: phong.specular.into(),
                exponent: phong.exponent,
                reflective: phong.reflective.into(),
                transparent: phong.transparent.into(),
                index_of_refraction: phong.index_of_refraction,
            }),
            description::MaterialSpec::Texture(texture) => Material::Texture(Texture {
                pattern: texture.pattern,
                to_texture: DAffine3::from_mat4(texture.to_texture),
                materials: texture.materials,
            }),
        }
    }
}

impl Texture {
    /// Where `point` (world space) falls between the first material (0) and the second (1).
    pub fn weight(&self, point: Vec3A) -> f32 {
        self.pattern
            .weight(self.to_texture.transform_point3(point.as_dvec3()))
    }
}

impl Pattern {
    /// Where point `p` of texture space falls between the first material (0) and the second
    /// (1).
    pub fn weight(&self, p: glam::DVec3) -> f32 {
        self.weight_with_noise(p, |q, octaves| octave_noise(q.x, q.y, q.z, octaves))
    }

    /// [`Pattern::weight`] with the sum of `octaves` octaves of noise at a point given by
    /// `noise` (check's fault library sums it otherwise).
    pub fn weight_with_noise(
        &self,
        p: glam::DVec3,
        noise: impl Fn(glam::DVec3, u32) -> f64,
    ) -> f32 {
        let weight = match *self {
            // Unit cubes alternate; the one at the origin (0 ≤ x, y, z < 1) is the first
            // material's.
            Pattern::Checkerboard => {
                let parity = p.x.floor() + p.y.floor() + p.z.floor();
                if parity.rem_euclid(2.0) == 0.0 {
                    0.0
                } else {
                    1.0
                }
            }
            // Noise of about -1…1 mapped onto 0…1.
            Pattern::Noise { octaves } => 0.5 * (noise(p, octaves) + 1.0),
            Pattern::Marble {
                octaves,
                frequency,
                amplitude,
            } => {
                let n = noise(p, octaves);
                0.5 * ((frequency * p.x + amplitude * n).sin() + 1.0)
            }
            // Rings about the y axis: sharp-edged bands of late wood, perturbed by the noise.
            Pattern::Wood {
                octaves,
                frequency,
                amplitude,
            } => {
                let n = noise(p, octaves);
                let radius = (p.x * p.x + p.z * p.z).sqrt();
                let ring = 0.5 * ((frequency * radius + amplitude * n).sin() + 1.0);
                ring * ring * ring
            }
        };
        weight.clamp(0.0, 1.0) as f32
    }
}

impl Materials {
    /// `list` in the file's order. A texture may refer only to materials before it (the parser
    /// sees to that), so that answering a question never loops.
    pub fn new(list: Vec<Material>) -> Materials {
        Materials { list }
    }

    /// How many materials the scene has.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether the scene has none, which it may only when it has no objects either.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The material at `index`; panics past the end (the parser checks every index).
    #[inline(always)]
    pub fn get(&self, index: u32) -> &Material {
        &self.list[index as usize]
    }

    /// The material at `index` as it is at `point`: every texture's weight on the way to its
    /// Phong materials worked out once, for all the questions one hit asks (the ambient term,
    /// each light, the mirror and glass terms), instead of once a question.
    /// (The tracer weighs a [`Surface::unweighed`] in place instead: a surface holds room
    /// for every weight a point can visit, a kilobyte, and returning one copied it for each hit.)
    pub fn at(&self, index: u32, point: Vec3A) -> Surface<'_> {
        let mut surface = Surface::unweighed(self, index);
        surface.weigh(point, Texture::weight);
        surface
    }

    /// Pushes the weight of each texture that answering at `point` visits, in the order
    /// [`Surface::blend`] visits them (only one side where the pattern is all one or the other,
    /// as everywhere on a checkerboard).
    fn weigh(
        &self,
        index: u32,
        point: Vec3A,
        weight_of: &impl Fn(&Texture, Vec3A) -> f32,
        weights: &mut ArrayVec<f32, MAX_TEXTURES_VISITED>,
    ) {
        if let Material::Texture(texture) = self.get(index) {
            let weight = weight_of(texture, point);
            weights.push(weight);
            let [first, second] = texture.materials;
            match weight {
                0.0 => self.weigh(first, point, weight_of, weights),
                1.0 => self.weigh(second, point, weight_of, weights),
                _ => {
                    self.weigh(first, point, weight_of, weights);
                    self.weigh(second, point, weight_of, weights);
                }
            }
        }
    }
}

/// Textures nest at most [`MAX_TEXTURE_DEPTH`] deep, each blending two materials: a point
/// visits at most this many.
const MAX_TEXTURES_VISITED: usize = (1 << MAX_TEXTURE_DEPTH) - 1;

/// A material at one point, from [`Materials::at`]: what shading asks of a hit.
#[derive(Debug, Clone)]
pub struct Surface<'a> {
    materials: &'a Materials,
    index: u32,
    /// The weights of the textures visited, in visiting order.
    weights: ArrayVec<f32, MAX_TEXTURES_VISITED>,
}

impl<'a> Surface<'a> {
    /// Material `index` with no texture weighed yet: [`Surface::weigh`] it before asking.
    #[inline(always)]
    pub fn unweighed(materials: &'a Materials, index: u32) -> Surface<'a> {
        Surface {
            materials,
            index,
            weights: ArrayVec::new(),
        }
    }

    /// Weighs every texture on the way to the Phong materials at `point`, with each texture's
    /// weight given by `weight` (check's faults of textures work it out as a student's tracer
    /// would); the common untextured material skips the recursive walk.
    #[inline(always)]
    pub fn weigh(&mut self, point: Vec3A, weight: impl Fn(&Texture, Vec3A) -> f32) {
        self.weights.clear();
        if let Material::Texture(_) = self.materials.get(self.index) {
            self.materials
                .weigh(self.index, point, &weight, &mut self.weights);
        }
    }
    /// `ask` of the material: for a texture, its two materials' answers interpolated.
    #[inline(always)]
    fn blend(&self, ask: &impl Fn(&Phong) -> Vec3A) -> Vec3A {
        if let Material::Phong(phong) = self.materials.get(self.index) {
            return ask(phong);
        }
        self.blend_from(self.index, &mut 0, ask)
    }

    fn blend_from(&self, index: u32, next: &mut usize, ask: &impl Fn(&Phong) -> Vec3A) -> Vec3A {
        match self.materials.get(index) {
            Material::Phong(phong) => ask(phong),
            Material::Texture(texture) => {
                let weight = self.weights[*next];
                *next += 1;
                let [first, second] = texture.materials;
                match weight {
                    0.0 => self.blend_from(first, next, ask),
                    1.0 => self.blend_from(second, next, ask),
                    w => {
                        let a = self.blend_from(first, next, ask);
                        let b = self.blend_from(second, next, ask);
                        a + w * (b - a)
                    }
                }
            }
        }
    }

    /// The colour that ambient light is multiplied by.
    #[inline]
    pub fn diffuse(&self) -> Vec3A {
        self.blend(&|phong| phong.diffuse)
    }

    /// Whether the material is a texture (its colours depend on the point).
    pub fn is_textured(&self) -> bool {
        matches!(self.materials.get(self.index), Material::Texture(_))
    }

    /// The diffuse colour of a texture's first material (or, with `second`, its second),
    /// through nested textures likewise: a colour the texture has nowhere in particular, as a
    /// tracer that asks a texture for one colour without the point may take.
    pub fn side_diffuse(&self, second: bool) -> Vec3A {
        let mut index = self.index;
        loop {
            match self.materials.get(index) {
                Material::Phong(phong) => return phong.diffuse,
                Material::Texture(texture) => index = texture.materials[usize::from(second)],
            }
        }
    }

    /// The light of one light source reflected toward the eye (the course's `Material::Shade`).
    /// `normal` and `to_light` are unit length, `normal` on the eye's side of the surface;
    /// `view` is the direction the eye looks along, of any length.
    #[inline]
    pub fn shade(
        &self,
        normal: Vec3A,
        view: Vec3A,
        to_light: Vec3A,
        light: Vec3A,
        falloff: SpecularFalloff,
        highlight: Highlight,
    ) -> Vec3A {
        self.blend(&|phong| phong.shade(normal, view, to_light, light, falloff, highlight))
    }

    /// The highlight's colour, k_s.
    #[inline]
    pub fn specular(&self) -> Vec3A {
        self.blend(&|phong| phong.specular)
    }

    /// What the mirror ray's colour is multiplied by.
    #[inline]
    pub fn reflective(&self) -> Vec3A {
        self.blend(&|phong| phong.reflective)
    }

    /// What the refracted ray's colour is multiplied by.
    #[inline]
    pub fn transparent(&self) -> Vec3A {
        self.blend(&|phong| phong.transparent)
    }

    /// The index of refraction (a texture's is its two materials' interpolated).
    #[inline]
    pub fn index_of_refraction(&self) -> f32 {
        self.blend(&|phong| Vec3A::splat(phong.index_of_refraction))
            .x
    }
}

impl Phong {
    /// Diffuse plus Blinn-Torrance specular, k_s (N·H)^q with H = normalize(L + V), as OpenGL
    /// and the course's lecture have it (for [`Highlight::Course`]); no distance term (point
    /// lights attenuate their colour). `view` is the direction the eye looks along, of any
    /// length: it is normalised only for a highlight, which most of the course's materials do
    /// not have.
    #[inline]
    pub fn shade(
        &self,
        normal: Vec3A,
        view: Vec3A,
        to_light: Vec3A,
        light: Vec3A,
        falloff: SpecularFalloff,
        highlight: Highlight,
    ) -> Vec3A {
        let n_dot_l = normal.dot(to_light);
        let mut colour = self.diffuse * n_dot_l.max(0.0);
        if self.specular != Vec3A::ZERO && (n_dot_l >= 0.0 || !highlight.gated()) {
            let to_eye = -view.normalize();
            let mut term = highlight.strength(&HighlightAt {
                normal,
                to_light,
                to_eye,
                exponent: self.exponent,
            });
            if falloff == SpecularFalloff::Fade {
                term *= n_dot_l;
            }
            let highlight_colour = highlight.colour();
            let highlight = highlight_colour.of(self.diffuse, self.specular) * term;
            if !highlight_colour.lit() {
                // A student's highlight, left out of the light's colour (check's fault).
                return colour * light + highlight;
            }
            colour += highlight;
        }
        colour * light
    }
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3};

    use super::*;
    use crate::scene::perlin::noise;

    #[test]
    fn highlights_by_hand() {
        let shiny = Phong {
            diffuse: Vec3A::ZERO,
            specular: Vec3A::ONE,
            exponent: 2.0,
            reflective: Vec3A::ZERO,
            transparent: Vec3A::ZERO,
            index_of_refraction: 1.0,
        };
        let highlight = |view: Vec3A, to_light: Vec3A, exponent: f32, highlight| {
            let phong = Phong { exponent, ..shiny };
            let cut = SpecularFalloff::Cut;
            phong
                .shade(Vec3A::Z, view, to_light, Vec3A::ONE, cut, highlight)
                .x
        };
        let close = |a: f32, b: f32| (a - b).abs() < 1e-4;
        // The eye straight above (looking along −Z), the light at 45°.
        let (above, at_45) = (-Vec3A::Z, Vec3A::new(1.0, 0.0, 1.0).normalize());
        // H = normalize(L + V) = (0.3827, 0, 0.9239): (N·H)² = 0.8536.
        assert!(close(
            highlight(above, at_45, 2.0, Highlight::Course),
            0.853_55
        ));
        // From the ray's direction, H = (0.9239, 0, −0.3827): N·H < 0, none.
        assert_eq!(highlight(above, at_45, 2.0, Highlight::HalfFromRay), 0.0);
        // L + V unnormalised: N·(L + V) = 1.7071, squared 2.9142.
        assert!(close(
            highlight(above, at_45, 2.0, Highlight::HalfNotUnit),
            2.914_21
        ));
        // Phong's mirror: R = (−0.7071, 0, 0.7071), (R·V)² = 0.5.
        assert!(close(highlight(above, at_45, 2.0, Highlight::Mirror), 0.5));
        // The light behind the surface and the eye grazing: the course has none; unclamped,
        // N·H = −0.88169, cubed −0.68541; a fractional power of it is no number: none.
        let grazing = -Vec3A::new(1.0, 0.0, 0.2).normalize();
        let behind = Vec3A::new(-1.0, 0.0, -1.0).normalize();
        assert_eq!(highlight(grazing, behind, 3.0, Highlight::Course), 0.0);
        assert!(close(
            highlight(grazing, behind, 3.0, Highlight::Unclamped),
            -0.685_41
        ));
        assert_eq!(highlight(grazing, behind, 2.5, Highlight::Unclamped), 0.0);
    }

    fn texture(pattern: Pattern, to_texture: DMat4) -> Texture {
        Texture {
            pattern,
            to_texture: DAffine3::from_mat4(to_texture),
            materials: [0, 1],
        }
    }

    #[test]
    fn checkerboard_cells_alternate_from_the_origin() {
        let checker = texture(Pattern::Checkerboard, DMat4::IDENTITY);
        let at = |x, y, z| checker.weight(Vec3A::new(x, y, z));
        assert_eq!(at(0.5, 0.5, 0.5), 0.0);
        assert_eq!(at(1.5, 0.5, 0.5), 1.0);
        assert_eq!(at(1.5, 1.5, 0.5), 0.0);
        assert_eq!(at(1.5, 1.5, 1.5), 1.0);
        assert_eq!(at(-0.5, 0.5, 0.5), 1.0);
        assert_eq!(at(-0.5, -0.5, -0.5), 1.0);
        // Scaled by 2, cells are half a unit wide in the world.
        let small = texture(Pattern::Checkerboard, DMat4::from_scale(DVec3::splat(2.0)));
        assert_eq!(small.weight(Vec3A::new(0.75, 0.25, 0.25)), 1.0);
    }

    #[test]
    fn noise_marble_and_wood_by_hand() {
        let p = Vec3A::new(0.3, 1.7, -2.2);
        let (x, y, z) = (0.3f32 as f64, 1.7f32 as f64, -2.2f32 as f64);
        let n1 = noise(x, y, z);
        let n2 = n1 + noise(2.0 * x, 2.0 * y, 2.0 * z) / 2.0;
        let noise_texture = texture(Pattern::Noise { octaves: 2 }, DMat4::IDENTITY);
        assert_eq!(noise_texture.weight(p), (0.5 * (n2 + 1.0)) as f32);
        let marble = texture(
            Pattern::Marble {
                octaves: 1,
                frequency: 3.0,
                amplitude: 2.0,
            },
            DMat4::IDENTITY,
        );
        assert_eq!(
            marble.weight(p),
            (0.5 * ((3.0 * x + 2.0 * n1).sin() + 1.0)) as f32
        );
        // No octaves: plain stripes across x.
        let stripes = texture(
            Pattern::Marble {
                octaves: 0,
                frequency: 1.0,
                amplitude: 5.0,
            },
            DMat4::IDENTITY,
        );
        let quarter = std::f32::consts::FRAC_PI_2;
        assert!((stripes.weight(Vec3A::new(quarter, 9.0, 9.0)) - 1.0).abs() < 1e-6);
        assert!(stripes.weight(Vec3A::new(-quarter, 9.0, 9.0)).abs() < 1e-6);
        let wood = texture(
            Pattern::Wood {
                octaves: 0,
                frequency: 1.0,
                amplitude: 0.0,
            },
            DMat4::IDENTITY,
        );
        // Rings about y: the same at every height and angle for one radius.
        let ring = (0.5 * (2f64.sin() + 1.0)).powi(3) as f32;
        assert!((wood.weight(Vec3A::new(2.0, 5.0, 0.0)) - ring).abs() < 1e-6);
        assert!((wood.weight(Vec3A::new(0.0, -3.0, 2.0)) - ring).abs() < 1e-6);
    }

    #[test]
    fn a_texture_interpolates_its_materials_answers() {
        let phong = |diffuse: Vec3A, reflective: Vec3A| {
            Material::Phong(Phong {
                diffuse,
                specular: Vec3A::ZERO,
                exponent: 1.0,
                reflective,
                transparent: Vec3A::ZERO,
                index_of_refraction: 1.0,
            })
        };
        let materials = Materials::new(vec![
            phong(Vec3A::X, Vec3A::ZERO),
            phong(Vec3A::Y, Vec3A::ONE),
            Material::Texture(texture(Pattern::Noise { octaves: 1 }, DMat4::IDENTITY)),
            Material::Texture(Texture {
                materials: [2, 0],
                ..texture(Pattern::Checkerboard, DMat4::IDENTITY)
            }),
        ]);
        let p = Vec3A::new(0.3, 0.7, 0.4);
        let w = match materials.get(2) {
            Material::Texture(t) => t.weight(p),
            _ => unreachable!(),
        };
        assert!(w > 0.0 && w < 1.0);
        let blended = materials.at(2, p).diffuse();
        assert!((blended - Vec3A::new(1.0 - w, w, 0.0)).abs().max_element() < 1e-6);
        assert_eq!(materials.at(2, p).reflective(), Vec3A::splat(w));
        // The shaded colour interpolates too (a light straight on: N·L = 1).
        let shaded = materials.at(2, p).shade(
            Vec3A::Z,
            -Vec3A::Z,
            Vec3A::Z,
            Vec3A::ONE,
            SpecularFalloff::Cut,
            Highlight::Course,
        );
        assert!((shaded - blended).abs().max_element() < 1e-6);
        // A checkerboard of the noise texture and red: the noise in the origin's cube, red next
        // to it.
        assert_eq!(materials.at(3, p).diffuse(), blended);
        assert_eq!(materials.at(3, p + Vec3A::X).diffuse(), Vec3A::X);
    }
}
