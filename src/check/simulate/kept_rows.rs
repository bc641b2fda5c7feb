//! Rows of a line's renders under plants, kept for the rest of the run. A screen renders a
//! plant's rows where a student's pictures differ most from their references, and the second
//! screen every few rows: each row's pixels depend on the line and the plant alone (each
//! pixel's samples are drawn from its own place, the rows a filter reaches traced with it), not
//! on the student. A class's students screen the same plants on the same lines, so each row of
//! a plant is rendered once for the whole class: on a line of many samples a pixel (the marble
//! vase's 36) the screens of the library's faults and of the course's open answers cost each
//! student that fails it as much as a few whole renders.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use crate::shade::Image;

/// The most bytes of rows kept in a run: rows past it are rendered again when asked for.
const MOST_BYTES: usize = 256 << 20;

/// Each plant's rows of each line: by the line's identity and the plant as planted.
#[derive(Default)]
struct Kept {
    plants: HashMap<(u64, String), PlantRows>,
    /// What the rows and their entries take, roughly.
    bytes: usize,
}

/// Row `r` of each of a render's images, shared by the store and the pictures read from it.
type Row = Arc<[Vec<[u8; 3]>]>;

/// The rows of one plant's render of a line rendered so far: row `r` of every image at once.
struct PlantRows {
    sizes: Vec<(u32, u32)>,
    rows: HashMap<usize, Row>,
}

/// What a plant's entry and a row's take beside their pixels, roughly (keys, maps, vectors).
const ENTRY_BYTES: usize = 256;
const ROW_BYTES: usize = 64;

static KEPT: Mutex<Option<Kept>> = Mutex::new(None);

/// The render of the rows `wanted` marks of line `line` (its identity) under `plant`, every
/// other row black, as `render` makes it for any rows it is asked for: the rows rendered before
/// in the run are read, and `render` renders only the others. Every image must be traced row
/// for row (as tall as `wanted` is long); a render whose images are not is passed on whole.
pub(super) fn rows_of<E>(
    line: u64,
    plant: &str,
    wanted: &[bool],
    render: impl Fn(&[bool]) -> Result<Vec<Image>, E>,
) -> Result<Vec<Image>, E> {
    let key = (line, plant.to_string());
    // The kept rows asked for, taken out under the lock (shared, not copied): every thread of
    // every student's screens waits on it.
    let (sizes_kept, kept_rows) = {
        let kept = lock();
        match kept.as_ref().and_then(|kept| kept.plants.get(&key)) {
            Some(have) => (
                have.sizes.clone(),
                (0..wanted.len())
                    .filter(|&row| wanted[row])
                    .filter_map(|row| Some((row, have.rows.get(&row)?.clone())))
                    .collect::<HashMap<_, _>>(),
            ),
            None => (Vec::new(), HashMap::new()),
        }
    };
    // Nothing kept of these rows: the render is the answer, as it was.
    if kept_rows.is_empty() {
        let fresh = render(wanted)?;
        keep(&key, wanted, &fresh);
        return Ok(fresh);
    }
    let missing: Vec<bool> = (0..wanted.len())
        .map(|row| wanted[row] && !kept_rows.contains_key(&row))
        .collect();
    let fresh = if missing.contains(&true) {
        let fresh = render(&missing)?;
        keep(&key, &missing, &fresh);
        Some(fresh)
    } else {
        None
    };
    let as_tall = sizes_kept
        .iter()
        .all(|&(_, height)| height as usize == wanted.len());
    if !as_tall
        || fresh
            .as_ref()
            .is_some_and(|fresh| sizes(fresh) != sizes_kept)
    {
        return render(wanted);
    }
    let mut pictures: Vec<Image> = sizes_kept
        .iter()
        .map(|&(width, height)| Image {
            width,
            height,
            pixels: vec![[0; 3]; width as usize * height as usize],
        })
        .collect();
    for (k, picture) in pictures.iter_mut().enumerate() {
        let width = picture.width as usize;
        for row in (0..wanted.len()).filter(|&row| wanted[row]) {
            let at = row * width..(row + 1) * width;
            match (kept_rows.get(&row), &fresh) {
                (Some(rows), _) => picture.pixels[at].copy_from_slice(&rows[k]),
                (None, Some(fresh)) => {
                    picture.pixels[at.clone()].copy_from_slice(&fresh[k].pixels[at]);
                }
                (None, None) => {}
            }
        }
    }
    Ok(pictures)
}

