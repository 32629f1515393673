//! Gymnasium-Robotics' Fetch v4 envs (specs/robotics/fetch/: Reach, Push, Slide, PickAndPlace,
//! sparse and dense) against the reference's own numbers, recorded by
//! tests/reference/record_robotics.py (fixtures/fetch/): every observation, achieved and desired
//! goal, reward, `is_success`, termination and truncation of a 60-step rollout (float64 and
//! float32 actions, some outside [−1, 1], through a truncation and a second reset), then the
//! batched `compute_reward` on 256 goal pairs. Each fixture replays under the numerics profile it
//! was recorded with. `ENVC_ROBOTICS_DIR=<dir>` replays a fresh recording instead (`<dir>/fetch/`;
//! the test command's live lane records one under a new seed). The other goal-conditioned
//! families (tests/hand.rs) replay through [`replay`] too.

use std::path::{Path, PathBuf};

use envc::{AnyEnv, Env};
use serde_json::Value;

pub(crate) fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub(crate) fn unhex(v: &Value) -> Vec<f64> {
    envc_tests::unhex(v.as_str().unwrap())
}

pub(crate) fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

const IDS: [&str; 8] = [
    "FetchReach-v4",
    "FetchReachDense-v4",
    "FetchPush-v4",
    "FetchPushDense-v4",
    "FetchSlide-v4",
    "FetchSlideDense-v4",
    "FetchPickAndPlace-v4",
    "FetchPickAndPlaceDense-v4",
];

pub(crate) fn open(id: &str) -> Env {
    match envc::open(id, &[]).unwrap() {
        AnyEnv::Task(e) => e,
        _ => panic!("{id} is not a task"),
    }
}

fn check_event(env: &Env, rec: &Value, k: usize, what: &str) {
    let id = rec["id"].as_str().unwrap();
    assert_eq!(
        bits(env.obs()),
        bits(&unhex(&rec["obs"][k])),
        "{id} {what}: observation"
    );
    let mut achieved = vec![];
    env.achieved_goal(&mut achieved);
    assert_eq!(
        bits(&achieved),
        bits(&unhex(&rec["achieved"][k])),
        "{id} {what}: achieved_goal"
    );
    assert_eq!(
        bits(env.goal()),
        bits(&unhex(&rec["desired"][k])),
        "{id} {what}: desired_goal"
    );
}

/// Replay the recording of `id` (in the fixtures' or `ENVC_ROBOTICS_DIR`'s `family` folder).
pub(crate) fn replay_family(family: &str, id: &str) {
    let dir = std::env::var_os("ENVC_ROBOTICS_DIR")
        .map_or_else(|| root().join("tests/reference/fixtures"), PathBuf::from)
        .join(family);
    let path = dir.join(format!("{id}.json"));
    let rec: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut env = open(id);
    let (nact, ngoal) = (env.act_dim(), env.goal().len());
    env.set_numerics(envc_tests::recorded_profile(&rec));
    let (_, info) = env.reset(Some(rec["seed"].as_u64().unwrap()));
    assert!(info.is_empty(), "{id}: the reset info is empty");
    check_event(&env, &rec, 0, "reset");
    let actions = unhex(&rec["actions"]);
    let (reward, success) = (unhex(&rec["reward"]), unhex(&rec["is_success"]));
    let mut event = 1;
    for (t, a) in actions.chunks(nact).enumerate() {
        let f32 = rec["float32"][t].as_bool().unwrap();
        let s = if f32 {
            let a: Vec<f32> = a.iter().map(|&x| x as f32).collect();
            env.step_f32(&a).unwrap()
        } else {
            env.step(a).unwrap()
        };
        assert_eq!(
            s.reward.to_bits(),
            reward[t].to_bits(),
            "{id} step {t}: reward"
        );
        assert_eq!(
            s.info.scalar("is_success"),
            Some(success[t]),
            "{id} step {t}: is_success"
        );
        assert_eq!(s.info.len(), 1, "{id}: the step info is is_success alone");
        assert_eq!(s.terminated, rec["terminated"][t].as_bool().unwrap());
        let truncated = s.truncated;
        assert_eq!(truncated, rec["truncated"][t].as_bool().unwrap());
        check_event(&env, &rec, event, &format!("step {t}"));
        event += 1;
        if truncated {
            env.reset(None);
            check_event(&env, &rec, event, &format!("reset after step {t}"));
            event += 1;
        }
    }
    let (g, d) = (unhex(&rec["batch_achieved"]), unhex(&rec["batch_desired"]));
    let mut out = vec![0.0; g.len() / ngoal];
    env.compute_reward(&g, &d, &mut out).unwrap();
    assert_eq!(
        bits(&out),
        bits(&unhex(&rec["batch_reward"])),
        "{id}: compute_reward"
    );
}

