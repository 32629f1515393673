//! Observation noise and delay, action latency (`envspec::noise`; docs/spec-reference.md,
//! "Observation noise, delay and action latency"):
//! - noise values equal, bit for bit, numpy's `default_rng(seed)` drawing in the documented order
//!   (`tests/reference/noise_draws.py`, run with the reference venv's Python), added before clip;
//! - a delayed segment at step t is the undelayed value at t − N (the reset value before);
//! - an env with action latency N is an env without latency fed the actions shifted by N;
//! - stepping and resetting allocate nothing; a spec without these keys draws nothing new.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use envc::{Env, Override};
use envc_tests::allocations;
use serde_json::{Value, json};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// A Hopper-model spec with `extra` appended (segments, `[latency]`), written to a fresh file
/// that is removed once dropped (an env reads it when it is built).
fn spec(name: &str, extra: &str) -> envc_tests::ScratchFile {
    let xml = Path::new(ROOT).join("assets/gymnasium/hopper.xml");
    let text = format!(
        r#"[env]
id = "NoisyHopper-v0"

[params]
xml_file = {xml:?}
frame_skip = 4
max_episode_steps = 1000
noise_level = 0.7
vel_delay = 2

[reset.qpos]
target = "qpos"
kind = "uniform"
low = -0.005
high = 0.005

[reset.qvel]
target = "qvel"
kind = "uniform"
low = -0.005
high = 0.005

[reward.ctrl]
kind = "sum_squares"
source = "action"
weight = 0.001
cost = true
info = "reward_ctrl"

[reward.forward]
kind = "velocity"
source = "xpos[torso][0]"
info = "x_velocity"
{extra}"#,
        xml = xml.display().to_string()
    );
    envc_tests::ScratchFile::new("envc-obs-noise", &format!("{name}.toml"), &text)
}

/// Raw twins (no noise, no clip) and the noisy segments they shadow.
const SEGMENTS: &str = r#"
[observation.raw_pos]
source = "qpos[1:]"

[observation.raw_vel]
source = "qvel"

[observation.pos]
source = "qpos[1:]"
clip = [-1.0, 1.0]
noise = { kind = "uniform", scale = 0.05, level = "noise_level" }

[observation.delayed_pos]
source = "qpos[1:3]"
delay = 3

[observation.vel]
source = "qvel"
clip = [-0.5, 0.5]
noise = { kind = "gaussian", scale = 0.2 }

[observation.delayed_vel]
source = "qvel[0:2]"
delay = "vel_delay"
noise = { kind = "uniform", scale = 0.01 }
"#;

fn actions(t: usize, nu: usize) -> Vec<f64> {
    (0..nu)
        .map(|i| 0.6 * ((t * 7 + i * 3) as f64 * 0.37).sin())
        .collect()
}

/// The observations of reset(seed) then `steps` steps (fewer if the episode ends).
fn rollout(env: &mut Env, seed: u64, steps: usize) -> Vec<Vec<f64>> {
    let mut obs = vec![env.reset(Some(seed)).0.to_vec()];
    for t in 0..steps {
        let s = env.step(&actions(t, env.act_dim())).unwrap();
        obs.push(s.obs.to_vec());
        if s.terminated || s.truncated {
            break;
        }
    }
    obs
}

fn python() -> PathBuf {
    let p = Path::new(ROOT).join(".venv/bin/python");
    assert!(
        p.exists(),
        "{} missing: the reference venv (scripts/setup.sh) computes the expected noise",
        p.display()
    );
    p
}

