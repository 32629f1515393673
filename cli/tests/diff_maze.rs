//! `envc diff` between maze specs: layout changes cell by cell, scalars, the robot's own changes,
//! each with its rule id. The full text is pinned in `cli/tests/diff_golden/maze.txt`
//! (ENVC_BLESS=1 regenerates it; review the change). Cell centres below are computed by hand from
//! Gymnasium-Robotics' `Maze.cell_rowcol_to_xy`: x = (col + 0.5)·s − cols·s/2,
//! y = rows·s/2 − (row + 0.5)·s, here with s = 4 on a 5 × 5 grid.

use std::path::{Path, PathBuf};
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

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

const OLD: &str = "cli/tests/diff_golden/maze/old.toml";
const NEW: &str = "cli/tests/diff_golden/maze/new.toml";

#[test]
fn maze_layout_scalars_and_robot_overrides_are_reported_with_rule_ids() {
    let o = envc(&["diff", OLD, NEW]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(3), "{text}");
    for line in [
        // g at (1, 3) → (3, 3): centres (4, 4) → (4, −4); the c cell removed leaves 1 goal candidate.
        "  ! [maze-goal-cell-moved] maze.map goal cell: position (row, col): was (1, 3), now (3, 3)",
        "      cell centre (x, y) (4.0, 4.0) → (4.0, -4.0); goal candidates 2 → 1",
        "  ! [maze-reset-cell-added] maze.map reset cells: added: (1, 2)",
        "      cell centres (x, y): (0.0, 4.0)",
        "  ! [maze-combined-cell-removed] maze.map combined cells: removed: was (3, 1)",
        "      cell centres (x, y): (-4.0, -4.0); goal candidates 2 → 1",
        "  ! [maze-wall-added] maze.map walls: added: (2, 3)",
        "      cell centres (x, y): (4.0, 0.0)",
        "  ! [maze-wall-removed] maze.map walls: removed: was (2, 1)",
        "      cell centres (x, y): (-4.0, 0.0)",
        "  ! [maze-reward-type-changed] maze: reward_type: was sparse, now dense",
        "  ! [maze-time-limit-changed] maze: max_episode_steps: was 700, now 500",
        "    [maze-robot-params-changed] maze.robot: overrides: was reset_noise_scale = 0.0, now reset_noise_scale = 0.1",
        "    [maze-id-changed] maze: id: was DiffMaze-v0, now DiffMaze-v1",
        // The robot (Ant-v5) resolved under each maze's overrides: its reset noise.
        "  ! [reset-step-resolved-changed] robot reset.qpos: resolved value: was qpos = initial + uniform[-0.0, 0.0) (specs/gymnasium/ant.toml:82), now qpos = initial + uniform[-0.1, 0.1) (specs/gymnasium/ant.toml:82)",
        "  ! [reset-step-resolved-changed] robot reset.qvel: resolved value: was qvel = initial + 0.0 × normal(0, 1) (specs/gymnasium/ant.toml:87), now qvel = initial + 0.1 × normal(0, 1) (specs/gymnasium/ant.toml:87)",
    ] {
        assert!(
            text.lines().any(|l| l == line),
            "missing `{line}` in\n{text}"
        );
    }
    // Unchanged scalars are not reported.
    for key in [
        "maze_size_scaling",
        "maze_height",
        "continuing_task",
        "reset_target",
    ] {
        assert!(!text.contains(&format!("maze: {key}:")), "{text}");
    }
    let golden = root().join("cli/tests/diff_golden/maze.txt");
    if std::env::var_os("ENVC_BLESS").is_some() {
        std::fs::write(&golden, &text).unwrap();
    } else {
        let want = std::fs::read_to_string(&golden).unwrap_or_default();
        assert_eq!(
            text,
            want,
            "differs from {} (ENVC_BLESS=1 to update)",
            golden.display()
        );
    }

    let o = envc(&["diff", OLD, NEW, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["verdict"], "breaking");
    let rules: Vec<&str> = v["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["rule"].as_str().unwrap())
        .collect();
    for r in [
        "maze-goal-cell-moved",
        "maze-wall-added",
        "maze-robot-params-changed",
    ] {
        assert!(rules.contains(&r), "{rules:?}");
    }
    let moved = v["changes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["rule"] == "maze-goal-cell-moved")
        .unwrap();
    assert_eq!(moved["category"], "reward");
    assert_eq!(moved["breaking"], true);
}

#[test]
fn identical_mazes_and_registered_ids() {
    let o = envc(&["diff", OLD, OLD]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert!(stdout(&o).contains("verdict: no change"));
    // Registered ids are the bundled spec under the registry's overrides.
    let o = envc(&["diff", "PointMaze_UMaze-v3", "PointMaze_UMazeDense-v3"]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(3), "{text}");
    assert!(
        text.starts_with("envc diff: PointMaze_UMaze-v3 ("),
        "{text}"
    );
    assert!(text.contains("→ PointMaze_UMazeDense-v3 ("), "{text}");
    let changes: Vec<&str> = text.lines().filter(|l| l.starts_with("  ")).collect();
    assert_eq!(
        changes,
        ["  ! [maze-reward-type-changed] maze: reward_type: was sparse, now dense"],
        "{text}"
    );
}

/// A maze in a temporary directory, with absolute paths to the bundled robot specs.
fn write_maze(dir: &Path, name: &str, robot: &str, map: &str) -> PathBuf {
    let robot = root()
        .join("specs/gymnasium")
        .join(robot)
        .canonicalize()
        .unwrap();
    let p = dir.join(name);
    std::fs::write(
        &p,
        format!(
            "[maze]\nid = \"DiffMaze-v0\"\nrobot = {:?}\nrobot_params = {{ reset_noise_scale = 0.0 }}\n\
             map = \"\"\"\n{map}\"\"\"\nmaze_size_scaling = 4.0\nmaze_height = 0.5\n",
            robot.display().to_string()
        ),
    )
    .unwrap();
    p
}

#[test]
fn another_robot_and_another_grid_size() {
    let dir = std::env::temp_dir().join(format!("envc-diff-maze-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let small = "1 1 1 1 1\n1 r 0 g 1\n1 1 1 1 1\n";
    let big = "1 1 1 1\n1 r g 1\n1 1 1 1\n";
    let old = write_maze(&dir, "old.toml", "ant_v4.toml", small);
    let new = write_maze(&dir, "new.toml", "ant.toml", big);
    let o = envc(&[
        "diff",
        old.to_str().unwrap(),
        new.to_str().unwrap(),
        "--no-model",
    ]);
    let text = stdout(&o);
    assert_eq!(o.status.code(), Some(3), "{text}");
    for needle in [
        "  ! [maze-grid-resized] maze.map: rows × columns: was 3 × 5, now 3 × 4",
        // 3 × 5: 12 walls, one g, one r; 3 × 4: 10 walls, one g, one r.
        "      12 walls, 1 goal and 1 reset candidates → 10 walls, 1 goal and 1 reset candidates",
        "    [maze-robot-changed] maze.robot: spec file: was ",
        // Ant-v4 → Ant-v5 as the robot: the observation grows (27 → 105), flagged under one id.
        "  ! [observation-layout-changed] robot observation: layout: was 27 elements, now 105 elements",
        "flag: this change breaks trained policies but the env id stays `DiffMaze-v0`",
        // The maze replaces the robot's reward: a robot reward change is not breaking.
        "    [reward-term-key-changed] robot reward.healthy: paid_when_unhealthy:",
        "the maze ignores the robot's own reward and termination",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    assert!(
        !text.contains("maze-wall-added"),
        "cells are not compared across sizes: {text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn specs_of_different_kinds_are_a_coded_error() {
    for (a, b, kinds) in [
        (
            "specs/robotics/maze/ant_maze.toml",
            "specs/gymnasium/ant.toml",
            "cannot diff a maze spec (specs/robotics/maze/ant_maze.toml) against a task spec",
        ),
        (
            "specs/gymnasium/ant.toml",
            "specs/mamujoco/ant.toml",
            "cannot diff a task spec (specs/gymnasium/ant.toml) against a multi-agent spec",
        ),
    ] {
        let o = envc(&["diff", a, b]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("error[E0905]"), "{err}");
        assert!(err.contains(kinds), "{err}");
        assert!(o.stdout.is_empty());
    }
}
