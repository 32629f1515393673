//! numpy's `SeedSequence` (the entropy-pool seeder behind `default_rng(seed)`), restricted to the
//! default configuration: pool size 4, no spawn key, 32-bit words.
//!
//! All arithmetic is on `u32` modulo 2^32. The integer entropy is split into 32-bit words,
//! least-significant first (`0` gives one word `[0]`); each word is hashed into the pool, the pool
//! words are cross-mixed, and [`SeedSequence::generate_state_u32`] hashes the pool again to produce
//! output words.

const POOL_SIZE: usize = 4;
const XSHIFT: u32 = 16; // half the word size
const INIT_A: u32 = 0x43b0_d7e5;
const MULT_A: u32 = 0x931e_8875;
const INIT_B: u32 = 0x8b51_f9dd;
const MULT_B: u32 = 0x58f3_8ded;
const MIX_MULT_L: u32 = 0xca01_f9dd;
const MIX_MULT_R: u32 = 0x4973_f715;

/// numpy `SeedSequence(entropy)` for a non-negative integer entropy below 2^128.
///
/// `SeedSequence::new(s).generate_state_u64(4)` is exactly the seed material numpy's `PCG64` uses
/// for `np.random.default_rng(s)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SeedSequence {
    entropy: u128,
    pool: [u32; POOL_SIZE],
}

/// One step of numpy's `hashmix`; `hash_const` is carried across calls.
fn hashmix(value: u32, hash_const: &mut u32) -> u32 {
    let mut v = value ^ *hash_const;
    *hash_const = hash_const.wrapping_mul(MULT_A);
    v = v.wrapping_mul(*hash_const);
    v ^ (v >> XSHIFT)
}

fn mix(x: u32, y: u32) -> u32 {
    let r = MIX_MULT_L
        .wrapping_mul(x)
        .wrapping_sub(MIX_MULT_R.wrapping_mul(y));
    r ^ (r >> XSHIFT)
}

/// Little-endian 32-bit words of `entropy`; `0` gives `[0]`.
fn entropy_words(entropy: u128) -> ([u32; 4], usize) {
    let mut words = [0u32; 4];
    let mut n = 0;
    let mut e = entropy;
    loop {
        words[n] = e as u32;
        n += 1;
        e >>= 32;
        if e == 0 {
            break;
        }
    }
    (words, n)
}

/// The pool after mixing in `words` (numpy's `mix_entropy`). Words beyond the pool size are mixed
/// into every pool entry; this only happens for entropy ≥ 2^128, which the public API cannot
/// express, but the general form is kept (and unit-tested) for fidelity.
pub(crate) fn mix_entropy(words: &[u32]) -> [u32; POOL_SIZE] {
    let mut hash_const = INIT_A;
    let mut pool = [0u32; POOL_SIZE];
    for (i, slot) in pool.iter_mut().enumerate() {
        *slot = hashmix(words.get(i).copied().unwrap_or(0), &mut hash_const);
    }
    for src in 0..POOL_SIZE {
        for dst in 0..POOL_SIZE {
            if src != dst {
                let h = hashmix(pool[src], &mut hash_const);
                pool[dst] = mix(pool[dst], h);
            }
        }
    }
    for &w in words.iter().skip(POOL_SIZE) {
        for slot in pool.iter_mut() {
            let h = hashmix(w, &mut hash_const);
            *slot = mix(*slot, h);
        }
    }
    pool
}

impl SeedSequence {
    /// `SeedSequence(entropy)` for an integer entropy (a gymnasium / numpy seed).
    pub fn new(entropy: u128) -> Self {
        let (words, n) = entropy_words(entropy);
        SeedSequence {
            entropy,
            pool: mix_entropy(&words[..n]),
        }
    }

    /// numpy `SeedSequence([a, b, ...])`: each integer's 32-bit words (least significant first,
    /// `0` is one word `[0]`) concatenated, e.g. `[seed, episode]` for per-episode streams that
    /// depend on nothing else. `entropy()` is then the first integer only.
    pub fn from_ints(values: &[u64]) -> Self {
        let mut words = Vec::with_capacity(2 * values.len());
        for &v in values {
            let (w, n) = entropy_words(u128::from(v));
            words.extend_from_slice(&w[..n]);
        }
        SeedSequence {
            entropy: values.first().map_or(0, |&v| u128::from(v)),
            pool: mix_entropy(&words),
        }
    }

    /// `SeedSequence(None)`: 128 bits of fresh OS entropy (`/dev/urandom`; if unavailable, a hash
    /// of std's randomly keyed `RandomState`, the time and the process id). Never panics.
    pub fn from_os_entropy() -> Self {
        Self::new(os_entropy_u128())
    }

    /// The integer entropy (numpy's `SeedSequence.entropy`; gymnasium's `np_random_seed`).
    pub fn entropy(&self) -> u128 {
        self.entropy
    }

    /// The mixed entropy pool (numpy's `SeedSequence.pool`).
    pub fn pool(&self) -> [u32; POOL_SIZE] {
        self.pool
    }

    /// numpy `generate_state(n, np.uint32)`.
    pub fn generate_state_u32(&self, n: usize) -> Vec<u32> {
        let mut hash_const = INIT_B;
        (0..n)
            .map(|i| {
                let mut v = self.pool[i % POOL_SIZE] ^ hash_const;
                hash_const = hash_const.wrapping_mul(MULT_B);
                v = v.wrapping_mul(hash_const);
                v ^ (v >> XSHIFT)
            })
            .collect()
    }

