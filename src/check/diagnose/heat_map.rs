//! A picture of where two pictures differ, and by how much.

use crate::check::rule::channel_difference;
use crate::shade::Image;

/// A picture of the difference, the reference's size: pixels within `tolerance` are dim grey
/// copies of the reference (black where it is black), so the scene stays recognisable; the others
/// ramp from dark red through red and yellow to white with their largest channel difference.
/// Where `actual` has no pixel (a picture of another size), the difference counts as the largest.
pub fn heat_map(actual: &Image, reference: &Image, tolerance: u8) -> Image {
    let (width, height) = (reference.width as usize, reference.height as usize);
    let (actual_width, actual_height) = (actual.width as usize, actual.height as usize);
    let mut pixels = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let want = reference
                .pixels
                .get(y * width + x)
                .copied()
                .unwrap_or_default();
            let got = if x < actual_width && y < actual_height {
                actual.pixels.get(y * actual_width + x).copied()
            } else {
                None
            };
            let difference = got.map_or(u8::MAX, |got| channel_difference(got, want));
            pixels.push(if difference <= tolerance {
                dimmed(want)
            } else {
                heat(difference)
            });
        }
    }
    Image {
        width: reference.width,
        height: reference.height,
        pixels,
    }
}

/// A matching pixel in the heat map: the reference's brightness, dimmed to a quarter, in grey.
fn dimmed([red, green, blue]: [u8; 3]) -> [u8; 3] {
    let luma = (299 * u32::from(red) + 587 * u32::from(green) + 114 * u32::from(blue)) / 1000;
    [(luma / 4) as u8; 3]
}

/// A differing pixel in the heat map, in three equal stages: dark red to red, red to yellow,
/// yellow to white. Even the smallest difference (128 of red) stands out from the dimmed grey.
fn heat(difference: u8) -> [u8; 3] {
    let step = 3 * u32::from(difference);
    match step {
        0..255 => [(128 + step / 2) as u8, 0, 0],
        255..510 => [255, (step - 255) as u8, 0],
        _ => [255, 255, (step - 510).min(255) as u8],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heat_map_dims_matches_and_ramps_differences() {
        let reference = Image {
            width: 4,
            height: 1,
            pixels: vec![[0, 0, 0], [200, 100, 40], [100, 100, 100], [0, 0, 0]],
        };
        let actual = Image {
            width: 4,
            height: 1,
            pixels: vec![[0, 0, 0], [201, 100, 40], [100, 110, 100], [255, 255, 255]],
        };
        let map = heat_map(&actual, &reference, 2);
        assert_eq!((map.width, map.height, map.pixels.len()), (4, 1, 4));
        assert_eq!(map.pixels[0], [0, 0, 0], "equal black stays black");
        let [r, g, b] = map.pixels[1];
        let grey = r == g && g == b && (1..64).contains(&r);
        assert!(grey, "a match is a dim grey: {:?}", map.pixels[1]);
        let [r, g, b] = map.pixels[2];
        assert!(
            r >= 128 && g == 0 && b == 0,
            "a small difference is red: {:?}",
            map.pixels[2]
        );
        assert_eq!(
            map.pixels[3],
            [255, 255, 255],
            "the largest difference is white"
        );

        let smaller = Image {
            width: 1,
            height: 1,
            pixels: vec![[0, 0, 0]],
        };
        let map = heat_map(&smaller, &reference, 2);
        assert_eq!(map.pixels.len(), 4);
        assert_eq!(
            map.pixels[1],
            [255, 255, 255],
            "no pixel counts as the largest difference"
        );
    }
}
