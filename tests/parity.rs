//! Replays the reference's recorded trajectories (tests/reference/fixtures, or a live recording in
//! $ENVC_PARITY_DIR) and requires every observation, reward, flag and info value to be
//! bit-identical to Gymnasium 1.4.0 on the MuJoCo envc is built for (`envc::MUJOCO_VERSION`).

use envc_tests::{fixtures_dir, manifest, replay};

#[test]
fn every_recorded_case_is_bit_identical() {
    replay_all(&fixtures_dir());
}

/// The suite recorded under an AVX2-only machine's profile (`openblas-haswell`; OpenBLAS's Haswell
/// kernel, as on AMD Zen 2/3): replayed under that profile on any CPU.
#[test]
fn avx2_recording_is_bit_identical() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/fixtures/avx2");
    assert_eq!(manifest(&dir).numerics, "openblas-haswell");
    replay_all(&dir);
}

fn replay_all(dir: &std::path::Path) {
    let dir = dir.to_path_buf();
    let m = manifest(&dir);
    assert_eq!(
        (m.gymnasium.as_str(), m.mujoco.as_str()),
        ("1.4.0", envc::MUJOCO_VERSION),
        "{} was recorded under another MuJoCo than this build's",
        dir.display()
    );
    assert!(
        m.cases.len() >= 33,
        "expected at least 3 cases per env, found {}",
        m.cases.len()
    );
    let mut failed = vec![];
    let mut steps = 0;
    for case in &m.cases {
        let mm = replay(&dir, m.profile(), case);
        steps += case.steps;
        if mm.count > 0 {
            failed.push(format!(
                "{} ({}): {} mismatches\n    {}",
                case.name,
                case.env_id,
                mm.count,
                mm.lines.join("\n    ")
            ));
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} cases differ from the reference:\n{}",
        failed.len(),
        m.cases.len(),
        failed.join("\n")
    );
    eprintln!(
        "{} cases, {steps} steps: bit-identical to the reference",
        m.cases.len()
    );
}
