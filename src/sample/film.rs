//! Every sample of every pixel, with where it fell, and the filtering that turns them into
//! pixels; the course's two debugging pictures.

use glam::{Vec2, Vec3A};
use rayon::prelude::*;

use super::{Filter, SampleSeam};
use crate::shade::Image;
use crate::shade::to_rgb;
use crate::variant::Exact;

/// The samples of an image: for pixel (i, j), i from the left and j from the bottom, and its
/// sample k, entry `(j·width + i)·samples + k`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Film {
    /// In pixels.
    pub width: u32,
    /// In pixels.
    pub height: u32,
    /// Samples per pixel.
    pub samples: u32,
    /// `width × height × samples` of them: rows from the bottom, each pixel's samples together.
    pub entries: Vec<FilmSample>,
}

/// One sample: where it fell and what it saw.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FilmSample {
    /// Offset from the pixel's lower-left corner, in [0, 1)².
    pub position: Vec2,
    /// The traced colour, unclamped.
    pub colour: Vec3A,
    /// The normal picture's colour (when asked for).
    pub normal: Vec3A,
    /// The depth picture's grey (when asked for).
    pub depth: f32,
}

impl Film {
    /// The filtered value of pixel (i, j): the filter-weighted mean of the samples of the pixels
    /// within its support radius, cropped at the image's border. Where every weight is 0 (a
    /// filter smaller than the gaps between samples), the mean of the pixel's own samples.
    pub fn filtered(
        &self,
        filter: Filter,
        i: u32,
        j: u32,
        value: impl Fn(&FilmSample) -> Vec3A,
    ) -> Vec3A {
        self.filtered_as(Exact, filter, i, j, value)
    }

    /// [`Film::filtered`], the weighted samples summed up as `variant` does.
    pub fn filtered_as(
        &self,
        variant: impl SampleSeam,
        filter: Filter,
        i: u32,
        j: u32,
        value: impl Fn(&FilmSample) -> Vec3A,
    ) -> Vec3A {
        let reach = filter.support_radius() as i64;
        let n = self.samples as usize;
        let (centre_x, centre_y) = (i as f32 + 0.5, j as f32 + 0.5);
        let mut sum = Vec3A::ZERO;
        let mut total = 0.0;
        let mut count = 0;
        let (low, high) = variant.neighbours(reach);
        let rows = (j as i64 + low).max(0)..=(j as i64 + high).min(self.height as i64 - 1);
        for pj in rows {
            let columns = (i as i64 + low).max(0)..=(i as i64 + high).min(self.width as i64 - 1);
            for pi in columns {
                let first = (pj as usize * self.width as usize + pi as usize) * n;
                for sample in &self.entries[first..first + n] {
                    let p = sample.position;
                    let (x, y) = (pi as f32 + p.x - centre_x, pj as f32 + p.y - centre_y);
                    let weight = variant.weight(filter, x, y);
                    if weight != 0.0 {
                        sum += value(sample) * weight;
                        total += weight;
                        count += 1;
                    }
                }
            }
        }
        if total > 0.0 {
            return variant.weighted_mean(sum, total, count);
        }
        let first = (j as usize * self.width as usize + i as usize) * n;
        let own: Vec3A = self.entries[first..first + n].iter().map(&value).sum();
        own / n as f32
    }

    /// A whole picture of one value of the samples, filtered, rows top first as images store
    /// them.
    pub fn picture(
        &self,
        variant: impl SampleSeam,
        filter: Filter,
        value: impl Fn(&FilmSample) -> Vec3A + Sync,
        to_pixel: impl Fn(Vec3A) -> [u8; 3] + Sync,
    ) -> Image {
        self.picture_rows(variant, filter, value, to_pixel, None)
    }

