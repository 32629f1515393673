//! Numbers that make a spec or model meaningless: infinite control ranges, NaN and infinite
//! values, huge positions and reset draws, option values, and limits on solver iterations,
//! frame skip and episode length.

use std::path::Path;

use super::{Edits, ROOT, Scratch, envc, refused, s};

#[test]
fn an_infinite_control_range_in_the_model_is_refused_not_a_panic() {
    let dir = Scratch::new("ctrlrange");
    for range in ["-1e308 1e308", "-inf inf", "-1e39 1e39"] {
        let spec = dir.spec(
            "hopper.toml",
            &[],
            &[(
                r#"gear="200" ctrllimited="true" ctrlrange="-1 1""#,
                &format!(r#"gear="200" ctrllimited="true" ctrlrange="{range}""#),
            )],
        );
        for cmd in [
            &["run", s(&spec), "--episodes", "1"][..],
            &["check", "--compile", s(&spec)],
            &[
                "collect",
                s(&spec),
                "--dataset-id",
                "x/y-v0",
                "--episodes",
                "1",
                "--policy",
                "random",
            ],
        ] {
            let text = refused(&envc(cmd), "E1003");
            assert!(
                text.contains("actuator #0 (on joint `thigh_joint`)")
                    && text.contains(&format!("ctrlrange [{range}]")),
                "{text}"
            );
        }
    }
}

#[test]
fn an_infinite_control_range_in_the_spec_is_located() {
    let dir = Scratch::new("spec-ctrlrange");
    let arm = std::fs::read_to_string(Path::new(ROOT).join("tests/fixtures/urdf/reach_arm.toml"))
        .unwrap();
    std::fs::copy(
        Path::new(ROOT).join("tests/fixtures/urdf/arm.urdf"),
        dir.0.join("arm.urdf"),
    )
    .unwrap();
    let spec = dir.0.join("arm.toml");
    std::fs::write(
        &spec,
        arm.replace("ctrlrange = [-1.0, 1.0]", "ctrlrange = [-inf, inf]"),
    )
    .unwrap();
    let text = refused(&envc(&["check", s(&spec)]), "E0105");
    assert!(text.contains("arm.toml:25:13"), "{text}");
    std::fs::write(&spec, arm.replace("gear = \"motor_gear\"", "gear = inf")).unwrap();
    let text = refused(&envc(&["check", s(&spec)]), "E0105");
    assert!(
        text.contains("arm.toml:24:8") && text.contains("must be a finite number"),
        "{text}"
    );
}

#[test]
fn solver_iterations_have_a_limit() {
    let dir = Scratch::new("solver");
    for (iterations, code, what) in [
        (
            "100000",
            "E0105",
            "physics.iterations is 100000, not in [1, 1000]",
        ),
        ("0", "E0105", "physics.iterations is 0, not in [1, 1000]"),
    ] {
        let spec = dir.spec(
            "hopper.toml",
            &[(
                "[params]",
                &format!("[physics]\niterations = {iterations}\n\n[params]"),
            )],
            &[],
        );
        let text = refused(&envc(&["check", s(&spec)]), code);
        assert!(text.contains(what), "{text}");
    }
}

#[test]
fn frame_skip_and_episode_length_have_limits_in_the_spec_and_in_overrides() {
    let dir = Scratch::new("steps");
    let spec = dir.spec("hopper.toml", &[], &[]);
    for (set, code, what) in [
        ("frame_skip=1000000000", "E0110", "limit of 1000"),
        ("frame_skip=0", "E0105", "positive"),
        ("max_episode_steps=2147483648", "E0110", "limit of 10000000"),
        ("max_episode_steps=-1", "E0105", "≥ 0"),
    ] {
        for cmd in [
            &["check", "--compile", s(&spec), "--set", set][..],
            &["run", s(&spec), "--set", set],
        ] {
            let text = refused(&envc(cmd), code);
            assert!(text.contains(what) && text.contains("override"), "{text}");
        }
    }
    let spec = dir.spec(
        "hopper.toml",
        &[("default = 4,", "default = 1000000000,")],
        &[],
    );
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("hopper.toml:10:"), "{text}");
}