/// Keeps the rows `rendered` marks of `pictures`, where they are traced row for row and the
/// run's rows are not yet at their limit.
fn keep(key: &(u64, String), rendered: &[bool], pictures: &[Image]) {
    let traced = pictures.iter().all(|p| {
        p.height as usize == rendered.len() && p.pixels.len() == p.width as usize * rendered.len()
    });
    if !traced || pictures.is_empty() {
        return;
    }
    let row_bytes: usize = ROW_BYTES + pictures.iter().map(|p| p.width as usize * 3).sum::<usize>();
    let rows: Vec<(usize, Row)> = (0..rendered.len())
        .filter(|&row| rendered[row])
        .map(|row| {
            let pixels: Vec<Vec<[u8; 3]>> = pictures
                .iter()
                .map(|p| {
                    let width = p.width as usize;
                    p.pixels[row * width..(row + 1) * width].to_vec()
                })
                .collect();
            (row, Arc::from(pixels))
        })
        .collect();
    let mut kept = lock();
    let Kept { plants, bytes } = kept.get_or_insert_with(Kept::default);
    if !plants.contains_key(key) {
        if *bytes + ENTRY_BYTES + row_bytes > MOST_BYTES {
            return;
        }
        *bytes += ENTRY_BYTES + key.1.len();
        plants.insert(
            key.clone(),
            PlantRows {
                sizes: sizes(pictures),
                rows: HashMap::new(),
            },
        );
    }
    let Some(entry) = plants.get_mut(key) else {
        return;
    };
    if entry.sizes != sizes(pictures) {
        return;
    }
    for (row, pixels) in rows {
        if *bytes + row_bytes > MOST_BYTES {
            return;
        }
        if entry.rows.insert(row, pixels).is_none() {
            *bytes += row_bytes;
        }
    }
}

fn sizes(pictures: &[Image]) -> Vec<(u32, u32)> {
    pictures.iter().map(|p| (p.width, p.height)).collect()
}

/// The kept rows: a thread that panicked holding them left whole rows or none.
fn lock() -> std::sync::MutexGuard<'static, Option<Kept>> {
    KEPT.lock().unwrap_or_else(PoisonError::into_inner)
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;

    /// A render of the rows asked for, as `render_rows_until` makes one (its test: a render of
    /// some rows is the whole render in those rows, the others black): two images, each pixel
    /// of a wanted row told apart by its row, image and column; and each ask written down.
    fn rendered(
        asked: &RefCell<Vec<Vec<usize>>>,
        height: u32,
    ) -> impl Fn(&[bool]) -> Result<Vec<Image>, ()> {
        move |wanted: &[bool]| {
            asked
                .borrow_mut()
                .push((0..wanted.len()).filter(|&row| wanted[row]).collect());
            Ok((0..2_u8)
                .map(|image| Image {
                    width: 3,
                    height,
                    pixels: (0..3 * height as usize)
                        .map(|i| match wanted.get(i / 3) {
                            Some(true) => [(i / 3) as u8, image, (i % 3) as u8],
                            _ => [0; 3],
                        })
                        .collect(),
                })
                .collect())
        }
    }

    fn rows(height: usize, these: &[usize]) -> Vec<bool> {
        (0..height).map(|row| these.contains(&row)).collect()
    }

    #[test]
    fn rows_rendered_before_are_read_and_only_the_others_rendered() {
        let asked = RefCell::new(Vec::new());
        let render = rendered(&asked, 9);
        let compared = RefCell::new(Vec::new());
        let whole = rendered(&compared, 9);
        for these in [&[2, 3, 7][..], &[3, 4, 7], &[2, 4]] {
            let kept = rows_of(11, "a plant", &rows(9, these), &render).unwrap();
            assert_eq!(kept, whole(&rows(9, these)).unwrap(), "rows {these:?}");
        }
        assert_eq!(*asked.borrow(), [vec![2, 3, 7], vec![4]]);
        // Another plant, or another line, has rows of its own.
        asked.borrow_mut().clear();
        rows_of(11, "another plant", &rows(9, &[2]), &render).unwrap();
        rows_of(12, "a plant", &rows(9, &[2]), &render).unwrap();
        assert_eq!(*asked.borrow(), [vec![2], vec![2]]);
    }

    #[test]
    fn pictures_not_traced_row_for_row_are_not_kept() {
        let asked = RefCell::new(Vec::new());
        // Twice as tall as the rows asked for: a zoomed picture.
        let zoomed = rendered(&asked, 8);
        rows_of(21, "a plant", &rows(4, &[1]), &zoomed).unwrap();
        rows_of(21, "a plant", &rows(4, &[1]), &zoomed).unwrap();
        assert_eq!(*asked.borrow(), [vec![1], vec![1]]);
    }
}

