//! Crashes, aborts, runaway memory and hangs found by fuzzing and by users, each as the user met it: every input
//! here once panicked, aborted, grew past gigabytes or never returned. Each now ends within
//! seconds, under a memory cap, with a coded error at the offending line (`envspec::limits` holds
//! the bounds; docs/limits.md explains them).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// `envc ARGS` under a 4 GB address-space cap and a 180 s wall clock (a regression must fail the
/// test, not the machine).
fn envc(args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(r#"ulimit -v 4000000; exec timeout -s KILL 180 "$0" "$@""#)
        .arg(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc")
}

/// The exit status is 1 (problems found) or 2 (refused) and stderr or stdout names `code`; never
/// a signal (abort, OOM kill, timeout) or a panic.
fn refused(o: &Output, code: &str) -> String {
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "status {:?} (a signal is an abort, an OOM kill or the timeout):\n{text}",
        o.status
    );
    assert!(!text.contains("panicked"), "{text}");
    assert!(
        text.contains(&format!("[{code}]")),
        "expected {code}:\n{text}"
    );
    text
}

/// A scratch directory holding a copy of a bundled spec and its model, edited.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("envc-limits-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
    /// `specs/gymnasium/<spec>` with `edit` applied, its model copied beside it with `edit_xml`.
    fn spec(&self, spec: &str, edit: &[(&str, &str)], edit_xml: &[(&str, &str)]) -> PathBuf {
        let mut text =
            std::fs::read_to_string(Path::new(ROOT).join("specs/gymnasium").join(spec)).unwrap();
        let xml_line = text
            .lines()
            .find(|l| l.starts_with("xml_file"))
            .unwrap()
            .to_string();
        let xml_rel = xml_line.split('"').nth(1).unwrap().to_string();
        let mut xml =
            std::fs::read_to_string(Path::new(ROOT).join("specs/gymnasium").join(&xml_rel))
                .unwrap();
        for (a, b) in edit_xml {
            assert!(xml.contains(a), "{a} not in {xml_rel}");
            xml = xml.replacen(a, b, 1);
        }
        std::fs::write(self.0.join("model.xml"), xml).unwrap();
        text = text.replace(&xml_rel, "model.xml");
        for (a, b) in edit {
            assert!(text.contains(a), "{a} not in {spec}");
            text = text.replacen(a, b, 1);
        }
        let p = self.0.join(spec);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Text replacements applied to a spec.
type Edits<'a> = &'a [(&'a str, &'a str)];

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

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
fn mujoco_sizes_that_would_exhaust_memory_are_refused_before_mujoco_allocates() {
    let dir = Scratch::new("sizes");
    let cases = [
        (r#"<size nuser_geom="999999999"/>"#, "nuser_geom"),
        (r#"<size memory="64G"/>"#, "memory"),
        (
            r#"<asset><texture name="huge" builtin="checker" width="100000" height="100000"/></asset>"#,
            "width",
        ),
        (
            r#"<asset><hfield name="huge" nrow="100000" ncol="100000" size="1 1 1 1"/></asset>"#,
            "nrow",
        ),
    ];
    for (element, attr) in cases {
        let spec = dir.spec(
            "hopper.toml",
            &[],
            &[("<worldbody>", &format!("{element}\n  <worldbody>"))],
        );
        for cmd in [&["check", "--compile", s(&spec)][..], &["show", s(&spec)]] {
            let text = refused(&envc(cmd), "E0110");
            assert!(text.contains(attr) && text.contains("model.xml:"), "{text}");
        }
    }
}

#[test]
fn devices_and_fifos_are_not_read() {
    let dir = Scratch::new("devices");
    let spec = dir.spec("hopper.toml", &[("model.xml", "/dev/zero")], &[]);
    let text = refused(&envc(&["check", "--compile", s(&spec)]), "E0301");
    assert!(text.contains("device, not a regular file"), "{text}");
    let text = refused(&envc(&["check", "/dev/zero"]), "E0600");
    assert!(text.contains("device, not a regular file"), "{text}");
    // A FIFO would block the open until a writer comes.
    let fifo = dir.0.join("fifo.toml");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let text = refused(&envc(&["check", s(&fifo)]), "E0600");
    assert!(text.contains("FIFO"), "{text}");
    // A spec over the size limit (a long comment keeps it valid TOML).
    let big = dir.0.join("big.toml");
    let hopper = std::fs::read_to_string(dir.spec("hopper.toml", &[], &[])).unwrap();
    std::fs::write(&big, format!("{hopper}\n#{}\n", "x".repeat(5 << 20))).unwrap();
    let text = refused(&envc(&["check", s(&big)]), "E0110");
    assert!(text.contains("4 MiB"), "{text}");
}

#[test]
fn a_resample_condition_that_cannot_be_met_is_a_spec_error() {
    let dir = Scratch::new("resample");
    for (cond, code, why) in [
        ("{ norm_below = 0.0 }", "E0110", "never below 0"),
        ("{ norm_below = -1.0 }", "E0110", "never below -1"),
        ("{ norm_below = nan }", "E0105", "NaN"),
        ("{ norm_below = 0.01 }", "E0110", "smallest norm"),
    ] {
        // Reacher's goal is drawn from [-0.2, 0.2]²; the last case also moves it away from 0.
        let low = if why == "smallest norm" {
            "low = 0.1\nhigh = 0.2\nmode = \"set\""
        } else {
            "low = -0.2\nhigh = 0.2\nmode = \"set\""
        };
        let spec = dir.spec(
            "reacher.toml",
            &[
                ("low = -0.2\nhigh = 0.2\nmode = \"set\"", low),
                (
                    "resample_until = { norm_below = 0.2 }",
                    &format!("resample_until = {cond}"),
                ),
            ],
            &[],
        );
        for cmd in [
            &["check", "--compile", s(&spec)][..],
            &["run", s(&spec), "--episodes", "1"],
        ] {
            let text = refused(&envc(cmd), code);
            assert!(
                text.contains(why) && text.contains("reacher.toml:61:"),
                "{text}"
            );
        }
    }
}

#[test]
fn a_reset_condition_that_is_merely_improbable_gives_up_with_e1104() {
    // Possible (the box touches the ball) but with probability ~1e-30 per draw.
    let dir = Scratch::new("improbable");
    let spec = dir.spec(
        "reacher.toml",
        &[
            (
                "low = -0.2\nhigh = 0.2\nmode = \"set\"",
                "low = -1e6\nhigh = 1e6\nmode = \"set\"",
            ),
            (
                "resample_until = { norm_below = 0.2 }",
                "resample_until = { norm_below = 1e-9 }",
            ),
        ],
        &[],
    );
    let text = refused(&envc(&["run", s(&spec), "--episodes", "1"]), "E1104");
    assert!(
        text.contains("[reset.goal]") && text.contains("1000000 times"),
        "{text}"
    );
}

#[test]
fn an_env_without_a_time_limit_needs_max_steps() {
    let text = refused(&envc(&["run", "Point-v0"]), "E1401");
    assert!(text.contains("--max-steps"), "{text}");
    let text = refused(
        &envc(&[
            "collect",
            "Point-v0",
            "--dataset-id",
            "tt/point-v0",
            "--episodes",
            "1",
            "--root",
            "/nonexistent-envc-root",
        ]),
        "E1401",
    );
    assert!(text.contains("--set max_episode_steps=N"), "{text}");
    let o = envc(&[
        "run",
        "Point-v0",
        "--episodes",
        "2",
        "--max-steps",
        "30",
        "--format",
        "json",
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["steps"], 60);
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

#[test]
fn a_rollout_too_long_to_hold_in_memory_is_refused_before_stepping() {
    let out = std::env::temp_dir().join(format!("envc-limits-{}-huge.npz", std::process::id()));
    let text = refused(
        &envc(&[
            "rollout",
            "Hopper-v5",
            "--policy",
            "random",
            "--steps",
            "100000000000",
            "--out",
            s(&out),
        ]),
        "E1402",
    );
    // envc's 4 GiB, or half the memory left when a machine has less than 8 GiB free.
    assert!(
        text.contains("beyond envc's limit (4.00 GiB)") || text.contains("beyond half the memory"),
        "{text}"
    );
    assert!(!out.exists());
}

#[test]
fn a_rollout_or_an_episode_beyond_the_memory_left_is_e1402_not_an_abort() {
    let dir = Scratch::new("episode-memory");
    // Under a 600 MB address space: a 300 000-step Humanoid rollout (about 0.8 GiB) aborted with
    // "memory allocation of 729808896 bytes failed"; it is refused before stepping.
    let o = envc_capped(
        600_000,
        &dir.0,
        &[
            "rollout",
            "Humanoid-v5",
            "--policy",
            "zero",
            "--steps",
            "300000",
            "--auto-reset",
            "--out",
            "t.npz",
        ],
    );
    let text = refused(&o, "E1402");
    assert!(
        text.contains("half the memory this process may still allocate"),
        "{text}"
    );
    // A collected episode that never ends grows until the memory left is spent: it stops with
    // E1402 (it aborted), and nothing is published.
    let o = envc_capped(
        600_000,
        &dir.0,
        &[
            "collect",
            "Humanoid-v5",
            "--dataset-id",
            "tt/long-v0",
            "--episodes",
            "1",
            "--format",
            "hdf5",
            "--set",
            "max_episode_steps=10000000",
            "--set",
            "terminate_when_unhealthy=false",
        ],
    );
    let text = refused(&o, "E1402");
    assert!(text.contains("nothing was published"), "{text}");
    assert!(!dir.0.join("datasets/tt/long-v0").exists());
}

#[test]
fn absurd_maze_sizes_and_empty_runs_are_refused_with_a_reason() {
    let dir = Scratch::new("maze");
    let maze = std::fs::read_to_string(Path::new(ROOT).join("specs/robotics/maze/point_maze.toml"))
        .unwrap();
    let maze = maze
        .replace(
            "robot = \"point.toml\"",
            &format!(
                "robot = {:?}",
                format!("{ROOT}/specs/robotics/maze/point.toml")
            ),
        )
        .replace(
            "map = \"maps/umaze.toml\"",
            &format!(
                "map = {:?}",
                format!("{ROOT}/specs/robotics/maze/maps/umaze.toml")
            ),
        );
    for (line, key) in [
        ("position_noise_range = 1e308", "position_noise_range"),
        ("maze_size_scaling = 1e300", "maze_size_scaling"),
    ] {
        let kept: Vec<&str> = maze.lines().filter(|l| !l.starts_with(key)).collect();
        let spec = dir.0.join("maze.toml");
        std::fs::write(&spec, format!("{}\n{line}\n", kept.join("\n"))).unwrap();
        let text = refused(&envc(&["run", s(&spec), "--episodes", "1"]), "E0110");
        assert!(
            text.contains(&format!("`{key}` is")) && text.contains("maze.toml:"),
            "{text}"
        );
    }
    let out = dir.0.join("t.npz");
    let o = envc(&[
        "rollout",
        "Hopper-v5",
        "--policy",
        "zero",
        "--steps",
        "0",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--steps"));
    let o = envc(&[
        "collect",
        "Hopper-v5",
        "--dataset-id",
        "tt/h-v0",
        "--episodes",
        "0",
        "--root",
        s(&dir.0),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--episodes"));
}

/// `envc ARGS` in `cwd` under an address-space cap of `kb` KiB and a 180 s wall clock.
fn envc_capped(kb: u64, cwd: &Path, args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!(
            r#"ulimit -v {kb}; exec timeout -s KILL 180 "$0" "$@""#
        ))
        .arg(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .current_dir(cwd)
        .env("MINARI_DATASETS_PATH", cwd.join("datasets"))
        .output()
        .expect("run envc")
}

#[test]
fn a_model_needing_more_memory_than_allowed_is_a_coded_error_not_an_abort() {
    let dir = Scratch::new("bad-alloc");
    // 10^8 heightfield samples, within envc's limits: MuJoCo's compiler asks for 400 MB in one
    // std::vector, more than a 400 MB address space leaves, and throws std::bad_alloc (which
    // ended the process: "terminating due to uncaught exception").
    let hfield =
        r#"<asset><hfield name="terrain" nrow="10000" ncol="10000" size="1 1 1 1"/></asset>"#;
    let with_hfield = format!("{hfield}\n  <worldbody>");
    let spec = dir.spec("hopper.toml", &[], &[("<worldbody>", &with_hfield)]);
    // A maze compiles its robot's model with its walls added: the same, through the maze.
    let point = Path::new(ROOT).join("specs/robotics/maze");
    let xml = std::fs::read_to_string(Path::new(ROOT).join("assets/robotics/point.xml")).unwrap();
    std::fs::write(
        dir.0.join("point.xml"),
        xml.replacen("<worldbody>", &with_hfield, 1),
    )
    .unwrap();
    let robot = std::fs::read_to_string(point.join("point.toml"))
        .unwrap()
        .replace("../../../assets/robotics/point.xml", "point.xml");
    std::fs::write(dir.0.join("point.toml"), robot).unwrap();
    let maze = std::fs::read_to_string(point.join("point_maze.toml"))
        .unwrap()
        .replace(
            "map = \"maps/umaze.toml\"",
            &format!("map = {:?}", point.join("maps/umaze.toml")),
        );
    let maze_spec = dir.0.join("maze.toml");
    std::fs::write(&maze_spec, maze).unwrap();
    let collect = [
        "collect",
        s(&spec),
        "--dataset-id",
        "x/y-v0",
        "--episodes",
        "1",
        "--policy",
        "random",
    ];
    for cmd in [
        &["check", "--compile", s(&spec)][..],
        &["show", s(&spec)],
        &["run", s(&spec), "--episodes", "1"],
        &collect,
        &["check", "--compile", s(&maze_spec)],
        &["run", s(&maze_spec), "--episodes", "1"],
    ] {
        let o = envc_capped(400_000, &dir.0, cmd);
        let text = refused(&o, "E1001");
        assert!(
            text.contains(
                "MuJoCo threw std::bad_alloc: the model needs more memory than is available"
            ),
            "{cmd:?}: {text}"
        );
        assert!(!text.contains("terminat"), "{cmd:?}: {text}");
        if cmd[0] != "check" {
            // (`check` reports on stdout; the others' errors go to stderr, nothing else is printed)
            assert!(o.stdout.is_empty(), "{cmd:?}: {text}");
        }
        assert!(!dir.0.join("MUJOCO_LOG.TXT").exists(), "{cmd:?}");
    }
}

/// A minimal task spec over `model` (MJCF or URDF) in `dir`.
fn tiny_spec(dir: &Path, model: &str, text: &str) -> PathBuf {
    std::fs::write(dir.join(model), text).unwrap();
    let spec = dir.join(format!("{model}.toml"));
    std::fs::write(
        &spec,
        format!(
            "[env]\nid = \"Deep-v0\"\n\n[params]\nxml_file = {{ default = \"{model}\" }}\n\
             frame_skip = {{ default = 1 }}\nmax_episode_steps = {{ default = 10 }}\n\n\
             [observation.qpos]\nsource = \"qpos\"\n"
        ),
    )
    .unwrap();
    spec
}

#[test]
fn deeply_nested_models_are_refused_not_a_stack_overflow() {
    let dir = Scratch::new("nesting");
    let nested = |open: &str, close: &str, n: usize| open.repeat(n) + &close.repeat(n);
    let cases = [
        (
            "bodies.xml",
            format!(
                "<mujoco><worldbody>{}</worldbody></mujoco>",
                nested(r#"<body><geom size=".01"/>"#, "</body>", 10_000)
            ),
        ),
        (
            "defaults.xml",
            format!(
                "<mujoco><default>{}</default><worldbody><body><freejoint/><geom size=\".1\"/></body></worldbody></mujoco>",
                nested(r#"<default class="c">"#, "</default>", 50_000)
            ),
        ),
        (
            "frames.xml",
            format!(
                "<mujoco><worldbody><body><freejoint/><geom size=\".1\"/>{}</body></worldbody></mujoco>",
                nested("<frame>", "</frame>", 100_000)
            ),
        ),
    ];
    for (model, xml) in &cases {
        let spec = tiny_spec(&dir.0, model, xml);
        for args in [&["check", s(&spec)][..], &["check", "--compile", s(&spec)]] {
            let text = refused(&envc(args), "E0110");
            assert!(text.contains("nested 501 elements deep"), "{model}: {text}");
        }
    }
    // A URDF chain deeper than the limit (its XML is flat).
    let mut urdf = String::from("<robot name=\"chain\">\n");
    for i in 0..=600 {
        urdf += &format!("<link name=\"l{i}\"/>\n");
    }
    for i in 0..600 {
        urdf += &format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n",
            i + 1
        );
    }
    urdf += "</robot>\n";
    let spec = tiny_spec(&dir.0, "chain.urdf", &urdf);
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("link `l500` is 501 links deep"), "{text}");
}

#[test]
fn models_with_more_bodies_than_the_limit_are_refused_before_compiling() {
    let dir = Scratch::new("bodies");
    let flat: String = (0..50_000)
        .map(|i| format!("<body name=\"b{i}\"><geom size=\".01\"/></body>\n"))
        .collect();
    let spec = tiny_spec(
        &dir.0,
        "flat.xml",
        &format!("<mujoco><worldbody>\n{flat}</worldbody></mujoco>"),
    );
    let started = std::time::Instant::now();
    let text = refused(&envc(&["check", "--compile", s(&spec)]), "E0110");
    assert!(text.contains("body number 5001"), "{text}");
    // The 5001st body, on line 5002.
    assert!(text.contains("flat.xml:5002:1"), "{text}");
    assert!(started.elapsed().as_secs() < 20, "{:?}", started.elapsed());
    // 5,000 bodies still compile.
    let ok: String = (0..5_000)
        .map(|i| format!("<body name=\"b{i}\"><geom size=\".01\"/></body>\n"))
        .collect();
    let spec = tiny_spec(
        &dir.0,
        "ok.xml",
        &format!("<mujoco><worldbody>\n{ok}</worldbody></mujoco>"),
    );
    let o = envc(&["check", s(&spec)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A URDF of 20,000 links.
    let mut urdf = String::from("<robot name=\"many\">\n<link name=\"base\"/>\n");
    for i in 0..20_000 {
        urdf += &format!(
            "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"fixed\"><parent link=\"base\"/><child link=\"l{i}\"/></joint>\n"
        );
    }
    urdf += "</robot>\n";
    let spec = tiny_spec(&dir.0, "many.urdf", &urdf);
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("link `l4999`"), "{text}");
    // Bodies a spec adds count with the model's (Hopper has 5 with the world).
    let added: String = (0..5_000)
        .map(|i| format!("[bodies.added{i}]\npos = [0.0, 0.0, 1.0]\n"))
        .collect();
    let spec = dir.spec("hopper.toml", &[], &[]);
    let mut text = std::fs::read_to_string(&spec).unwrap();
    text.push('\n');
    text.push_str(&added);
    std::fs::write(&spec, text).unwrap();
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("[bodies.added4995]"), "{text}");
}

#[test]
fn a_nul_byte_in_an_added_element_name_is_a_spec_error_not_a_panic() {
    let dir = Scratch::new("nul-names");
    let sections = [
        "[sites.\"a\\u0000b\"]\nbody = \"torso\"\n",
        "[bodies.\"a\\u0000b\"]\npos = [0.0, 0.0, 1.0]\n",
        "[bodies.g]\njoints = { \"x\\u0000y\" = \"slide x\" }\n",
        "[geoms.\"a\\u0000b\"]\nbody = \"torso\"\ntype = \"box\"\nsize = [0.1, 0.1, 0.1]\n",
        "[cameras.\"a\\u0000b\"]\npos = [0.0, -1.0, 1.0]\n",
        "[lights.\"a\\u0000b\"]\npos = [0.0, 0.0, 2.0]\n",
        "[actuators.\"a\\u0000b\"]\njoint = \"rootx\"\n",
        "[keyframes.\"a\\u0000b\"]\njoints = { rootz = 0.0 }\n",
    ];
    for (i, section) in sections.iter().enumerate() {
        let spec = dir.spec("hopper.toml", &[], &[]);
        let mut text = std::fs::read_to_string(&spec).unwrap();
        text.push('\n');
        text.push_str(section);
        let spec = dir.0.join(format!("nul{i}.toml"));
        std::fs::write(&spec, text).unwrap();
        for args in [
            &["check", "--compile", s(&spec)][..],
            &["show", s(&spec)],
            &["run", s(&spec), "--episodes", "1"],
        ] {
            let text = refused(&envc(args), "E0102");
            assert!(text.contains("contains a NUL byte"), "{section}: {text}");
        }
    }
}

/// The rough terrain example with `edits`, its model path made absolute, in `dir`.
fn rough_spec(dir: &Path, name: &str, edits: Edits) -> PathBuf {
    let mut text = std::fs::read_to_string(
        Path::new(ROOT).join("specs/examples/mjlab_velocity_rough_go1.toml"),
    )
    .unwrap()
    .replace("\"../../assets/", &format!("\"{ROOT}/assets/"));
    for (a, b) in edits {
        assert!(text.contains(a), "{a} not in the rough spec");
        text = text.replacen(a, b, 1);
    }
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn terrain_work_beyond_its_limits_is_refused_before_anything_is_built() {
    let dir = Scratch::new("terrain-work");
    let cases: [(&str, Edits); 5] = [
        // Billions of stairs boxes: an allocation of 6 GB aborted envc.
        ("stairs", &[("step_width = 0.3", "step_width = 1e-6")]),
        // Default stairs on 1000 m tiles: did not compile in 30 s.
        (
            "tiles",
            &[("tile_size = [8.0, 8.0]", "tile_size = [1000.0, 1000.0]")],
        ),
        // A 4 GiB table of height levels: abort.
        (
            "levels",
            &[(
                "noise = [0.02, 0.10]\nnoise_step = 0.02\n",
                "noise = [-1000.0, 1000.0]\nnoise_step = 1e-6\nvertical_scale = 1e-6\n",
            )],
        ),
        // Saturated integer heights: an index out of bounds.
        (
            "saturation",
            &[(
                "noise_step = 0.02\n",
                "noise_step = 0.02\nvertical_scale = 1e-300\n",
            )],
        ),
        // A slope too tall for its scale: reported at its key, not by MuJoCo at the model.
        ("slope", &[("slope = [0.0, 1.0]", "slope = [0.0, 1000.0]")]),
    ];
    for (name, edits) in cases {
        let edits: Vec<(&str, &str)> = if name == "slope" {
            vec![
                edits[0],
                (
                    "border_width = 0.25\n",
                    "border_width = 0.25\nvertical_scale = 1e-4\n",
                ),
            ]
        } else {
            edits.to_vec()
        };
        let spec = rough_spec(&dir.0, &format!("{name}.toml"), &edits);
        for args in [
            &["check", "--compile", s(&spec)][..],
            &["run", s(&spec), "--episodes", "1"],
        ] {
            let text = refused(&envc(args), "E0110");
            assert!(text.contains(&format!("{}.toml:", name)), "{name}: {text}");
        }
    }
}
