//! numpy's `PCG64` bit generator: a 128-bit LCG with the XSL-RR 128→64 output function, plus
//! numpy's one-word buffer for 32-bit draws.

/// The 128-bit LCG multiplier (PCG's default for 128-bit state).
const PCG_MULT: u128 = 0x2360_ed05_1fc6_5da4_4385_df64_9fcc_f645;

/// 2^-53, exact.
const TWO_POW_M53: f64 = 1.0 / 9_007_199_254_740_992.0;

#[derive(Clone, Debug)]
pub(crate) struct Pcg64 {
    state: u128,
    inc: u128,
    /// numpy's `has_uint32` / `uinteger`: the unused high half of the last 64-bit output drawn
    /// for a 32-bit request. Like numpy, `uinteger` keeps its stale value once consumed.
    has_uint32: bool,
    uinteger: u32,
}

/// Equal when the generators will produce the same future stream (a consumed, stale `uinteger`
/// is ignored).
impl PartialEq for Pcg64 {
    fn eq(&self, other: &Self) -> bool {
        self.state == other.state
            && self.inc == other.inc
            && self.has_uint32 == other.has_uint32
            && (!self.has_uint32 || self.uinteger == other.uinteger)
    }
}

impl Eq for Pcg64 {}

impl Pcg64 {
    /// numpy `pcg64_set_seed(state, seed=&w[0], inc=&w[2])`, i.e. PCG's `srandom_r(initstate,
    /// initseq)` with `initstate = w0<<64 | w1` and `initseq = w2<<64 | w3`.
    pub(crate) fn from_seed_words(w: [u64; 4]) -> Self {
        let initstate = (u128::from(w[0]) << 64) | u128::from(w[1]);
        let initseq = (u128::from(w[2]) << 64) | u128::from(w[3]);
        let mut rng = Pcg64 {
            state: 0,
            inc: (initseq << 1) | 1,
            has_uint32: false,
            uinteger: 0,
        };
        rng.step();
        rng.state = rng.state.wrapping_add(initstate);
        rng.step();
        rng
    }

    #[inline]
    fn step(&mut self) {
        self.state = self.state.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
    }

    /// `next64`: advance, then output `rotr64(hi ^ lo, state >> 122)` of the new state.
    #[inline]
    pub(crate) fn next64(&mut self) -> u64 {
        self.step();
        let x = ((self.state >> 64) as u64) ^ (self.state as u64);
        x.rotate_right((self.state >> 122) as u32)
    }

    /// `next32`: the low half of a fresh 64-bit output, keeping the high half for the next call.
    /// Only 32-bit requests use the buffer; `next64`/`next_double` leave it alone.
    #[inline]
    pub(crate) fn next32(&mut self) -> u32 {
        if self.has_uint32 {
            self.has_uint32 = false;
            return self.uinteger;
        }
        let next = self.next64();
        self.has_uint32 = true;
        self.uinteger = (next >> 32) as u32;
        next as u32
    }

    /// `next_double`: `(next64 >> 11) * 2^-53`, uniform on [0, 1).
    #[inline]
    pub(crate) fn next_double(&mut self) -> f64 {
        (self.next64() >> 11) as f64 * TWO_POW_M53
    }

    #[cfg(test)]
    pub(crate) fn raw_state(&self) -> (u128, u128, bool, u32) {
        (self.state, self.inc, self.has_uint32, self.uinteger)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SEED0_WORDS: [u64; 4] = [
        0xdb2cd7e7b0f478be,
        0xabf4641a2c71ba49,
        0x20c6ed6d9d7b8d41,
        0x2c4099de223c39d4,
    ];

    #[test]
    fn seeding_matches_numpy_state() {
        // numpy: np.random.PCG64(0).state
        let rng = Pcg64::from_seed_words(SEED0_WORDS);
        assert_eq!(
            rng.raw_state(),
            (
                35399562948360463058890781895381311971,
                87136372517582989555478159403783844777,
                false,
                0
            )
        );
    }

    #[test]
    fn next32_buffers_high_half() {
        let mut a = Pcg64::from_seed_words(SEED0_WORDS);
        let mut b = a.clone();
        let w = b.next64();
        assert_eq!(w, 0xa30febcfd9c2825f);
        assert_eq!(a.next32(), w as u32);
        let _ = a.next_double(); // does not touch the buffer
        let _ = b.next64();
        assert_eq!(a.next32(), (w >> 32) as u32);
        assert_eq!(a, b);
    }
}
