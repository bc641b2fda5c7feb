//! Ken Perlin's improved noise (2002), in doubles, as the course's staff file has it: the same
//! permutation, fade curve and gradients, so a texture's noise is the course's noise.

/// Perlin's permutation of 0..=255.
#[rustfmt::skip]
const PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// The permutation twice over, so that `p[i + 1]` never needs a wrap.
const P: [u8; 512] = {
    let mut p = [0; 512];
    let mut i = 0;
    while i < 512 {
        p[i] = PERMUTATION[i % 256];
        i += 1;
    }
    p
};

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn lerp(t: f64, a: f64, b: f64) -> f64 {
    a + t * (b - a)
}

/// The dot product of (x, y, z) with one of twelve gradient directions, picked by the hash.
fn grad(hash: u8, x: f64, y: f64, z: f64) -> f64 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Improved noise at (x, y, z): smooth, zero at every integer lattice point, within about ±1.
pub fn noise(x: f64, y: f64, z: f64) -> f64 {
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    // The unit cube holding the point; `as i64` saturates, so far-off points still land in it.
    let cube = |f: f64| (f as i64 & 255) as usize;
    let (xi, yi, zi) = (cube(fx), cube(fy), cube(fz));
    let (x, y, z) = (x - fx, y - fy, z - fz);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let p = |i: usize| P[i] as usize;
    let a = p(xi) + yi;
    let aa = p(a) + zi;
    let ab = p(a + 1) + zi;
    let b = p(xi + 1) + yi;
    let ba = p(b) + zi;
    let bb = p(b + 1) + zi;
    lerp(
        w,
        lerp(
            v,
            lerp(u, grad(P[aa], x, y, z), grad(P[ba], x - 1.0, y, z)),
            lerp(
                u,
                grad(P[ab], x, y - 1.0, z),
                grad(P[bb], x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(P[aa + 1], x, y, z - 1.0),
                grad(P[ba + 1], x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(P[ab + 1], x, y - 1.0, z - 1.0),
                grad(P[bb + 1], x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// The handout's sum over octaves: N = noise(p) + noise(2p)/2 + noise(4p)/4 + … (`octaves`
/// terms; 0 octaves is 0).
pub fn octave_noise(x: f64, y: f64, z: f64, octaves: u32) -> f64 {
    // Each octave weighed ½^i: the same bits as dividing by 2^i.
    octave_noise_weighed(x, y, z, octaves, 0.5)
}

/// The sum of `octaves` octaves of noise at (x, y, z), each at twice the frequency of the
/// last and `ratio` times its weight ([`octave_noise`] is the ratio ½; check's fault library
/// weighs them otherwise).
pub fn octave_noise_weighed(x: f64, y: f64, z: f64, octaves: u32, ratio: f64) -> f64 {
    let mut sum = 0.0;
    let (mut scale, mut weight) = (1.0, 1.0);
    for _ in 0..octaves {
        sum += noise(x * scale, y * scale, z * scale) * weight;
        scale *= 2.0;
        weight *= ratio;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octaves_weighed_by_a_half_are_the_courses() {
        for (x, y, z) in [(0.3, 1.7, -2.2), (10.5, 0.25, 3.0)] {
            assert_eq!(
                octave_noise_weighed(x, y, z, 4, 0.5),
                octave_noise(x, y, z, 4)
            );
        }
    }

    #[test]
    fn the_table_is_a_permutation() {
        let mut seen = [false; 256];
        for &v in &PERMUTATION {
            assert!(!seen[v as usize], "{v} twice");
            seen[v as usize] = true;
        }
    }

    #[test]
    fn zero_on_the_lattice() {
        for (x, y, z) in [
            (0.0, 0.0, 0.0),
            (1.0, 2.0, 3.0),
            (-7.0, 4.0, 255.0),
            (300.0, -1.0, 0.0),
        ] {
            assert_eq!(noise(x, y, z), 0.0);
        }
    }

    #[test]
    fn values_of_the_published_algorithm() {
        // Computed by a separate transcription of Perlin's Java reference (ImprovedNoise, 2002)
        // in Python's doubles; the Rust must agree to the last bit, as the staff's C++ does.
        assert_eq!(noise(0.5, 0.5, 0.5), -0.25);
        assert_eq!(noise(3.25, 42.0, -7.25), -0.04640007019042969);
        assert_eq!(noise(-0.3, 1.7, 2.2), -0.029045453419571002);
        assert_eq!(noise(100.9, -55.1, 0.01), -0.19675668916187689);
    }

    #[test]
    fn octaves_add_halved_copies() {
        let (x, y, z) = (0.3, 1.7, -2.2);
        assert_eq!(octave_noise(x, y, z, 0), 0.0);
        assert_eq!(octave_noise(x, y, z, 1), noise(x, y, z));
        assert_eq!(
            octave_noise(x, y, z, 3),
            noise(x, y, z)
                + noise(2.0 * x, 2.0 * y, 2.0 * z) / 2.0
                + noise(4.0 * x, 4.0 * y, 4.0 * z) / 4.0
        );
    }
}
