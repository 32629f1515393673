//! The floating-point operations whose exact order decides the last bit, written to match what
//! numpy and OpenBLAS do in the reference (docs/numerics.md). Nothing here may be "simplified":
//! a different association order or a fused multiply-add changes results.
//!
//! Two of them depend on the CPU the reference runs on: OpenBLAS's `ddot` (behind
//! `np.linalg.norm`) and numpy's float64 `exp`. A [`Profile`] names one choice for each; `auto`
//! picks what numpy would on this machine, under the same overrides (`OPENBLAS_CORETYPE`,
//! `NPY_ENABLE_CPU_FEATURES`, `NPY_DISABLE_CPU_FEATURES`). Every profile is computed in portable
//! code, so any machine reproduces any profile. See docs/numerics.md.

pub mod cpu;
mod npy;
pub mod openblas;
mod openblas_gemv;
mod profile;
mod svml_acos;
mod svml_atan2;
mod svml_exp;

pub use openblas::Kernel;

/// The reference envc reproduces, by version: on the MuJoCo this build is for.
#[cfg(not(feature = "mujoco-4.0.1"))]
pub const REFERENCE: &str = "Gymnasium 1.4.0, Gymnasium-Robotics 1.4.2, Minari 0.5.4, numpy 2.4.6 with OpenBLAS 0.3.31 (scipy-openblas, DYNAMIC_ARCH), MuJoCo 3.17.0";
/// The reference envc reproduces, by version: on the MuJoCo this build is for.
#[cfg(feature = "mujoco-4.0.1")]
pub const REFERENCE: &str = "Gymnasium 1.4.0, Gymnasium-Robotics 1.4.2, Minari 0.5.4, numpy 2.4.6 with OpenBLAS 0.3.31 (scipy-openblas, DYNAMIC_ARCH), MuJoCo 4.0.1";
pub use profile::{
    Auto, NpyOverrides, NumericsError, Profile, auto, auto_for, default_profile,
    set_default_profile,
};

/// The float types numpy sums in (float64, and float32 for float32 actions).
pub trait Real: Copy + std::ops::Add<Output = Self> + std::ops::AddAssign {
    /// -0.0, the start of numpy's sums (so that a sum of nothing but -0.0 stays -0.0).
    const NEG_ZERO: Self;
}
impl Real for f64 {
    const NEG_ZERO: f64 = -0.0;
}
impl Real for f32 {
    const NEG_ZERO: f32 = -0.0;
}

/// numpy's pairwise sum of `n` values `f(0..n)` (contiguous, `np.sum` / `.sum()`), in `T`.
///
/// n < 8: sequential from −0.0. 8 ≤ n ≤ 128: eight interleaved accumulators, combined as
/// `((r0+r1)+(r2+r3)) + ((r4+r5)+(r6+r7))`, then the leftovers in order. Larger n: split at
/// `n/2` rounded down to a multiple of 8 and add the halves.
pub fn pairwise_sum<T: Real>(n: usize, f: &dyn Fn(usize) -> T) -> T {
    pairwise(0, n, f)
}

fn pairwise<T: Real>(start: usize, n: usize, f: &dyn Fn(usize) -> T) -> T {
    if n < 8 {
        let mut res = T::NEG_ZERO;
        for i in 0..n {
            res += f(start + i);
        }
        res
    } else if n <= 128 {
        let mut r = [T::NEG_ZERO; 8];
        for (j, r) in r.iter_mut().enumerate() {
            *r = f(start + j);
        }
        let mut i = 8;
        while i < n - n % 8 {
            for (j, r) in r.iter_mut().enumerate() {
                *r += f(start + i + j);
            }
            i += 8;
        }
        let mut res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        while i < n {
            res += f(start + i);
            i += 1;
        }
        res
    } else {
        let mut n2 = n / 2;
        n2 -= n2 % 8;
        pairwise(start, n2, f) + pairwise(start + n2, n - n2, f)
    }
}

