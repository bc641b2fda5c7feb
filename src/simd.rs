//! Eight lanes of `f32` for the tree's box test and the triangle blocks, in three paths chosen
//! once at run time: AVX-512 where the CPU has it (the eight lanes in one 256-bit register, the
//! work compiled for AVX-512: twice the vector registers, so the traversal's working set stays
//! in them, and comparisons into mask registers; and sixteen lanes, [`Avx16`], for two rays
//! against one block of triangles at once), AVX (eight lanes, compiled for AVX), and a portable
//! one (two of glam's `Vec4`, SSE2 on x86-64) everywhere else. `RAYCAST_SIMD` set to
//! `portable`, `avx` or `avx512` caps the choice (for tests and comparisons: see [`Path`]).
//!
//! All perform the same IEEE operations in the same order, lane by lane, so they give the same
//! bits: additions, subtractions, multiplications and divisions are exactly rounded on all; no
//! fused multiply-add is used (it would round once where another path rounds twice, and Rust
//! never fuses on its own); `min`/`max` keep SSE's rule (the second operand when either is NaN)
//! on all; comparisons are the same predicates (ordered, except `ne`, which is true for NaN).
//!
//! This is the crate's one module with `unsafe` code. The invariant every `unsafe` block here
//! rests on: **a value of type [`Avx`], [`Avx512`], [`Avx8`] or [`Avx16`] exists only after
//! `is_x86_feature_detected!` said yes to the features it names** ([`Avx`] and [`Avx512`]
//! have a private field and one constructor each, `Path::detect`'s; every [`Avx8`] is made
//! from one of them or from other [`Avx8`]s, every [`Avx16`] from an [`Avx512`] or other
//! [`Avx16`]s, and AVX-512 implies AVX). So the intrinsics called on them, and the work
//! compiled for their features, run on a CPU that has those features, which is all that their
//! `unsafe` asks.

#![allow(unsafe_code)]

use std::ops::{Add, Div, Mul, Sub};
use std::sync::OnceLock;

use glam::Vec4;

/// A way of doing eight-lane arithmetic: a token saying which instructions may be used.
pub trait Wide: Copy {
    /// Eight `f32` lanes.
    type F: Lanes<Array = [f32; 8]>;
    /// Sixteen lanes, two sets of eight side by side, where the path has registers that wide
    /// (AVX-512): two rays against one block of eight triangles at once. [`Unpaired`] where it
    /// has not.
    type Pair: Lanes<Array = [f32; 16]>;
    /// Whether [`Wide::join`] gives sixteen lanes (a constant, so that code for pairs vanishes
    /// from the paths without them).
    const PAIRS: bool;
    /// `value` in every lane.
    fn splat(self, value: f32) -> Self::F;
    /// Eight values from memory.
    fn load(self, values: &[f32; 8]) -> Self::F;
    /// `a`'s lanes, then `b`'s; `None` where the path does not pair.
    fn join(self, a: Self::F, b: Self::F) -> Option<Self::Pair>;
    /// Eight values from memory, twice over; `None` where the path does not pair.
    fn load_twice(self, values: &[f32; 8]) -> Option<Self::Pair>;
}

/// Lanes of `f32` and the lane-wise operations the kernels use. Comparisons return a bit mask:
/// bit k for lane k.
pub trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The lanes as an array.
    type Array;
    /// `value` in every lane (of as many lanes as `self` has).
    fn splat_like(self, value: f32) -> Self;
    /// Lane-wise `if self < other { self } else { other }` (so `other` when either is NaN).
    fn min(self, other: Self) -> Self;
    /// Lane-wise `if self > other { self } else { other }` (so `other` when either is NaN).
    fn max(self, other: Self) -> Self;
    /// `self <= other` (false for NaN).
    fn le(self, other: Self) -> u32;
    /// `self < other` (false for NaN).
    fn lt(self, other: Self) -> u32;
    /// `self > other` (false for NaN).
    fn gt(self, other: Self) -> u32;
    /// `self >= other` (false for NaN).
    fn ge(self, other: Self) -> u32;
    /// `self == other` (false for NaN).
    fn eq(self, other: Self) -> u32;
    /// `self != other` (true for NaN).
    fn ne(self, other: Self) -> u32;
    /// The lanes, in order.
    fn to_array(self) -> Self::Array;
}

