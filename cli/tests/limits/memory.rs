//! Memory: MuJoCo sizes that would exhaust it, rollouts and episodes too long to hold, and a
//! model MuJoCo cannot allocate under an address-space cap.

use std::path::Path;
use std::process::{Command, Output};

use super::{ROOT, Scratch, envc, refused, s};

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
