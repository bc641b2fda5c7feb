//! The unit tests' pictures: a synthetic renderer of a disc, a rectangle and a triangle whose
//! faults the tests plant, and the check that a planted fault gets its diagnosis.

use super::{Diagnosis, diagnose};
use crate::check::rule::{Rule, compare};
use crate::shade::Image;

pub(super) const WIDTH: u32 = 64;
pub(super) const HEIGHT: u32 = 48;
pub(super) const GREY: [u8; 3] = [127, 127, 127];
pub(super) const TOLERANCE: u8 = 2;
/// The course's rule, as the tests grade by it.
pub(super) const RULE: Rule = Rule::COURSE;

pub(super) const RED: [u8; 3] = [220, 40, 30];
pub(super) const GREEN: [u8; 3] = [40, 200, 60];
pub(super) const BLUE: [u8; 3] = [50, 70, 230];
pub(super) const YELLOW: [u8; 3] = [230, 220, 40];
/// Centre x, centre y, radius.
pub(super) const DISC: (f64, f64, f64) = (16.3, 15.6, 9.7);
pub(super) const TRIANGLE: [(f64, f64); 3] = [(30.4, 44.2), (46.1, 26.3), (58.3, 43.6)];

/// What the synthetic renderer draws, and where within each pixel it samples.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scene {
    /// The sample point within a pixel: (0.5, 0.5) is its centre, (0, 0) its top left corner.
    pub(super) offset: (f64, f64),
    pub(super) background: [u8; 3],
    pub(super) triangle: bool,
    pub(super) square: bool,
    pub(super) black_lower_disc: bool,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            offset: (0.5, 0.5),
            background: GREY,
            triangle: true,
            square: false,
            black_lower_disc: false,
        }
    }
}

/// A gradient across the picture, so that channels vary (but by at most the tolerance from
/// one pixel to the next, so that only outlines are edges).
pub(super) fn shade(base: [u8; 3], x: f64, y: f64) -> [u8; 3] {
    let factor = 0.55 + 0.25 * x / f64::from(WIDTH) + 0.2 * y / f64::from(HEIGHT);
    base.map(|level| (f64::from(level) * factor) as u8)
}

pub(super) fn inside_triangle(x: f64, y: f64) -> bool {
    let side =
        |(ax, ay): (f64, f64), (bx, by): (f64, f64)| (bx - ax) * (y - ay) - (by - ay) * (x - ax);
    let [a, b, c] = TRIANGLE;
    let sides = [side(a, b), side(b, c), side(c, a)];
    sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0)
}

/// A grey picture with a red disc, a green rectangle and a blue triangle, analytically, one
/// sample per pixel.
pub(super) fn render(scene: Scene) -> Image {
    let (cx, cy, radius) = DISC;
    let mut pixels = Vec::new();
    for row in 0..HEIGHT {
        for column in 0..WIDTH {
            let x = f64::from(column) + scene.offset.0;
            let y = f64::from(row) + scene.offset.1;
            let colour = if (x - cx) * (x - cx) + (y - cy) * (y - cy) <= radius * radius {
                if scene.black_lower_disc && y > cy {
                    [0, 0, 0]
                } else {
                    shade(RED, x, y)
                }
            } else if (34.2..57.6).contains(&x) && (5.3..20.8).contains(&y) {
                shade(GREEN, x, y)
            } else if scene.triangle && inside_triangle(x, y) {
                shade(BLUE, x, y)
            } else if scene.square && (4.0..10.0).contains(&x) && (32.0..38.0).contains(&y) {
                shade(YELLOW, x, y)
            } else {
                scene.background
            };
            pixels.push(colour);
        }
    }
    Image {
        width: WIDTH,
        height: HEIGHT,
        pixels,
    }
}

pub(super) fn reference() -> Image {
    render(Scene::default())
}

pub(super) fn map_pixels(image: &Image, mut change: impl FnMut([u8; 3]) -> [u8; 3]) -> Image {
    Image {
        width: image.width,
        height: image.height,
        pixels: image.pixels.iter().map(|&colour| change(colour)).collect(),
    }
}

pub(super) fn rearranged(image: &Image, source: impl Fn(usize, usize) -> (usize, usize)) -> Image {
    let (width, height) = (image.width as usize, image.height as usize);
    let mut pixels = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let (from_x, from_y) = source(x, y);
            pixels.push(image.pixels[from_y * width + from_x]);
        }
    }
    Image {
        width: image.width,
        height: image.height,
        pixels,
    }
}

/// A deterministic byte stream (a 64-bit LCG's top byte).
pub(super) struct Noise(pub(super) u64);

impl Noise {
    pub(super) fn byte(&mut self) -> u8 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 56) as u8
    }
}

/// The planted fault fails the conformance rule and gets exactly `expected`.
pub(super) fn assert_diagnosed(actual: &Image, expected: &[Diagnosis]) {
    let reference = reference();
    let comparison = compare(actual, &reference, TOLERANCE).expect("the sizes agree");
    assert!(
        !RULE.passes(&comparison),
        "the planted fault must fail; {} pixels differ",
        comparison.differing
    );
    assert_eq!(diagnose(actual, &reference, RULE), expected);
}
