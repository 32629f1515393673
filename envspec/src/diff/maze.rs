//! Maze specs: the layout cell by cell (walls; goal, reset and combined cells added, removed or
//! moved), the grid size, every scalar of `[maze]`, and the robot (another spec file or other
//! overrides, with the robot's own task diff).

use std::path::{Component, Path, PathBuf};

use super::rules::{Category, RuleId};
use super::{Change, Report};
use crate::maze::{Cell, MazeSpec, RewardType};
use crate::params::{Override, OverrideValue};

/// The maze's own reward and termination replace the robot's.
const ROBOT_REWARD_IGNORED: &str = "the maze ignores the robot's own reward and termination";

/// How many cells a change lists before `…`.
const SHOWN: usize = 8;

/// Cells of one kind, row-major.
fn cells(m: &MazeSpec, kind: Cell) -> Vec<(usize, usize)> {
    let mut out = vec![];
    for (i, row) in m.grid.iter().enumerate() {
        for (j, c) in row.iter().enumerate() {
            if *c == kind {
                out.push((i, j));
            }
        }
    }
    out
}

fn cell_list(cs: &[(usize, usize)]) -> String {
    let mut s: Vec<String> = cs
        .iter()
        .take(SHOWN)
        .map(|(i, j)| format!("({i}, {j})"))
        .collect();
    if cs.len() > SHOWN {
        s.push(format!("… ({} cells)", cs.len()));
    }
    s.join(", ")
}

/// The world coordinates of a cell's centre in `m`, e.g. `(1.0, -2.0)`.
fn centre(m: &MazeSpec, (i, j): (usize, usize)) -> String {
    let [x, y] = m.cell_xy(i, j);
    format!("({x:?}, {y:?})")
}

fn centres(m: &MazeSpec, cs: &[(usize, usize)]) -> String {
    let mut s: Vec<String> = cs.iter().take(SHOWN).map(|&c| centre(m, c)).collect();
    if cs.len() > SHOWN {
        s.push("…".into());
    }
    format!("cell centres (x, y): {}", s.join(", "))
}

/// Whether goals (resets) come from the free cells: a map without `g` and `c` (`r` and `c`) cells,
/// as in the reference's `Maze.make_maze`.
fn free_goals(m: &MazeSpec) -> bool {
    cells(m, Cell::Goal).is_empty() && cells(m, Cell::Combined).is_empty()
}

fn free_resets(m: &MazeSpec) -> bool {
    cells(m, Cell::Reset).is_empty() && cells(m, Cell::Combined).is_empty()
}

/// The number of goal and reset candidates the env draws from, where a change of `kind` cells
/// changes it (other kinds only through the free-cell fallback).
fn candidates(o: &MazeSpec, n: &MazeSpec, kind: Cell) -> Option<String> {
    let (a, b) = (o.layout(), n.layout());
    let feeds_goals = matches!(kind, Cell::Goal | Cell::Combined) || free_goals(o) || free_goals(n);
    let feeds_resets =
        matches!(kind, Cell::Reset | Cell::Combined) || free_resets(o) || free_resets(n);
    let mut w = vec![];
    if feeds_goals && a.goals.len() != b.goals.len() {
        w.push(format!(
            "goal candidates {} → {}",
            a.goals.len(),
            b.goals.len()
        ));
    }
    if feeds_resets && a.resets.len() != b.resets.len() {
        w.push(format!(
            "reset candidates {} → {}",
            a.resets.len(),
            b.resets.len()
        ));
    }
    (!w.is_empty()).then(|| w.join("; "))
}

fn with_candidates(w: String, cands: &Option<String>) -> String {
    match cands {
        Some(c) => format!("{w}; {c}"),
        None => w,
    }
}

