//! Commands, PD actions and the legged reward kinds of `specs/examples/go1_joystick.toml` (over
//! the shared Go1), checked against independent computations:
//! - every term, observation element and the reward, recomputed in numpy from Playground's
//!   published formulas on the same states (`tests/reference/joystick_terms.py`; skipped with a
//!   note when the venv is missing);
//! - the command schedule and standing-still probability, the PD targets and gains, and the
//!   draw order, against values computed here from the spec and a separate numpy-compatible RNG.

use std::path::Path;

use envc::Env;
use envc::rng::NumpyRng;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
const GO1: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/models/unitree_go1/scene.xml"
);

fn joystick(extra: &[(&str, &str)]) -> Env {
    let mut o = vec![envc::Override::text("xml_file", GO1)];
    o.extend(extra.iter().map(|(k, v)| envc::Override::text(k, v)));
    Env::from_spec_file(format!("{ROOT}/specs/examples/go1_joystick.toml"), &o).unwrap()
}

fn command(env: &Env) -> [f64; 3] {
    let o = env.obs();
    [o[45], o[46], o[47]]
}

/// The draws of `reset(seed)`: the spec's [reset.*] steps (17 + 2 + 6 uniforms), then the
/// command: 3 uniforms and one `random()` for the standing-still choice.
fn expected_reset_command(seed: u64, standing: f64) -> [f64; 3] {
    let mut rng = NumpyRng::from_seed(seed);
    for _ in 0..17 + 2 + 6 {
        rng.next_f64();
    }
    let c = [
        rng.uniform(-1.5, 1.5),
        rng.uniform(-0.8, 0.8),
        rng.uniform(-1.2, 1.2),
    ];
    if rng.next_f64() < standing {
        [0.0; 3]
    } else {
        c
    }
}

#[test]
fn reset_draws_commands_after_the_reset_steps() {
    let mut env = joystick(&[]);
    for seed in [0, 1, 7, 12345] {
        env.reset(Some(seed));
        assert_eq!(
            command(&env),
            expected_reset_command(seed, 0.1),
            "seed {seed}"
        );
    }
}

#[test]
fn commands_resample_on_schedule_and_stand_still_with_their_probability() {
    // 0.1 s at dt 0.02: every 5 steps; between draws the command holds.
    let mut env = joystick(&[
        ("command_resample_seconds", "0.1"),
        ("standing_probability", "0.3"),
        ("max_episode_steps", "0"),
    ]);
    env.reset(Some(3));
    let a = vec![0.0; 12];
    let mut last = command(&env);
    let (mut draws, mut standing) = (0u32, 0u32);
    for t in 1..=2000u64 {
        let s = env.step(&a).unwrap();
        let done = s.terminated || s.truncated;
        let c = command(&env);
        if t % 5 == 0 {
            draws += 1;
            standing += (c == [0.0; 3]) as u32;
        } else {
            assert_eq!(c, last, "step {t}: the command changed between draws");
        }
        last = c;
        assert!(!done, "the zero policy stands");
    }
    // 400 draws at p = 0.3: mean 120, sd ≈ 9.2; 4 sd either side.
    assert_eq!(draws, 400);
    assert!(
        (83..=157).contains(&standing),
        "{standing} standing draws of 400"
    );
    // Without standing_probability the stream has no `random()` per draw: p = 0 draws 3 numbers.
    let mut env = joystick(&[("standing_probability", "0.0")]);
    env.reset(Some(5));
    let mut rng = NumpyRng::from_seed(5);
    for _ in 0..25 {
        rng.next_f64();
    }
    let c = [
        rng.uniform(-1.5, 1.5),
        rng.uniform(-0.8, 0.8),
        rng.uniform(-1.2, 1.2),
    ];
    assert_eq!(command(&env), c);
}

