//! Goal terms of the spec language (`goal_sparse`, `goal_dense`, `goal_reached`,
//! `[termination.*]`, the env-held goal), checked against Gymnasium / Gymnasium-Robotics numbers
//! recorded by tests/reference/record_goal.py (fixtures/goal/), never against envc's own code.

use std::path::{Path, PathBuf};

use envc::maze::MazeEnv;
use envc::{Env, Override};
use envspec::{Code, Spec};
use serde_json::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn fixture(name: &str) -> Value {
    let p = root().join("tests/reference/fixtures/goal").join(name);
    serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap()
}

fn unhex(v: &Value) -> Vec<f64> {
    let s = v.as_str().unwrap();
    let b: Vec<u8> = (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect();
    b.chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn flags(v: &Value) -> Vec<bool> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_bool().unwrap())
        .collect()
}

fn pairs(v: &Value) -> Vec<[f64; 2]> {
    unhex(v).chunks(2).map(|c| [c[0], c[1]]).collect()
}

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

/// The maze's batched `compute_reward` (sparse, dense) and `compute_terminated` (episodic,
/// continuing) — now evaluated from its goal terms — on 3000 goal pairs, a third at distance 0.45
/// up to rounding, where the pairwise and the BLAS norm disagree: the fixture holds such pairs, so
/// a goal term using the wrong norm fails here.
#[test]
fn maze_goal_functions_match_gymnasium_robotics() {
    let rec = fixture("maze_compute.json");
    let profile = envc_tests::recorded_profile(&rec);
    let (a, d) = (pairs(&rec["achieved"]), pairs(&rec["desired"]));
    let episodic_ref = flags(&rec["terminated_episodic"]);
    let sparse_ref = unhex(&rec["sparse"]);
    let split = (0..a.len())
        .filter(|&k| (sparse_ref[k] == 1.0) != episodic_ref[k])
        .count();
    assert!(split > 0, "the fixture must separate the two norms");

    for (id, key) in [
        ("PointMaze_UMaze-v3", "sparse"),
        ("PointMaze_UMazeDense-v3", "dense"),
    ] {
        let mut env = MazeEnv::make(id, &[]).unwrap();
        env.set_numerics(profile);
        let mut out = vec![0.0; a.len()];
        env.compute_reward(&a, &d, &mut out);
        assert_eq!(bits(&out), bits(&unhex(&rec[key])), "{id} compute_reward");
    }
    for (over, key) in [
        ("false", "terminated_episodic"),
        ("true", "terminated_continuing"),
    ] {
        let mut env = MazeEnv::make(
            "PointMaze_UMaze-v3",
            &[Override::text("continuing_task", over)],
        )
        .unwrap();
        env.set_numerics(profile);
        let ours: Vec<bool> = (0..a.len())
            .map(|k| env.compute_terminated(a[k], d[k]))
            .collect();
        assert_eq!(ours, flags(&rec[key]), "continuing_task={over}");
    }
}

fn reacher_goal() -> PathBuf {
    root().join("specs/examples/reacher_goal.toml")
}

/// The recorded Reacher-v5 rollout and its distances, with the threshold that is first reached on
/// the step of the smallest distance (steps only: the reset is event 0).
struct Rollout {
    rec: Value,
    dp: Vec<f64>,
    db: Vec<f64>,
    threshold: f64,
    reach_event: usize,
}

fn rollout() -> Rollout {
    let rec = fixture("reacher_rollout.json");
    let (dp, db) = (unhex(&rec["d_pairwise"]), unhex(&rec["d_blas"]));
    let reach_event = (1..db.len())
        .min_by(|&i, &j| db[i].total_cmp(&db[j]))
        .unwrap();
    Rollout {
        threshold: db[reach_event],
        rec,
        dp,
        db,
        reach_event,
    }
}

