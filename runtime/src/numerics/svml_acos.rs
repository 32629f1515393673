//! `np.arccos(x)` for float64 as numpy 2.4 computes it where its X86_V4 (AVX-512) loop runs:
//! `DOUBLE_arccos_X86_V4` calls Intel SVML's `__svml_acos8_ha` there (the high-accuracy variant;
//! `__svml_acos8` is linked but unused), which differs from glibc's `acos` (Rust's `f64::acos`)
//! in the last bit for about 9.4 % of inputs uniform in [-1, 1] (`acos(0.5)` among them). This
//! computes the same way, one lane at a time:
//!
//! - |x| ≤ 1, with `Y = (1 − |x|)/2` (one fused multiply-add) and `z = min(x², Y)`:
//!   - `z = x²` (|x| < ½): `π/2 − x − x·z·P(z)`, π/2 as hi + lo.
//!   - `z = Y` (|x| ≥ ½): `acos|x| = 2·asin(√Y)`, with `√(4Y) ≈ S − corr`: `S = 2Y·r` from the
//!     hardware estimate `r = vrsqrt14pd(Y)` (taken as 0 for Y < 2^-255, i.e. at |x| = 1), and
//!     `corr` a degree-4 polynomial in `e = 2Y·r² − 2` less the fused remainder of `S`. Then
//!     `S + ((S − corr)·z·P(z) − corr)`, and `π − ·` for x < 0.
//!
//!   P is one degree-11 polynomial in an Estrin-like order. `vrsqrt14pd` is emulated bit for bit
//!   (`rsqrt14`): on the reference CPU (AMD EPYC Zen 4, AVX-512) its result depends only on the
//!   exponent's parity and the top 15 fraction bits, and is a 2 × 32-piece linear interpolation
//!   cut to 17 bits (exact only for powers of 4), checked against the instruction on 1 179 648
//!   arguments covering all 2^16 cases at nine exponents and 20 000 000 random ones. The last
//!   bits do depend on it: `1/√Y` cut to 17 bits instead changes 3 787 of the 11 million results
//!   below, so a CPU whose `vrsqrt14pd` differs (Intel's might) would differ from this as rarely.
//! - NaN: the vector path carries it, quieted with its payload, but with its sign flipped (the
//!   code works on `x | sign` and flips by the sign of x at the end).
//! - |x| > 1 and infinities: SVML's scalar callout `__svml_dacos_ha_cout_rare_internal`, which
//!   for these returns `0/0` (or `x/x`): the negative default NaN. Its full scalar acos is never
//!   reached from the vector code.
//!
//! Checked against numpy 2.4.6 on 2 × 11 010 263 inputs (two seeds; uniform in [-1, 1] and in
//! ±[½, 1], near ±1 at every scale, `1 − 2^-k` and 50 ulps either side for every k, log-uniform
//! magnitudes down to subnormals, near ±½ where the paths meet, random bit patterns over all
//! doubles and over |x| < 1, 31 specials): all bit-identical, NaN payloads included. numpy takes
//! this path for scalars, any length, alignment or positive stride; with a negative-stride input
//! and a positive-stride output (`np.arccos(x[::-1])`) its loop calls glibc's `acos` instead, as
//! it does everywhere without X86_V4 (see `npy`).

const SIGN: u64 = 0x8000_0000_0000_0000;
const fn f(bits: u64) -> f64 {
    f64::from_bits(bits)
}

/// `np.arccos(x)` for float64 (see the module doc).
pub fn acos(x: f64) -> f64 {
    if x.is_nan() {
        // The vector code carries `x | sign`, quieted; its final sign fix-up flips that.
        return f((x.to_bits() ^ SIGN) | 0x0008_0000_0000_0000);
    }
    if x.abs() > 1.0 {
        return f(0xfff8_0000_0000_0000); // the callout's 0/0
    }
    main_path(x)
}

const PI: (f64, f64) = (f(0x400921fb54442d18), f(0x3ca1a62633145c07));
const PI_2: (f64, f64) = (f(0x3ff921fb54442d18), f(0x3c91a62633145c07));
/// The correction polynomial for √: terms of e⁴, e³, e², e.
const SQ: [f64; 4] = [
    f(0xbf918000993b24c3),
    f(0x3fa400006f70d42d),
    f(0xbfb7fffffffffe97),
    f(0x3fcfffffffffff9d),
];
/// P's coefficients, highest degree (z¹¹) first.
const P: [f64; 12] = [
    f(0x3fa07520c70eb909),
    f(0xbf90fb17f7dbb0ed),
    f(0x3f943f44bfbc3bae),
    f(0x3f7a583395d45ed5),
    f(0x3f88f8dc2afccad6),
    f(0x3f8c6dbbcb88bd57),
    f(0x3f91c6dcf538ad2e),
    f(0x3f96e89cebdefadd),
    f(0x3f9f1c72e13ad8be),
    f(0x3fa6db6db3b445f8),
    f(0x3fb333333337e0de),
    f(0x3fc555555555529c),
];

