//! The CLI's contract at its edges: exit status 0 / 1 (problems found) / 2 (bad arguments,
//! unknown ids, unreadable files), a one-line message, never a panic.

use std::process::{Command, Output};

fn envc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn list_prints_every_bundled_env() {
    let o = envc(&["list"]);
    assert_eq!(o.status.code(), Some(0));
    let out = String::from_utf8_lossy(&o.stdout);
    for id in ["Ant-v5", "Humanoid-v5", "Walker2d-v5"] {
        assert!(out.contains(id), "{out}");
    }
    assert!(
        out.lines()
            .any(|l| l.starts_with("Ant-v5") && l.contains(" 105 ") && l.contains(" 8 ")),
        "{out}"
    );
}

#[test]
fn check_reports_problems_with_status_1() {
    let dir = std::env::temp_dir().join(format!("envc-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spec = dir.join("typo.toml");
    let ant = concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/gymnasium/ant.toml");
    let text = std::fs::read_to_string(ant)
        .unwrap()
        .replace(
            "../../assets",
            concat!(env!("CARGO_MANIFEST_DIR"), "/../assets"),
        )
        .replace("healthy_reward = {", "helthy_reward = {");
    std::fs::write(&spec, text).unwrap();
    let o = envc(&["check", spec.to_str().unwrap(), "--format", "json"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let err = &v[0]["errors"][0];
    assert_eq!(err["code"], "E0201");
    // The error points at the use of the renamed parameter in [reward.healthy].
    let line = std::fs::read_to_string(ant)
        .unwrap()
        .lines()
        .position(|l| l == "weight = \"healthy_reward\"")
        .unwrap()
        + 1;
    assert_eq!(err["line"], line, "{v}");
    assert_eq!(err["help"], "did you mean `helthy_reward`?");
    assert_eq!(
        envc(&["check", "Ant-v5", "Hopper-v5"]).status.code(),
        Some(0)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_2_with_one_line() {
    for args in [
        vec!["show", "Nope-v9"],
        vec![
            "rollout",
            "Ant-v5",
            "--actions",
            "/nonexistent.npy",
            "--out",
            "/tmp/x.npz",
        ],
        vec!["show", "Ant-v5", "--set", "no_such_param=1"],
        vec!["frobnicate"],
    ] {
        let o = envc(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{args:?}");
    }
    let o = envc(&["show", "Hoper-v5"]);
    assert!(
        stderr(&o).contains("did you mean `Hopper-v5`?"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn rollout_rejects_actions_of_the_wrong_width() {
    let dir = std::env::temp_dir().join(format!("envc-cli-w-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let a = dir.join("a.npy");
    ndarray_npy::write_npy(&a, &ndarray::Array2::<f64>::zeros((5, 3))).unwrap();
    let o = envc(&[
        "rollout",
        "Ant-v5",
        "--seed",
        "1",
        "--actions",
        a.to_str().unwrap(),
        "--out",
        dir.join("t.npz").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("has 3 columns but Ant-v5 takes 8 actions"),
        "{}",
        stderr(&o)
    );
    std::fs::remove_dir_all(&dir).ok();
}
