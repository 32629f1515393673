//! A bit-exact port of numpy's default random generator,
//! `np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed)))` (numpy 2.x).
//!
//! This is what `np.random.default_rng(seed)` and gymnasium's `seeding.np_random(seed)` return,
//! so environments seeded through [`NumpyRng::from_seed`] draw exactly the numbers the Python
//! reference draws, as long as the calls are made in the same order.
//!
//! Pieces (each in its own module):
//! * [`SeedSequence`] — integer seed → 4 × u64 of PCG64 seed material (pool size 4, hashmix/mix).
//! * PCG64 — 128-bit LCG with XSL-RR output; numpy's one-slot buffer for 32-bit draws.
//! * ziggurat — numpy's 256-layer `standard_normal`, with tables taken from numpy.
//!
//! Call-for-call equivalents:
//!
//! | Rust                          | numpy                                                   |
//! |-------------------------------|---------------------------------------------------------|
//! | `next_u64()`                  | `bit_generator.random_raw()`                            |
//! | `next_u32()`                  | `bit_generator.ctypes.next_uint32(...)` (buffered)      |
//! | `next_f64()`                  | `Generator.random()`                                    |
//! | `uniform(lo, hi)`             | `Generator.uniform(lo, hi)`                             |
//! | `fill_uniform(lo, hi, out)`   | `Generator.uniform(lo, hi, size=out.len())`             |
//! | `standard_normal()`           | `Generator.standard_normal()` (one element of `size=n`) |
//! | `integers(lo, hi)`            | `Generator.integers(lo, hi)` (int64, high exclusive)    |
//!
//! Bit-exactness is checked against vectors recorded from numpy 2.4.6 by
//! `tests/reference/record_rng.py` (see `tests/rng_numpy.rs`). Floating-point code avoids fused
//! multiply-add (Rust never contracts `a * b + c`; do not introduce `mul_add`). The normal
//! sampler's rare wedge/tail branches call `exp`/`log1p` from the platform libm, exactly like
//! numpy does; on a libm that rounds these differently from glibc a result could in principle
//! differ.

mod pcg64;
mod seed_sequence;
mod ziggurat;
mod ziggurat_tables;

pub use seed_sequence::SeedSequence;

use pcg64::Pcg64;

/// numpy `Generator(PCG64(SeedSequence(seed)))`, bit-exact.
///
/// Cloning snapshots the full generator state (including the buffered 32-bit half-word).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NumpyRng {
    bitgen: Pcg64,
}

impl NumpyRng {
    /// `np.random.default_rng(seed)` / gymnasium `seeding.np_random(seed)`.
    pub fn from_seed(seed: u64) -> Self {
        Self::from_seed_u128(u128::from(seed))
    }

    /// Same as [`from_seed`](Self::from_seed) for seeds up to 2^128 − 1 (the seed's 32-bit words
    /// are the `SeedSequence` entropy words, least significant first).
    pub fn from_seed_u128(seed: u128) -> Self {
        Self::from_seed_sequence(&SeedSequence::new(seed))
    }

    /// `Generator(PCG64(seed_seq))` for an explicit [`SeedSequence`].
    pub fn from_seed_sequence(seed_seq: &SeedSequence) -> Self {
        NumpyRng {
            bitgen: Pcg64::from_seed_words(seed_seq.pcg64_seed_words()),
        }
    }

    /// `np.random.default_rng()` / `SeedSequence(None)`: seeded with 128 bits of OS entropy
    /// (`/dev/urandom`, or a hash of std's `RandomState` keys, the time and the process id when
    /// that is unavailable). Never panics. Use [`SeedSequence::from_os_entropy`] +
    /// [`from_seed_sequence`](Self::from_seed_sequence) to also learn the entropy value
    /// (gymnasium's `np_random_seed`).
    pub fn from_entropy() -> Self {
        Self::from_seed_sequence(&SeedSequence::from_os_entropy())
    }

