//! Where a difference lies. For a shaded picture no fault explains, which of the scene's
//! materials its differing pixels show, and which of its lights reach them: a difference
//! confined to the objects of one material points at what that material has and the others
//! lack (a highlight, a mirror, glass, a texture); one confined to where one light of several
//! reaches points at that light (its direction, colour, dimming or shadow). It is what a
//! teaching assistant says first with the picture beside the scene.

use std::path::Path;

use super::prepare;
use crate::camera::pixel_to_screen;
use crate::check::rule::channel_difference;
use crate::check::suite::Line;
use crate::geometry::Ray;
use crate::parse::description::{MaterialSpec, Pattern};
use crate::scene::{Light, Scene};
use crate::shade::Image;
use crate::trace::{clearance, shadow_end, start_t};

/// At least this share of the differing pixels show the one material...
const CONFINED: f64 = 0.9;
/// ...which shows on at most this share of the picture's object pixels (else the place says
/// little: nearly everything is that material)...
const MOST_OF_THE_OBJECTS: f64 = 0.8;
/// ...and the picture differs in at least this many pixels.
const MIN_DIFFERING: usize = 20;

/// What a picture's difference lies on.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// The objects of one material.
    Material {
        /// Its number in the scene file, counted from 1 in the file's order.
        number: usize,
        /// How many materials the file lists.
        of: usize,
        /// What it has: a highlight, a mirror, glass, a texture.
        has: Vec<&'static str>,
    },
    /// The points one light reaches (in front of it, and not in its shadow under `-shadows`).
    Light {
        /// Its number in the scene file, counted from 1 in the file's order.
        number: usize,
        /// How many lights the file lists.
        of: usize,
        /// Whether it is a point light (else directional).
        point: bool,
    },
}

/// Where a picture's difference lies, and how much of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    /// The place.
    pub place: Place,
    /// The share of the differing pixels that lie there.
    pub share: f64,
}

impl Located {
    /// As `summary.json` carries it (`where`): `place` (`material` or `light`), its `number`
    /// in the file (from 1) and how many the file lists (`of`), the `share` of the differing
    /// pixels it holds, and what a material `has` or whether a light is a `point` light.
    pub fn json(&self) -> serde_json::Value {
        match &self.place {
            Place::Material { number, of, has } => serde_json::json!({
                "place": "material", "number": number, "of": of, "share": self.share,
                "has": has,
            }),
            Place::Light { number, of, point } => serde_json::json!({
                "place": "light", "number": number, "of": of, "share": self.share,
                "point": point,
            }),
        }
    }

    /// A place as [`Located::json`] wrote it (a shard's `summary.json`); `None` for what it
    /// does not read as one.
    pub fn from_json(value: &serde_json::Value) -> Option<Located> {
        let count = |key: &str| value[key].as_u64().map(|n| n as usize);
        let (number, of) = (count("number")?, count("of")?);
        let place = match value["place"].as_str()? {
            "material" => Place::Material {
                number,
                of,
                // What a material has is one of a few phrases of this file's own.
                has: value["has"]
                    .as_array()?
                    .iter()
                    .map(|said| HAS.iter().copied().find(|&h| Some(h) == said.as_str()))
                    .collect::<Option<_>>()?,
            },
            "light" => Place::Light {
                number,
                of,
                point: value["point"].as_bool()?,
            },
            _ => return None,
        };
        Some(Located {
            place,
            share: value["share"].as_f64()?,
        })
    }

    /// The sentence the explanation ends with.
    pub fn sentence(&self) -> String {
        let share = self.share * 100.0;
        match &self.place {
            Place::Material { number, of, has } => {
                let has = match has.as_slice() {
                    [] => String::new(),
                    [one] => format!(", which has {one}"),
                    [first @ .., last] => format!(", which has {} and {last}", first.join(", ")),
                };
                format!(
                    "Where it differs: {share:.0}% of the differing pixels show the scene's \
                     material {number} of {of} (counted in the file's order){has}, and the \
                     other materials' pixels nearly all match: look first at what your tracer \
                     does otherwise for the objects of that material: the material's terms, or \
                     the objects' shapes."
                )
            }
            Place::Light { number, of, point } => {
                let kind = if *point {
                    "a point light"
                } else {
                    "a directional light"
                };
                format!(
                    "Where it differs: {share:.0}% of the differing pixels are reached by the \
                     scene's light {number} of {of} (counted in the file's order; {kind}), and \
                     the pixels it does not reach nearly all match: look first at what your \
                     tracer does with that light: its direction, its colour, its dimming, its \
                     shadow rays."
                )
            }
        }
    }
}