/// The pair type of paths without sixteen-lane registers: it has no values, so nothing is
/// ever done with it.
#[derive(Debug, Clone, Copy)]
pub enum Unpaired {}

macro_rules! unpaired_op {
    ($trait:ident, $method:ident) => {
        impl $trait for Unpaired {
            type Output = Unpaired;
            fn $method(self, _: Unpaired) -> Unpaired {
                match self {}
            }
        }
    };
}
unpaired_op!(Add, add);
unpaired_op!(Sub, sub);
unpaired_op!(Mul, mul);
unpaired_op!(Div, div);

impl Lanes for Unpaired {
    type Array = [f32; 16];
    fn splat_like(self, _: f32) -> Unpaired {
        match self {}
    }
    fn min(self, _: Unpaired) -> Unpaired {
        match self {}
    }
    fn max(self, _: Unpaired) -> Unpaired {
        match self {}
    }
    fn le(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn lt(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn gt(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn ge(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn eq(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn ne(self, _: Unpaired) -> u32 {
        match self {}
    }
    fn to_array(self) -> [f32; 16] {
        match self {}
    }
}

/// Work that runs with whichever [`Wide`] the CPU allows (see [`dispatch`]).
pub trait WithWide {
    /// What the work returns.
    type Output;
    /// Does the work with `wide`'s instructions.
    fn run<K: Wide>(self, wide: K) -> Self::Output;
}

/// Runs `job` on the widest path the CPU has (and `RAYCAST_SIMD` allows): compiled for
/// AVX-512 or for AVX (the job's inlined code vectorised with those instructions), or with the
/// portable lanes. All give the same result.
#[inline(always)]
pub fn dispatch<J: WithWide>(job: J) -> J::Output {
    match Path::detect() {
        #[cfg(target_arch = "x86_64")]
        Token::Avx512(avx512) => {
            // SAFETY: `run_with_avx512` needs AVX-512 F, VL, DQ and BW, and `avx512` exists only
            // where the CPU has them.
            unsafe { run_with_avx512(job, avx512) }
        }
        #[cfg(target_arch = "x86_64")]
        Token::Avx(avx) => {
            // SAFETY: `run_with_avx` needs AVX, and `avx` exists only where the CPU has it.
            unsafe { run_with_avx(job, avx) }
        }
        Token::Portable => job.run(Portable),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,popcnt")]
fn run_with_avx<J: WithWide>(job: J, avx: Avx) -> J::Output {
    job.run(avx)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,avx,popcnt")]
fn run_with_avx512<J: WithWide>(job: J, avx512: Avx512) -> J::Output {
    job.run(avx512)
}

/// A way through [`dispatch`], widest last.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Path {
    /// glam's `Vec4` pairs: every CPU.
    Portable,
    /// AVX: x86-64 CPUs since 2011.
    Avx,
    /// AVX-512 (F, VL, DQ and BW): x86-64 server and recent desktop CPUs.
    Avx512,
}

/// What `Path::detect` hands [`dispatch`]: the path, with its proof where it needs one.
#[derive(Debug, Clone, Copy)]
enum Token {
    Portable,
    #[cfg(target_arch = "x86_64")]
    Avx(Avx),
    #[cfg(target_arch = "x86_64")]
    Avx512(Avx512),
}

impl Path {
    /// The names `RAYCAST_SIMD` takes, in the order of [`Path`].
    pub const NAMES: [&'static str; 3] = ["portable", "avx", "avx512"];

    /// The path named `name` (one of [`Path::NAMES`]).
    pub fn from_name(name: &str) -> Option<Path> {
        let index = Path::NAMES.iter().position(|&n| n == name)?;
        Some([Path::Portable, Path::Avx, Path::Avx512][index])
    }

    /// The path's name, as `RAYCAST_SIMD` takes it.
    pub fn name(self) -> &'static str {
        Path::NAMES[self as usize]
    }

    /// The cap `RAYCAST_SIMD` puts on the path: none where it is unset; an error naming the
    /// value where it names no path.
    pub fn requested() -> Result<Option<Path>, String> {
        let Some(value) = std::env::var_os("RAYCAST_SIMD") else {
            return Ok(None);
        };
        let value = value.to_string_lossy();
        Path::from_name(&value).map(Some).ok_or_else(|| {
            format!(
                "RAYCAST_SIMD must be one of {}, found '{value}'",
                Path::NAMES.join(", ")
            )
        })
    }

    /// Every path this CPU has, narrowest first.
    pub fn available() -> Vec<Path> {
        // Only x86_64 has wider paths (Apple silicon's NEON is the portable path's own).
        #[cfg(target_arch = "x86_64")]
        {
            let mut paths = vec![Path::Portable];
            if cpu_has_avx() {
                paths.push(Path::Avx);
            }
            if cpu_has_avx512() {
                paths.push(Path::Avx512);
            }
            paths
        }
        #[cfg(not(target_arch = "x86_64"))]
        vec![Path::Portable]
    }

    /// The path [`dispatch`] takes: the widest this CPU has, within `RAYCAST_SIMD`'s cap (a
    /// value that names no path caps nothing here; the command line refuses it first).
    pub fn chosen() -> Path {
        let cap = Path::requested().ok().flatten().unwrap_or(Path::Avx512);
        Path::available()
            .into_iter()
            .filter(|&path| path <= cap)
            .max()
            .unwrap_or(Path::Portable)
    }

    /// The chosen path with its proof, worked out once.
    #[inline(always)]
    fn detect() -> Token {
        static CHOSEN: OnceLock<Path> = OnceLock::new();
        match *CHOSEN.get_or_init(Path::chosen) {
            #[cfg(target_arch = "x86_64")]
            Path::Avx512 => Token::Avx512(Avx512(Avx(()))),
            #[cfg(target_arch = "x86_64")]
            Path::Avx => Token::Avx(Avx(())),
            _ => Token::Portable,
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn cpu_has_avx() -> bool {
    std::is_x86_feature_detected!("avx") && std::is_x86_feature_detected!("popcnt")
}

#[cfg(target_arch = "x86_64")]
fn cpu_has_avx512() -> bool {
    cpu_has_avx()
        && std::is_x86_feature_detected!("avx2")
        && std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx512vl")
        && std::is_x86_feature_detected!("avx512dq")
        && std::is_x86_feature_detected!("avx512bw")
}

/// The portable lanes: two of glam's `Vec4` (SSE2 on x86-64, plain `f32` elsewhere).
#[derive(Debug, Clone, Copy, Default)]
pub struct Portable;

/// Eight lanes as two `Vec4`.
#[derive(Debug, Clone, Copy)]
pub struct Portable8([Vec4; 2]);

impl Wide for Portable {
    type F = Portable8;
    type Pair = Unpaired;
    const PAIRS: bool = false;

    #[inline(always)]
    fn join(self, _: Portable8, _: Portable8) -> Option<Unpaired> {
        None
    }

    #[inline(always)]
    fn load_twice(self, _: &[f32; 8]) -> Option<Unpaired> {
        None
    }

    #[inline(always)]
    fn splat(self, value: f32) -> Portable8 {
        Portable8([Vec4::splat(value); 2])
    }

    #[inline(always)]
    fn load(self, values: &[f32; 8]) -> Portable8 {
        Portable8([
            Vec4::from_slice(&values[..4]),
            Vec4::from_slice(&values[4..]),
        ])
    }
}

macro_rules! portable_op {
    ($trait:ident, $method:ident) => {
        impl $trait for Portable8 {
            type Output = Portable8;
            #[inline(always)]
            fn $method(self, other: Portable8) -> Portable8 {
                Portable8([self.0[0].$method(other.0[0]), self.0[1].$method(other.0[1])])
            }
        }
    };
}
portable_op!(Add, add);
portable_op!(Sub, sub);
portable_op!(Mul, mul);
portable_op!(Div, div);

macro_rules! portable_compare {
    ($($name:ident => $glam:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self, other: Portable8) -> u32 {
                self.0[0].$glam(other.0[0]).bitmask() | self.0[1].$glam(other.0[1]).bitmask() << 4
            }
        )*
    };
}

impl Lanes for Portable8 {
    type Array = [f32; 8];

    #[inline(always)]
    fn splat_like(self, value: f32) -> Portable8 {
        Portable8([Vec4::splat(value); 2])
    }

    #[inline(always)]
    fn min(self, other: Portable8) -> Portable8 {
        Portable8([self.0[0].min(other.0[0]), self.0[1].min(other.0[1])])
    }

    #[inline(always)]
    fn max(self, other: Portable8) -> Portable8 {
        Portable8([self.0[0].max(other.0[0]), self.0[1].max(other.0[1])])
    }

    portable_compare!(le => cmple, lt => cmplt, gt => cmpgt, ge => cmpge, eq => cmpeq, ne => cmpne);

    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let [low, high] = self.0;
        let (low, high) = (low.to_array(), high.to_array());
        [
            low[0], low[1], low[2], low[3], high[0], high[1], high[2], high[3],
        ]
    }
}

#[cfg(target_arch = "x86_64")]
pub use avx::{Avx, Avx8, Avx16, Avx512};

#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;
    use std::ops::{Add, Div, Mul, Sub};

    use super::{Lanes, Path, Token, Wide};

    /// Proof that the CPU has AVX (and POPCNT, which every AVX CPU has): made only where
    /// `Path::detect` found them.
    #[derive(Debug, Clone, Copy)]
    pub struct Avx(pub(super) ());

    /// Proof that the CPU has AVX-512 F, VL, DQ and BW (and so AVX): made only where
    /// `Path::detect` found them. Its lanes are [`Avx8`]'s; what differs is the code the
    /// work around them is compiled to.
    #[derive(Debug, Clone, Copy)]
    pub struct Avx512(pub(super) Avx);

    impl Avx {
        /// `Some` where [`dispatch`](super::dispatch) takes AVX or AVX-512 (for tests that
        /// compare the paths).
        pub fn detect() -> Option<Avx> {
            match Path::detect() {
                Token::Avx(avx) | Token::Avx512(Avx512(avx)) => Some(avx),
                Token::Portable => None,
            }
        }
    }

    impl Avx512 {
        /// `Some` where [`dispatch`](super::dispatch) takes AVX-512 (for tests that compare
        /// the paths).
        pub fn detect() -> Option<Avx512> {
            match Path::detect() {
                Token::Avx512(avx512) => Some(avx512),
                _ => None,
            }
        }
    }

    impl Wide for Avx512 {
        type F = Avx8;
        type Pair = Avx16;
        const PAIRS: bool = true;

        #[inline(always)]
        fn join(self, a: Avx8, b: Avx8) -> Option<Avx16> {
            // SAFETY: `self` exists, so the CPU has AVX-512 F and DQ.
            Some(Avx16(unsafe {
                _mm512_insertf32x8::<1>(_mm512_castps256_ps512(a.0), b.0)
            }))
        }

        #[inline(always)]
        fn load_twice(self, values: &[f32; 8]) -> Option<Avx16> {
            // SAFETY: AVX-512 F and DQ as above; `values` is eight readable f32 (unaligned).
            Some(Avx16(unsafe {
                _mm512_broadcast_f32x8(_mm256_loadu_ps(values.as_ptr()))
            }))
        }

        #[inline(always)]
        fn splat(self, value: f32) -> Avx8 {
            self.0.splat(value)
        }

        #[inline(always)]
        fn load(self, values: &[f32; 8]) -> Avx8 {
            self.0.load(values)
        }
    }

    /// Eight lanes in one AVX register; made only from an [`Avx`] (or other `Avx8`s).
    #[derive(Debug, Clone, Copy)]
    pub struct Avx8(__m256);

    impl Wide for Avx {
        type F = Avx8;
        type Pair = super::Unpaired;
        const PAIRS: bool = false;

        #[inline(always)]
        fn join(self, _: Avx8, _: Avx8) -> Option<super::Unpaired> {
            None
        }

        #[inline(always)]
        fn load_twice(self, _: &[f32; 8]) -> Option<super::Unpaired> {
            None
        }

        #[inline(always)]
        fn splat(self, value: f32) -> Avx8 {
            // SAFETY: `self` exists, so the CPU has AVX.
            Avx8(unsafe { _mm256_set1_ps(value) })
        }

        #[inline(always)]
        fn load(self, values: &[f32; 8]) -> Avx8 {
            // SAFETY: AVX as above; `values` is eight readable f32 (unaligned load).
            Avx8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
        }
    }

    macro_rules! avx_op {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for Avx8 {
                type Output = Avx8;
                #[inline(always)]
                fn $method(self, other: Avx8) -> Avx8 {
                    // SAFETY: an `Avx8` exists only where the CPU has AVX.
                    Avx8(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    avx_op!(Add, add, _mm256_add_ps);
    avx_op!(Sub, sub, _mm256_sub_ps);
    avx_op!(Mul, mul, _mm256_mul_ps);
    avx_op!(Div, div, _mm256_div_ps);

    macro_rules! avx_compare {
        ($($name:ident => $predicate:ident),*) => {
            $(
                #[inline(always)]
                fn $name(self, other: Avx8) -> u32 {
                    // SAFETY: an `Avx8` exists only where the CPU has AVX.
                    unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<$predicate>(self.0, other.0)) as u32 }
                }
            )*
        };
    }

    impl Lanes for Avx8 {
        type Array = [f32; 8];

        #[inline(always)]
        fn splat_like(self, value: f32) -> Avx8 {
            // SAFETY: an `Avx8` exists only where the CPU has AVX.
            Avx8(unsafe { _mm256_set1_ps(value) })
        }

        #[inline(always)]
        fn min(self, other: Avx8) -> Avx8 {
            // SAFETY: as above. `_mm256_min_ps` keeps `_mm_min_ps`'s NaN rule.
            Avx8(unsafe { _mm256_min_ps(self.0, other.0) })
        }

        #[inline(always)]
        fn max(self, other: Avx8) -> Avx8 {
            // SAFETY: as above.
            Avx8(unsafe { _mm256_max_ps(self.0, other.0) })
        }

        // The predicates SSE's `cmple`, `cmplt`, ... use: ordered and signalling, except `ne`
        // (unordered) and `eq` (ordered, quiet); signalling or not changes no result.
        avx_compare!(
            le => _CMP_LE_OS, lt => _CMP_LT_OS, gt => _CMP_GT_OS, ge => _CMP_GE_OS,
            eq => _CMP_EQ_OQ, ne => _CMP_NEQ_UQ
        );

        #[inline(always)]
        fn to_array(self) -> [f32; 8] {
            let mut out = [0.0; 8];
            // SAFETY: as above; `out` is eight writable f32 (unaligned store).
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }

    /// Sixteen lanes in one AVX-512 register (two rays' eight side by side); made only from an
    /// [`Avx512`] (or other `Avx16`s).
    #[derive(Debug, Clone, Copy)]
    pub struct Avx16(__m512);

    macro_rules! avx16_op {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for Avx16 {
                type Output = Avx16;
                #[inline(always)]
                fn $method(self, other: Avx16) -> Avx16 {
                    // SAFETY: an `Avx16` exists only where the CPU has AVX-512 F.
                    Avx16(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    avx16_op!(Add, add, _mm512_add_ps);
    avx16_op!(Sub, sub, _mm512_sub_ps);
    avx16_op!(Mul, mul, _mm512_mul_ps);
    avx16_op!(Div, div, _mm512_div_ps);

    macro_rules! avx16_compare {
        ($($name:ident => $predicate:ident),*) => {
            $(
                #[inline(always)]
                fn $name(self, other: Avx16) -> u32 {
                    // SAFETY: an `Avx16` exists only where the CPU has AVX-512 F.
                    u32::from(unsafe { _mm512_cmp_ps_mask::<$predicate>(self.0, other.0) })
                }
            )*
        };
    }

    impl Lanes for Avx16 {
        type Array = [f32; 16];

        #[inline(always)]
        fn splat_like(self, value: f32) -> Avx16 {
            // SAFETY: an `Avx16` exists only where the CPU has AVX-512 F.
            Avx16(unsafe { _mm512_set1_ps(value) })
        }

        #[inline(always)]
        fn min(self, other: Avx16) -> Avx16 {
            // SAFETY: as above. `_mm512_min_ps` keeps `_mm_min_ps`'s NaN rule.
            Avx16(unsafe { _mm512_min_ps(self.0, other.0) })
        }

        #[inline(always)]
        fn max(self, other: Avx16) -> Avx16 {
            // SAFETY: as above.
            Avx16(unsafe { _mm512_max_ps(self.0, other.0) })
        }

        // The predicates of `Avx8`'s comparisons.
        avx16_compare!(
            le => _CMP_LE_OS, lt => _CMP_LT_OS, gt => _CMP_GT_OS, ge => _CMP_GE_OS,
            eq => _CMP_EQ_OQ, ne => _CMP_NEQ_UQ
        );

        #[inline(always)]
        fn to_array(self) -> [f32; 16] {
            let mut out = [0.0; 16];
            // SAFETY: as above; `out` is sixteen writable f32 (unaligned store).
            unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values that exercise rounding, signs, zeros, infinities and NaN.
    const AWKWARD: [f32; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        1.0 / 3.0,
        f32::MIN_POSITIVE,
        f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        1e-30,
        -7.25,
        3.0e8,
        f32::EPSILON,
        2.5,
    ];

    fn all_results<K: Wide>(wide: K, a: &[f32; 8], b: &[f32; 8]) -> (Vec<u32>, Vec<u32>) {
        let (x, y) = (wide.load(a), wide.load(b));
        let values = [
            x + y,
            x - y,
            x * y,
            x / y,
            x.min(y),
            x.max(y),
            wide.splat(a[3]),
        ];
        let bits = values
            .iter()
            .flat_map(|v| v.to_array().map(f32::to_bits))
            .collect();
        let masks = vec![x.le(y), x.lt(y), x.gt(y), x.ge(y), x.eq(y), x.ne(y)];
        (bits, masks)
    }

    #[test]
    fn both_paths_give_the_same_bits() {
        let Some(avx) = avx_if_any() else {
            return;
        };
        for shift in 0..16 {
            let a: [f32; 8] = std::array::from_fn(|i| AWKWARD[(i + shift) % 16]);
            for step in 1..16 {
                let b: [f32; 8] = std::array::from_fn(|i| AWKWARD[(i * step + 3) % 16]);
                assert_eq!(all_results(Portable, &a, &b), all_results(avx, &a, &b));
            }
        }
    }

    #[test]
    fn comparisons_and_min_follow_sse_rules_for_nan() {
        let nan = Portable.splat(f32::NAN);
        let one = Portable.splat(1.0);
        assert_eq!(nan.le(one) | nan.eq(one), 0);
        assert_eq!(nan.ne(one), 0xff);
        assert_eq!(nan.min(one).to_array(), [1.0; 8]);
        assert!(one.min(nan).to_array().iter().all(|v| v.is_nan()));
    }

    #[cfg(target_arch = "x86_64")]
    fn avx_if_any() -> Option<Avx> {
        Avx::detect()
    }

    #[cfg(not(target_arch = "x86_64"))]
    fn avx_if_any() -> Option<Portable> {
        None
    }
}
