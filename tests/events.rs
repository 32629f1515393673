//! `[events]` (domain randomization): the randomized model values agree bit for bit with an
//! independent numpy + MuJoCo reproduction of the documented draw order
//! (`reference/check_events.py`); the same seed gives the same model and trajectory in a single
//! env, at any vector-env position and on 1, 2 and 4 threads, whatever happened before; other
//! envs sharing the compiled model are unaffected; reset and step stay allocation-free.

use std::sync::Arc;

use envc::{Autoreset, Env, VecEnv};
use envc_tests::allocations;

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/reference/events_go1.toml");
const STEPS: usize = 150;

/// The model arrays events write, by the names check_events.py prints.
fn model_values(m: &envc::mujoco_rs::mujoco_c::mjModel) -> Vec<(&'static str, Vec<f64>)> {
    // SAFETY: each call below passes a model array with its length from the model's sizes.
    let v = |p: *const f64, n: i64| unsafe { std::slice::from_raw_parts(p, n as usize) }.to_vec();
    vec![
        ("geom_friction", v(m.geom_friction, 3 * m.ngeom)),
        ("body_mass", v(m.body_mass, m.nbody)),
        ("body_ipos", v(m.body_ipos, 3 * m.nbody)),
        ("dof_damping", v(m.dof_damping, m.nv)),
        ("dof_armature", v(m.dof_armature, m.nv)),
        ("actuator_gainprm", v(m.actuator_gainprm, 10 * m.nu)),
        ("actuator_biasprm", v(m.actuator_biasprm, 10 * m.nu)),
        ("gravity", m.opt.gravity.to_vec()),
        ("timestep", vec![m.opt.timestep]),
    ]
}

fn env_values(env: &Env) -> Vec<(&'static str, Vec<f64>)> {
    model_values(env.model().ffi())
}

fn action(t: usize, i: usize) -> f64 {
    0.4 * (0.1 * t as f64 + i as f64).sin()
}

/// Observations and rewards of `STEPS` steps, as bit patterns.
fn trajectory(env: &mut Env) -> Vec<u64> {
    let mut out = vec![];
    let n = env.act_dim();
    for t in 0..STEPS {
        let a: Vec<f64> = (0..n).map(|i| action(t, i)).collect();
        let s = env.step(&a).unwrap();
        out.extend(s.obs.iter().map(|x| x.to_bits()));
        out.push(s.reward.to_bits());
    }
    out
}

#[test]
fn model_values_match_numpy() {
    let python = concat!(env!("CARGO_MANIFEST_DIR"), "/../.venv/bin/python");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/reference/check_events.py");
    for seed in [7u64, 12345] {
        let out = std::process::Command::new(python)
            .args([script, SPEC, &seed.to_string()])
            .output()
            .unwrap_or_else(|e| panic!("cannot run {python} (scripts/setup.sh makes it): {e}"));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let theirs: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let mut env = Env::from_spec_file(SPEC, &[]).unwrap();
        let compiled = env_values(&env);
        env.reset(Some(seed));
        let mut changed = 0;
        for ((name, ours), (_, before)) in env_values(&env).iter().zip(&compiled) {
            let want: Vec<f64> = theirs[name]
                .as_array()
                .unwrap()
                .iter()
                .map(|h| f64::from_bits(u64::from_str_radix(h.as_str().unwrap(), 16).unwrap()))
                .collect();
            assert_eq!(ours.len(), want.len(), "{name}");
            for (k, (a, b)) in ours.iter().zip(&want).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "seed {seed}: {name}[{k}] {a} vs {b}"
                );
            }
            changed += ours.iter().zip(before).filter(|(a, b)| a != b).count();
        }
        // 4 + 1 + 2 frictions, 4 + 1 masses, 3 ipos, 12 damping, 4 armature, 12 kp × 2, 3 bias
        // (FR_hip's biasprm[1] is also its kp's), 3 gravity, 1 timestep.
        assert_eq!(changed, 61, "seed {seed}: values the events changed");
    }
}