/// Where the shaded picture `actual` of `line` differs from `reference` by more than
/// `tolerance`, when that is the objects of one material or, where the scene has two lights or
/// more, the points one light reaches (see [`CONFINED`]); `None` otherwise, or where the line
/// cannot be read.
pub fn locate(
    line: &Line,
    scenes: &Path,
    actual: &Image,
    reference: &Image,
    tolerance: u8,
) -> Option<Located> {
    let prepared = prepare(line, scenes).ok()?;
    let line = &prepared.line;
    let (width, height) = (line.options.width, line.options.height);
    let same_size = |image: &Image| (image.width, image.height) == (width, height);
    if !same_size(actual) || !same_size(reference) {
        return None;
    }
    let scene = &line.scene;
    let materials = line.description.materials.len();
    let lights = scene.lights.len();
    // Per material and per light: its pixels, and those of them that differ.
    let mut on_material = vec![(0usize, 0usize); materials];
    let mut lit_by = vec![(0usize, 0usize); lights];
    let (mut differing, mut objects) = (0usize, 0usize);
    for (pixel, (&a, &r)) in actual.pixels.iter().zip(&reference.pixels).enumerate() {
        let differs = channel_difference(a, r) > tolerance;
        differing += usize::from(differs);
        let (i, row) = (pixel as u32 % width, pixel as u32 / width);
        let (u, v) = pixel_to_screen(i, height - 1 - row, width, height);
        let ray = scene.camera.ray(u, v);
        let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) else {
            continue;
        };
        objects += 1;
        let count = |counts: &mut (usize, usize)| {
            counts.0 += 1;
            counts.1 += usize::from(differs);
        };
        if let Some(counts) = on_material.get_mut(hit.material as usize) {
            count(counts);
        }
        let point = ray.at(hit.t);
        let toward_eye = if ray.direction.dot(hit.normal) > 0.0 {
            -hit.normal
        } else {
            hit.normal
        };
        for (light, counts) in scene.lights.iter().zip(&mut lit_by) {
            if reaches(
                scene,
                light,
                point,
                ray.origin,
                toward_eye,
                line.options.trace.shadows,
            ) {
                count(counts);
            }
        }
    }
    if differing < MIN_DIFFERING || objects == 0 {
        return None;
    }
    // The place that holds the most of the difference, if it holds enough of it and is not
    // nearly every object pixel: materials first, then lights (where there are several).
    let confined = |counts: &[(usize, usize)]| {
        let (index, &(pixels, on_it)) = counts
            .iter()
            .enumerate()
            .max_by_key(|&(_, &(_, on_it))| on_it)?;
        let share = on_it as f64 / differing as f64;
        let telling = pixels as f64 <= MOST_OF_THE_OBJECTS * objects as f64;
        (share >= CONFINED && telling).then_some((index, share))
    };
    if let Some((index, share)) = confined(&on_material) {
        let has = what_it_has(&line.description.materials[index]);
        let place = Place::Material {
            number: index + 1,
            of: materials,
            has,
        };
        return Some(Located { place, share });
    }
    let (index, share) = confined(&lit_by).filter(|_| lights >= 2)?;
    let place = Place::Light {
        number: index + 1,
        of: lights,
        point: matches!(scene.lights[index], Light::Point { .. }),
    };
    Some(Located { place, share })
}

/// Whether `light` reaches `point` (seen from `from`, its surface's normal `normal` turned
/// toward the eye): in front of the surface, and under `-shadows` with nothing between.
fn reaches(
    scene: &Scene,
    light: &Light,
    point: glam::Vec3A,
    from: glam::Vec3A,
    normal: glam::Vec3A,
    shadows: bool,
) -> bool {
    let Some(lit) = light.illuminate(point) else {
        return false;
    };
    if normal.dot(lit.to_light) <= 0.0 {
        return false;
    }
    if !shadows {
        return true;
    }
    let near = start_t(clearance(point, from), lit.to_light, normal);
    let shadow = Ray::new(point, lit.to_light);
    !scene
        .world
        .occluded(&shadow, near, shadow_end(lit.distance))
}

/// What a material may have that a plain diffuse one does not, as the file names it: a
/// highlight, a mirror, glass, then each texture.
const HAS: [&str; 7] = [
    "a highlight (specularColor)",
    "a mirror (reflectiveColor)",
    "glass (transparentColor)",
    "a texture (Checkerboard)",
    "a texture (Noise)",
    "a texture (Marble)",
    "a texture (Wood)",
];

/// What `material` has of [`HAS`].
fn what_it_has(material: &MaterialSpec) -> Vec<&'static str> {
    match material {
        MaterialSpec::Phong(phong) => [phong.specular, phong.reflective, phong.transparent]
            .into_iter()
            .zip(HAS)
            .filter(|(colour, _)| *colour != glam::Vec3::ZERO)
            .map(|(_, said)| said)
            .collect(),
        MaterialSpec::Texture(texture) => vec![match texture.pattern {
            Pattern::Checkerboard => HAS[3],
            Pattern::Noise { .. } => HAS[4],
            Pattern::Marble { .. } => HAS[5],
            Pattern::Wood { .. } => HAS[6],
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sentences_name_the_material_and_what_it_has_or_the_light() {
        let material = Located {
            place: Place::Material {
                number: 3,
                of: 4,
                has: vec!["a highlight (specularColor)", "a mirror (reflectiveColor)"],
            },
            share: 0.964,
        };
        assert_eq!(
            material.sentence(),
            "Where it differs: 96% of the differing pixels show the scene's material 3 of 4 \
             (counted in the file's order), which has a highlight (specularColor) and a mirror \
             (reflectiveColor), and the other materials' pixels nearly all match: look first at \
             what your tracer does otherwise for the objects of that material: the material's \
             terms, or the objects' shapes."
        );
        let light = Located {
            place: Place::Light {
                number: 2,
                of: 2,
                point: true,
            },
            share: 1.0,
        };
        for located in [&material, &light] {
            assert_eq!(Located::from_json(&located.json()).as_ref(), Some(located));
        }
        assert_eq!(
            light.sentence(),
            "Where it differs: 100% of the differing pixels are reached by the scene's light 2 \
             of 2 (counted in the file's order; a point light), and the pixels it does not \
             reach nearly all match: look first at what your tracer does with that light: its \
             direction, its colour, its dimming, its shadow rays."
        );
    }
}