/// Added, removed and moved cells of one kind (same grid size).
fn layout(o: &MazeSpec, n: &MazeSpec, out: &mut Vec<Change>) {
    let kinds = [
        (
            Cell::Wall,
            "wall",
            RuleId::MazeWallAdded,
            RuleId::MazeWallRemoved,
            None,
        ),
        (
            Cell::Goal,
            "goal cell",
            RuleId::MazeGoalCellAdded,
            RuleId::MazeGoalCellRemoved,
            Some(RuleId::MazeGoalCellMoved),
        ),
        (
            Cell::Reset,
            "reset cell",
            RuleId::MazeResetCellAdded,
            RuleId::MazeResetCellRemoved,
            Some(RuleId::MazeResetCellMoved),
        ),
        (
            Cell::Combined,
            "combined cell",
            RuleId::MazeCombinedCellAdded,
            RuleId::MazeCombinedCellRemoved,
            Some(RuleId::MazeCombinedCellMoved),
        ),
    ];
    for (kind, name, added_rule, removed_rule, moved_rule) in kinds {
        let (a, b) = (cells(o, kind), cells(n, kind));
        let cands = candidates(o, n, kind);
        let mut removed: Vec<(usize, usize)> =
            a.iter().filter(|c| !b.contains(c)).copied().collect();
        let mut added: Vec<(usize, usize)> = b.iter().filter(|c| !a.contains(c)).copied().collect();
        if let Some(rule) = moved_rule {
            // One removed and one added cell of a kind, paired in row-major order, moved.
            let k = removed.len().min(added.len());
            for (&from, &to) in removed.iter().zip(&added).take(k) {
                out.push(
                    Change::new(rule, format!("maze.map {name}"), "position (row, col)")
                        .values(Some(cell_list(&[from])), Some(cell_list(&[to])))
                        .witness(with_candidates(
                            format!("cell centre (x, y) {} → {}", centre(o, from), centre(n, to)),
                            &cands,
                        )),
                );
            }
            removed.drain(..k);
            added.drain(..k);
        }
        if !added.is_empty() {
            out.push(
                Change::new(added_rule, format!("maze.map {name}s"), "added")
                    .values(None, Some(cell_list(&added)))
                    .witness(with_candidates(centres(n, &added), &cands)),
            );
        }
        if !removed.is_empty() {
            out.push(
                Change::new(removed_rule, format!("maze.map {name}s"), "removed")
                    .values(Some(cell_list(&removed)), None)
                    .witness(with_candidates(centres(o, &removed), &cands)),
            );
        }
    }
}

fn float(x: f64) -> String {
    format!("{x:?}")
}

fn scalars(o: &MazeSpec, n: &MazeSpec, out: &mut Vec<Change>) {
    let reward = |r: RewardType| match r {
        RewardType::Sparse => "sparse",
        RewardType::Dense => "dense",
    };
    let opt = |x: Option<String>| x.unwrap_or_else(|| "none".into());
    let rows: [(RuleId, &str, String, String); 9] = [
        (
            RuleId::MazeScalingChanged,
            "maze_size_scaling",
            float(o.maze_size_scaling),
            float(n.maze_size_scaling),
        ),
        (
            RuleId::MazeHeightChanged,
            "maze_height",
            float(o.maze_height),
            float(n.maze_height),
        ),
        (
            RuleId::MazeRewardTypeChanged,
            "reward_type",
            reward(o.reward_type).into(),
            reward(n.reward_type).into(),
        ),
        (
            RuleId::MazeContinuingTaskChanged,
            "continuing_task",
            o.continuing_task.to_string(),
            n.continuing_task.to_string(),
        ),
        (
            RuleId::MazeResetTargetChanged,
            "reset_target",
            o.reset_target.to_string(),
            n.reset_target.to_string(),
        ),
        (
            RuleId::MazeTimeLimitChanged,
            "max_episode_steps",
            opt(o.max_episode_steps.map(|x| x.to_string())),
            opt(n.max_episode_steps.map(|x| x.to_string())),
        ),
        (
            RuleId::MazePositionNoiseChanged,
            "position_noise_range",
            float(o.position_noise_range),
            float(n.position_noise_range),
        ),
        (
            RuleId::MazeVelocityClipChanged,
            "velocity_clip",
            opt(o.velocity_clip.map(float)),
            opt(n.velocity_clip.map(float)),
        ),
        (
            RuleId::MazeGoalThresholdChanged,
            "goal_threshold",
            float(o.goal_threshold),
            float(n.goal_threshold),
        ),
    ];
    for (rule, key, was, now) in rows {
        if was != now {
            out.push(Change::new(rule, "maze", key).values(Some(was), Some(now)));
        }
    }
}