fn run_reacher(r: &Rollout, overrides: &[Override], mut each: impl FnMut(usize, envc::Step<'_>)) {
    let mut env = Env::from_spec_file(reacher_goal(), overrides).unwrap();
    env.set_numerics(envc_tests::recorded_profile(&r.rec));
    let obs = r.rec["obs"].as_array().unwrap();
    let (o, info) = env.reset(Some(r.rec["seed"].as_u64().unwrap()));
    assert_eq!(bits(o), bits(&unhex(&obs[0])), "reset obs");
    let success = info.scalar("success").unwrap();
    assert_eq!(
        success,
        (r.db[0] <= r.threshold) as u8 as f64,
        "reset success"
    );
    let actions = unhex(&r.rec["actions"]);
    for (k, a) in actions.chunks(2).enumerate() {
        let s = env.step(a).unwrap();
        assert_eq!(bits(s.obs), bits(&unhex(&obs[k + 1])), "step {k} obs");
        let done = s.terminated;
        each(k + 1, s);
        if done {
            return;
        }
    }
}

/// The reaching arm of specs/examples/reacher_goal.toml: sparse reward from the pairwise norm,
/// `success` and termination from the BLAS norm, against the distances Gymnasium's Reacher-v5
/// reports for the same seed and actions; the episode ends on the first step that reaches.
#[test]
fn reacher_goal_sparse_reward_and_termination() {
    let r = rollout();
    let th = Override::value("goal_threshold", envc::ParamValue::Float(r.threshold));
    let mut last = 0;
    run_reacher(&r, &[th], |e, s| {
        let want: f64 = if r.dp[e] <= r.threshold { 1.0 } else { 0.0 };
        assert_eq!(s.reward.to_bits(), want.to_bits(), "event {e} reward");
        assert_eq!(s.terminated, r.db[e] <= r.threshold, "event {e} terminated");
        let success = s.info.scalar("success").unwrap();
        assert_eq!(success, (r.db[e] <= r.threshold) as u8 as f64, "event {e}");
        last = e;
    });
    assert_eq!(last, r.reach_event, "the episode ends on the reaching step");
    assert!(last > 1, "the fixture reaches after a few steps");
}

/// `dense_reward = true`: the reward is Reacher-v5's `np.exp(-d)` bit for bit on every step, and
/// with `terminate_on_reach = false` nothing terminates.
#[test]
fn reacher_goal_dense_reward() {
    let r = rollout();
    let ex = unhex(&r.rec["exp"]);
    let mut n = 0;
    let ov = [
        Override::text("dense_reward", "true"),
        Override::text("terminate_on_reach", "false"),
        Override::value("goal_threshold", envc::ParamValue::Float(r.threshold)),
    ];
    run_reacher(&r, &ov, |e, s| {
        assert_eq!(s.reward.to_bits(), ex[e].to_bits(), "event {e} reward");
        assert!(!s.terminated);
        n += 1;
    });
    assert_eq!(n, 40);
}

fn with_text(edit: impl Fn(&str) -> String) -> Result<envspec::ResolvedSpec, envspec::Diagnostics> {
    let path = reacher_goal();
    let text = edit(&std::fs::read_to_string(&path).unwrap());
    envspec::resolve(&Spec::parse(&path, text)?, &[])
}

/// `desired = "goal"`: the term reads the env-held goal vector. Achieved is the target's slide
/// joints (the reference's observation `obs[4:6]`), the goal is put 0.01 / 0.03 away on both
/// axes: d = 0.01·√2 reaches the 0.02 threshold, 0.03·√2 does not.
#[test]
fn env_held_goal_vector() {
    let spec = with_text(|t| {
        t.replacen(
            "achieved = \"xpos[fingertip][0:2]\"\ndesired = \"xpos[target][0:2]\"\nthreshold = \"goal_threshold\"\nwhen = \"!dense_reward\"",
            "achieved = \"qpos[2:4]\"\ndesired = \"goal\"\nthreshold = 0.02",
            1,
        )
    })
    .unwrap();
    assert_eq!(spec.goal_dim, 2);
    let r = rollout();
    let obs0 = unhex(&r.rec["obs"][0]);
    let mut env = Env::new(std::sync::Arc::new(spec)).unwrap();
    for (offset, want) in [(0.01, 1.0), (0.03, 0.0)] {
        env.reset(Some(r.rec["seed"].as_u64().unwrap()));
        env.goal_mut()
            .copy_from_slice(&[obs0[4] + offset, obs0[5] - offset]);
        let s = env.step(&[0.0, 0.0]).unwrap();
        assert_eq!(s.reward, want, "goal {offset} away");
    }
}

/// The maze's goal task is exactly these spec-language tables (docs/maze.md) over its robot.
#[test]
fn maze_goal_task_is_spec_language() {
    let point = root().join("specs/robotics/maze/point.toml");
    let base = std::fs::read_to_string(&point).unwrap();
    for (kind, threshold_line) in [("goal_sparse", "threshold = 0.45\n"), ("goal_dense", "")] {
        let text = format!(
            "{base}\n[reward.goal]\nkind = \"{kind}\"\nachieved = \"qpos[0:2]\"\ndesired = \"goal\"\n{threshold_line}\n\
             [termination.goal_reached]\nkind = \"goal_reached\"\nachieved = \"qpos[0:2]\"\ndesired = \"goal\"\nthreshold = 0.45\n"
        );
        let spec = envspec::resolve(&Spec::parse(&point, text).unwrap(), &[]).unwrap();
        let mut env = MazeEnv::make(
            "PointMaze_UMaze-v3",
            &[
                Override::text("continuing_task", "false"),
                Override::text(
                    "reward_type",
                    if kind == "goal_dense" {
                        "dense"
                    } else {
                        "sparse"
                    },
                ),
            ],
        )
        .unwrap();
        env.set_numerics(env.numerics());
        let task = env.goal_task();
        let goal = spec.reward.iter().find(|t| t.name == "goal").unwrap();
        assert_eq!(
            format!("{:?}", goal.kind),
            format!("{:?}", task.reward.kind)
        );
        assert_eq!(
            format!("{:?}", spec.termination[0].reached),
            format!("{:?}", task.reached)
        );
        assert_eq!(
            format!("{:?}", env.robot().spec().termination[0].reached),
            format!("{:?}", task.reached)
        );
    }
}

fn code_of(edit: impl Fn(&str) -> String) -> Vec<Code> {
    match with_text(edit) {
        Ok(_) => vec![],
        Err(d) => d.0.iter().map(|d| d.code).collect(),
    }
}

#[test]
fn bad_goal_terms_have_codes() {
    let sparse =
        "desired = \"xpos[target][0:2]\"\nthreshold = \"goal_threshold\"\nwhen = \"!dense_reward\"";
    let cases: [(&str, String, Code); 6] = [
        (
            "desired of another length",
            sparse.replacen("xpos[target][0:2]", "xpos[target]", 1),
            Code::E0801,
        ),
        (
            "unknown norm",
            format!("{sparse}\nnorm = \"euclid\""),
            Code::E0802,
        ),
        (
            "negative threshold",
            sparse.replacen("\"goal_threshold\"", "-0.1", 1),
            Code::E0803,
        ),
        (
            "missing threshold",
            sparse.replacen("threshold = \"goal_threshold\"\n", "", 1),
            Code::E0103,
        ),
        (
            "missing desired",
            sparse.replacen("desired = \"xpos[target][0:2]\"\n", "", 1),
            Code::E0103,
        ),
        (
            "goal vectors of two lengths",
            format!(
                "{}\n[info.other]\nkind = \"goal_reached\"\nachieved = \"qpos[0:3]\"\ndesired = \"goal\"\nthreshold = 1.0\n",
                sparse.replacen("\"xpos[target][0:2]\"", "\"goal\"", 1)
            ),
            Code::E0801,
        ),
    ];
    for (what, new, code) in cases {
        let got = code_of(|t| t.replacen(sparse, &new, 1));
        assert_eq!(got, vec![code], "{what}");
    }
    let empty = code_of(|t| {
        t.replacen(
            "achieved = \"xpos[fingertip][0:2]\"\ndesired = \"xpos[target][0:2]\"\nthreshold = \"goal_threshold\"\nwhen",
            "achieved = \"qpos[2:2]\"\ndesired = \"xpos[target][0:2]\"\nthreshold = \"goal_threshold\"\nwhen",
            1,
        )
    });
    assert_eq!(empty, vec![Code::E0804]);
    let unknown_kind =
        code_of(|t| t.replacen("kind = \"goal_reached\"", "kind = \"goal_reachd\"", 1));
    assert_eq!(unknown_kind, vec![Code::E0104]);
}

// The typed env generated from the example (codegen handles the goal kinds: its docs list them).
envc::env!(ReacherGoal = "../specs/examples/reacher_goal.toml");

/// The typed env: sparse reward, `terminated` and `info.success` per step, as in
/// `reacher_goal_sparse_reward_and_termination`, through the generated API.
#[test]
fn typed_reacher_goal() {
    let r = rollout();
    let config = ReacherGoalConfig {
        goal_threshold: r.threshold,
        ..Default::default()
    };
    let mut env = ReacherGoal::new(&config).unwrap();
    env.inner_mut()
        .set_numerics(envc_tests::recorded_profile(&r.rec));
    let (_, info) = env.reset(Some(r.rec["seed"].as_u64().unwrap()));
    assert_eq!(info.success, (r.db[0] <= r.threshold) as u8 as f64);
    let actions = unhex(&r.rec["actions"]);
    for (k, a) in actions.chunks(2).enumerate() {
        let e = k + 1;
        let mut act = ReacherGoalAction::zeros();
        act.0.copy_from_slice(a);
        let s = env.step(&act).unwrap();
        let want: f64 = if r.dp[e] <= r.threshold { 1.0 } else { 0.0 };
        assert_eq!(s.reward.to_bits(), want.to_bits(), "event {e}");
        assert_eq!(s.terminated, r.db[e] <= r.threshold, "event {e}");
        assert_eq!(s.info.success, (r.db[e] <= r.threshold) as u8 as f64);
        if s.terminated {
            assert_eq!(e, r.reach_event);
            return;
        }
    }
    panic!("never terminated");
}