/// `z·P(z)`, in SVML's order.
fn poly(z: f64) -> f64 {
    let a0 = P[2].mul_add(z, P[3]);
    let a1 = P[0].mul_add(z, P[1]);
    let a2 = P[8].mul_add(z, P[9]);
    let z2 = z * z;
    let a3 = P[4].mul_add(z, P[5]);
    let a1 = z2.mul_add(a1, a0);
    let z4 = z2 * z2;
    let a4 = P[6].mul_add(z, P[7]);
    let a3 = z2.mul_add(a3, a4);
    let a1 = z4.mul_add(a1, a3);
    let a1 = z2.mul_add(a1, a2);
    let a1 = z.mul_add(a1, P[10]);
    let a1 = z.mul_add(a1, P[11]);
    a1 * z
}

/// √(4y) as (S, corr) with √(4y) ≈ S − corr.
fn sqrt4(y: f64) -> (f64, f64) {
    let r = if y < f(0x3000_0000_0000_0000) {
        0.0
    } else {
        rsqrt14(y)
    };
    let two_y = y + y;
    let rr = r * r;
    let s = two_y * r;
    let e = rr.mul_add(two_y, -2.0);
    let s_lo = r.mul_add(two_y, -s);
    let mut c = SQ[0].mul_add(e, SQ[1]);
    let se = s * e;
    c = e.mul_add(c, SQ[2]);
    c = e.mul_add(c, SQ[3]);
    (s, se.mul_add(c, -s_lo))
}

fn main_path(x: f64) -> f64 {
    let sx = x.to_bits() & SIGN;
    let nx = f(x.to_bits() | SIGN); // −|x|
    let y = 0.5f64.mul_add(nx, 0.5);
    let xx = nx * nx;
    let z = if xx < y { xx } else { y };
    let sqrt_path = z >= y;
    let (s, corr) = sqrt4(y);
    let p = poly(z);
    let (hi, lo, base, corr) = if sqrt_path {
        // π for x < 0 (z ≥ x holds exactly there), nothing otherwise.
        let (hi, lo) = if z >= x { PI } else { (0.0, 0.0) };
        (hi, lo, s, corr)
    } else {
        (PI_2.0, PI_2.1, nx, 0.0)
    };
    let lo = f(lo.to_bits() ^ sx) - corr;
    let t = base - corr;
    let res = t.mul_add(p, lo) + base;
    f(res.to_bits() ^ sx) + hi
}

/// `vrsqrt14pd` as this CPU computes it for a positive normal `y`: exact for powers of 4,
/// otherwise `q·2^-17·2^-⌊E/2⌋` with `q = ⌊(A_j − K_j·t) / 2^10⌋`, where E is the unbiased
/// exponent of `y`, and its parity, the top 5 fraction bits (`j`) and the next 10 (`t`) pick the
/// piece.
fn rsqrt14(y: f64) -> f64 {
    let bits = y.to_bits();
    let e = (bits >> 52) as i64 - 1023; // sign is clear
    let m = bits & ((1 << 52) - 1);
    let half = e.div_euclid(2);
    let odd = e.rem_euclid(2) as usize;
    if m == 0 && odd == 0 {
        return f(((1023 - half) as u64) << 52);
    }
    let i = (m >> 37) as usize;
    let (a, k) = RSQRT14[odd * 32 + (i >> 10)];
    let q = (a - k * (i as u64 & 1023)) >> 10; // in [2^16, 2^17)
    f((((1022 - half) as u64) << 52) | ((q - (1 << 16)) << 36))
}

