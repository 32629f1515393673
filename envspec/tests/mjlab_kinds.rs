//! The spec features mjlab's velocity tasks need, over the flat G1 example: per-joint action
//! scales, posture widths by speed regime, solver options, geom contact properties, feet
//! clearance, landings, self contacts and command-speed gates resolve to what the spec says; each
//! mistake is a located, coded error.

use std::path::{Path, PathBuf};

use envspec::ir::{LeggedTerm, SolverOption, TermKind};
use envspec::{Code, Diagnostics, ResolvedSpec, load};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("root")
        .to_path_buf()
}

/// The flat G1 example with each `(from, to)` replaced once, loaded from a temporary file.
fn g1(test: &str, edits: &[(&str, &str)]) -> Result<ResolvedSpec, Diagnostics> {
    let original = repo().join("specs/examples/mjlab_velocity_flat_g1.toml");
    let mut text = std::fs::read_to_string(&original).expect("the G1 spec");
    for (from, to) in edits {
        assert_eq!(text.matches(from).count(), 1, "`{from}` must occur once");
        text = text.replacen(from, to, 1);
    }
    let p = std::env::temp_dir().join(format!(
        "envc-mjlab-kinds-{}-{test}.toml",
        std::process::id()
    ));
    std::fs::write(&p, absolute_model(&text)).expect("write the spec");
    let r = load(&p, &[]);
    let _ = std::fs::remove_file(&p);
    r
}

/// A spec's text with its repository-relative model path made absolute, to be written outside the
/// repository: a file written (even briefly) under `specs/` makes cargo rebuild envspec, which
/// embeds that directory, and everything above it.
fn absolute_model(text: &str) -> String {
    text.replace(
        "\"../../assets/",
        &format!("\"{}/assets/", repo().display()),
    )
}

/// The one error of a broken edit: (code, line of the edited text, message).
fn error(test: &str, from: &str, to: &str) -> (Code, bool, String) {
    let d = match g1(test, &[(from, to)]) {
        Ok(_) => panic!("{test}: accepted"),
        Err(d) => d,
    };
    assert_eq!(d.len(), 1, "{test}: {d}");
    let e = &d.0[0];
    let original =
        std::fs::read_to_string(repo().join("specs/examples/mjlab_velocity_flat_g1.toml")).unwrap();
    let line = original[..original.find(from).unwrap()]
        .matches('\n')
        .count()
        + 1;
    let at = e.position().expect("a position");
    let on_line = at.rsplit(':').nth(1) == Some(&line.to_string());
    (e.code, on_line, e.message.clone())
}