    /// [`Film::picture`], only the rows `wanted` marks (top first) where it is given; the others
    /// black.
    pub fn picture_rows(
        &self,
        variant: impl SampleSeam,
        filter: Filter,
        value: impl Fn(&FilmSample) -> Vec3A + Sync,
        to_pixel: impl Fn(Vec3A) -> [u8; 3] + Sync,
        wanted: Option<&[bool]>,
    ) -> Image {
        let (width, height) = (self.width, self.height);
        let mut pixels = vec![[0u8; 3]; width as usize * height as usize];
        pixels
            .par_chunks_mut(width as usize)
            .enumerate()
            .filter(|(row, _)| wanted.is_none_or(|wanted| wanted[*row]))
            .for_each(|(row, out)| {
                let j = height - 1 - row as u32;
                for (i, pixel) in out.iter_mut().enumerate() {
                    *pixel = to_pixel(self.filtered_as(variant, filter, i as u32, j, &value));
                }
            });
        Image {
            width,
            height,
            pixels,
        }
    }
}

/// The course's `Film::renderSamples`: each pixel a `zoom`×`zoom` block, dark grey and black
/// in a checkerboard (grey at the lower-left pixel), and each sample one image pixel of its own
/// colour where it falls.
pub fn render_samples_picture(film: &Film, zoom: u32) -> Image {
    let (width, height) = (film.width * zoom, film.height * zoom);
    let mut picture = Picture::new(width, height, [0, 0, 0]);
    let grey = to_rgb(Vec3A::splat(0.2));
    let n = film.samples as usize;
    for i in 0..film.width {
        for j in 0..film.height {
            let block = if (i + j) % 2 == 0 { grey } else { [0, 0, 0] };
            for x in i * zoom..(i + 1) * zoom {
                for y in j * zoom..(j + 1) * zoom {
                    picture.set(x, y, block);
                }
            }
            let first = (j as usize * film.width as usize + i as usize) * n;
            for sample in &film.entries[first..first + n] {
                let p = sample.position;
                let x = (((i as f32 + p.x) * zoom as f32).floor() as u32).min(width - 1);
                let y = (((j as f32 + p.y) * zoom as f32).floor() as u32).min(height - 1);
                picture.set(x, y, to_rgb(sample.colour));
            }
        }
    }
    picture.image
}

/// The course's `Film::renderFilter`: the filter's weights about the centre pixel of a
/// `width`×`height` image, each pixel `zoom`×`zoom` and each of those showing the weight at its
/// lower-left corner, on dark blue, with a blue line between pixels.
pub fn render_filter_picture(width: u32, height: u32, filter: Filter, zoom: u32) -> Image {
    let mut picture = Picture::new(width * zoom + 1, height * zoom + 1, [0, 0, 127]);
    let reach = filter.support_radius() as i64;
    // As the course: the centre pixel is width/2 across and up alike.
    let center = (width / 2) as i64;
    for i in center - reach..=center + reach {
        for j in center - reach..=center + reach {
            if i < 0 || i >= width as i64 || j < 0 || j >= height as i64 {
                continue;
            }
            for i2 in 0..zoom {
                for j2 in 0..zoom {
                    let x = i as f32 + i2 as f32 / zoom as f32 - (center as f32 + 0.5);
                    let y = j as f32 + j2 as f32 / zoom as f32 - (center as f32 + 0.5);
                    let weight = filter.weight(x, y);
                    let (px, py) = (i as u32 * zoom + i2, j as u32 * zoom + j2);
                    picture.set(px, py, to_rgb(Vec3A::splat(weight)));
                }
            }
        }
    }
    for x in 0..width * zoom + 1 {
        for y in 0..height * zoom + 1 {
            if x % zoom == 0 || y % zoom == 0 {
                picture.set(x, y, [0, 0, 255]);
            }
        }
    }
    picture.image
}

/// An image addressed as the course's `Image` is: (x, y) with y = 0 the bottom row.
struct Picture {
    image: Image,
}

impl Picture {
    fn new(width: u32, height: u32, fill: [u8; 3]) -> Picture {
        Picture {
            image: Image {
                width,
                height,
                pixels: vec![fill; width as usize * height as usize],
            },
        }
    }

