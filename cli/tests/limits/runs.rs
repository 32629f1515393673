//! Runs that would never end or never start: reset conditions that cannot be met or hardly
//! ever are, an env without a time limit, absurd maze sizes and runs of nothing.

use std::path::Path;

use super::{ROOT, Scratch, envc, refused, s};

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
