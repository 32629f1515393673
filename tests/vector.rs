//! Vectorized envs: replays Gymnasium 1.4.0 `make_vec(..., vectorization_mode="sync")` recordings
//! (tests/reference/record_vector.py; both autoreset modes) bit for bit, and checks that the batch
//! buffers do not depend on the number of threads or on the order in which threads finish.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::PathBuf;

use envc::{Autoreset, Override, VecEnv};
use ndarray::{ArrayD, Axis};
use ndarray_npy::NpzReader;
use serde::Deserialize;

#[derive(Deserialize)]
struct Manifest {
    gymnasium: String,
    mujoco: String,
    numerics: String,
    cases: Vec<Case>,
}

#[derive(Deserialize)]
struct Case {
    name: String,
    env_id: String,
    num_envs: usize,
    steps: usize,
    mode: String,
    seed: u64,
    overrides: BTreeMap<String, String>,
}

fn dir() -> PathBuf {
    match std::env::var_os("ENVC_VECTOR_DIR") {
        Some(d) => PathBuf::from(d),
        None => envc_tests::fixtures_of("vector"),
    }
}

fn rows(a: &ArrayD<f64>, t: usize) -> Vec<f64> {
    a.index_axis(Axis(0), t).iter().copied().collect()
}

fn flags(a: &ArrayD<bool>, t: usize) -> Vec<bool> {
    a.index_axis(Axis(0), t).iter().copied().collect()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn replays_gymnasium_sync_vector_env_bit_for_bit() {
    let dir = dir();
    let text = std::fs::read_to_string(dir.join("manifest.json")).expect("vector manifest");
    let m: Manifest = serde_json::from_str(&text).expect("manifest format");
    assert_eq!(
        (m.gymnasium.as_str(), m.mujoco.as_str()),
        ("1.4.0", envc::MUJOCO_VERSION)
    );
    assert!(m.cases.iter().any(|c| c.mode == "same_step"));
    let mut total_ends = 0;
    for case in &m.cases {
        let mut npz =
            NpzReader::new(File::open(dir.join(format!("{}.npz", case.name))).unwrap()).unwrap();
        let mut f = |k: &str| -> ArrayD<f64> { npz.by_name(k).unwrap() };
        let (actions, obs0, obs, reward, final_obs) = (
            f("actions"),
            f("obs0"),
            f("obs"),
            f("reward"),
            f("final_obs"),
        );
        let mut b = |k: &str| -> ArrayD<bool> { npz.by_name(k).unwrap() };
        let (terminated, truncated, has_final) = (b("terminated"), b("truncated"), b("has_final"));
        let mode = match case.mode.as_str() {
            "next_step" => Autoreset::NextStep,
            _ => Autoreset::SameStep,
        };
        let overrides: Vec<Override> = case
            .overrides
            .iter()
            .map(|(k, v)| Override::text(k, v))
            .collect();
        let mut v = VecEnv::make(&case.env_id, &overrides, case.num_envs, 2, mode).unwrap();
        v.set_numerics(envc_tests::parse_profile(&m.numerics));
        let what = &case.name;
        assert_eq!(
            bits(v.reset(Some(case.seed))),
            bits(obs0.as_slice().unwrap()),
            "{what}: obs0"
        );
        for t in 0..case.steps {
            v.step(&rows(&actions, t)).unwrap();
            assert_eq!(
                bits(v.obs()),
                bits(&rows(&obs, t)),
                "{what}: obs at step {t}"
            );
            assert_eq!(
                bits(v.rewards()),
                bits(&rows(&reward, t)),
                "{what}: reward at {t}"
            );
            assert_eq!(
                v.terminated(),
                flags(&terminated, t),
                "{what}: terminated at {t}"
            );
            assert_eq!(
                v.truncated(),
                flags(&truncated, t),
                "{what}: truncated at {t}"
            );
            if mode == Autoreset::SameStep {
                let hf = flags(&has_final, t);
                assert_eq!(v.has_final(), hf, "{what}: final_obs mask at {t}");
                let od = v.obs_dim();
                let want = rows(&final_obs, t);
                for (i, _) in hf.iter().enumerate().filter(|(_, h)| **h) {
                    let r = i * od..(i + 1) * od;
                    assert_eq!(
                        bits(&v.final_obs()[r.clone()]),
                        bits(&want[r]),
                        "{what}: final_obs[{i}] at {t}"
                    );
                    assert!(v.final_info(i).is_some());
                }
            }
            total_ends += v
                .terminated()
                .iter()
                .chain(v.truncated())
                .filter(|x| **x)
                .count();
        }
    }
    // The cases must exercise autoreset, not just plain stepping.
    assert!(total_ends > 50, "only {total_ends} episode ends replayed");
}

/// Every batch buffer after every step, concatenated bitwise.
fn run(id: &str, n: usize, threads: usize, mode: Autoreset, jitter: u64) -> Vec<u64> {
    let mut v = VecEnv::make(id, &[], n, threads, mode).unwrap();
    v.set_completion_jitter(jitter);
    let mut out = bits(v.reset(Some(7)));
    let ad = v.act_dim();
    for t in 0..40 {
        // Deterministic actions spanning beyond the bounds.
        let a: Vec<f64> = (0..n * ad)
            .map(|k| (((t * 31 + k * 17) % 13) as f64 - 6.0) / 5.0)
            .collect();
        v.step(&a).unwrap();
        out.extend(bits(v.obs()));
        out.extend(bits(v.rewards()));
        out.extend(
            v.terminated()
                .iter()
                .chain(v.truncated())
                .chain(v.has_final())
                .map(|&b| b as u64),
        );
        out.extend(bits(v.final_obs()));
    }
    out
}

#[test]
fn results_do_not_depend_on_threads_or_completion_order() {
    for (id, mode) in [
        ("Hopper-v5", Autoreset::NextStep),
        ("InvertedDoublePendulum-v5", Autoreset::SameStep),
    ] {
        let base = run(id, 7, 1, mode, 0);
        for (threads, jitter) in [(2, 0), (3, 0), (2, 11), (3, 12), (3, 13)] {
            assert!(
                base == run(id, 7, threads, mode, jitter),
                "{id} {mode:?}: {threads} threads (jitter {jitter}) differ from 1 thread"
            );
        }
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mut v = VecEnv::make("Hopper-v5", &[], 3, 2, Autoreset::NextStep).unwrap();
    let a = vec![0.0; 9];
    assert_eq!(v.step(&a).unwrap_err().code(), envspec::Code::E1103);
    v.reset(Some(0));
    assert_eq!(v.step(&a[..8]).unwrap_err().code(), envspec::Code::E1101);
    let mut bad = a.clone();
    bad[5] = f64::NAN;
    let e = v.step(&bad).unwrap_err();
    assert_eq!(e.code(), envspec::Code::E1102);
    // Nothing moved: the batch still holds the reset observations.
    v.step(&a).unwrap();
    assert!(v.envs().iter().all(|e| e.elapsed_steps() == 1));
    assert!(VecEnv::make("Hoper-v5", &[], 2, 2, Autoreset::NextStep).is_err());
    let mut empty = VecEnv::make("Hopper-v5", &[], 0, 4, Autoreset::NextStep).unwrap();
    empty.reset(Some(0));
    empty.step(&[]).unwrap();
}

#[test]
fn an_interrupted_step_skips_the_envs_not_started_and_needs_a_reset() {
    // Never asked to stop: the same bits as `step`.
    let mut a = VecEnv::make("Hopper-v5", &[], 5, 2, Autoreset::NextStep).unwrap();
    let mut b = VecEnv::make("Hopper-v5", &[], 5, 2, Autoreset::NextStep).unwrap();
    a.reset(Some(3));
    b.reset(Some(3));
    let act: Vec<f64> = (0..15).map(|k| (k % 7) as f64 / 7.0 - 0.5).collect();
    for _ in 0..3 {
        a.step(&act).unwrap();
        let got = b
            .step_interruptible(envc::JointAction::F64(&act), &mut || false)
            .unwrap();
        assert_eq!(got, envc::Stepped::Done);
        assert_eq!(bits(a.obs()), bits(b.obs()));
        assert_eq!(bits(a.rewards()), bits(b.rewards()));
    }
    // 40 slow envs (about 10 ms each at frame_skip 1000, so the step takes far more than the
    // 50 ms between checks), one thread, a check that says stop: the envs after it are skipped.
    let slow = [Override::text("frame_skip", "1000")];
    let mut v = VecEnv::make("Hopper-v5", &slow, 40, 1, Autoreset::NextStep).unwrap();
    v.reset(Some(0));
    let mut asked = 0;
    let got = v
        .step_interruptible(envc::JointAction::F64(&[0.0; 120]), &mut || {
            asked += 1;
            true
        })
        .unwrap();
    assert_eq!(got, envc::Stepped::Interrupted);
    assert_eq!(asked, 1);
    let stepped = v.envs().iter().filter(|e| e.elapsed_steps() == 1).count();
    assert!((1..40).contains(&stepped), "{stepped} of 40 envs stepped");
    assert_eq!(
        v.step(&[0.0; 120]).unwrap_err().code(),
        envspec::Code::E1103
    );
    v.reset(Some(1));
    v.step(&[0.0; 120]).unwrap();
    assert!(v.envs().iter().all(|e| e.elapsed_steps() == 1));
}

/// One single env's side of `a_goal_task_batches_what_single_envs_stepped_alone_observe`: the
/// observation, achieved and desired goal it reports now, bitwise.
fn observed(e: &envc::Env) -> Vec<u64> {
    let mut achieved = vec![];
    e.achieved_goal(&mut achieved);
    [e.obs(), &achieved, e.goal()]
        .concat()
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

/// Env i's rows of a vector's observation and goal buffers, bitwise.
fn rows_of(
    obs: &[f64],
    achieved: &[f64],
    desired: &[f64],
    i: usize,
    (od, gd): (usize, usize),
) -> Vec<u64> {
    let (o, g) = (i * od..(i + 1) * od, i * gd..(i + 1) * gd);
    bits(&[&obs[o], &achieved[g.clone()], &desired[g]].concat())
}

#[test]
fn a_goal_task_batches_what_single_envs_stepped_alone_observe() {
    // FetchPush-v4 ([goal]): the goal buffers hold each env's achieved and desired goal after
    // every reset and step, SameStep's final rows what the ending env observed, across
    // autoresets (a 20-step limit) and a masked reset.
    let over = [Override::text("max_episode_steps", "20")];
    let n = 3;
    for mode in [Autoreset::NextStep, Autoreset::SameStep] {
        let mut v = VecEnv::make("FetchPush-v4", &over, n, 2, mode).unwrap();
        let (od, gd) = (v.obs_dim(), v.goal_dim());
        assert_eq!(gd, 3);
        let mut singles: Vec<envc::Env> = (0..n)
            .map(|_| envc::Env::make("FetchPush-v4", &over).unwrap())
            .collect();
        v.reset(Some(5));
        for (i, e) in singles.iter_mut().enumerate() {
            e.reset(Some(5 + i as u64));
        }
        let mut pending = vec![false; n];
        let mut ends = 0;
        for t in 0..50 {
            if t == 30 {
                let mask = [true, false, true];
                let seeds = (0..n as u64).map(|i| Some(100 + i));
                v.reset_masked(seeds, &mask).unwrap();
                for i in [0, 2] {
                    singles[i].reset(Some(100 + i as u64));
                    pending[i] = false;
                }
            }
            let a: Vec<f64> = (0..n * v.act_dim())
                .map(|k| (((t * 31 + k * 17) % 13) as f64 - 6.0) / 5.0)
                .collect();
            v.step(&a).unwrap();
            for (i, e) in singles.iter_mut().enumerate() {
                let what = format!("{mode:?} step {t} env {i}");
                let (obs, ach, des) = (v.obs(), v.achieved_goals(), v.desired_goals());
                if pending[i] {
                    e.reset(None);
                    pending[i] = false;
                    assert_eq!(rows_of(obs, ach, des, i, (od, gd)), observed(e), "{what}");
                    continue;
                }
                let s = e.step(&a[i * 4..(i + 1) * 4]).unwrap();
                let (r, ended) = (s.reward, s.terminated || s.truncated);
                assert_eq!(v.rewards()[i].to_bits(), r.to_bits(), "{what}: reward");
                ends += usize::from(ended);
                if ended && mode == Autoreset::SameStep {
                    assert!(v.has_final()[i], "{what}");
                    let last = (
                        v.final_obs(),
                        v.final_achieved_goals(),
                        v.final_desired_goals(),
                    );
                    assert_eq!(
                        rows_of(last.0, last.1, last.2, i, (od, gd)),
                        observed(e),
                        "{what}: final"
                    );
                    e.reset(None);
                } else {
                    pending[i] = ended;
                }
                assert_eq!(rows_of(obs, ach, des, i, (od, gd)), observed(e), "{what}");
            }
        }
        assert!(ends >= n * 2, "{mode:?}: only {ends} episodes ended");
    }
}