    /// One raw PCG64 output (`next64`).
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.bitgen.next64()
    }

    /// numpy's buffered 32-bit draw: the low half of a new 64-bit output, and on the next call the
    /// saved high half. The saved half survives any number of 64-bit-based draws
    /// (`next_u64`, `next_f64`, `uniform`, `standard_normal`, 64-bit-range `integers`) in between.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.bitgen.next32()
    }

    /// Uniform on [0, 1): `(next_u64() >> 11) * 2^-53` (numpy `Generator.random()`).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        self.bitgen.next_double()
    }

    /// numpy `Generator.uniform(low, high)`: `low + (high - low) * next_f64()`, no FMA.
    ///
    /// # Panics
    /// Like numpy (which raises), if `high - low` is not finite (`OverflowError`) or is negative
    /// (`ValueError`). `low == high` is allowed and returns `low` (still consuming one draw).
    #[inline]
    pub fn uniform(&mut self, low: f64, high: f64) -> f64 {
        let range = checked_range(low, high);
        low + range * self.bitgen.next_double()
    }

    /// numpy `Generator.uniform(low, high, size=out.len())`: `out.len()` draws in order, with
    /// `high - low` computed once. Panics like [`uniform`](Self::uniform) (even if `out` is empty).
    pub fn fill_uniform(&mut self, low: f64, high: f64, out: &mut [f64]) {
        let range = checked_range(low, high);
        for v in out.iter_mut() {
            *v = low + range * self.bitgen.next_double();
        }
    }

    /// numpy `Generator.standard_normal()` (256-layer ziggurat, bit-exact).
    /// `standard_normal(size=n)` is `n` successive calls.
    #[inline]
    pub fn standard_normal(&mut self) -> f64 {
        ziggurat::standard_normal(&mut self.bitgen)
    }

    /// numpy `Generator.integers(low, high)` with the default `int64` dtype: uniform on
    /// `[low, high)`.
    ///
    /// With `span = high - low`: `span == 1` returns `low` **without consuming anything**;
    /// `span < 2^32` uses Lemire's method on buffered 32-bit draws ([`next_u32`](Self::next_u32));
    /// `span == 2^32` returns `low + next_u32()`; larger spans use Lemire's method on 64-bit draws
    /// (128-bit products), which leave the 32-bit buffer alone.
    ///
    /// # Panics
    /// If `low >= high` (numpy raises `ValueError`).
    pub fn integers(&mut self, low: i64, high: i64) -> i64 {
        assert!(
            low < high,
            "NumpyRng::integers: low >= high ({low} >= {high})"
        );
        // numpy works with the closed range [low, high - 1]: `rng` is the inclusive span - 1.
        let rng = (high as i128 - 1 - low as i128) as u64;
        let off = low as u64;
        let v = if rng == 0 {
            0
        } else if rng < 0xffff_ffff {
            u64::from(self.bounded_lemire_u32(rng as u32))
        } else if rng == 0xffff_ffff {
            u64::from(self.bitgen.next32())
        } else {
            // rng == u64::MAX (a 2^64 span) cannot occur with an i64 exclusive `high`.
            self.bounded_lemire_u64(rng)
        };
        off.wrapping_add(v) as i64
    }

    /// Lemire's nearly-divisionless bounded draw on [0, rng] (rng < 2^32 − 1), 32-bit words.
    fn bounded_lemire_u32(&mut self, rng: u32) -> u32 {
        let rng_excl = rng + 1;
        let mut m = u64::from(self.bitgen.next32()) * u64::from(rng_excl);
        let mut leftover = m as u32;
        if leftover < rng_excl {
            let threshold = (u32::MAX - rng) % rng_excl; // (2^32 - n) mod n
            while leftover < threshold {
                m = u64::from(self.bitgen.next32()) * u64::from(rng_excl);
                leftover = m as u32;
            }
        }
        (m >> 32) as u32
    }

    /// Lemire's method on [0, rng] (2^32 − 1 < rng < 2^64 − 1), 64-bit words.
    fn bounded_lemire_u64(&mut self, rng: u64) -> u64 {
        let rng_excl = rng + 1;
        let mut m = u128::from(self.bitgen.next64()) * u128::from(rng_excl);
        let mut leftover = m as u64;
        if leftover < rng_excl {
            let threshold = (u64::MAX - rng) % rng_excl;
            while leftover < threshold {
                m = u128::from(self.bitgen.next64()) * u128::from(rng_excl);
                leftover = m as u64;
            }
        }
        (m >> 64) as u64
    }
}