/// The robot path as the maze file names it (relative to the maze file's directory).
fn robot_shown(m: &MazeSpec) -> String {
    let dir = m.path.parent().unwrap_or(Path::new(""));
    m.robot
        .strip_prefix(dir)
        .unwrap_or(&m.robot)
        .display()
        .to_string()
}

fn override_text(o: &Override) -> String {
    match &o.value {
        OverrideValue::Text(t) => format!("{} = {t}", o.name),
        OverrideValue::Value(v) => format!("{} = {v}", o.name),
    }
}

fn overrides_text(m: &MazeSpec) -> Vec<String> {
    let mut v: Vec<String> = m.robot_overrides.iter().map(override_text).collect();
    v.sort();
    v
}

/// `a/b/../c` → `a/c`, so positions in the robot spec read `specs/gymnasium/ant.toml:81`.
fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// The robot: another file or other overrides, then the robot's own task diff (each side
/// resolved with its maze's overrides).
fn robot(o: &MazeSpec, n: &MazeSpec, out: &mut Vec<Change>) {
    // Another file as the maze names it; the same name may still be another file (two git
    // revisions), whose changes the robot's diff shows.
    let renamed = robot_shown(o) != robot_shown(n);
    let file_changed = renamed || !same_file(&o.robot, &n.robot);
    let (oo, no) = (overrides_text(o), overrides_text(n));
    if renamed {
        out.push(
            Change::new(RuleId::MazeRobotChanged, "maze.robot", "spec file")
                .values(Some(robot_shown(o)), Some(robot_shown(n))),
        );
    }
    if oo != no {
        let show = |v: &[String]| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        out.push(
            Change::new(RuleId::MazeRobotParamsChanged, "maze.robot", "overrides")
                .values(Some(show(&oo)), Some(show(&no))),
        );
    }
    if !file_changed && oo == no {
        return;
    }
    let side = |m: &MazeSpec| -> Result<_, String> {
        let path = normalize(&m.robot);
        let syntax = crate::syntax::Spec::load(&path).map_err(|d| d.to_string())?;
        let resolved = crate::load(&path, &m.robot_overrides).map_err(|d| d.to_string())?;
        Ok((syntax, resolved))
    };
    match (side(o), side(n)) {
        (Ok((os, or)), Ok((ns, nr))) => {
            for mut c in super::diff(&os, &or, &ns, &nr).changes {
                c.subject = format!("robot {}", c.subject);
                c.witness = c.witness.map(|w| {
                    w.replace(
                        "under the default parameters",
                        "as the maze resolves the robot",
                    )
                });
                if c.breaking && matches!(c.category(), Category::Reward | Category::Termination) {
                    c.breaking = false;
                    c.witness = Some(match c.witness.take() {
                        Some(w) => format!("{w}; {ROBOT_REWARD_IGNORED}"),
                        None => ROBOT_REWARD_IGNORED.into(),
                    });
                }
                out.push(c);
            }
        }
        (a, b) => {
            for (m, r, side) in [(o, a.err(), "old"), (n, b.err(), "new")] {
                if let Some(e) = r {
                    let first = e.lines().next().unwrap_or("").to_string();
                    out.push(
                        Change::new(RuleId::MazeRobotUnresolved, "maze.robot", "resolution")
                            .values(
                                (side == "old").then(|| robot_shown(m)),
                                (side == "new").then(|| robot_shown(m)),
                            )
                            .witness(format!("the {side} robot spec does not resolve: {first}")),
                    );
                }
            }
        }
    }
}