fn term<'a>(r: &'a ResolvedSpec, name: &str) -> &'a LeggedTerm {
    match &r.reward.iter().find(|t| t.name == name).expect(name).kind {
        TermKind::Legged(l) => l,
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn the_g1_example_resolves_scales_widths_and_solver_options() {
    let r = g1("resolves", &[]).expect("resolves");
    let a = r.actions.as_ref().expect("[actions]");
    // G1_ACTION_SCALE in actuator (joint) order: left hip pitch (7520-14), hip roll (7520-22),
    // hip yaw (7520-14), knee (7520-22), ankle pitch and roll (2 × 5020); … wrists (4010).
    assert_eq!(a.scale.len(), 29);
    assert_eq!(
        a.scale[..6],
        [
            0.5475464629911068,
            0.35066146637882434,
            0.5475464629911068,
            0.35066146637882434,
            0.43857731392336724,
            0.43857731392336724
        ]
    );
    assert_eq!(a.scale[28], 0.07450087032950714);
    let LeggedTerm::Posture {
        thresholds, sigma, ..
    } = term(&r, "pose")
    else {
        panic!("pose is a posture")
    };
    assert_eq!(*thresholds, [0.05, 1.5]);
    // Standing: 0.05 everywhere; walking and running by pattern (left knee is joint 3).
    assert_eq!(sigma[0], vec![0.05; 29]);
    assert_eq!((sigma[1][3], sigma[2][3]), (0.35, 0.6));
    assert_eq!(
        r.model_edits.solver,
        [
            (SolverOption::Iterations, 10.0),
            (SolverOption::LsIterations, 20.0),
            (SolverOption::CcdIterations, 50.0)
        ]
    );
    let LeggedTerm::FeetClearance {
        height,
        target,
        max_height,
        gate,
        ..
    } = term(&r, "foot_clearance")
    else {
        panic!("foot_clearance")
    };
    assert_eq!((height.len(), *target, *max_height), (2, 0.1, 1.0));
    assert_eq!(gate.as_ref().expect("a gate").command.len(), 2);
    // FULL_COLLISION: every collision geom (later rows win), the 14 foot capsules last.
    let feet: Vec<_> = r
        .model_edits
        .geoms
        .iter()
        .filter(|g| g.geom.contains("_foot"))
        .collect();
    assert_eq!(feet.len(), 14);
    assert_eq!(feet[0].ints, [Some(1), Some(1), Some(3), Some(1)]);
    assert_eq!(feet[0].friction, [0.6]);
    let pelvis = r
        .model_edits
        .geoms
        .iter()
        .find(|g| g.geom == "pelvis_collision");
    assert_eq!(
        pelvis.expect("pelvis").ints,
        [Some(1), Some(1), Some(1), Some(0)]
    );
    // upright: the tracking kernel with `zero` alone.
    let LeggedTerm::Tracking { source, zero, .. } = term(&r, "upright") else {
        panic!("upright")
    };
    assert!(source.is_empty());
    assert_eq!(
        zero.as_ref().expect("zero").text,
        "site_gravity[torso][0:2]"
    );
}

#[test]
fn posture_mistakes_are_located_errors() {
    let cases: &[(&str, &str, &str, Code, &str)] = &[
        (
            "std_nothing",
            r#"{ "*" = 0.05 },"#,
            r#"{ "*" = 0.05, "*elbw*" = 0.1 },"#,
            Code::E0160,
            "`*elbw*` matches none of the 29 joints the posture reads",
        ),
        (
            "std_twice",
            r#"{ "*" = 0.05 },"#,
            r#"{ "*" = 0.05, "*knee*" = 0.1 },"#,
            Code::E0135,
            "joint `left_knee_joint` matches both `*` and `*knee*`",
        ),
        (
            "std_missing",
            r#"{ "*" = 0.05 },"#,
            r#"{ "left_*" = 0.05 },"#,
            Code::E0135,
            "no pattern of this std table matches joint `right_hip_pitch_joint` (13 of 29 joints have a width)",
        ),
        (
            "std_zero",
            r#"{ "*" = 0.05 },"#,
            r#"{ "*" = 0.0 },"#,
            Code::E0135,
            "std 0 for `*`",
        ),
        (
            "thresholds",
            "thresholds = [0.05, 1.5]",
            "thresholds = [0.05]",
            Code::E0135,
            "a posture with 3 std tables needs 2 ascending finite thresholds and a speed; 1 thresholds were given",
        ),
    ];
    for (test, from, to, code, message) in cases {
        let (c, _, m) = error(test, from, to);
        assert_eq!((c, m.as_str()), (*code, *message), "{test}");
    }
}

#[test]
fn action_scale_solver_and_clearance_mistakes_are_located_errors() {
    let cases: &[(&str, &str, &str, Code, &str)] = &[
        (
            "scale_nothing",
            r#""*_elbow_joint" = 0.43857731392336724,"#,
            r#""*_elbo_joint" = 0.43857731392336724,"#,
            Code::E0160,
            "`*_elbo_joint` matches none of the joints of the model's 29 actuators",
        ),
        (
            "scale_uncovered",
            r#""*_wrist_roll_joint" = 0.43857731392336724,"#,
            "",
            Code::E0132,
            "[actions] scale covers 27 of the model's 29 actuators: no row matches actuator `left_wrist_roll_joint`",
        ),
        (
            "iterations",
            "iterations = 10 ",
            "iterations = 1.5 ",
            Code::E0105,
            "physics.iterations is 1.5, not in [1, 1000]",
        ),
        (
            "cone",
            "ccd_iterations = 50",
            "ccd_iterations = 50\ncone = \"eliptic\"",
            Code::E0104,
            "physics.cone is \"eliptic\"",
        ),
        (
            "clearance_target",
            "target_height = 0.1\nmax_height = 1.0                          # foot_height_scan's max_distance:",
            "max_height = 1.0                          # foot_height_scan's max_distance:",
            Code::E0103,
            "missing `target_height` in [reward.foot_clearance]",
        ),
        (
            "swing_target",
            "target_height = 0.1\nmax_height = 1.0                          # foot_height_scan's max_distance\n",
            "target_height = 0.0\nmax_height = 1.0                          # foot_height_scan's max_distance\n",
            Code::E0135,
            "feet_swing_height target_height is 0",
        ),
        (
            "self_subtree_geom",
            r#"subtree = "pelvis""#,
            r#"subtree = "pelvis_collision""#,
            Code::E0134,
            "`pelvis_collision` is a geom, not a body",
        ),
        (
            "self_subtree_missing",
            "subtree = \"pelvis\"\n",
            "",
            Code::E0103,
            "missing `subtree` in [reward.self_collisions]",
        ),
        (
            "geom_nothing",
            r#""*_foot?_collision" = { condim"#,
            r#""*_fot?_collision" = { condim"#,
            Code::E0160,
            "`*_fot?_collision` matches none of the 34 named geoms of",
        ),
        (
            "geom_condim",
            "condim = 3, priority = 1",
            "condim = 2, priority = 1",
            Code::E0161,
            "geom_properties.\"*_foot?_collision\".condim is 2",
        ),
        (
            "geom_friction",
            "friction = [0.6] }",
            "friction = [0.6, 0.1, 0.1, 0.1] }",
            Code::E0161,
            "geom_properties.\"*_foot?_collision\".friction has 4 numbers",
        ),
        (
            "clearance_power",
            "max_height = 1.0                          # foot_height_scan's max_distance:",
            "power = -1.0\nmax_height = 1.0                          # foot_height_scan's max_distance:",
            Code::E0135,
            "feet_clearance power is -1",
        ),
    ];
    for (test, from, to, code, message) in cases {
        let (c, _, m) = error(test, from, to);
        // Messages naming the model file are compared up to it.
        let m = m.split(" .../").next().unwrap_or(&m).to_string();
        let m = m.split(" /").next().unwrap_or(&m).to_string();
        assert_eq!((c, m.as_str()), (*code, *message), "{test}");
    }
    // The errors point at what was written.
    for (test, from, to) in [
        (
            "at_scale",
            r#""*_elbow_joint" = 0.43857731392336724,"#,
            r#""*_elbo_joint" = 0.43857731392336724,"#,
        ),
        ("at_iterations", "iterations = 10 ", "iterations = 0 "),
    ] {
        assert!(error(test, from, to).1, "{test}: not at the edited line");
    }
}
