//! The fits of one line, in turn, for the failing pictures no listed fault explains: the depth
//! picture's range, the shading and the textures where the objects stand in place, the numbers
//! of the later assignments' stages, and the camera where the objects stand elsewhere than the reference's. Each
//! fit's render is proven against the pictures before the next fit runs, so that a picture a
//! fit explains costs no later fit.

use super::camera::{Named, fit_camera};
use super::depth::fit_depth_range;
use super::parameters::fit_parameters;
use super::shading::fit_shading;
use super::texture::fit_texture;
use crate::check::diagnose::silhouette_moved;
use crate::check::faults::{FAULTS, LineScene, PictureFault, Plant, Planted, shows_veins};
use crate::check::rule::Rule;
use crate::shade::Image;

/// The share of a picture's difference from the course's shading that the shading fit must
/// account for where the picture's objects seem to stand elsewhere.
const MOVED_SHARE: f64 = 0.9;

/// A failing picture of the line, as the fits see it.
#[derive(Debug, Clone, Copy)]
pub struct Picture<'p> {
    /// Where it stands among the job's pictures (the shaded, normals and depth pictures first,
    /// in that order, each where the line asks for it).
    pub slot: usize,
    /// The student's.
    pub actual: &'p Image,
    /// The course's, where there is one.
    pub reference: Option<&'p Image>,
}

/// What the fits ask of the simulation: the measure a search minimises, and the proof of where
/// it lands.
pub trait Trial {
    type Error;

    /// How far `plant`'s render is from the failing pictures `pictures` (indices among the
    /// line's failing pictures), over some of its rows: a search's measure, never kept.
    fn distance(&mut self, plant: Plant, pictures: &[usize]) -> Result<f64, Self::Error>;

    /// `plant`'s render compared with every failing picture as a listed fault's is, and kept
    /// among the line's tries as the faults `named` with their numbers: which pictures it
    /// explains.
    fn prove(&mut self, plant: Plant, named: &Named) -> Result<Vec<bool>, Self::Error>;
}

/// Runs the line's fits for the failing `pictures` of which `explained` says which a listed
/// fault explains (updated as the fits explain more).
pub fn fit_line<T: Trial>(
    line: &LineScene,
    pictures: &[Picture<'_>],
    explained: &mut [bool],
    rule: Rule,
    trial: &mut T,
) -> Result<(), T::Error> {
    let options = &line.options;
    let shaded_slot = options.output.is_some().then_some(0);
    let normals_slot = options
        .normals
        .is_some()
        .then_some(usize::from(options.output.is_some()));
    let depth_slot = options
        .depth
        .is_some()
        .then_some(usize::from(options.output.is_some()) + usize::from(options.normals.is_some()));
    let traced = |slot: usize| [shaded_slot, normals_slot, depth_slot].contains(&Some(slot));
    let moved = |picture: &Picture<'_>| {
        picture
            .reference
            .is_some_and(|reference| silhouette_moved(picture.actual, reference, rule))
    };
    // The depth picture's range.
    if let (Some((near, far, _)), Some(fault)) = (
        &options.depth,
        FAULTS.iter().find(|f| f.name == "depth_range"),
    ) {
        for (k, picture) in pictures.iter().enumerate() {
            let Some(reference) = picture.reference.filter(|_| !explained[k]) else {
                continue;
            };
            if Some(picture.slot) != depth_slot {
                continue;
            }
            if let Some((a, b)) = fit_depth_range(*near, *far, picture.actual, reference) {
                let plant = Plant::one(Planted::Picture(PictureFault::DepthRange(a, b)));
                let numbers = vec![("near", f64::from(a)), ("far", f64::from(b))];
                prove(trial, plant, &(vec![fault], numbers), explained)?;
            }
        }
    }
    // The shading, for the shaded and normals pictures whose objects stand in place; and for
    // those whose objects seem to stand elsewhere, where the fit draws them nearly whole (a
    // dark object's highlight or light lost reads as its silhouette moved).
    let unexplained = |slot: Option<usize>, explained: &[bool], displaced: bool| {
        (0..pictures.len())
            .find(|&k| {
                !explained[k] && Some(pictures[k].slot) == slot && moved(&pictures[k]) == displaced
            })
            .map(|k| pictures[k].actual)
    };
    for (displaced, least_share) in [(false, 0.0), (true, MOVED_SHARE)] {
        let (shaded, normals) = (
            unexplained(shaded_slot, explained, displaced),
            unexplained(normals_slot, explained, displaced),
        );
        if (shaded.is_some() || normals.is_some())
            && let Some((plants, named)) = fit_shading(line, shaded, normals, least_share)
        {
            let plant = match plants[..] {
                [one] => Some(Plant::one(one)),
                [first, second] => Some(Plant::two(first, second)),
                _ => None,
            };
            if let Some(plant) = plant {
                prove(trial, plant, &named, explained)?;
            }
        }
        if explained.iter().all(|&e| e) {
            return Ok(());
        }
    }
    // Marble's and Wood's numbers, for the shaded picture where its objects stand in place.
    if shows_veins(line)
        && let Some(shaded) = unexplained(shaded_slot, explained, false)
        && let Some((plant, named)) = fit_texture(line, shaded)
    {
        prove(trial, Plant::one(plant), &named, explained)?;
    }
    // The numbers of the stages past the first ray (secondary rays' offset, the filter's
    // reach), for every picture still unexplained.
    let left: Vec<usize> = (0..pictures.len()).filter(|&k| !explained[k]).collect();
    if !left.is_empty() {
        for alternatives in fit_parameters(line, |plant| trial.distance(plant, &left))? {
            // A family's numbers in turn, until one explains a picture.
            for (plant, named) in alternatives {
                let before = explained.iter().filter(|&&e| e).count();
                prove(trial, plant, &named, explained)?;
                if explained.iter().filter(|&&e| e).count() > before {
                    break;
                }
            }
        }
    }
    // The camera, last (its search renders the line hundreds of times), for the pictures whose
    // objects stand elsewhere than the reference's: a camera's mistake written in a form the
    // library does not list is named by where the fit lands.
    let displaced: Vec<usize> = (0..pictures.len())
        .filter(|&k| !explained[k] && traced(pictures[k].slot) && moved(&pictures[k]))
        .collect();
    if !displaced.is_empty() {
        let pairs: Vec<(&Image, &Image)> = displaced
            .iter()
            .filter_map(|&k| Some((pictures[k].actual, pictures[k].reference?)))
            .collect();
        let fitted = fit_camera(line, &pairs, |plant| trial.distance(plant, &displaced))?;
        for fitted in fitted {
            for named in &fitted.names {
                prove(trial, Plant::one(fitted.plant), named, explained)?;
            }
        }
    }
    Ok(())
}

/// `plant`'s render proven, and the pictures it explains marked.
fn prove<T: Trial>(
    trial: &mut T,
    plant: Plant,
    named: &Named,
    explained: &mut [bool],
) -> Result<(), T::Error> {
    let proven = trial.prove(plant, named)?;
    for (was, now) in explained.iter_mut().zip(proven) {
        *was |= now;
    }
    Ok(())
}