fn numpy_noisy(input: &Value) -> Vec<Vec<Vec<u64>>> {
    let mut child = Command::new(python())
        .arg(Path::new(ROOT).join("tests/reference/noise_draws.py"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.to_string().as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "noise_draws.py failed");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v["noisy"]
        .as_array()
        .unwrap()
        .iter()
        .map(|seg| {
            seg.as_array()
                .unwrap()
                .iter()
                .map(|t| {
                    t.as_array()
                        .unwrap()
                        .iter()
                        .map(|b| b.as_str().unwrap().parse().unwrap())
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// (offset, len) of a segment by name.
fn seg(env: &Env, name: &str) -> (usize, usize) {
    let s = env
        .spec()
        .observation
        .iter()
        .find(|s| s.name == name)
        .unwrap();
    (s.offset, s.len())
}

fn slice(o: &[f64], (off, len): (usize, usize)) -> Vec<f64> {
    o[off..off + len].to_vec()
}

#[test]
fn noise_matches_numpy_bit_for_bit_and_delay_is_exact() {
    let mut env = Env::from_spec_file(spec("noisy", SEGMENTS), &[]).unwrap();
    let seed = 42;
    let obs = rollout(&mut env, seed, 40);
    assert!(obs.len() > 10, "the episode should run a while");
    let (raw_pos, raw_vel) = (seg(&env, "raw_pos"), seg(&env, "raw_vel"));
    let raw_vel2 = (raw_vel.0, 2);
    let noisy = [
        ("pos", raw_pos, "uniform", 0.7, 0.05, Some([-1.0, 1.0])),
        ("vel", raw_vel, "gaussian", 1.0, 0.2, Some([-0.5, 0.5])),
        ("delayed_vel", raw_vel2, "uniform", 1.0, 0.01, None),
    ];
    let input = json!({
        "seed": seed,
        "reset_draws": 12,
        "segments": noisy.iter().map(|(_, raw, kind, level, scale, clip)| json!({
            "kind": kind, "level": level, "scale": scale, "clip": clip,
            "raw": obs.iter().map(|o| slice(o, *raw)).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    });
    let expected = numpy_noisy(&input);
    for (j, (name, ..)) in noisy.iter().enumerate() {
        let (delay, at) = match *name {
            "delayed_vel" => (2, seg(&env, name)),
            _ => (0, seg(&env, name)),
        };
        for (t, o) in obs.iter().enumerate() {
            let want = &expected[j][t.saturating_sub(delay)];
            let got: Vec<u64> = slice(o, at).iter().map(|x| x.to_bits()).collect();
            assert_eq!(&got, want, "{name} at t={t}");
        }
    }
    // The uniform noise did move the values, within its bound; the clip binds on the height.
    let (p, rp) = (seg(&env, "pos"), raw_pos);
    let d: Vec<f64> = obs
        .iter()
        .flat_map(|o| (1..p.1).map(move |k| o[p.0 + k] - o[rp.0 + k]))
        .collect();
    assert!(d.iter().all(|x| x.abs() <= 0.035 + 1e-12) && d.iter().any(|x| x.abs() > 0.01));
    assert!(
        obs.iter().all(|o| o[p.0] == 1.0),
        "height 1.25 + noise clipped to 1"
    );
    // Delay without noise: the undelayed value 3 steps before (the reset value before that).
    let dp = seg(&env, "delayed_pos");
    for (t, o) in obs.iter().enumerate() {
        let then = &obs[t.saturating_sub(3)];
        assert_eq!(slice(o, dp), slice(then, (rp.0, 2)), "delayed_pos at t={t}");
    }
}

#[test]
fn noise_leaves_the_dynamics_and_other_segments_alone() {
    let clean = SEGMENTS
        .lines()
        .filter(|l| !l.starts_with("noise") && !l.starts_with("delay"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut a = Env::from_spec_file(spec("noisy2", SEGMENTS), &[]).unwrap();
    let mut b = Env::from_spec_file(spec("clean", &clean), &[]).unwrap();
    assert!(b.spec().corruption.is_empty());
    let (oa, ob) = (rollout(&mut a, 7, 30), rollout(&mut b, 7, 30));
    assert_eq!(oa.len(), ob.len());
    let raw = (0, 11);
    for (x, y) in oa.iter().zip(&ob) {
        assert_eq!(slice(x, raw), slice(y, raw));
    }
    // Noise switched off by `when`: no draws, the clipped raw value.
    let off = SEGMENTS.replace("scale = 0.2 }", "scale = 0.2, when = \"vel_noise\" }")
        + "\n[params.vel_noise]\ndefault = false\n";
    let mut c = Env::from_spec_file(spec("off", &off), &[]).unwrap();
    assert!(c.spec().corruption.segment("vel").is_none());
    let (v, rv) = (seg(&c, "vel"), seg(&c, "raw_vel"));
    for o in rollout(&mut c, 7, 30) {
        let want: Vec<f64> = slice(&o, rv).iter().map(|x| x.clamp(-0.5, 0.5)).collect();
        assert_eq!(slice(&o, v), want);
    }
}

#[test]
fn action_latency_is_the_shifted_action_sequence() {
    let n = 3;
    let lat = format!(
        "[observation.qpos]\nsource = \"qpos\"\n[observation.qvel]\nsource = \"qvel\"\n[latency]\naction = {n}\n"
    );
    let plain = "[observation.qpos]\nsource = \"qpos\"\n[observation.qvel]\nsource = \"qvel\"\n";
    let mut a = Env::from_spec_file(spec("latent", &lat), &[]).unwrap();
    let mut b = Env::from_spec_file(spec("plain", plain), &[]).unwrap();
    assert_eq!(a.spec().corruption.action_latency, n);
    for seed in [0, 5] {
        assert_eq!(a.reset(Some(seed)).0, b.reset(Some(seed)).0);
        let nu = a.act_dim();
        let mut moved = false;
        for t in 0..60 {
            let shifted = if t < n {
                vec![0.0; nu]
            } else {
                actions(t - n, nu)
            };
            let sa = a.step(&actions(t, nu)).unwrap();
            let (oa, ra, da) = (sa.obs.to_vec(), sa.reward, sa.terminated);
            let ia: Vec<f64> = sa.info.iter().flat_map(|(_, v)| v.to_vec()).collect();
            let sb = b.step(&shifted).unwrap();
            let ib: Vec<f64> = sb.info.iter().flat_map(|(_, v)| v.to_vec()).collect();
            assert_eq!(oa, sb.obs, "obs at t={t}");
            assert_eq!(ra.to_bits(), sb.reward.to_bits(), "reward at t={t}");
            assert_eq!(ia, ib, "info at t={t}");
            assert_eq!(da, sb.terminated);
            moved |= oa[1] != b.obs()[1] || t > n;
            if da {
                break;
            }
        }
        assert!(moved);
    }
    // Without latency the two differ from the first step (the test has teeth).
    let mut c = Env::from_spec_file(spec("plain2", plain), &[]).unwrap();
    c.reset(Some(0));
    b.reset(Some(0));
    let x = c.step(&actions(0, 3)).unwrap().obs.to_vec();
    assert_ne!(x, b.step(&[0.0; 3]).unwrap().obs);
}

#[test]
fn noisy_delayed_latent_stepping_does_not_allocate() {
    let extra = format!("{SEGMENTS}\n[latency]\naction = 2\n");
    let mut env = Env::from_spec_file(spec("alloc", &extra), &[]).unwrap();
    env.reset(Some(0));
    let a = vec![0.1; env.act_dim()];
    let n = allocations(|| {
        for i in 0..300u64 {
            let s = env.step(&a).unwrap();
            if s.terminated || s.truncated || i % 50 == 0 {
                env.reset(Some(i));
            }
        }
    });
    assert_eq!(n, 0, "{n} allocations");
}

#[test]
fn parameters_switch_and_scale_the_terms() {
    let path = spec("params", SEGMENTS);
    let over = [
        Override::text("vel_delay", "0"),
        Override::text("noise_level", "2.0"),
    ];
    let env = Env::from_spec_file(&path, &over).unwrap();
    let c = &env.spec().corruption;
    let dv = c.segment("delayed_vel").unwrap();
    assert_eq!(dv.delay, 0);
    assert_eq!(c.segment("pos").unwrap().noise.unwrap().level, 2.0);
    assert_eq!(c.segment("delayed_pos").unwrap().delay, 3);
}

// The typed env accepts these terms: it runs the same core.
envc::env!(NoisyHopper = "noise/hopper_noisy.toml");

#[test]
fn typed_env_runs_the_same_noisy_trajectory() {
    assert_eq!(NoisyHopper::OBS_DIM, 11);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("noise/hopper_noisy.toml");
    let mut dynamic = Env::from_spec_file(&path, &[]).unwrap();
    let mut typed = NoisyHopper::make().unwrap();
    let (o, _) = typed.reset(Some(3));
    assert_eq!(o.qvel().len(), 6);
    let first = o.as_slice().to_vec();
    assert_eq!(first, dynamic.reset(Some(3)).0);
    let inner = typed.inner_mut();
    for t in 0..50 {
        let a = actions(t, 3);
        let x = inner.step(&a).unwrap().obs.to_vec();
        assert_eq!(x, dynamic.step(&a).unwrap().obs, "t={t}");
    }
}

/// Noise, delay and latency in a vector env: member i with seed s + i runs exactly the single env
/// reset with that seed, on 1 or 2 threads (each env draws from its own stream).
#[test]
fn vector_env_members_match_single_envs_on_any_thread_count() {
    use envc::{Autoreset, VecEnv};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("noise/hopper_noisy.toml");
    let p = path.to_str().unwrap();
    let n = 3;
    let run_vec = |threads: usize| {
        let mut v = VecEnv::make(p, &[], n, threads, Autoreset::NextStep).unwrap();
        let mut out = vec![v.reset(Some(10)).to_vec()];
        for t in 0..40 {
            let a: Vec<f64> = (0..n).flat_map(|i| actions(t + i, 3)).collect();
            v.step(&a).unwrap();
            out.push(v.obs().to_vec());
        }
        out
    };
    let (one, two) = (run_vec(1), run_vec(2));
    assert_eq!(one, two);
    let od = NoisyHopper::OBS_DIM;
    for i in 0..n {
        let mut e = Env::from_spec_file(&path, &[]).unwrap();
        let mut obs = vec![e.reset(Some(10 + i as u64)).0.to_vec()];
        for t in 0..40 {
            let s = e.step(&actions(t + i, 3)).unwrap();
            let done = s.terminated || s.truncated;
            obs.push(s.obs.to_vec());
            if done {
                break;
            }
        }
        for (t, o) in obs.iter().enumerate() {
            assert_eq!(&one[t][i * od..(i + 1) * od], &o[..], "env {i} at t={t}");
        }
    }
}
