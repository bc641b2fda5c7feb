//! Where a difference lies. For a shaded picture no fault explains, which of the scene's
//! materials its differing pixels show: a difference confined to the objects of one material
//! points at what that material has and the others lack (a highlight, a mirror, glass, a
//! texture), which is what a teaching assistant says first with the picture beside the scene.

use std::path::Path;

use super::prepare;
use crate::camera::pixel_to_screen;
use crate::check::rule::channel_difference;
use crate::check::suite::Line;
use crate::parse::description::{MaterialSpec, Pattern};
use crate::shade::Image;

/// At least this share of the differing pixels show the one material...
const CONFINED: f64 = 0.9;
/// ...which shows on at most this share of the picture's object pixels (else the place says
/// little: nearly everything is that material)...
const MOST_OF_THE_OBJECTS: f64 = 0.8;
/// ...and the picture differs in at least this many pixels.
const MIN_DIFFERING: usize = 20;

/// The material a picture's difference lies on.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    /// The material's number in the scene file, counted from 1 in the file's order.
    pub material: usize,
    /// How many materials the file lists.
    pub of: usize,
    /// The share of the differing pixels that show it.
    pub share: f64,
    /// What it has: a highlight, a mirror, glass, a texture.
    pub has: Vec<&'static str>,
}

impl Located {
    /// The sentence the explanation ends with.
    pub fn sentence(&self) -> String {
        let has = match self.has.as_slice() {
            [] => String::new(),
            [one] => format!(", which has {one}"),
            [first @ .., last] => format!(", which has {} and {last}", first.join(", ")),
        };
        format!(
            "Where it differs: {:.0}% of the differing pixels show the scene's material {} of {} \
             (counted in the file's order){has}, and the other materials' pixels nearly all \
             match: look first at what your tracer does otherwise for the objects of that \
             material: the material's terms, or the objects' shapes.",
            self.share * 100.0,
            self.material,
            self.of,
        )
    }
}

/// Where the shaded picture `actual` of `line` (its image `image`) differs from `reference`
/// by more than `tolerance`, when that is the objects of one material (see [`CONFINED`]);
/// `None` otherwise, or where the line cannot be read.
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
    // Per material: its pixels, and those of them that differ.
    let mut shown = vec![(0usize, 0usize); materials];
    let mut differing = 0usize;
    for (pixel, (&a, &r)) in actual.pixels.iter().zip(&reference.pixels).enumerate() {
        let differs = channel_difference(a, r) > tolerance;
        differing += usize::from(differs);
        let (i, row) = (pixel as u32 % width, pixel as u32 / width);
        let (u, v) = pixel_to_screen(i, height - 1 - row, width, height);
        let ray = scene.camera.ray(u, v);
        if let Some(hit) = scene.world.intersect(&ray, scene.camera.t_min()) {
            let Some(counts) = shown.get_mut(hit.material as usize) else {
                continue;
            };
            counts.0 += 1;
            counts.1 += usize::from(differs);
        }
    }
    let objects: usize = shown.iter().map(|&(pixels, _)| pixels).sum();
    if differing < MIN_DIFFERING || objects == 0 {
        return None;
    }
    let (index, &(pixels, on_it)) = shown
        .iter()
        .enumerate()
        .max_by_key(|&(_, &(_, on_it))| on_it)?;
    let share = on_it as f64 / differing as f64;
    if share < CONFINED || pixels as f64 > MOST_OF_THE_OBJECTS * objects as f64 {
        return None;
    }
    Some(Located {
        material: index + 1,
        of: materials,
        share,
        has: what_it_has(&line.description.materials[index]),
    })
}

/// What a material has that a plain diffuse one does not, as the file names it.
fn what_it_has(material: &MaterialSpec) -> Vec<&'static str> {
    match material {
        MaterialSpec::Phong(phong) => [
            (phong.specular, "a highlight (specularColor)"),
            (phong.reflective, "a mirror (reflectiveColor)"),
            (phong.transparent, "glass (transparentColor)"),
        ]
        .into_iter()
        .filter(|(colour, _)| *colour != glam::Vec3::ZERO)
        .map(|(_, said)| said)
        .collect(),
        MaterialSpec::Texture(texture) => vec![match texture.pattern {
            Pattern::Checkerboard => "a texture (Checkerboard)",
            Pattern::Noise { .. } => "a texture (Noise)",
            Pattern::Marble { .. } => "a texture (Marble)",
            Pattern::Wood { .. } => "a texture (Wood)",
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sentence_names_the_material_and_what_it_has() {
        let located = Located {
            material: 3,
            of: 4,
            share: 0.964,
            has: vec!["a highlight (specularColor)", "a mirror (reflectiveColor)"],
        };
        assert_eq!(
            located.sentence(),
            "Where it differs: 96% of the differing pixels show the scene's material 3 of 4 \
             (counted in the file's order), which has a highlight (specularColor) and a mirror \
             (reflectiveColor), and the other materials' pixels nearly all match: look first at \
             what your tracer does otherwise for the objects of that material: the material's \
             terms, or the objects' shapes."
        );
    }
}
