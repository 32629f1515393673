//! `[commands.*]`, `[actions]` and the legged reward kinds: resolution, located errors with
//! suggestions, and their diff rules. Written over the joystick example and MuJoCo Menagerie's Go1
//! (a checkout beside the repository, see `go1()`), each case one edit of the example.

use std::path::{Path, PathBuf};

use envspec::diff::{Category, diff};
use envspec::{Code, Override, Spec};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn go1() -> String {
    root()
        .join("../shared/models/unitree_go1/scene.xml")
        .display()
        .to_string()
}

/// The joystick spec with each `(old, new)` replaced once, written to a scratch file.
fn joystick(test: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text =
        std::fs::read_to_string(root().join("specs/examples/go1_joystick.toml")).unwrap();
    for (old, new) in edits {
        assert!(text.contains(old), "{old}");
        text = text.replacen(old, new, 1);
    }
    let dir = std::env::temp_dir().join(format!("envspec-commands-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("go1_joystick.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// `line:col` of the first line of the joystick spec holding `pattern` (the spec's own layout may
/// change; the column is the value's within that line).
fn line_col(pattern: &str, col: usize) -> &'static str {
    let text = std::fs::read_to_string(root().join("specs/examples/go1_joystick.toml")).unwrap();
    let line = text[..text.find(pattern).expect(pattern)]
        .matches('\n')
        .count()
        + 1;
    Box::leak(format!("{line}:{col}").into_boxed_str())
}

fn load(p: &Path) -> Result<envspec::ResolvedSpec, envspec::Diagnostics> {
    envspec::load(p, &[Override::text("xml_file", &go1())])
}

/// The single error of a broken spec: (code, line:col, message, help).
fn error(test: &str, edits: &[(&str, &str)]) -> (Code, String, String, Option<String>) {
    let p = joystick(test, edits);
    let d = load(&p).expect_err("the spec is broken");
    let _ = std::fs::remove_dir_all(p.parent().unwrap());
    assert_eq!(d.len(), 1, "{d}");
    let e = d.iter().next().unwrap();
    let pos = e.position().unwrap();
    let at = pos.rsplitn(3, ':').collect::<Vec<_>>();
    (
        e.code,
        format!("{}:{}", at[1], at[0]),
        e.message.clone(),
        e.help.clone(),
    )
}

#[test]
fn the_joystick_resolves() {
    let r = load(&root().join("specs/examples/go1_joystick.toml")).unwrap();
    assert_eq!(r.obs_dim, 48);
    assert_eq!(r.commands.len(), 1);
    let c = &r.commands[0];
    assert_eq!(c.components, ["lin_vel_x", "lin_vel_y", "ang_vel_z"]);
    assert_eq!(
        (c.low.clone(), c.high.clone()),
        (vec![-1.5, -0.8, -1.2], vec![1.5, 0.8, 1.2])
    );
    // 5 s at dt = 0.004 × 5.
    assert_eq!(c.resample_steps, 250);
    let a = r.actions.as_ref().unwrap();
    assert_eq!(
        (a.scale.clone(), a.kp, a.damping, a.range),
        (vec![0.5; 12], Some(35.0), Some(0.5), (-1.0, 1.0))
    );
    // The keyframe pose is taken at each actuator's joint: qpos 7.. for the Go1.
    match &a.default_pose {
        envspec::ir::DefaultPose::Keyframe { name, qposadr } => {
            assert_eq!(name, "home");
            assert_eq!(*qposadr, (7..19).map(Some).collect::<Vec<_>>());
        }
        other => panic!("{other:?}"),
    }
    let names: Vec<&str> = r.reward.iter().map(|t| t.kind_name()).collect();
    for k in [
        "tracking",
        "sum_abs",
        "action_rate",
        "feet_air_time",
        "feet_slip",
        "joint_limits",
    ] {
        assert!(names.contains(&k), "{k}");
    }
}

#[test]
fn errors_are_located_with_suggestions() {
    let (code, at, _, help) = error(
        "e0131",
        &[(
            "source = \"command[base_velocity]\"       # info",
            "source = \"command[base_velocty]\"       # info",
        )],
    );
    assert_eq!(
        (code, at.as_str()),
        (
            Code::E0131,
            line_col("source = \"command[base_velocity]\"", 10)
        )
    );
    assert_eq!(help.as_deref(), Some("did you mean `base_velocity`?"));

    let (code, at, msg, help) = error(
        "e0131c",
        &[(
            "target = \"command[base_velocity].ang_vel_z\"",
            "target = \"command[base_velocity].ang_vel\"",
        )],
    );
    assert_eq!(
        (code, at.as_str()),
        (
            Code::E0131,
            line_col("target = \"command[base_velocity].ang_vel_z\"", 10)
        ),
        "{msg}"
    );
    assert_eq!(help.as_deref(), Some("did you mean `ang_vel_z`?"));

    let (code, at, _, help) = error(
        "e0133",
        &[("default_pose = \"home\"", "default_pose = \"hmoe\"")],
    );
    assert_eq!(
        (code, at.as_str()),
        (Code::E0133, line_col("default_pose = \"home\"", 16))
    );
    assert_eq!(help.as_deref(), Some("did you mean `home`?"));

    let (code, at, _, _) = error(
        "e0130",
        &[("lin_vel_y = [-0.8, 0.8]", "lin_vel_y = [0.8, -0.8]")],
    );
    assert_eq!(
        (code, at.as_str()),
        (Code::E0130, line_col("lin_vel_y = [-0.8, 0.8]", 53))
    );

    let (code, _, msg, _) = error(
        "e0130p",
        &[(
            "standing_probability = { default = 0.1",
            "standing_probability = { default = 1.5",
        )],
    );
    assert_eq!(code, Code::E0130, "{msg}");

    let (code, at, _, help) = error("e0134", &[("floor = \"floor\"", "floor = \"flor\"")]);
    assert_eq!(
        (code, at.as_str()),
        (Code::E0134, line_col("floor = \"floor\"", 9))
    );
    assert_eq!(help.as_deref(), Some("did you mean `floor`?"));

    let (code, at, _, _) = error(
        "e0135",
        &[(
            "source = \"qpos[7:]\"\nfactor",
            "source = \"qpos[0:8]\"\nfactor",
        )],
    );
    assert_eq!(
        (code, at.as_str()),
        (Code::E0135, line_col("source = \"qpos[7:]\"\nfactor", 10))
    );

    let (code, _, _, _) = error("e0135s", &[("sigma = 1.0", "sigma = 0.0")]);
    assert_eq!(code, Code::E0135);

    let (code, at, _, _) = error("e0132", &[("range = [-1.0, 1.0]", "range = [-1.0, inf]")]);
    assert_eq!(
        (code, at.as_str()),
        (Code::E0132, line_col("range = [-1.0, 1.0]", 9))
    );

    // `default_pose` read without [actions].
    let text = std::fs::read_to_string(root().join("specs/examples/go1_joystick.toml")).unwrap();
    let start = text.find("\n[actions]").unwrap() + 1;
    let end = text.find("\n[commands.base_velocity]").unwrap() + 1;
    let cut = &text[start..end];
    let (code, _, msg, _) = error("e0132n", &[(cut, "")]);
    assert_eq!(code, Code::E0132, "{msg}");
}

fn report(test: &str, edits: &[(&str, &str)]) -> envspec::diff::Report {
    let a = root().join("specs/examples/go1_joystick.toml");
    let b = joystick(test, edits);
    let (sa, sb) = (Spec::load(&a).unwrap(), Spec::load(&b).unwrap());
    let rb = load(&b).unwrap();
    let _ = std::fs::remove_dir_all(b.parent().unwrap());
    diff(&sa, &load(&a).unwrap(), &sb, &rb)
}

#[test]
fn diff_puts_command_ranges_in_randomization_and_gains_in_action() {
    let r = report(
        "diff",
        &[
            ("lin_vel_x = [-1.5, 1.5]", "lin_vel_x = [-2.0, 2.0]"),
            ("kp = 35.0", "kp = 50.0"),
            (
                "[reward.action_rate]",
                "[reward.hold]\nkind = \"sum_abs\"\nsource = \"qvel[6:]\"\ncost = true\n\n[reward.action_rate]",
            ),
        ],
    );
    let json = serde_json::to_value(&r).unwrap();
    let changes = json["changes"].as_array().unwrap();
    let find = |rule: &str| {
        changes
            .iter()
            .find(|c| c["rule"] == rule)
            .unwrap_or_else(|| panic!("no {rule} in {json:#}"))
    };
    let range = find("commands-range-changed");
    assert_eq!(range["category"], Category::Randomization.key());
    assert_eq!(range["was"], "[-1.5, 1.5]");
    assert_eq!(range["now"], "[-2, 2]");
    assert!(range["witness"].as_str().unwrap().starts_with("widened"));
    let kp = find("actions-gains-changed");
    assert_eq!(
        (
            kp["category"].as_str(),
            kp["was"].as_str(),
            kp["now"].as_str()
        ),
        (Some("action"), Some("35"), Some("50"))
    );
    assert_eq!(find("reward-term-added")["subject"], "reward.hold");
    // A narrowed range and a schedule change.
    let r = report(
        "diff2",
        &[
            ("ang_vel_z = [-1.2, 1.2]", "ang_vel_z = [-0.5, 0.5]"),
            (
                "standing_probability = { default = 0.1",
                "standing_probability = { default = 0.2",
            ),
        ],
    );
    let json = serde_json::to_value(&r).unwrap();
    let rules: Vec<&str> = json["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["rule"].as_str().unwrap())
        .collect();
    assert!(rules.contains(&"commands-range-changed"), "{rules:?}");
    assert!(rules.contains(&"commands-schedule-changed"), "{rules:?}");
}
