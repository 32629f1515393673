//! `envc::rng::NumpyRng` must reproduce numpy 2.4.6's
//! `Generator(PCG64(SeedSequence(seed)))` bit-for-bit.
//!
//! The vectors are recorded from real numpy by `tests/reference/record_rng.py` into
//! `tests/reference/fixtures/rng_vectors.json` (u64/i64/seeds as decimal strings, f64 as
//! 16-hex-digit IEEE bit patterns). Every value is compared exactly (`to_bits`).

use std::sync::OnceLock;

use envc::rng::{NumpyRng, SeedSequence};
use serde_json::Value;

const FIXTURE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/reference/fixtures/rng_vectors.json"
);

fn fixture() -> &'static Value {
    static DOC: OnceLock<Value> = OnceLock::new();
    DOC.get_or_init(|| {
        let text = std::fs::read_to_string(FIXTURE).unwrap_or_else(|e| {
            panic!("cannot read {FIXTURE}: {e} (run tests/reference/record_rng.py)")
        });
        let doc: Value = serde_json::from_str(&text).expect("rng_vectors.json is not valid JSON");
        assert_eq!(doc["format"], 1, "unexpected fixture format");
        doc
    })
}

fn seeds() -> &'static [Value] {
    fixture()["seeds"].as_array().expect("seeds array")
}

fn s(v: &Value) -> &str {
    v.as_str()
        .unwrap_or_else(|| panic!("expected a string, got {v}"))
}

fn dec<T: std::str::FromStr>(v: &Value) -> T
where
    T::Err: std::fmt::Debug,
{
    s(v).parse()
        .unwrap_or_else(|e| panic!("bad decimal {v}: {e:?}"))
}

/// f64 from a 16-hex-digit IEEE-754 bit pattern.
fn f(v: &Value) -> f64 {
    f64::from_bits(u64::from_str_radix(s(v), 16).unwrap_or_else(|e| panic!("bad f64 hex {v}: {e}")))
}

fn arr(v: &Value) -> &[Value] {
    v.as_array()
        .unwrap_or_else(|| panic!("expected an array, got {v}"))
}

fn seed_of(entry: &Value) -> u128 {
    dec(&entry["seed"])
}

fn rng_for(entry: &Value) -> NumpyRng {
    let seed = seed_of(entry);
    match u64::try_from(seed) {
        Ok(small) => {
            let r = NumpyRng::from_seed(small);
            assert_eq!(
                r,
                NumpyRng::from_seed_u128(seed),
                "u64 and u128 seeding disagree for {seed}"
            );
            r
        }
        Err(_) => NumpyRng::from_seed_u128(seed),
    }
}

fn assert_bits(got: f64, want: f64, what: &dyn Fn() -> String) {
    assert!(
        got.to_bits() == want.to_bits(),
        "{}: got {got:?} ({:016x}), numpy {want:?} ({:016x})",
        what(),
        got.to_bits(),
        want.to_bits()
    );
}

#[test]
fn fixture_is_from_pinned_numpy() {
    assert_eq!(fixture()["numpy_version"], "2.4.6");
    assert!(seeds().len() >= 10);
}

#[test]
fn seed_sequence_state_words() {
    // numpy's `SeedSequence(0).generate_state(4, np.uint64)`.
    assert_eq!(
        SeedSequence::new(0).generate_state_u64(4),
        [
            0xdb2cd7e7b0f478be,
            0xabf4641a2c71ba49,
            0x20c6ed6d9d7b8d41,
            0x2c4099de223c39d4
        ]
    );
    let mut n = 0;
    for e in seeds() {
        let seed = seed_of(e);
        let ss = SeedSequence::new(seed);
        assert_eq!(ss.entropy(), seed);
        let rec = &e["seed_sequence"];
        let pool: Vec<u32> = arr(&rec["pool_u32"]).iter().map(dec).collect();
        assert_eq!(ss.pool().to_vec(), pool, "pool, seed {seed}");
        let words: Vec<u64> = arr(&rec["state_u64"])
            .iter()
            .map(|w| u64::from_str_radix(s(w), 16).unwrap())
            .collect();
        assert_eq!(
            ss.generate_state_u64(4),
            words,
            "generate_state(4, uint64), seed {seed}"
        );
        let words32: Vec<u32> = arr(&rec["state_u32_10"]).iter().map(dec).collect();
        assert_eq!(
            ss.generate_state_u32(10),
            words32,
            "generate_state(10, uint32), seed {seed}"
        );
        assert_eq!(
            NumpyRng::from_seed_sequence(&ss),
            NumpyRng::from_seed_u128(seed)
        );
        n += pool.len() + words.len() + words32.len();
    }
    eprintln!(
        "seed_sequence: {n} words checked over {} seeds",
        seeds().len()
    );
}

#[test]
fn next_u64_first_20() {
    let mut n = 0;
    for e in seeds() {
        let mut r = rng_for(e);
        for (i, w) in arr(&e["next64"]).iter().enumerate() {
            assert_eq!(
                r.next_u64(),
                dec::<u64>(w),
                "next64 #{i}, seed {}",
                seed_of(e)
            );
            n += 1;
        }
    }
    eprintln!("next_u64: {n} values checked");
}