#[test]
fn pd_targets_and_gains() {
    let mut env = joystick(&[]);
    env.reset(Some(0));
    let m = env.model().ffi();
    // The home keyframe's joint angles (MJCF text), gains 35, damping 0.5, timestep 0.004.
    let home = [0.0, 0.9, -1.8];
    for i in 0..12 {
        // SAFETY: 12 actuators × 10 parameters, 6 + 12 dofs.
        unsafe {
            assert_eq!(*m.actuator_gainprm.add(10 * i), 35.0);
            assert_eq!(*m.actuator_biasprm.add(10 * i + 1), -35.0);
            assert_eq!(*m.actuator_biasprm.add(10 * i + 2), 0.0);
            assert_eq!(*m.dof_damping.add(6 + i), 0.5);
        }
    }
    assert_eq!(m.opt.timestep, 0.004);
    assert_eq!(env.action_space().low, vec![-1.0; 12]);
    assert_eq!(env.action_space().high, vec![1.0; 12]);
    let mut rng = NumpyRng::from_seed(9);
    for _ in 0..5 {
        let a: Vec<f64> = (0..12).map(|_| rng.uniform(-1.0, 1.0)).collect();
        env.step(&a).unwrap();
        // SAFETY: ctrl holds nu = 12 numbers.
        let ctrl = unsafe { std::slice::from_raw_parts(env.data().ctrl, 12) };
        for i in 0..12 {
            assert_eq!(ctrl[i], home[i % 3] + 0.5 * a[i], "ctrl[{i}]");
        }
    }
    // Specs without [actions] keep ctrl = action and the model's own gains (Go1-v0: kp 100).
    let mut go1 = Env::from_spec_file(
        format!("{ROOT}/specs/examples/go1.toml"),
        &[envc::Override::text("xml_file", GO1)],
    )
    .unwrap();
    go1.reset(Some(0));
    let a = vec![0.25; 12];
    go1.step(&a).unwrap();
    // SAFETY: ctrl holds nu = 12 numbers.
    let ctrl = unsafe { std::slice::from_raw_parts(go1.data().ctrl, 12) };
    assert_eq!(ctrl, &a[..]);
    assert_eq!(go1.model().actuator_gainprm()[0][0], 100.0);
}

