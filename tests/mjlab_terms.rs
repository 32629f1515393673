//! `specs/examples/mjlab_velocity_flat_go1.toml` and `mjlab_velocity_flat_g1.toml` term by term
//! against mjlab 1.6.0's term functions, recomputed in numpy (`tests/reference/mjlab_terms.py`,
//! written from mjlab's `tasks/velocity/mdp/rewards.py`, `envs/mdp/rewards.py`,
//! `envs/mdp/observations.py`, the entity's derived quantities and soft joint limits, the robots'
//! action scales and posture widths, and `ManagerBasedRlEnv.step`) on states dumped from envc's
//! env: the observation (read after `mj_forward`, as mjlab's), the PD targets, every reward term
//! and the termination (read from the last physics substep's kinematics, as mjlab's), the reward
//! and the solver options.

use std::path::Path;

use envc::Env;
use envc::rng::NumpyRng;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// A flat mjlab spec without noise or randomization, with commands redrawn every 0.2 s and a
/// standing probability of 0.4, so both sides of every gate and every posture regime occur.
/// `fresh = false` leaves out the `mj_forward` before the observation: the data after a step then
/// holds what the reward read.
fn flat(robot: &str, fresh: bool) -> Env {
    let original = Path::new(ROOT).join(format!("specs/examples/mjlab_velocity_flat_{robot}.toml"));
    let text = std::fs::read_to_string(&original)
        .unwrap()
        .replacen("resample_seconds = 5.5", "resample_seconds = 0.2", 1)
        .replacen(
            "standing_probability = 0.1",
            "standing_probability = 0.4",
            1,
        )
        .replacen(
            "forward_before_observation = true",
            &format!("forward_before_observation = {fresh}"),
            1,
        );
    // Written outside the repository (a file written under `specs/`, even briefly, makes cargo
    // rebuild envspec, which embeds that directory), so the model path is made absolute.
    let text = text.replace("\"../../assets/", &format!("\"{ROOT}/assets/"));
    let p = std::env::temp_dir().join(format!(
        "envc-mjlab-terms-{robot}-{}-{fresh}.toml",
        std::process::id()
    ));
    std::fs::write(&p, text).unwrap();
    let o = [
        envc::Override::text("observation_noise", "false"),
        envc::Override::text("domain_randomization", "false"),
    ];
    let env = Env::from_spec_file(&p, &o);
    let _ = std::fs::remove_file(&p);
    env.unwrap()
}

#[test]
fn go1_terms_match_numpy_from_mjlabs_term_functions() {
    check("go1");
}

#[test]
fn g1_terms_match_numpy_from_mjlabs_term_functions() {
    check("g1");
}

fn check(robot: &str) {
    let py = format!("{ROOT}/.venv/bin/python");
    if !Path::new(&py).exists() {
        eprintln!("skipped: no venv at {py} (scripts/setup.sh makes it)");
        return;
    }
    // `env` is the spec as written; `stale` the same without the forward: the same states (an
    // extra mj_forward changes no state, checked below), read where mjlab's rewards read them.
    let mut env = flat(robot, true);
    let mut stale = flat(robot, false);
    let keys: Vec<String> = env
        .spec()
        .reward
        .iter()
        .map(|t| format!("reward_{}", t.name))
        .collect();
    let dir = std::env::temp_dir().join(format!("envc-mjlab-terms-{robot}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let m = env.model();
    let mut mjb = vec![0u8; m.size()];
    m.save_to_buffer(&mut mjb).unwrap();
    std::fs::write(dir.join("model.mjb"), &mjb).unwrap();
    let (nq, nv, nu, nbody, nsite) = {
        let f = m.ffi();
        (
            f.nq as usize,
            f.nv as usize,
            f.nu as usize,
            f.nbody as usize,
            f.nsite as usize,
        )
    };
    // SAFETY: each call passes a data array with its length from the model's sizes.
    let arr = |p: *const f64, n: usize| unsafe { std::slice::from_raw_parts(p, n) }.to_vec();
    let row = |env: &Env, stale: &Env, kind: &str, action: &[f64], reward: f64, done: bool| {
        let (d, s) = (env.data(), stale.data());
        let contacts: Vec<[i32; 2]> = (0..s.ncon as usize)
            // SAFETY: the contact list holds ncon contacts.
            .map(|c| unsafe { (*s.contact.add(c)).geom })
            .collect();
        let info: serde_json::Map<String, serde_json::Value> = if kind == "step" {
            keys.iter()
                .map(|k| (k.to_string(), env.step_info().scalar(k).unwrap().into()))
                .collect()
        } else {
            Default::default()
        };
        let derived = |d: &envc::mujoco_rs::mujoco_c::mjData| {
            serde_json::json!({
                "qpos": arr(d.qpos, nq), "qvel": arr(d.qvel, nv),
                "cvel": arr(d.cvel, nbody * 6), "subtree_com": arr(d.subtree_com, nbody * 3),
                "site_xpos": arr(d.site_xpos, nsite * 3), "site_xmat": arr(d.site_xmat, nsite * 9),
                "xipos": arr(d.xipos, nbody * 3), "ximat": arr(d.ximat, nbody * 9),
            })
        };
        serde_json::json!({
            "kind": kind, "action": action, "reward": reward, "done": done, "obs": env.obs(),
            "fresh": derived(d), "stale": derived(s), "contacts": contacts, "info": info,
            "ctrl": arr(d.ctrl, nu),
        })
    };
    let mut rng = NumpyRng::from_seed(77);
    let mut rows = vec![];
    let zero = vec![0.0; nu];
    env.reset(Some(5));
    stale.reset(Some(5));
    rows.push(row(&env, &stale, "reset", &zero, 0.0, false));
    for steps in 0..900 {
        // Small actions keep it walking-ish; large ones make it fall, and the largest drive the
        // joints past their soft limits.
        let amp = match steps {
            0..450 => 0.5,
            450..700 => 3.0,
            _ => 8.0,
        };
        let a: Vec<f64> = (0..nu).map(|_| rng.uniform(-amp, amp)).collect();
        // What numpy needs to replay the step's physics substeps with MuJoCo itself.
        let pre = {
            let d = stale.data();
            serde_json::json!({
                "qpos": arr(d.qpos, nq), "qvel": arr(d.qvel, nv),
                "qacc_warmstart": arr(d.qacc_warmstart, nv), "time": d.time,
            })
        };
        let s = env.step(&a).unwrap();
        let (r, term, done) = (s.reward, s.terminated, s.terminated || s.truncated);
        let t = stale.step(&a).unwrap();
        assert_eq!((t.reward.to_bits(), t.terminated), (r.to_bits(), term));
        assert_eq!(env.state(), stale.state(), "the forward changed the state");
        let mut step_row = row(&env, &stale, "step", &a, r, term);
        step_row["pre"] = pre;
        rows.push(step_row);
        if done {
            env.reset(None);
            stale.reset(None);
            rows.push(row(&env, &stale, "reset", &zero, 0.0, false));
        }
    }
    let dump = dir.join("rollout.json");
    std::fs::write(&dump, serde_json::to_string(&rows).unwrap()).unwrap();
    let out = std::process::Command::new(&py)
        .arg(format!("{ROOT}/tests/reference/mjlab_terms.py"))
        .arg(robot)
        .arg(&dump)
        .arg(dir.join("model.mjb"))
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out.stdout);
    eprintln!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "numpy disagrees");
    assert!(text.contains("all terms agree"), "{text}");
}