#[test]
fn uniform_scalar_calls() {
    let mut n = 0;
    for e in seeds() {
        let mut r = rng_for(e);
        let values = arr(&e["uniform_m01_p01"]);
        assert_eq!(values.len(), 1000);
        for (i, v) in values.iter().enumerate() {
            assert_bits(r.uniform(-0.1, 0.1), f(v), &|| {
                format!("uniform(-0.1, 0.1) #{i}, seed {}", seed_of(e))
            });
            n += 1;
        }
    }
    eprintln!("uniform(-0.1, 0.1): {n} values checked");
}

#[test]
fn uniform_fill_blocks() {
    let mut n = 0;
    for e in seeds() {
        // One generator; consecutive `uniform(low, high, size=25)` blocks with different bounds.
        let mut r = rng_for(e);
        for (b, block) in arr(&e["uniform_blocks"]).iter().enumerate() {
            let (low, high) = (f(&block["low"]), f(&block["high"]));
            let want = arr(&block["values"]);
            let mut out = vec![0.0; want.len()];
            r.fill_uniform(low, high, &mut out);
            for (i, (got, w)) in out.iter().zip(want).enumerate() {
                assert_bits(*got, f(w), &|| {
                    format!(
                        "uniform({low:?}, {high:?}, size) block {b} #{i}, seed {}",
                        seed_of(e)
                    )
                });
                n += 1;
            }
        }
    }
    eprintln!("fill_uniform: {n} values checked");
}

#[test]
fn standard_normal_values() {
    let mut n = 0;
    let (mut tail, mut fi_reject, mut tail_retry) = (0, 0, 0);
    for e in seeds() {
        let mut r = rng_for(e);
        let rec = &e["standard_normal"];
        for (i, v) in arr(&rec["values"]).iter().enumerate() {
            assert_bits(r.standard_normal(), f(v), &|| {
                format!("standard_normal #{i}, seed {}", seed_of(e))
            });
            n += 1;
        }
        tail += rec["paths"]["tail"].as_u64().unwrap();
        fi_reject += rec["paths"]["fi_reject"].as_u64().unwrap();
        tail_retry += rec["paths"]["tail_retries"].as_u64().unwrap();
    }
    // The recorder classifies each recorded draw; the vectors must exercise the rare branches.
    assert!(
        tail > 0,
        "fixture never reaches the ziggurat tail (idx == 0)"
    );
    assert!(
        fi_reject > 0,
        "fixture never rejects in the wedge (fi) test"
    );
    eprintln!(
        "standard_normal: {n} values checked ({tail} tail, {tail_retry} tail retries, \
         {fi_reject} wedge rejections)"
    );
}

/// FNV-1a over 64-bit words, as record_rng.py's `fnv1a64_words`.
fn fnv1a64(h: u64, word: u64) -> u64 {
    (h ^ word).wrapping_mul(0x0000_0100_0000_01b3)
}

#[test]
fn standard_normal_bulk_digest() {
    let mut n = 0u64;
    for e in seeds() {
        let rec = &e["standard_normal_digest"];
        let count = rec["count"].as_u64().unwrap();
        let want = u64::from_str_radix(s(&rec["fnv1a64_of_bits"]), 16).unwrap();
        let mut r = rng_for(e);
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        let mut last = 0.0;
        for _ in 0..count {
            last = r.standard_normal();
            h = fnv1a64(h, last.to_bits());
        }
        assert_bits(last, f(&rec["last"]), &|| {
            format!("last of {count} normals, seed {}", seed_of(e))
        });
        assert_eq!(h, want, "digest of {count} normals, seed {}", seed_of(e));
        n += count;
    }
    eprintln!("standard_normal: {n} values checked by digest");
}

#[test]
fn interleaved_integers_uniform_raw() {
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    for e in seeds() {
        let seed = seed_of(e);
        let mut r = rng_for(e);
        for (i, op) in arr(&e["ops"]).iter().enumerate() {
            let op = arr(op);
            let kind = s(&op[0]);
            let ctx = || format!("op #{i} {op:?}, seed {seed}");
            match kind {
                "int" => {
                    let (low, high, want): (i64, i64, i64) =
                        (dec(&op[1]), dec(&op[2]), dec(&op[3]));
                    assert_eq!(r.integers(low, high), want, "{}", ctx());
                }
                "uniform" => assert_bits(r.uniform(f(&op[1]), f(&op[2])), f(&op[3]), &ctx),
                "u32" => assert_eq!(r.next_u32(), dec::<u32>(&op[1]), "{}", ctx()),
                "u64" => assert_eq!(r.next_u64(), dec::<u64>(&op[1]), "{}", ctx()),
                "f64" => assert_bits(r.next_f64(), f(&op[1]), &ctx),
                "normal" => assert_bits(r.standard_normal(), f(&op[1]), &ctx),
                other => panic!("unknown op {other:?}"),
            }
            *counts.entry(kind).or_default() += 1;
        }
    }
    let cov = &fixture()["coverage"];
    for key in [
        "int_no_draw",
        "int32_rejections",
        "int_span_2pow32",
        "int64_calls",
        "int64_rejections",
        "uniform_with_pending_u32",
    ] {
        assert!(cov[key].as_u64().unwrap() > 0, "fixture coverage: no {key}");
    }
    eprintln!("interleaved ops checked: {counts:?}; recorder coverage: {cov}");
}