/// `high - low`, rejected exactly where numpy's `Generator.uniform` raises.
#[inline]
fn checked_range(low: f64, high: f64) -> f64 {
    let range = high - low;
    assert!(
        range.is_finite(),
        "NumpyRng::uniform: high - low range exceeds valid bounds ({low}, {high})"
    );
    assert!(
        range >= 0.0,
        "NumpyRng::uniform: high - low < 0 ({low}, {high})"
    );
    range
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_vectors() {
        let mut r = NumpyRng::from_seed(0);
        assert_eq!(r.clone().next_u64(), 0xa30febcfd9c2825f);
        assert_eq!(r.uniform(-0.1, 0.1), 0.027392337464290872);
        assert_eq!(NumpyRng::from_seed(0).standard_normal(), 0.1257302210933933);
        let mut r = NumpyRng::from_seed(42);
        assert_eq!(r.clone().next_u64(), 0xc621fbcd16d92688);
        assert_eq!(r.uniform(-0.1, 0.1), 0.05479120971119267);
        assert_eq!(
            NumpyRng::from_seed(42).standard_normal(),
            0.30471707975443135
        );
    }

    #[test]
    fn u64_and_u128_seeding_agree() {
        for s in [0u64, 1, 42, u32::MAX as u64 + 6, u64::MAX] {
            assert_eq!(
                NumpyRng::from_seed(s),
                NumpyRng::from_seed_u128(u128::from(s))
            );
        }
    }

    #[test]
    fn integers_span_one_consumes_nothing() {
        let mut a = NumpyRng::from_seed(3);
        let _ = a.next_u32(); // leave a half-word buffered
        let b = a.clone();
        assert_eq!(a.integers(5, 6), 5);
        assert_eq!(a.integers(i64::MIN, i64::MIN + 1), i64::MIN);
        assert_eq!(a, b);
    }

    #[test]
    fn integers_bounds() {
        let mut r = NumpyRng::from_seed(9);
        for _ in 0..2000 {
            let v = r.integers(-3, 4);
            assert!((-3..4).contains(&v));
            let w = r.integers(i64::MIN, i64::MAX);
            assert!(w < i64::MAX);
            let z = r.integers(10, 10 + (1 << 40));
            assert!((10..10 + (1 << 40)).contains(&z));
        }
    }

    #[test]
    fn fill_matches_scalar() {
        let mut a = NumpyRng::from_seed(5);
        let mut b = a.clone();
        let mut out = [0.0; 17];
        a.fill_uniform(-2.0, 3.0, &mut out);
        for v in out {
            assert_eq!(v.to_bits(), b.uniform(-2.0, 3.0).to_bits());
        }
        assert_eq!(a, b);
    }

    #[test]
    #[should_panic(expected = "high - low < 0")]
    fn uniform_rejects_reversed_bounds() {
        NumpyRng::from_seed(0).uniform(1.0, 0.0);
    }

    #[test]
    #[should_panic(expected = "exceeds valid bounds")]
    fn uniform_rejects_nan() {
        NumpyRng::from_seed(0).uniform(f64::NAN, 0.0);
    }

    #[test]
    #[should_panic(expected = "low >= high")]
    fn integers_rejects_empty_range() {
        NumpyRng::from_seed(0).integers(3, 3);
    }

    #[test]
    fn from_entropy_differs() {
        assert_ne!(NumpyRng::from_entropy(), NumpyRng::from_entropy());
    }
}
