//! `np.exp` for float64 as numpy 2.4 computes it where its X86_V4 (AVX-512) loop runs: numpy calls Intel SVML's `__svml_exp8_ha` there, which differs from
//! glibc's `exp` (Rust's `f64::exp`) in the last bit for about 5 % of inputs. The maze's dense
//! reward `exp(-d)` must match it, so this computes the same way, one lane at a time:
//! `N = x·log2(e)` rounded down to a multiple of 1/16, `r = x − N·ln2` (two fused steps), a
//! degree-6 polynomial for `exp(r) − 1` plus the table correction `Tlr`, times the table value
//! `Th = 2^frac(N)`, scaled by `2^floor(N)`. Checked against numpy on 300 000 inputs (all equal).
//! Inputs with `|x| ≥ 707.70…` (SVML's slow path: overflow, underflow, subnormal results) and NaN
//! use glibc's `exp`; `exp(-d)` for a maze distance never gets there. Elsewhere numpy itself uses
//! glibc's `exp` (see `npy`).

/// 2^(j/16), j = 0..16, as bit patterns.
const TH: [u64; 16] = [
    0x3ff0000000000000,
    0x3ff0b5586cf9890f,
    0x3ff172b83c7d517b,
    0x3ff2387a6e756238,
    0x3ff306fe0a31b715,
    0x3ff3dea64c123422,
    0x3ff4bfdad5362a27,
    0x3ff5ab07dd485429,
    0x3ff6a09e667f3bcd,
    0x3ff7a11473eb0187,
    0x3ff8ace5422aa0db,
    0x3ff9c49182a3f090,
    0x3ffae89f995ad3ad,
    0x3ffc199bdd85529c,
    0x3ffd5818dcfba487,
    0x3ffea4afa2a490da,
];
/// The relative rest of 2^(j/16) beyond `TH[j]`.
const TLR: [u64; 16] = [
    0x0,
    0x3c979aa65d837b6d,
    0xbc801b15eaa59348,
    0x3c968efde3a8a894,
    0x3c834d754db0abb6,
    0x3c859f48a72a4c6d,
    0x3c7690cebb7aafb0,
    0x3c9063e1e21c5409,
    0xbc93b3efbf5e2228,
    0xbc7b32dcb94da51d,
    0x3c8db72fc1f0eab4,
    0x3c71affc2b91ce27,
    0x3c8c1a7792cb3387,
    0x3c736eae30af0cb3,
    0x3c74a385a63d07a7,
    0xbc8ff7128fd391f0,
];
const LOG2E: f64 = f64::from_bits(0x3ff71547652b82fe);
const LN2_HI: f64 = f64::from_bits(0x3fe62e42fefa39ef);
const LN2_LO: f64 = f64::from_bits(0x3c7abc9e3b39803f);
const C1: f64 = f64::from_bits(0x3fefffffffffff70);
const C2: f64 = f64::from_bits(0x3fe000000000d008);
const C3: f64 = f64::from_bits(0x3fc5555553939732);
const C4: f64 = f64::from_bits(0x3fa55557242d68fe);
const C5: f64 = f64::from_bits(0x3f81101cbbc265c0);
const C6: f64 = f64::from_bits(0x3f57411836940c04);
const SLOW: f64 = f64::from_bits(0x40861da04cbafe44);

/// `np.exp(x)` for a float64 (see the module doc).
pub fn exp(x: f64) -> f64 {
    if x.is_nan() || x.abs() >= SLOW {
        return x.exp();
    }
    // N = x·log2(e) rounded down to a multiple of 1/16 (SVML adds 1.5·2^48 + 1023 with a
    // round-toward-zero FMA; that sum is positive, so this is the floor of the exact product).
    let p = x * LOG2E;
    let e = x.mul_add(LOG2E, -p); // p + e == x·log2(e) exactly
    let mut n = (p * 16.0).floor() / 16.0;
    if n == p && e < 0.0 {
        n -= 1.0 / 16.0;
    }
    let j = ((n * 16.0) as i64).rem_euclid(16) as usize;
    let r = (-n).mul_add(LN2_HI, x);
    let r = (-n).mul_add(LN2_LO, r);
    let r2 = r * r;
    let p56 = C6.mul_add(r, C5);
    let p34 = C4.mul_add(r, C3);
    let p12 = C2.mul_add(r, C1);
    let p36 = r2.mul_add(p56, p34);
    let p16 = r2.mul_add(p36, p12);
    let q = p16.mul_add(r, f64::from_bits(TLR[j]));
    let th = f64::from_bits(TH[j]);
    let res = th.mul_add(q, th);
    // scalef: × 2^floor(N); exact, as the result is normal on this path.
    res * f64::from_bits(((n.floor() as i64 + 1023) as u64) << 52)
}