/// `np.linalg.norm(v)` for a 1-D float64 vector under `profile`: `sqrt(v.dot(v))`, where numpy
/// squares a single element itself and hands longer vectors to OpenBLAS `ddot` (adding the result
/// to 0.0).
pub fn norm(profile: Profile, n: usize, f: &dyn Fn(usize) -> f64) -> f64 {
    match n {
        0 => 0.0,
        1 => {
            let v = f(0);
            (v * v).sqrt()
        }
        _ => (0.0 + openblas::ddot(profile.blas, n, f, f)).sqrt(),
    }
}

/// `np.dot(a, b)` for two 1-D float64 vectors under `profile` (numpy multiplies single elements
/// itself; longer vectors go to OpenBLAS `ddot`, added to 0.0).
pub fn dot(profile: Profile, n: usize, a: &dyn Fn(usize) -> f64, b: &dyn Fn(usize) -> f64) -> f64 {
    match n {
        0 => 0.0,
        1 => a(0) * b(0),
        _ => 0.0 + openblas::ddot(profile.blas, n, a, b),
    }
}

/// `np.exp(x)` for a float64 under `profile`: SVML's `exp` where numpy's X86_V4 loop runs,
/// glibc's otherwise.
pub fn exp(profile: Profile, x: f64) -> f64 {
    if profile.svml_exp {
        svml_exp::exp(x)
    } else {
        x.exp()
    }
}

/// `np.arctan2(y, x)` for float64 under `profile`: SVML's where numpy's X86_V4 loop runs (the
/// `+svml` profiles), glibc's otherwise.
pub fn atan2(profile: Profile, y: f64, x: f64) -> f64 {
    if profile.svml_exp {
        svml_atan2::atan2(y, x)
    } else {
        y.atan2(x)
    }
}

/// `np.arccos(x)` for float64 under `profile`: SVML's where numpy's X86_V4 loop runs (the
/// `+svml` profiles), glibc's otherwise: under `NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL"`
/// numpy gave glibc's `acos` bits for all 11 million inputs the SVML port was checked on, NaN
/// payloads included.
pub fn acos(profile: Profile, x: f64) -> f64 {
    if profile.svml_exp {
        svml_acos::acos(x)
    } else {
        x.acos()
    }
}

/// numpy's `a @ x` for a C-contiguous float64 `rows × n` matrix and a vector of `n`: OpenBLAS
/// `dgemv` under `profile` (numpy hands matrix-vector products to `cblas_dgemv`).
pub fn matvec(profile: Profile, rows: usize, n: usize, a: &[f64], x: &[f64], y: &mut [f64]) {
    openblas_gemv::dgemv_t(profile.blas, rows, n, a, x, y);
}

/// `x**2` as numpy computes it for a float64 scalar: libm `pow` (the compiler would make
/// `x.powf(2.0)` into `x * x`, which differs in the last bit).
pub fn square_pow(x: f64) -> f64 {
    crate::os::pow(x, std::hint::black_box(2.0))
}

/// `np.clip`: NaN stays NaN (unlike `f64::clamp`, which also panics on bad bounds).
pub fn clip(x: f64, lo: f64, hi: f64) -> f64 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairwise_groups_like_numpy() {
        // With 1e16-scale values, left-to-right and pairwise orders give different results.
        let v = [1e16, 1.0, -1e16, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let s = pairwise_sum(v.len(), &|i| v[i]);
        // r = v[0..8]; leftovers v[8], v[9] added after the tree:
        let tree = ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
        assert_eq!(s, tree + v[8] + v[9]);
        assert_ne!(s, v.iter().sum::<f64>());
    }

    #[test]
    fn small_sums_start_from_negative_zero() {
        assert!(pairwise_sum(0, &|_| 0.0f64).is_sign_negative());
        assert!(pairwise_sum(2, &|_| -0.0f64).is_sign_negative());
    }

    #[test]
    fn clip_keeps_nan() {
        assert!(clip(f64::NAN, -1.0, 1.0).is_nan());
        assert_eq!(clip(3.0, -1.0, 1.0), 1.0);
    }
}
