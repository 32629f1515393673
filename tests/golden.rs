//! Golden values of Gymnasium 1.4.0 on MuJoCo 3.17.0, the same as the `GOLDEN` table of
//! `tests/reference/record.py`, which checks them against the live Gymnasium before every
//! recording and alone with `record.py --verify-golden` (protocol: tests/reference/README.md,
//! "Golden check"): `reset(seed=0)`, then up to 50 steps with the float32 action
//! `a_t[i] = float32(k) · high[i]`, `k = ((t + i) % 5 − 2) / 2`, stopping at the episode end.

use envc::Env;
use sha2::{Digest, Sha256};

/// First 16 hex digits of SHA-256 of the observation as little-endian float64 bytes.
fn sha(obs: &[f64]) -> String {
    let mut h = Sha256::new();
    for x in obs {
        h.update(x.to_le_bytes());
    }
    h.finalize()
        .iter()
        .take(8)
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// (id, sha(obs0), obs0[0], reward at t=0, steps, Σ reward, sha(last obs), terminated)
type Row = (
    &'static str,
    &'static str,
    f64,
    f64,
    usize,
    f64,
    &'static str,
    bool,
);

/// The `GOLDEN` table of `tests/reference/record.py`.
const GOLDEN: [Row; 11] = [
    (
        "Ant-v5",
        "6d2a57d259c8e2f3",
        0.658194704787239,
        -0.5333905414870339,
        50,
        -44.73110757129683,
        "2e156614fb3cf0bf",
        false,
    ),
    (
        "HalfCheetah-v5",
        "3893de29648ab677",
        -0.04604265724722594,
        -0.5318076279428017,
        50,
        -126.27466179588382,
        "df9290393c4bd624",
        false,
    ),
    (
        "Hopper-v5",
        "1615db91f7b6b239",
        1.2476978671376386,
        0.9367581717518246,
        19,
        17.31894978108758,
        "8e0d6c280f122bed",
        true,
    ),
    (
        "Humanoid-v5",
        "dc7485050d99c1bc",
        1.3908194704787238,
        4.862387432048007,
        21,
        98.05816604618224,
        "2dbb63226a2faded",
        true,
    ),
    (
        "HumanoidStandup-v5",
        "6c12e6770c9961f6",
        0.09581947047872388,
        34.29042761970081,
        50,
        1659.5917779894419,
        "23f116aff42fbeec",
        false,
    ),
    (
        "InvertedPendulum-v5",
        "3de12464dc6de755",
        0.002739233746429086,
        1.0,
        3,
        2.0,
        "c179c057b6a752a4",
        true,
    ),
    (
        "InvertedDoublePendulum-v5",
        "2e0c1497986bc784",
        0.027392337464290872,
        9.173176903084205,
        4,
        25.939897954833167,
        "255abcc72fc45f02",
        true,
    ),
    (
        "Pusher-v5",
        "a30963a131ed2732",
        0.0,
        -2.190607158475637,
        50,
        -106.2999013731421,
        "366e055642952e62",
        false,
    ),
    (
        "Reacher-v5",
        "481ca8999b42fe37",
        0.9996248533822988,
        -1.4454819905766316,
        50,
        -64.33549595828254,
        "cbfa2c0b195a1e0d",
        false,
    ),
    (
        "Swimmer-v5",
        "b8c8bad02202fb41",
        -0.09180529521276107,
        0.030093296518804918,
        50,
        3.045338518969584,
        "deae885f913e30c3",
        false,
    ),
    (
        "Walker2d-v5",
        "7c7c18cf80e39d30",
        1.2476978671376386,
        0.859785999095982,
        35,
        6.316525015706321,
        "f425072e66c0de57",
        true,
    ),
];

#[test]
fn golden_table_of_the_reference_doc() {
    // The table was recorded on an AVX-512 Intel Xeon: its numerics profile, forced so the table
    // holds on every CPU and under every OPENBLAS_CORETYPE.
    let recorded = envc::numerics::Profile::parse("openblas-skylakex+svml").unwrap();
    for row in GOLDEN {
        check_row(row, recorded);
    }
}

/// One env of the table replayed under the recorded profile.
fn check_row(row: Row, recorded: envc::numerics::Profile) {
    let (id, sha0, obs00, r0, steps, total, sha_last, term) = row;
    let mut env = Env::make(id, &[]).unwrap();
    env.set_numerics(recorded);
    let high: Vec<f32> = env.action_space().high.iter().map(|&h| h as f32).collect();
    let obs0 = env.reset(Some(0)).0.to_vec();
    assert_eq!(sha(&obs0), sha0, "{id} sha(obs0)");
    assert_eq!(obs0[0].to_bits(), obs00.to_bits(), "{id} obs0[0]");
    let (mut sum, mut n, mut first, mut last, mut ended) = (0.0f64, 0, f64::NAN, vec![], false);
    for t in 0..50 {
        let a: Vec<f32> = (0..high.len())
            .map(|i| (((t + i) % 5) as f32 - 2.0) / 2.0 * high[i])
            .collect();
        let s = env.step_f32(&a).unwrap();
        if t == 0 {
            first = s.reward;
        }
        sum += s.reward;
        n += 1;
        last = s.obs.to_vec();
        ended = s.terminated;
        if s.terminated || s.truncated {
            break;
        }
    }
    assert_eq!(
        first.to_bits(),
        r0.to_bits(),
        "{id} reward at t=0: {first:?} vs {r0:?}"
    );
    assert_eq!(n, steps, "{id} steps");
    assert_eq!(
        sum.to_bits(),
        total.to_bits(),
        "{id} sum of rewards: {sum:?} vs {total:?}"
    );
    assert_eq!(sha(&last), sha_last, "{id} sha(last obs)");
    assert_eq!(ended, term, "{id} terminated");
}

#[test]
fn float32_actions_make_float32_control_costs() {
    // Trap T3: with a float32 action numpy computes Ant's ctrl cost in float32.
    let mut env = Env::make("Ant-v5", &[]).unwrap();
    env.reset(Some(0));
    let a = [0.3f32, -0.7, 0.1, 0.9, -0.2, 0.5, -0.6, 0.05];
    let c32 = env
        .step_f32(&a)
        .unwrap()
        .info
        .scalar("reward_ctrl")
        .unwrap();
    assert_eq!(c32, (c32 as f32) as f64, "a float32 number");
    env.reset(Some(0));
    let a64: Vec<f64> = a.iter().map(|&x| x as f64).collect();
    let c64 = env.step(&a64).unwrap().info.scalar("reward_ctrl").unwrap();
    assert_ne!(c32, c64, "float64 actions give the float64 cost");
    assert!((c32 - c64).abs() < 1e-6);
}