/// The rows kept are sound only where a plant's render of some rows is its whole render in
/// those rows, whatever other rows are asked for with them: so for every fault of the library.
#[cfg(test)]
mod every_fault {
    use super::super::{FAULTS, Plant, prepare};
    use crate::check::suite::parse_line;
    use crate::job::{render_pictures_until, render_rows_until};
    use crate::render::StopFlag;

    /// Mirrors, glass, a checkerboard, a highlight, both kinds of light and a plane, jittered
    /// samples under a tent: most faults change something here.
    const SCENE: &str = "PerspectiveCamera { center 0 1 9 direction 0 -0.1 -1 up 0 1 0 angle 40 }
        Lights { numLights 2
            DirectionalLight { direction -0.4 -1 -0.6 color 0.6 0.5 0.4 }
            PointLight { position 2 3 4 color 0.9 0.9 0.9 attenuation 1 0.1 0.02 } }
        Background { color 0.2 0.1 0.3 ambientLight 0.2 0.2 0.2 }
        Materials { numMaterials 5
            PhongMaterial { diffuseColor 0.8 0.2 0.1 specularColor 0.6 0.6 0.3 exponent 20 }
            PhongMaterial { diffuseColor 0.1 0.1 0.1 specularColor 0.3 0.3 0.3 exponent 40
                reflectiveColor 0.6 0.7 0.8 }
            PhongMaterial { diffuseColor 0 0 0 specularColor 0.5 0.5 0.5 exponent 30
                transparentColor 0.7 0.9 0.8 indexOfRefraction 1.4 }
            PhongMaterial { diffuseColor 0.9 0.9 0.9 }
            Checkerboard { Transform { UniformScale 1 } materialIndex 0 materialIndex 3 } }
        Group { numObjects 5
            MaterialIndex 0 Sphere { center -1.8 0.2 0 radius 1 }
            MaterialIndex 1 Sphere { center 0.4 0.4 -1 radius 1.1 }
            MaterialIndex 2 Sphere { center 1.6 -0.2 1.5 radius 0.8 }
            MaterialIndex 4 Plane { normal 0 1 0 offset -1 }
            MaterialIndex 3 Transform { Translate -0.5 -0.5 2 Scale 0.6 0.3 0.6
                Triangle { vertex0 -1 0 0 vertex1 1 0 0 vertex2 0 1.5 1 } } }";

    #[test]
    fn a_render_of_some_rows_is_the_whole_render_in_those_rows_for_every_fault() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("scene.txt"), SCENE).unwrap();
        let stop = StopFlag::leaked();
        let (width, height) = (20, 14);
        let lines = [
            format!(
                "raytracer -input scene.txt -size {width} {height} -output out.tga -shadows \
                 -bounces 3 -weight 0.01 -shade_back -jittered_samples 4 -tent_filter 1.5 \
                 -normals normals.tga -depth 7 12 depth.tga"
            ),
            format!(
                "raytracer -input scene.txt -size {width} {height} -output out.tga -shadows \
                 -grid 4 4 4 -uniform_samples 4 -gaussian_filter 0.5"
            ),
        ];
        let asks: [Vec<bool>; 2] = [
            (0..height).map(|row| row % 5 == 1 || row == 6).collect(),
            (0..height).map(|row| row % 4 == 2 || row == 6).collect(),
        ];
        let mut tried = 0;
        for text in &lines {
            let line = parse_line(text).unwrap();
            let prepared = prepare(&line, dir.path()).unwrap();
            let scene = &prepared.line;
            for fault in FAULTS {
                for candidate in (fault.candidates)(scene) {
                    let plant = Plant::one(candidate.planted);
                    let whole = render_pictures_until(&scene.options, &scene.scene, plant, stop)
                        .unwrap()
                        .pictures;
                    for wanted in &asks {
                        let rows =
                            render_rows_until(&scene.options, &scene.scene, plant, stop, wanted)
                                .unwrap()
                                .pictures;
                        for (k, (whole, rows)) in
                            whole.iter().zip(&rows).take(prepared.traced).enumerate()
                        {
                            let w = whole.width as usize;
                            for row in (0..wanted.len()).filter(|&row| wanted[row]) {
                                assert_eq!(
                                    whole.pixels[row * w..(row + 1) * w],
                                    rows.pixels[row * w..(row + 1) * w],
                                    "{} {candidate:?}: picture {k}, row {row} of {text}",
                                    fault.name
                                );
                            }
                        }
                    }
                    tried += 1;
                }
            }
        }
        assert!(tried > 100, "{tried} renders tried");
    }
}