fn replay(id: &str) {
    replay_family("fetch", id);
}

#[test]
fn fetch_reach() {
    replay(IDS[0]);
    replay(IDS[1]);
}

#[test]
fn fetch_push() {
    replay(IDS[2]);
    replay(IDS[3]);
}

#[test]
fn fetch_slide() {
    replay(IDS[4]);
    replay(IDS[5]);
}

#[test]
fn fetch_pick_and_place() {
    replay(IDS[6]);
    replay(IDS[7]);
}

/// The reward is a function of the goals alone only when every term is a goal term: otherwise
/// `compute_reward` says which term is not (the Python binding raises it as E0170).
#[test]
fn compute_reward_needs_goal_terms() {
    let spec = root().join("specs/gymnasium/reacher.toml");
    let env = Env::from_spec_file(spec, &[]).unwrap();
    let err = env
        .compute_reward(&[0.0; 3], &[0.0; 3], &mut [0.0])
        .unwrap_err();
    assert!(err.contains("no [goal] table"), "{err}");
}

envc::env!(FetchPush = "../specs/robotics/fetch/push.toml");

/// The typed env of a manipulation spec: a Cartesian action of 4 (`dx`, `dy`, `dz`, `gripper`),
/// the flat observation of 25, the same numbers as the dynamic env (the goal dict's other two
/// entries are the inner env's `achieved_goal` and `goal`).
#[test]
fn typed_fetch_push() {
    assert_eq!(FetchPushAction::ACT_DIM, 4);
    assert_eq!(FetchPushAction::ACTUATORS, ["dx", "dy", "dz", "gripper"]);
    let mut typed = FetchPush::new(&FetchPushConfig::default()).unwrap();
    let mut dynamic = open("FetchPush-v4");
    typed.reset(Some(7));
    dynamic.reset(Some(7));
    let a = [0.5, -0.25, 0.75, 0.0];
    for _ in 0..5 {
        let s = typed.step(&FetchPushAction::from(a)).unwrap();
        let d = dynamic.step(&a).unwrap();
        assert_eq!(s.reward.to_bits(), d.reward.to_bits());
        assert_eq!(bits(typed.inner().obs()), bits(d.obs));
    }
    assert_eq!(bits(typed.inner().goal()), bits(dynamic.goal()));
}

/// Hostile manipulation values are located, coded errors before anything runs: a settling that
/// would take hours, a pose beyond envc's coordinates, an unknown record, a marker on a 2-D goal.
#[test]
fn hostile_manipulation_tables_are_coded_errors() {
    use envc::envspec::Code;
    let text = std::fs::read_to_string(root().join("specs/robotics/fetch/reach.toml"))
        .unwrap()
        .replace(
            "\"../../../assets/",
            &format!("\"{}/assets/", root().display()),
        );
    let dir = std::env::temp_dir().join(format!("envc-fetch-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, (from, to, code)) in [
        ("settle_steps = 10", "settle_steps = 9999999", Code::E0110),
        (
            "lift = \"gripper_extra_height\"",
            "lift = 1e300",
            Code::E0110,
        ),
        (
            "\"robot0:slide1\" = 0.48",
            "\"robot0:slide1\" = 1e300",
            Code::E0110,
        ),
        ("around = \"grip\"", "around = \"gripp\"", Code::E0170),
        (
            "rotation = [1.0, 0.0, 1.0, 0.0]",
            "rotation = [1.0, 0.0]",
            Code::E0102,
        ),
        (
            "[goal]\nachieved = \"site_xpos[robot0:grip]\"",
            "[goal]\nachieved = \"site_xpos[robot0:grip][0:2]\"\nmarker = \"robot0:mocap\"",
            Code::E0170,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        assert!(text.contains(from), "{from}");
        let p = dir.join(format!("case{i}.toml"));
        std::fs::write(&p, text.replace(from, to)).unwrap();
        let codes: Vec<Code> = match envc::envspec::load(&p, &[]) {
            Ok(_) => vec![],
            Err(d) => d.0.iter().map(|e| e.code).collect(),
        };
        assert!(codes.contains(&code), "{to}: {codes:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