    /// numpy `generate_state(n, np.uint64)`: `2n` u32 words paired little-endian (low word first).
    pub fn generate_state_u64(&self, n: usize) -> Vec<u64> {
        self.generate_state_u32(2 * n)
            .chunks_exact(2)
            .map(|p| u64::from(p[0]) | (u64::from(p[1]) << 32))
            .collect()
    }

    /// The four words PCG64 is seeded from (`generate_state(4, np.uint64)`), without allocating
    /// (envs reseed inside `reset`, which must not allocate).
    pub(crate) fn pcg64_seed_words(&self) -> [u64; 4] {
        let mut hash_const = INIT_B;
        let mut words = [0u32; 8];
        for (i, w) in words.iter_mut().enumerate() {
            let mut v = self.pool[i % POOL_SIZE] ^ hash_const;
            hash_const = hash_const.wrapping_mul(MULT_B);
            v = v.wrapping_mul(hash_const);
            *w = v ^ (v >> XSHIFT);
        }
        std::array::from_fn(|i| u64::from(words[2 * i]) | (u64::from(words[2 * i + 1]) << 32))
    }
}

/// 128 bits of entropy, as numpy's `SeedSequence(None)` draws with `secrets.randbits(128)`.
///
/// Reads `/dev/urandom`; if that is unavailable, falls back to hashing with std's randomly keyed
/// `RandomState` together with the time, process id, a counter and a stack address. Never panics.
pub(crate) fn os_entropy_u128() -> u128 {
    use std::io::Read;
    let mut buf = [0u8; 16];
    if let Ok(mut f) = std::fs::File::open("/dev/urandom")
        && f.read_exact(&mut buf).is_ok()
    {
        return u128::from_le_bytes(buf);
    }
    fallback_entropy_u128()
}

fn fallback_entropy_u128() -> u128 {
    use std::collections::hash_map::RandomState;
    use std::hash::{BuildHasher, Hash, Hasher};
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);

    let count = COUNTER.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let local = 0u8;
    let addr = &local as *const u8 as usize;
    let half = |tag: u8| {
        // Each RandomState::new() carries fresh random keys (per-thread seeded, then incremented).
        let mut h = RandomState::new().build_hasher();
        tag.hash(&mut h);
        nanos.hash(&mut h);
        count.hash(&mut h);
        std::process::id().hash(&mut h);
        std::thread::current().id().hash(&mut h);
        addr.hash(&mut h);
        h.finish()
    };
    let lo = half(0);
    let hi = half(1);
    (u128::from(hi) << 64) | u128::from(lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `np.random.SeedSequence([a, b])`, values printed by numpy 2.4.6 (multi-word ints too).
    #[test]
    fn integer_lists_match_numpy() {
        for (ints, pool, state) in [
            (
                vec![7u64, 3],
                [3693270713, 2271544259, 605415413, 2511051269],
                [5061563556724077661u64, 9433490490806083541],
            ),
            (
                vec![(1 << 40) + 5, 1 << 33],
                [1523050712, 1071355882, 95162771, 806140555],
                [4444572008089138481, 1397609466882526199],
            ),
        ] {
            let ss = SeedSequence::from_ints(&ints);
            assert_eq!(ss.pool(), pool, "{ints:?}");
            assert_eq!(ss.generate_state_u64(2), state, "{ints:?}");
        }
        // `default_rng([7, 3]).random()`.
        let mut rng = super::super::NumpyRng::from_seed_sequence(&SeedSequence::from_ints(&[7, 3]));
        assert_eq!(rng.next_f64(), 0.9750335537195014);
    }

    #[test]
    fn seed_zero_matches_numpy() {
        let ss = SeedSequence::new(0);
        assert_eq!(ss.pool(), [4265667335, 1328953910, 1320288413, 3365567143]);
        assert_eq!(
            ss.generate_state_u64(4),
            vec![
                0xdb2cd7e7b0f478be,
                0xabf4641a2c71ba49,
                0x20c6ed6d9d7b8d41,
                0x2c4099de223c39d4
            ]
        );
        assert_eq!(ss.entropy(), 0);
        assert_eq!(ss.pcg64_seed_words().to_vec(), ss.generate_state_u64(4));
    }

    #[test]
    fn word_split() {
        assert_eq!(entropy_words(0), ([0, 0, 0, 0], 1));
        assert_eq!(entropy_words(1 << 32), ([0, 1, 0, 0], 2));
        assert_eq!(entropy_words(u128::MAX), ([u32::MAX; 4], 4));
    }

    #[test]
    fn extra_words_beyond_pool() {
        // numpy: SeedSequence(2**160 - 12345).pool (five words, one beyond the pool).
        let e: [u32; 5] = [u32::MAX - 12344, u32::MAX, u32::MAX, u32::MAX, u32::MAX];
        assert_eq!(
            mix_entropy(&e),
            [2136213048, 137817071, 1165637125, 2680757280]
        );
    }

    #[test]
    fn fallback_entropy_varies() {
        assert_ne!(fallback_entropy_u128(), fallback_entropy_u128());
        // and the normal path works here
        let _ = SeedSequence::from_os_entropy();
    }
}