#[test]
fn nan_and_infinite_values_are_refused_where_they_make_a_spec_meaningless() {
    let dir = Scratch::new("nan");
    let cases: [(Edits, &str, &str); 3] = [
        (
            &[("weight = \"ctrl_cost_weight\"", "weight = nan")],
            "E0105",
            "weight is NaN",
        ),
        (
            &[("default = [0.7, inf]", "default = [nan, nan]")],
            "E0105",
            "is NaN",
        ),
        (
            &[("weight = \"ctrl_cost_weight\"", "weight = -inf")],
            "E0105",
            "must be a finite number",
        ),
    ];
    for (edit, code, what) in cases {
        let spec = dir.spec("hopper.toml", edit, &[]);
        let text = refused(&envc(&["check", s(&spec)]), code);
        assert!(
            text.contains(what) && text.contains("hopper.toml:"),
            "{text}"
        );
    }
    let text = refused(
        &envc(&["run", "Hopper-v5", "--set", "ctrl_cost_weight=nan"]),
        "E0105",
    );
    assert!(
        text.contains("override of `ctrl_cost_weight` is NaN"),
        "{text}"
    );
    let text = refused(
        &envc(&["run", "Hopper-v5", "--set", "ctrl_cost_weight=inf"]),
        "E0105",
    );
    assert!(
        text.contains("inf") && text.contains("ctrl_cost_weight"),
        "{text}"
    );
    let text = refused(
        &envc(&[
            "run",
            "Hopper-v5",
            "--set",
            "ctrl_cost_weight=0.1",
            "--set",
            "ctrl_cost_weight=0.2",
        ]),
        "E0205",
    );
    assert!(text.contains("more than once"), "{text}");
    // Layers are not duplicates: a user's override replaces a bundled id's own (the maze family's
    // camera), and a family's replaces its spec's `robot_params`.
    let o = envc(&[
        "run",
        "PointMaze_Large-v3",
        "--episodes",
        "1",
        "--set",
        "default_camera_config={distance=5.0}",
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn non_finite_or_huge_model_positions_are_refused() {
    let dir = Scratch::new("positions");
    for pos in ["1e308 0 0", "nan 0 0", "0 0 1e7"] {
        let spec = dir.spec(
            "hopper.toml",
            &[],
            &[(
                r#"<body name="torso" pos="0 0 1.25">"#,
                &format!(r#"<body name="torso" pos="{pos}">"#),
            )],
        );
        let text = refused(&envc(&["run", s(&spec), "--episodes", "1"]), "E1003");
        assert!(text.contains("body `torso`"), "{text}");
    }
}

#[test]
fn reset_draws_beyond_the_coordinate_limit_are_refused() {
    let text = refused(
        &envc(&[
            "run",
            "Hopper-v5",
            "--set",
            "reset_noise_scale=1e300",
            "--episodes",
            "1",
        ]),
        "E0110",
    );
    assert!(
        text.contains("[reset.qpos]: a draw as large as 1e300")
            && text.contains("hopper.toml:76:9"),
        "{text}"
    );
}

#[test]
fn option_numbers_must_be_finite_and_the_timestep_positive() {
    let dir = Scratch::new("option");
    for (option, attr) in [
        (r#"<option timestep="0"/>"#, "timestep"),
        (r#"<option timestep="-1"/>"#, "timestep"),
        (r#"<option timestep="nan"/>"#, "timestep"),
        (r#"<option timestep="1e10"/>"#, "timestep"),
        (r#"<option gravity="nan 0 -9.81"/>"#, "gravity"),
        (r#"<option wind="0 inf 0"/>"#, "wind"),
    ] {
        let spec = dir.spec(
            "hopper.toml",
            &[],
            &[("<worldbody>", &format!("{option}\n  <worldbody>"))],
        );
        let text = refused(&envc(&["run", s(&spec), "--episodes", "1"]), "E0105");
        assert!(
            text.contains(&format!("<option {attr}=")) && text.contains("model.xml:"),
            "{text}"
        );
    }
}
