//! The CLI on multi-agent specs: `envc show` (actuators and observation layout per agent),
//! `envc check`, `envc diff` (v1 → v2 is a breaking observation change) and `envc rollout` (global
//! actions in, obs.<agent> / state / reward / terminated / truncated out). Parity of the rollout
//! arrays with the reference is checked by tests/reference/check_mamujoco_rollout.py.

use std::path::Path;
use std::process::{Command, Output};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn envc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_envc"))
        .current_dir(root())
        .args(args)
        .output()
        .expect("run envc")
}

fn text(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
}

#[test]
fn show_prints_each_agents_actuators_and_layout() {
    let o = envc(&[
        "show",
        "specs/mamujoco/walker2d.toml",
        "--set",
        "agent_obsk=0",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("agent_0: 3 actions in [-1, 1], observation 11 float64"),
        "{t}"
    );
    assert!(t.contains("foot_joint           -> action[2]"), "{t}");
    assert!(
        t.contains("[0:1]  k0.foot_joint.qpos  = qpos[foot_joint]"),
        "{t}"
    );
    // Bad overrides are one-line errors (exit 2), not panics.
    let o = envc(&[
        "show",
        "specs/mamujoco/walker2d.toml",
        "--set",
        "agent_conf=9x9",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("E0203"), "{}", text(&o));
}

#[test]
fn check_and_diff() {
    let o = envc(&[
        "check",
        "specs/mamujoco/ant.toml",
        "specs/mamujoco/many_segment_ant_3.toml",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = envc(&[
        "diff",
        "specs/mamujoco/humanoid.toml",
        "specs/mamujoco/humanoid_v2.toml",
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o));
    assert!(text(&o).contains("qpos[abdomen_z] → qpos[abdomen_y]"));
    let o = envc(&["diff", "specs/mamujoco/ant.toml", "specs/mamujoco/ant.toml"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

#[test]
fn rollout_writes_per_agent_arrays() {
    let dir = std::env::temp_dir().join(format!("envc-ma-rollout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let actions = dir.join("a.npy");
    let a =
        ndarray::Array2::<f64>::from_shape_fn((7, 6), |(t, i)| ((t + i) % 3) as f64 * 0.3 - 0.3);
    ndarray_npy::write_npy(&actions, &a).unwrap();
    let out = dir.join("t.npz");
    let o = envc(&[
        "rollout",
        "specs/mamujoco/half_cheetah.toml",
        "--set",
        "agent_conf=6x1",
        "--seed",
        "3",
        "--actions",
        actions.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let mut npz = ndarray_npy::NpzReader::new(std::fs::File::open(&out).unwrap()).unwrap();
    let mut names = npz.names().unwrap();
    names.sort();
    assert_eq!(
        names,
        [
            "envc_version",
            "mujoco_version",
            "obs.agent_0",
            "obs.agent_1",
            "obs.agent_2",
            "obs.agent_3",
            "obs.agent_4",
            "obs.agent_5",
            "reward",
            "state",
            "terminated",
            "truncated"
        ]
    );
    // What made the file: the loaded MuJoCo's version string, as UTF-8 bytes.
    let made: ndarray::Array1<u8> = npz.by_name("mujoco_version").unwrap();
    assert_eq!(made.to_vec(), b"3.17.0");
    let state: ndarray::Array2<f64> = npz.by_name("state").unwrap();
    assert_eq!(state.dim(), (8, 17));
    let o0: ndarray::Array2<f64> = npz.by_name("obs.agent_0").unwrap();
    assert_eq!(o0.dim(), (8, 9));
    // Wrong width: a one-line error.
    let bad = dir.join("b.npy");
    ndarray_npy::write_npy(&bad, &ndarray::Array2::<f64>::zeros((3, 5))).unwrap();
    let o = envc(&[
        "rollout",
        "specs/mamujoco/half_cheetah.toml",
        "--actions",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    std::fs::remove_dir_all(&dir).ok();
}