/// Dump states and term values of seeded random rollouts; numpy recomputes them.
#[test]
fn terms_match_numpy_from_published_formulas() {
    let py = format!("{ROOT}/.venv/bin/python");
    if !Path::new(&py).exists() {
        eprintln!("skipped: no venv at {py} (scripts/setup.sh makes it)");
        return;
    }
    // Short command intervals and a high standing probability so both sides of every gate occur.
    let mut env = joystick(&[
        ("command_resample_seconds", "0.2"),
        ("standing_probability", "0.4"),
    ]);
    let keys = [
        "reward_tracking_lin_vel",
        "reward_tracking_ang_vel",
        "reward_lin_vel_z",
        "reward_ang_vel_xy",
        "reward_orientation",
        "reward_dof_pos_limits",
        "reward_pose",
        "reward_stand_still",
        "reward_torques_norm",
        "reward_torques_abs",
        "reward_action_rate",
        "reward_feet_slip",
        "reward_feet_air_time",
    ];
    let mut rng = NumpyRng::from_seed(2024);
    let mut rows = vec![];
    let row = |env: &Env, kind: &str, action: &[f64], reward: f64, done: bool| {
        let d = env.data();
        let (nbody, nsite) = (14, env.model().ffi().nsite as usize);
        // SAFETY: each call below passes a data array with its length from the model's sizes.
        let arr = |p: *const f64, n: usize| unsafe { std::slice::from_raw_parts(p, n) }.to_vec();
        let contacts: Vec<[i32; 2]> = (0..d.ncon as usize)
            // SAFETY: the contact list holds ncon contacts.
            .map(|c| unsafe { (*d.contact.add(c)).geom })
            .collect();
        let info: serde_json::Map<String, serde_json::Value> = if kind == "step" {
            keys.iter()
                .map(|k| (k.to_string(), env.step_info().scalar(k).unwrap().into()))
                .collect()
        } else {
            Default::default()
        };
        serde_json::json!({
            "kind": kind, "action": action, "reward": reward, "done": done,
            "obs": env.obs(), "qpos": arr(d.qpos, 19), "qvel": arr(d.qvel, 18),
            "cvel": arr(d.cvel, nbody * 6), "subtree_com": arr(d.subtree_com, nbody * 3),
            "site_xpos": arr(d.site_xpos, nsite * 3), "site_xmat": arr(d.site_xmat, nsite * 9),
            "actuator_force": arr(d.actuator_force, 12), "contacts": contacts, "info": info,
        })
    };
    let zero = vec![0.0; 12];
    env.reset(Some(11));
    rows.push(row(&env, "reset", &zero, 0.0, false));
    let mut steps = 0;
    while steps < 900 {
        // Random actions of ±0.4 keep the robot up; then ±2.5 (targets past the soft joint
        // limits) make it fall, so every term and the termination take nonzero values.
        let amp = if steps < 400 { 0.4 } else { 2.5 };
        let a: Vec<f64> = (0..12).map(|_| rng.uniform(-amp, amp)).collect();
        let s = env.step(&a).unwrap();
        let (r, term, done) = (s.reward, s.terminated, s.terminated || s.truncated);
        rows.push(row(&env, "step", &a, r, term));
        steps += 1;
        if done {
            env.reset(None);
            rows.push(row(&env, "reset", &zero, 0.0, false));
        }
    }
    let dir = std::env::temp_dir().join(format!("envc-joystick-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dump = dir.join("rollout.json");
    std::fs::write(&dump, serde_json::to_string(&rows).unwrap()).unwrap();
    let out = std::process::Command::new(&py)
        .arg(format!("{ROOT}/tests/reference/joystick_terms.py"))
        .arg(&dump)
        .arg(GO1)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out.stdout);
    eprintln!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "numpy disagrees");
    assert!(text.contains("all terms agree"), "{text}");
}

/// Feet named by body (any geom of the body; for models whose foot geoms have no names) and the
/// floor as `world` give the same contacts as the named geoms while only the feet touch.
#[test]
fn feet_by_body_match_feet_by_geom() {
    let text = std::fs::read_to_string(format!("{ROOT}/specs/examples/go1_joystick.toml")).unwrap();
    let by_body = text
        .replace(
            "feet = [\"FR\", \"FL\", \"RR\", \"RL\"]\nfloor = \"floor\"",
            "feet = [\"FR_calf\", \"FL_calf\", \"RR_calf\", \"RL_calf\"]\nfloor = \"world\"",
        )
        .replace("id = \"Go1Joystick-v0\"", "id = \"Go1JoystickBodies-v0\"");
    assert_eq!(by_body.matches("floor = \"world\"").count(), 2);
    let dir = std::env::temp_dir().join(format!("envc-joystick-bodies-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bodies.toml");
    std::fs::write(&path, by_body).unwrap();
    let mut b = Env::from_spec_file(&path, &[envc::Override::text("xml_file", GO1)]).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let mut g = joystick(&[]);
    b.reset(Some(4));
    g.reset(Some(4));
    let mut rng = NumpyRng::from_seed(4);
    let mut touched = 0.0;
    for _ in 0..300 {
        let a: Vec<f64> = (0..12).map(|_| rng.uniform(-0.3, 0.3)).collect();
        let (sb, sg) = (b.step(&a).unwrap(), g.step(&a).unwrap());
        assert!(!sg.terminated);
        for k in ["reward_feet_slip", "reward_feet_air_time"] {
            assert_eq!(sb.info.scalar(k), sg.info.scalar(k), "{k}");
        }
        touched += sg.info.scalar("reward_feet_slip").unwrap().abs();
    }
    assert!(touched > 0.0, "feet in contact and slipping");
}
