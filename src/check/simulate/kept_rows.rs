//! Rows of a line's renders under plants, kept for the rest of the run. A screen renders a
//! plant's rows where a student's pictures differ most from their references, and the second
//! screen every few rows: each row's pixels depend on the line and the plant alone (each
//! pixel's samples are drawn from its own place, the rows a filter reaches traced with it), not
//! on the student. A class's students screen the same plants on the same lines, so each row of
//! a plant is rendered once for the whole class: on a line of many samples a pixel (the marble
//! vase's 36) the screens of the library's faults and of the course's open answers cost each
//! student that fails it as much as a few whole renders.

use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};

use crate::shade::Image;

/// The most bytes of rows kept in a run: rows past it are rendered again when asked for.
const MOST_BYTES: usize = 256 << 20;

/// Each plant's rows of each line: by the line's identity and the plant as planted.
#[derive(Default)]
struct Kept {
    plants: HashMap<(u64, String), PlantRows>,
    bytes: usize,
}

/// The rows of one plant's render of a line rendered so far: row `r` of every image at once.
struct PlantRows {
    sizes: Vec<(u32, u32)>,
    rows: HashMap<usize, Vec<Vec<[u8; 3]>>>,
}

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
    let missing: Vec<bool> = {
        let kept = lock();
        let have = kept.as_ref().and_then(|kept| kept.plants.get(&key));
        wanted
            .iter()
            .enumerate()
            .map(|(row, &w)| w && have.is_none_or(|have| !have.rows.contains_key(&row)))
            .collect()
    };
    // Nothing kept of these rows: the render is the answer, as it was.
    if missing == wanted {
        let fresh = render(wanted)?;
        keep(&key, wanted, &fresh);
        return Ok(fresh);
    }
    let fresh = if missing.contains(&true) {
        let fresh = render(&missing)?;
        keep(&key, &missing, &fresh);
        Some(fresh)
    } else {
        None
    };
    let kept = lock();
    let Some(have) = kept.as_ref().and_then(|kept| kept.plants.get(&key)) else {
        drop(kept);
        return render(wanted);
    };
    if fresh
        .as_ref()
        .is_some_and(|fresh| sizes(fresh) != have.sizes)
    {
        drop(kept);
        return render(wanted);
    }
    let mut pictures: Vec<Image> = have
        .sizes
        .iter()
        .map(|&(width, height)| Image {
            width,
            height,
            pixels: vec![[0; 3]; width as usize * height as usize],
        })
        .collect();
    for (row, _) in wanted.iter().enumerate().filter(|(_, w)| **w) {
        for (k, picture) in pictures.iter_mut().enumerate() {
            let width = picture.width as usize;
            let target = &mut picture.pixels[row * width..(row + 1) * width];
            match (have.rows.get(&row), &fresh) {
                (Some(rows), _) => target.copy_from_slice(&rows[k]),
                (None, Some(fresh)) => {
                    target.copy_from_slice(&fresh[k].pixels[row * width..(row + 1) * width]);
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
    let mut kept = lock();
    let Kept { plants, bytes } = kept.get_or_insert_with(Kept::default);
    let row_bytes: usize = pictures.iter().map(|p| p.width as usize * 3).sum();
    let entry = plants.entry(key.clone()).or_insert_with(|| PlantRows {
        sizes: sizes(pictures),
        rows: HashMap::new(),
    });
    if entry.sizes != sizes(pictures) {
        return;
    }
    for (row, _) in rendered.iter().enumerate().filter(|(_, r)| **r) {
        if *bytes + row_bytes > MOST_BYTES {
            return;
        }
        let pixels = pictures
            .iter()
            .map(|p| {
                let width = p.width as usize;
                p.pixels[row * width..(row + 1) * width].to_vec()
            })
            .collect();
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
    fn pictures_not_traced_row_for_row_and_stopped_renders_are_not_kept() {
        let asked = RefCell::new(Vec::new());
        // Twice as tall as the rows asked for: a zoomed picture.
        let zoomed = rendered(&asked, 8);
        rows_of(21, "a plant", &rows(4, &[1]), &zoomed).unwrap();
        rows_of(21, "a plant", &rows(4, &[1]), &zoomed).unwrap();
        assert_eq!(*asked.borrow(), [vec![1], vec![1]]);
        let stopped = |_: &[bool]| -> Result<Vec<Image>, ()> { Err(()) };
        assert_eq!(rows_of(22, "a plant", &rows(4, &[1]), stopped), Err(()));
        asked.borrow_mut().clear();
        rows_of(22, "a plant", &rows(4, &[1]), rendered(&asked, 4)).unwrap();
        assert_eq!(*asked.borrow(), [vec![1]]);
    }
}