/// (A_j, K_j) of `rsqrt14`, even exponents then odd, fitted to all 2^16 cases of the
/// instruction.
const RSQRT14: [(u64, u64); 64] = [
    (134211840, 2002),
    (132161792, 1910),
    (130204928, 1830),
    (128332288, 1754),
    (126537216, 1682),
    (124815104, 1614),
    (123161856, 1550),
    (121573632, 1494),
    (120044032, 1438),
    (118571264, 1386),
    (117151488, 1338),
    (115782656, 1294),
    (114459136, 1250),
    (113179136, 1206),
    (111943424, 1170),
    (110746368, 1134),
    (109586176, 1098),
    (108462848, 1066),
    (107372288, 1034),
    (106313728, 1002),
    (105286912, 974),
    (104289024, 946),
    (103319552, 922),
    (102376192, 898),
    (101457664, 874),
    (100563712, 850),
    (99694080, 830),
    (98844160, 806),
    (98017024, 786),
    (97211904, 770),
    (96423680, 750),
    (95656448, 734),
    (94901504, 1414),
    (93452544, 1350),
    (92068864, 1294),
    (90743808, 1238),
    (89476096, 1190),
    (88258304, 1142),
    (87089408, 1098),
    (85965056, 1054),
    (84884736, 1018),
    (83843840, 982),
    (82838784, 946),
    (81870080, 914),
    (80934144, 882),
    (80030208, 854),
    (79155456, 826),
    (78310144, 802),
    (77489920, 778),
    (76694272, 754),
    (75923200, 730),
    (75176192, 710),
    (74449664, 690),
    (73743872, 670),
    (73057280, 650),
    (72390656, 634),
    (71741952, 618),
    (71109888, 602),
    (70493952, 586),
    (69893632, 570),
    (69309696, 558),
    (68738304, 542),
    (68182016, 530),
    (67638784, 518),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// (x, np.arccos(x)) as bit patterns, from numpy 2.4.6's SVML loop: both paths and signs,
    /// the edges, |x| > 1, infinities, NaN.
    const CASES: [(u64, u64); 25] = [
        (0x3fdde64acf7c0c08, 0x3ff15aeae36cc806), // acos(0.4671809221474068) (glibc differs)
        (0x3fd8afb5aa41b50c, 0x3ff2cbfea710275e), // acos(0.3857244646704465) (glibc differs)
        (0xbfdc8ed43b099be0, 0x40004442e014641e), // acos(-0.44621759190925836) (glibc differs)
        (0xbfdeb52078190804, 0x400091e073ea560e), // acos(-0.4798051045255536) (glibc differs)
        (0x3fed8bca9d2ff14c, 0x3fd93a2275423bbc), // acos(0.9233143873275735) (glibc differs)
        (0x3fe359ef35e389b8, 0x3fed7be05718c97c), // acos(0.60472832226906) (glibc differs)
        (0xbfe6c616c27dc4fa, 0x4002e6c6f8f0ece0), // acos(-0.7116807745607325) (glibc differs)
        (0xbfe2fa96dec626f8, 0x4001a53f3dc7070a), // acos(-0.5930895186477008) (glibc differs)
        (0x3fefffffd04d01fb, 0x3f3ba0370a75131d), // acos(0.9999999111533379) (glibc differs)
        (0x3fe0000000000000, 0x3ff0c152382d7365), // acos(0.5) (glibc differs)
        (0xbfe0000000000000, 0x4000c152382d7366), // acos(-0.5)
        (0x3fe097dae8acd43e, 0x3ff06917979d1e6e), // needs the exact vrsqrt14pd (1/√Y cut to 17 bits gives ...e6d)
        (0x0000000000000000, 0x3ff921fb54442d18), // acos(0.0)
        (0x8000000000000000, 0x3ff921fb54442d18), // acos(-0.0)
        (0x0000000000000001, 0x3ff921fb54442d18), // acos(5e-324)
        (0x3ff0000000000000, 0x0000000000000000), // acos(1.0)
        (0xbff0000000000000, 0x400921fb54442d18), // acos(-1.0)
        (0x3fefffffffffffff, 0x3e50000000000000), // acos(1 - 2^-53)
        (0xbfefffffffffffff, 0x400921fb52442d18), // acos(-1 + 2^-53)
        (0x3ff0000000000001, 0xfff8000000000000), // acos(1 + 2^-52): the callout's NaN
        (0x4000000000000000, 0xfff8000000000000), // acos(2.0)
        (0xfff0000000000000, 0xfff8000000000000), // acos(-inf)
        (0x7ff8000000000000, 0xfff8000000000000), // acos(nan): sign flipped
        (0x7ff4000000000123, 0xfffc000000000123), // signalling NaN: quieted, payload kept
        (0xfff8000000abcdef, 0x7ff8000000abcdef), // negative NaN comes back positive
    ];

    #[test]
    fn matches_numpy_svml() {
        for (x, want) in CASES {
            let got = acos(f64::from_bits(x)).to_bits();
            assert_eq!(got, want, "acos({x:#018x})");
        }
    }

    #[test]
    fn rsqrt14_matches_the_instruction() {
        // Values read off `vrsqrt14pd` on the reference CPU.
        assert_eq!(rsqrt14(1.0), 1.0);
        assert_eq!(rsqrt14(4.0), 0.5);
        assert_eq!(rsqrt14(2.0).to_bits(), 0x3fe6a05000000000);
        assert_eq!(rsqrt14(f(0x3ff0000000000001)).to_bits(), 0x3fefffa000000000);
        assert_eq!(rsqrt14(f(0x3fe8000000000000)).to_bits(), 0x3ff2799000000000);
        assert_eq!(rsqrt14(f(0x3370000000000001)).to_bits(), 0x462fffa000000000);
    }
}
