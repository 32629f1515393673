//! numpy's `random_standard_normal`: a 256-layer ziggurat (Marsaglia & Tsang) driven by one
//! 64-bit draw per attempt.
//!
//! Per attempt: `r = next64`; `idx = r & 0xff`; `r >>= 8`; `sign = r & 1`;
//! `rabs = (r >> 1) & (2^52 - 1)`; `x = ±rabs * WI[idx]`.
//! * `rabs < KI[idx]` → return `x` (≈ 99.3 % of attempts);
//! * `idx == 0` → sample the tail beyond `R` with Marsaglia's exponential method (two
//!   `next_double`s per try, `log1p(-u)` so that `u = 0` is harmless) and return `±(R + xx)`,
//!   the sign taken from bit 8 of `rabs`;
//! * otherwise → wedge test `(FI[idx-1] - FI[idx]) * u + FI[idx] < exp(-x²/2)` with one
//!   `next_double`; on failure start over with a fresh 64-bit draw.
//!
//! The floating-point expressions are written in the same order as numpy's C so that, without
//! FMA contraction (Rust never contracts), every result is bit-identical. `f64::ln_1p` and
//! `f64::exp` call the platform libm (glibc on Linux), as numpy's `npy_log1p`/`exp` do.

use super::pcg64::Pcg64;
use super::ziggurat_tables::{FI_DOUBLE, KI_DOUBLE, WI_DOUBLE};

/// Start of the tail, `R` (numpy `ziggurat_nor_r` = 3.6541528853610087963519472518, rounded to
/// f64; bits `0x400D_3BB4_8209_AD33`, checked in the tests).
const ZIGGURAT_NOR_R: f64 = 3.654_152_885_361_009;
/// `1 / R` (numpy `ziggurat_nor_inv_r` = 0.27366123732975827203338247596, a separately rounded
/// literal, not computed from `R`).
const ZIGGURAT_NOR_INV_R: f64 = 0.273_661_237_329_758_3;

/// Which branch of the ziggurat an attempt ended in (for tests / coverage accounting).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    /// `rabs < KI[idx]`: accepted without any extra draw.
    Fast,
    /// Wedge test passed.
    WedgeAccept,
    /// Wedge test failed: the sampler starts over.
    WedgeReject,
    /// One tail try that was rejected (the tail loop draws again).
    TailRetry,
    /// Tail value accepted.
    Tail,
}

/// One standard normal, reporting each attempt's outcome to `observe`.
#[inline]
pub(crate) fn standard_normal_observed(bg: &mut Pcg64, mut observe: impl FnMut(Path)) -> f64 {
    loop {
        let mut r = bg.next64();
        let idx = (r & 0xff) as usize;
        r >>= 8;
        let sign = r & 1;
        let rabs = (r >> 1) & 0x000f_ffff_ffff_ffff;
        let mut x = rabs as f64 * WI_DOUBLE[idx];
        if sign & 1 == 1 {
            x = -x;
        }
        if rabs < KI_DOUBLE[idx] {
            observe(Path::Fast);
            return x;
        }
        if idx == 0 {
            loop {
                let xx = -ZIGGURAT_NOR_INV_R * (-bg.next_double()).ln_1p();
                let yy = -(-bg.next_double()).ln_1p();
                if yy + yy > xx * xx {
                    observe(Path::Tail);
                    return if (rabs >> 8) & 1 == 1 {
                        -(ZIGGURAT_NOR_R + xx)
                    } else {
                        ZIGGURAT_NOR_R + xx
                    };
                }
                observe(Path::TailRetry);
            }
        } else {
            let u = bg.next_double();
            if (FI_DOUBLE[idx - 1] - FI_DOUBLE[idx]) * u + FI_DOUBLE[idx] < (-0.5 * x * x).exp() {
                observe(Path::WedgeAccept);
                return x;
            }
            observe(Path::WedgeReject);
        }
    }
}

/// numpy `Generator.standard_normal()` (one value).
#[inline]
pub(crate) fn standard_normal(bg: &mut Pcg64) -> f64 {
    standard_normal_observed(bg, |_| {})
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::seed_sequence::SeedSequence;

    #[test]
    #[allow(clippy::excessive_precision)]
    fn constants_are_numpys_literals() {
        assert_eq!(ZIGGURAT_NOR_R, 3.6541528853610087963519472518);
        assert_eq!(ZIGGURAT_NOR_INV_R, 0.27366123732975827203338247596);
        assert_eq!(ZIGGURAT_NOR_R.to_bits(), 0x400D_3BB4_8209_AD33);
        assert_eq!(ZIGGURAT_NOR_INV_R.to_bits(), 0x3FD1_83AA_6C20_E8C1);
    }

    #[test]
    fn table_shape() {
        assert_eq!(KI_DOUBLE[0], 0x000E_F33D_8025_EF6A);
        assert_eq!(KI_DOUBLE[1], 0);
        assert_eq!(FI_DOUBLE[0], 1.0);
        // layer edges x_i = WI[i] * 2^52 increase with i (i >= 1), densities decrease
        for i in 2..256 {
            assert!(WI_DOUBLE[i] > WI_DOUBLE[i - 1], "wi not increasing at {i}");
            assert!(FI_DOUBLE[i] < FI_DOUBLE[i - 1], "fi not decreasing at {i}");
            assert!(KI_DOUBLE[i] < 1 << 52);
        }
        // outermost edge is R, and FI is the density there
        assert_eq!(WI_DOUBLE[255] * 4_503_599_627_370_496.0, ZIGGURAT_NOR_R);
        assert!((FI_DOUBLE[255] - (-0.5 * ZIGGURAT_NOR_R * ZIGGURAT_NOR_R).exp()).abs() < 1e-15);
        for i in 1..255 {
            let xi = WI_DOUBLE[i] * 4_503_599_627_370_496.0;
            assert!(
                (FI_DOUBLE[i] - (-0.5 * xi * xi).exp()).abs() < 1e-12,
                "fi/wi mismatch at {i}"
            );
        }
    }

    #[test]
    fn first_values_match_numpy() {
        let mut bg = Pcg64::from_seed_words(SeedSequence::new(0).pcg64_seed_words());
        assert_eq!(standard_normal(&mut bg), 0.1257302210933933);
        let mut bg = Pcg64::from_seed_words(SeedSequence::new(42).pcg64_seed_words());
        assert_eq!(standard_normal(&mut bg), 0.30471707975443135);
    }

    #[test]
    fn all_paths_reachable_and_moments_sane() {
        let mut bg = Pcg64::from_seed_words(SeedSequence::new(7).pcg64_seed_words());
        let mut counts = [0usize; 5];
        let (mut s1, mut s2) = (0.0, 0.0);
        let n = 400_000;
        for _ in 0..n {
            let v = standard_normal_observed(&mut bg, |p| counts[p as usize] += 1);
            s1 += v;
            s2 += v * v;
        }
        let [fast, wedge_accept, wedge_reject, tail_retry, tail] = counts;
        assert!(fast > n * 98 / 100);
        assert!(
            wedge_accept > 0 && wedge_reject > 0 && tail > 0,
            "{counts:?}"
        );
        let _ = tail_retry; // rare (~1 in 10 tail tries); exercised by the numpy fixture
        let mean = s1 / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.01,
            "mean {mean} var {var}"
        );
    }
}