    fn set(&mut self, x: u32, y: u32, colour: [u8; 3]) {
        let row = self.image.height - 1 - y;
        self.image.pixels[(row * self.image.width + x) as usize] = colour;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×2 film with the same samples in every pixel, each pixel's colour its index.
    fn film(samples_at: &[Vec2]) -> Film {
        let n = samples_at.len();
        let mut f = Film {
            width: 3,
            height: 2,
            samples: n as u32,
            ..Film::default()
        };
        for pixel in 0..6 {
            for &position in samples_at {
                f.entries.push(FilmSample {
                    position,
                    colour: Vec3A::splat(pixel as f32),
                    ..FilmSample::default()
                });
            }
        }
        f
    }

    fn colour(s: &FilmSample) -> Vec3A {
        s.colour
    }

    #[test]
    fn a_box_of_half_a_pixel_takes_the_pixels_own_samples() {
        let f = film(&[Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.75)]);
        for j in 0..2 {
            for i in 0..3 {
                let v = f.filtered(Filter::Box(0.5), i, j, colour);
                assert_eq!(v, Vec3A::splat((j * 3 + i) as f32));
            }
        }
    }

    #[test]
    fn wider_filters_weigh_the_neighbours_and_crop_at_the_border() {
        let f = film(&[Vec2::splat(0.5)]);
        // Tent of radius 1.5 at pixel (1, 0): itself (weight 1), left and right (1/3 each), and
        // above (1/3) and above left and right (1 - √2/1.5 each); no row below (cropped).
        let diagonal = 1.0 - 2f32.sqrt() / 1.5;
        let third = 1.0 - 1.0 / 1.5;
        let total = 1.0 + 3.0 * third + 2.0 * diagonal;
        let expected = (1.0 * 1.0 + third * (0.0 + 2.0 + 4.0) + diagonal * (3.0 + 5.0)) / total;
        let v = f.filtered(Filter::Tent(1.5), 1, 0, colour);
        assert!((v.x - expected).abs() < 1e-5, "{v} {expected}");
        // A box of 1.7 at the corner (0, 0) takes the centres 0 and 1 pixels away on each axis
        // (pixels 0, 1, 3 and 4), not those 2 away: -1.7 <= x < 1.7.
        assert_eq!(
            f.filtered(Filter::Box(1.7), 0, 0, colour),
            Vec3A::splat(2.0)
        );
    }

    #[test]
    fn a_filter_that_misses_every_sample_falls_back_to_the_pixels_mean() {
        let f = film(&[Vec2::new(0.1, 0.1), Vec2::new(0.9, 0.9)]);
        assert_eq!(
            f.filtered(Filter::Tent(0.1), 2, 1, colour),
            Vec3A::splat(5.0)
        );
    }

    #[test]
    fn the_filter_picture_as_the_course_draws_it() {
        // 3×3 pixels at zoom 2, a box of 0.5: the centre pixel (1, 1) white (its lower-left
        // corners at offsets -0.5 and 0 are inside), the rest dark blue, lines blue.
        let image = render_filter_picture(3, 3, Filter::Box(0.5), 2);
        assert_eq!((image.width, image.height), (7, 7));
        let at = |x: u32, y: u32| image.pixels[((6 - y) * 7 + x) as usize];
        assert_eq!(at(3, 3), [255, 255, 255]);
        assert_eq!(at(2, 3), [0, 0, 255]);
        assert_eq!(at(1, 1), [0, 0, 127]);
        assert_eq!(at(5, 5), [0, 0, 127]);
        assert_eq!(at(0, 5), [0, 0, 255]);
    }

    #[test]
    fn the_samples_picture_as_the_course_draws_it() {
        let mut f = film(&[Vec2::new(0.25, 0.75)]);
        for sample in &mut f.entries {
            sample.colour = Vec3A::X;
        }
        let image = render_samples_picture(&f, 4);
        assert_eq!((image.width, image.height), (12, 8));
        let at = |x: u32, y: u32| image.pixels[((7 - y) * 12 + x) as usize];
        // Pixel (0, 0) is grey, its sample at (1, 3); pixel (1, 0) black, its sample at (5, 3).
        assert_eq!(at(0, 0), [51, 51, 51]);
        assert_eq!(at(1, 3), [255, 0, 0]);
        assert_eq!(at(4, 0), [0, 0, 0]);
        assert_eq!(at(5, 3), [255, 0, 0]);
        assert_eq!(at(4, 4), [51, 51, 51]);
    }
}