/// Semantic diff of two maze specs (each loaded with `maze::load_maze`).
pub fn diff_mazes(old: &MazeSpec, new: &MazeSpec) -> Report {
    let mut changes = vec![];
    if old.id != new.id {
        changes.push(
            Change::new(RuleId::MazeIdChanged, "maze", "id")
                .values(Some(old.id.clone()), Some(new.id.clone())),
        );
    }
    if (old.rows(), old.cols()) != (new.rows(), new.cols()) {
        let size = |m: &MazeSpec| format!("{} × {}", m.rows(), m.cols());
        let l = |m: &MazeSpec| {
            let l = m.layout();
            format!(
                "{} walls, {} goal and {} reset candidates",
                l.walls.len(),
                l.goals.len(),
                l.resets.len()
            )
        };
        changes.push(
            Change::new(RuleId::MazeGridResized, "maze.map", "rows × columns")
                .values(Some(size(old)), Some(size(new)))
                .witness(format!("{} → {}", l(old), l(new))),
        );
    } else {
        layout(old, new, &mut changes);
    }
    scalars(old, new, &mut changes);
    robot(old, new, &mut changes);
    let mut report = Report::new(
        &old.id,
        &new.id,
        old.path.display().to_string(),
        new.path.display().to_string(),
    );
    report.extend(changes);
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::maze::{Cell, load_maze};

    /// A grid written as the map strings of maze specs (`1 0 r g c`).
    fn parse_grid(map: &str) -> Vec<Vec<Cell>> {
        let cell = |t: &str| match t {
            "1" => Cell::Wall,
            "r" => Cell::Reset,
            "g" => Cell::Goal,
            "c" => Cell::Combined,
            _ => Cell::Free,
        };
        map.lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split_whitespace().map(cell).collect())
            .collect()
    }

    /// PointMaze's U-maze (scaling 1, velocity clip 5) with another map.
    fn point_maze(map: &str) -> MazeSpec {
        let p = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../specs/robotics/maze/point_maze.toml"
        ));
        let mut m = load_maze(p, &[]).unwrap();
        m.grid = parse_grid(map);
        m
    }

    const UMAZE: &str = "1 1 1 1 1\n1 0 0 0 1\n1 1 1 0 1\n1 0 0 0 1\n1 1 1 1 1\n";

    fn lines(r: &Report) -> Vec<(String, String, Option<String>)> {
        r.changes
            .iter()
            .map(|c| {
                let v = format!("{:?} → {:?}", c.was, c.now);
                (c.rule.id().to_string(), v, c.witness.clone())
            })
            .collect()
    }

    #[test]
    fn a_goal_cell_in_a_map_without_one_replaces_the_free_cell_fallback() {
        // Without g, r or c cells the 7 free cells are goal and reset candidates; one g at (1, 1)
        // leaves 1 goal candidate and 6 free cells for resets.
        let (o, n) = (point_maze(UMAZE), point_maze(&UMAZE.replacen('0', "g", 1)));
        let r = diff_mazes(&o, &n);
        assert_eq!(
            lines(&r),
            [(
                "maze-goal-cell-added".to_string(),
                "None → Some(\"(1, 1)\")".to_string(),
                Some(
                    "cell centres (x, y): (-1.0, 1.0); goal candidates 7 → 1; reset candidates 7 → 6"
                        .to_string()
                )
            )]
        );
        assert_eq!(r.verdict(), super::super::Verdict::Breaking);
        assert_eq!(r.changes[0].category(), Category::Reward);
    }

    #[test]
    fn moves_pair_in_row_major_order_and_scalars_are_compared() {
        let o = point_maze("1 1 1 1\n1 g r 1\n1 g 0 1\n1 1 1 1\n");
        let mut n = point_maze("1 1 1 1\n1 0 r 1\n1 g g 1\n1 1 1 1\n");
        n.maze_size_scaling = 1.0;
        n.velocity_clip = None;
        n.goal_threshold = 0.5;
        let r = diff_mazes(&o, &n);
        let got = lines(&r);
        // (1, 1) → (2, 2): centres (-0.5, 0.5) → (0.5, -0.5) on a 4 × 4 grid of unit cells.
        assert!(got.contains(&(
            "maze-goal-cell-moved".into(),
            "Some(\"(1, 1)\") → Some(\"(2, 2)\")".into(),
            Some("cell centre (x, y) (-0.5, 0.5) → (0.5, -0.5)".into())
        )));
        assert!(got.contains(&(
            "maze-velocity-clip-changed".into(),
            "Some(\"5.0\") → Some(\"none\")".into(),
            None
        )));
        assert!(got.contains(&(
            "maze-goal-threshold-changed".into(),
            "Some(\"0.45\") → Some(\"0.5\")".into(),
            None
        )));
        // Scaling was already 1.0: not a change. Nothing else changed.
        assert_eq!(got.len(), 3, "{got:?}");
    }
}
