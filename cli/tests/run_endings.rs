//! `envc run` says why episodes ended: the health check, the element that failed it and its
//! value; and when the reset state already fails a check, it says so (a biped whose
//! slide-joint root starts at z = 0 terminates at once, and the summary says why).

use std::process::Command;

fn run(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn a_reset_state_that_fails_a_check_is_named() {
    // Hopper starts with its root at z = 1.25 (± reset noise 0.005): outside [2, 3].
    let out = run(&[
        "run",
        "Hopper-v5",
        "--episodes",
        "3",
        "--set",
        "healthy_z_range=[2.0, 3.0]",
    ]);
    assert!(out.contains("3 episodes, 3 steps (3 terminated)"), "{out}");
    let line = out
        .lines()
        .find(|l| l.contains("terminated 3× by health check `height`"))
        .unwrap_or_else(|| panic!("no ending line in\n{out}"));
    let value: f64 = line
        .split("qpos[rootz] = ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no value in {line}"));
    assert!((1.2..1.3).contains(&value), "{line}");
    assert!(
        out.contains("warning: the reset state already fails health check `height`"),
        "{out}"
    );
}

#[test]
fn a_healthy_start_gets_no_warning() {
    let out = run(&["run", "Hopper-v5", "--episodes", "2", "--seed", "1"]);
    assert!(out.contains("by health check `"), "{out}");
    assert!(!out.contains("warning"), "{out}");
}

/// `--episodes 0` is an honest summary, not `min inf max -inf`; one episode is one
/// episode, not "1 episodes".
#[test]
fn no_episodes_and_one_episode_are_said_as_such() {
    let out = run(&["run", "Hopper-v5", "--episodes", "0"]);
    assert_eq!(out, "Hopper-v5: no episodes run (--episodes 0)\n");
    let out = run(&["run", "Hopper-v5", "--episodes", "0", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    assert_eq!(v["episodes"], 0);
    assert!(v["return"].is_null() && v["length"].is_null(), "{out}");
    assert!(!out.contains("inf"), "{out}");
    let out = run(&[
        "run",
        "Hopper-v5",
        "--episodes",
        "1",
        "--set",
        "healthy_z_range=[2.0, 3.0]",
    ]);
    assert!(
        out.contains("Hopper-v5: 1 episode, 1 step (1 terminated)"),
        "{out}"
    );
}