#[test]
fn same_seed_same_model_and_trajectory_anywhere() {
    let mut single = Env::from_spec_file(SPEC, &[]).unwrap();
    single.reset(Some(7));
    let model = env_values(&single);
    let traj = trajectory(&mut single);

    // Whatever happened before: other seeds, unseeded resets, steps.
    let mut used = Env::from_spec_file(SPEC, &[]).unwrap();
    used.reset(Some(3));
    trajectory(&mut used);
    used.reset(None);
    used.reset(Some(7));
    assert_eq!(env_values(&used), model);
    assert_eq!(
        trajectory(&mut used),
        traj,
        "a used env reset with the same seed"
    );
    // An unseeded reset keeps the startup values and redraws only the reset events.
    let mut again = Env::from_spec_file(SPEC, &[]).unwrap();
    again.reset(Some(7));
    again.reset(None);
    let (a, b) = (env_values(&again), &model);
    assert_eq!(
        a[0].1[3], b[0].1[3],
        "floor torsional friction is a startup draw"
    );
    assert_ne!(a[8].1, b[8].1, "the timestep is a reset draw");

    let spec = Arc::new(envspec::load(SPEC.as_ref(), &[]).unwrap());
    let (n, od) = (4, spec.obs_dim);
    let ad = spec.act_dim();
    for threads in [1, 2, 4] {
        for k in [0, 3] {
            let mut v = VecEnv::new(Arc::clone(&spec), n, threads, Autoreset::NextStep).unwrap();
            v.reset_each((0..n).map(|i| Some(if i == k { 7 } else { 100 + i as u64 })));
            assert_eq!(
                env_values(&v.envs()[k]),
                model,
                "{threads} threads, position {k}"
            );
            let mut got = vec![];
            for t in 0..STEPS {
                let a: Vec<f64> = (0..n * ad).map(|j| action(t, j % ad)).collect();
                v.step(&a).unwrap();
                got.extend(v.obs()[k * od..(k + 1) * od].iter().map(|x| x.to_bits()));
                got.push(v.rewards()[k].to_bits());
            }
            assert_eq!(got, traj, "{threads} threads, position {k}");
        }
    }
}

#[test]
fn envs_sharing_a_compiled_model_are_unaffected() {
    let spec = Arc::new(envspec::load(SPEC.as_ref(), &[]).unwrap());
    let model = Arc::new(envc::env::compile(&spec).unwrap());
    let compiled = model_values(model.ffi());
    let mut a = Env::with_model(Arc::clone(&spec), Arc::clone(&model)).unwrap();
    let b = Env::with_model(Arc::clone(&spec), Arc::clone(&model)).unwrap();
    a.reset(Some(1));
    trajectory(&mut a);
    assert_ne!(env_values(&a), compiled);
    assert_eq!(model_values(model.ffi()), compiled, "the shared model");
    assert_eq!(env_values(&b), compiled, "another env over it");
}

#[test]
fn pushes_kick_the_trunk() {
    // The same seed with kicks of zero: the same draws, so the trajectories part at the first
    // push.
    let text = std::fs::read_to_string(SPEC).unwrap();
    let zero = text
        .replace("x = [-0.5, 0.5]", "x = [0.0, 0.0]")
        .replace("y = [-0.3, 0.3]", "y = [0.0, 0.0]");
    assert_ne!(zero, text);
    let dir = std::env::temp_dir().join(format!("envc-events-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("zero_push.toml");
    let xml = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/models/unitree_go1/scene.xml"
    );
    std::fs::write(&path, zero).unwrap();
    let over = [envc::Override::text("xml_file", xml)];
    let mut plain = Env::from_spec_file(&path, &over).unwrap();
    let mut pushed = Env::from_spec_file(SPEC, &[]).unwrap();
    plain.reset(Some(5));
    pushed.reset(Some(5));
    assert_eq!(env_values(&plain), env_values(&pushed));
    let n = plain.act_dim();
    let a = vec![0.0; n];
    let mut parted = None;
    for t in 0..30 {
        let (p, q) = (
            plain.step(&a).unwrap().obs.to_vec(),
            pushed.step(&a).unwrap().obs,
        );
        if parted.is_none() && p != q {
            // qvel of the free joint starts at qpos' 19 entries: vx, vy kicked.
            assert!(p[19] != q[19] && p[20] != q[20], "step {t}: x and y kicked");
            parted = Some(t);
        }
    }
    // The first interval is uniform in [0.2, 0.4] s; a step is 10 × 0.002 s ± 10 %.
    let t = parted.expect("a push within 30 steps");
    assert!((8..=23).contains(&t), "first push at step {t}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn reset_and_step_do_not_allocate() {
    let mut env = Env::from_spec_file(SPEC, &[]).unwrap();
    env.reset(Some(0));
    let a = vec![0.1; env.act_dim()];
    let n = allocations(|| {
        for i in 0..300u64 {
            let s = env.step(&a).unwrap();
            std::hint::black_box(s.reward);
            if i % 40 == 0 {
                env.reset(None);
            }
            if i % 90 == 0 {
                env.reset(Some(i));
            }
        }
    });
    assert_eq!(n, 0, "{n} allocations in 300 steps with events");
}
