//! Maze specs: a maze layout (a grid of cells) composed with any robot task spec, as in
//! Gymnasium-Robotics' PointMaze/AntMaze (v4 maze logic). No MuJoCo here: this reads and checks
//! the maze file; the runtime builds the world (mjSpec) and runs the goal-conditioned env.
//!
//! ```toml
//! [maze]
//! id = "MyMaze-v0"
//! robot = "../../gymnasium/ant.toml"        # any robot task spec (its obs is `observation`)
//! robot_params = { reset_noise_scale = 0.0 } # overrides passed to the robot spec
//! map = """
//! 1 1 1 1
//! 1 r g 1
//! 1 1 1 1
//! """                                        # or a path to a map file: map = "maps/u_maze.toml"
//! maze_size_scaling = 4.0
//! maze_height = 0.5
//! reward_type = "sparse"                     # or "dense"
//! continuing_task = true
//! reset_target = false
//! max_episode_steps = 700
//! ```
//!
//! Registered families (`[[family]]` in a registry file) expand map × reward type into ids.

use std::path::{Path, PathBuf};

use crate::diagnostic::{Code, Diagnostic, Diagnostics, show_path};
use crate::params::Override;

/// One maze cell, as in `gymnasium_robotics.envs.maze.maps`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    /// `1`: a wall block.
    Wall,
    /// `0`: free.
    Free,
    /// `r`: a reset (start) candidate.
    Reset,
    /// `g`: a goal candidate.
    Goal,
    /// `c`: both.
    Combined,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RewardType {
    /// `float64(d <= 0.45)`.
    Sparse,
    /// `exp(-d)`.
    Dense,
}

/// A resolved maze spec.
#[derive(Clone, Debug)]
pub struct MazeSpec {
    pub id: String,
    /// The maze file.
    pub path: PathBuf,
    /// The robot task spec (resolved path).
    pub robot: PathBuf,
    /// Overrides for the robot spec (`robot_params`, then robot parameters given to the maze).
    pub robot_overrides: Vec<Override>,
    /// Rows top to bottom, columns left to right.
    pub grid: Vec<Vec<Cell>>,
    pub maze_size_scaling: f64,
    pub maze_height: f64,
    pub reward_type: RewardType,
    pub continuing_task: bool,
    pub reset_target: bool,
    /// `TimeLimit` of the maze env (0 or absent: none).
    pub max_episode_steps: Option<u64>,
    /// Goal and reset noise: `uniform(-r, r) * maze_size_scaling` per axis.
    pub position_noise_range: f64,
    /// Before every step, clip the robot's qvel to `±x` and recompute (`mj_forward`), as
    /// PointMaze's point robot does.
    pub velocity_clip: Option<f64>,
    /// Goal-reaching threshold (0.45 in every reference env).
    pub goal_threshold: f64,
}

/// The maze parameters a user may override (`--set key=value`); any other key goes to the robot.
pub const MAZE_PARAMS: &[&str] = &[
    "map",
    "maze_size_scaling",
    "maze_height",
    "reward_type",
    "continuing_task",
    "reset_target",
    "max_episode_steps",
    "position_noise_range",
    "velocity_clip",
];

const MAZE_KEYS: &[&str] = &[
    "id",
    "description",
    "robot",
    "robot_params",
    "map",
    "maze_size_scaling",
    "maze_height",
    "reward_type",
    "continuing_task",
    "reset_target",
    "max_episode_steps",
    "position_noise_range",
    "velocity_clip",
    "goal_threshold",
];

fn err(code: Code, path: &Path, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::new(code, format!("{}: {}", show_path(path), msg.into()))
}

/// Whether a TOML file is a maze spec (has a top-level `[maze]` table).
pub fn is_maze_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.get("maze").is_some_and(|m| m.is_table()))
}

fn read_table(path: &Path) -> Result<toml::Table, Diagnostics> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Diagnostics(vec![err(Code::E0600, path, format!("cannot read: {e}"))]))?;
    text.parse::<toml::Table>()
        .map_err(|e| Diagnostics(vec![err(Code::E0100, path, format!("not valid TOML: {e}"))]))
}

/// Parse a grid: rows of whitespace-separated cells `1 0 r g c`, one row per line (a string), or
/// an array of rows (each a string or an array of `1`/`0`/`"r"`/`"g"`/`"c"`).
pub fn parse_grid(v: &toml::Value) -> Result<Vec<Vec<Cell>>, String> {
    fn cell(tok: &str) -> Result<Cell, String> {
        Ok(match tok {
            "1" => Cell::Wall,
            "0" => Cell::Free,
            "r" => Cell::Reset,
            "g" => Cell::Goal,
            "c" => Cell::Combined,
            _ => return Err(format!("unknown cell `{tok}` (expected 1, 0, r, g or c)")),
        })
    }
    fn row_of(v: &toml::Value) -> Result<Vec<Cell>, String> {
        match v {
            toml::Value::String(s) => s.split_whitespace().map(cell).collect(),
            toml::Value::Array(a) => a
                .iter()
                .map(|c| match c {
                    toml::Value::Integer(i) => cell(&i.to_string()),
                    toml::Value::String(s) => cell(s),
                    _ => Err("a cell must be 1, 0, \"r\", \"g\" or \"c\"".into()),
                })
                .collect(),
            _ => Err("a row must be a string or an array of cells".into()),
        }
    }
    let rows: Vec<Vec<Cell>> = match v {
        toml::Value::String(s) => s
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split_whitespace().map(cell).collect())
            .collect::<Result<_, _>>()?,
        toml::Value::Array(a) => a.iter().map(row_of).collect::<Result<_, _>>()?,
        _ => return Err("expected a grid (a string of rows or an array of rows)".into()),
    };
    if rows.is_empty() || rows[0].is_empty() {
        return Err("the grid is empty".into());
    }
    if let Some(i) = rows.iter().position(|r| r.len() != rows[0].len()) {
        return Err(format!(
            "row {i} has {} cells but row 0 has {}",
            rows[i].len(),
            rows[0].len()
        ));
    }
    if rows.iter().flatten().all(|c| *c == Cell::Wall) {
        return Err("the grid has no free cell".into());
    }
    Ok(rows)
}

/// Load a maze spec with overrides (maze parameters by name; anything else goes to the robot).
pub fn load_maze(path: &Path, overrides: &[Override]) -> Result<MazeSpec, Diagnostics> {
    let table = read_table(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut d = Diagnostics::default();
    let Some(maze) = table.get("maze").and_then(|m| m.as_table()) else {
        return Err(Diagnostics(vec![err(
            Code::E0103,
            path,
            "a maze spec needs a `[maze]` table",
        )]));
    };
    for k in table.keys() {
        if k != "maze" {
            d.push(err(
                Code::E0101,
                path,
                format!("unknown top-level key `{k}` in a maze spec"),
            ));
        }
    }
    let mut m = maze.clone();
    for k in m.keys() {
        if !MAZE_KEYS.contains(&k.as_str()) {
            d.push(
                err(Code::E0101, path, format!("unknown key `{k}` in [maze]"))
                    .help_opt(crate::diagnostic::suggest(k, MAZE_KEYS.iter().copied())),
            );
        }
    }
    // Overrides: maze parameters replace [maze] values (map paths resolve against the working
    // directory); everything else is a robot parameter.
    let mut robot_overrides = vec![];
    let mut map_dir = dir.to_path_buf();
    for o in overrides {
        if MAZE_PARAMS.contains(&o.name.as_str()) {
            let crate::params::OverrideValue::Text(t) = &o.value else {
                d.push(err(
                    Code::E0203,
                    path,
                    format!("override `{}` must be text", o.name),
                ));
                continue;
            };
            let v = t
                .parse::<toml::Value>()
                .or_else(|_| {
                    format!("v = {t}")
                        .parse::<toml::Table>()
                        .map(|t| t["v"].clone())
                })
                .unwrap_or_else(|_| toml::Value::String(t.clone()));
            if o.name == "map" {
                map_dir = PathBuf::from(".");
            }
            m.insert(o.name.clone(), v);
        } else {
            robot_overrides.push(o.clone());
        }
    }
    let id = match m.get("id") {
        Some(toml::Value::String(s)) => s.clone(),
        Some(_) => {
            d.push(err(Code::E0102, path, "`id` must be a string"));
            String::new()
        }
        None => {
            d.push(err(Code::E0103, path, "[maze] needs an `id`"));
            String::new()
        }
    };
    let robot = match m.get("robot") {
        Some(toml::Value::String(s)) => dir.join(s),
        _ => {
            d.push(err(
                Code::E0103,
                path,
                "[maze] needs `robot`: the path of a robot task spec",
            ));
            PathBuf::new()
        }
    };
    let mut base_overrides = vec![];
    match m.get("robot_params") {
        None => {}
        Some(toml::Value::Table(t)) => {
            for (k, v) in t {
                let text = match v {
                    toml::Value::String(s) if s.starts_with("../") || s.starts_with("./") => {
                        toml::Value::String(dir.join(s).display().to_string()).to_string()
                    }
                    _ => v.to_string(),
                };
                base_overrides.push(Override::text(k, &text));
            }
        }
        Some(_) => d.push(err(Code::E0102, path, "`robot_params` must be a table")),
    }
    base_overrides.extend(robot_overrides);

    let float = |d: &mut Diagnostics, key: &str, default: Option<f64>| -> f64 {
        match m.get(key) {
            Some(toml::Value::Float(x)) if x.is_finite() => *x,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(_) => {
                d.push(err(
                    Code::E0102,
                    path,
                    format!("`{key}` must be a finite number"),
                ));
                0.0
            }
            None => default.unwrap_or_else(|| {
                d.push(err(Code::E0103, path, format!("[maze] needs `{key}`")));
                0.0
            }),
        }
    };
    let boolean = |d: &mut Diagnostics, key: &str, default: bool| -> bool {
        match m.get(key) {
            Some(toml::Value::Boolean(b)) => *b,
            Some(_) => {
                d.push(err(
                    Code::E0102,
                    path,
                    format!("`{key}` must be true or false"),
                ));
                default
            }
            None => default,
        }
    };
    let maze_size_scaling = float(&mut d, "maze_size_scaling", None);
    let maze_height = float(&mut d, "maze_height", None);
    let position_noise_range = float(&mut d, "position_noise_range", Some(0.25));
    let goal_threshold = float(&mut d, "goal_threshold", Some(0.45));
    if maze_size_scaling <= 0.0 || maze_height <= 0.0 {
        d.push(err(
            Code::E0104,
            path,
            "`maze_size_scaling` and `maze_height` must be positive",
        ));
    }
    let velocity_clip = m
        .get("velocity_clip")
        .map(|_| float(&mut d, "velocity_clip", None));
    let continuing_task = boolean(&mut d, "continuing_task", true);
    let reset_target = boolean(&mut d, "reset_target", false);
    let reward_type = match m.get("reward_type").and_then(|v| v.as_str()) {
        None if m.get("reward_type").is_none() => RewardType::Sparse,
        Some("sparse") => RewardType::Sparse,
        Some("dense") => RewardType::Dense,
        _ => {
            d.push(err(
                Code::E0104,
                path,
                "`reward_type` must be \"sparse\" or \"dense\"",
            ));
            RewardType::Sparse
        }
    };
    let max_episode_steps = match m.get("max_episode_steps") {
        None => None,
        Some(toml::Value::Integer(0)) => None,
        Some(toml::Value::Integer(n)) if *n > 0 => Some(*n as u64),
        Some(_) => {
            d.push(err(
                Code::E0104,
                path,
                "`max_episode_steps` must be a non-negative integer",
            ));
            None
        }
    };
    let grid = match m.get("map") {
        None => {
            d.push(err(
                Code::E0103,
                path,
                "[maze] needs `map`: a grid or a map file",
            ));
            vec![]
        }
        Some(toml::Value::String(s)) if s.trim_end().ends_with(".toml") => {
            let p = map_dir.join(s.trim());
            match read_table(&p) {
                Err(e) => {
                    d.0.extend(e.0);
                    vec![]
                }
                Ok(t) => match t.get("grid").map(parse_grid) {
                    Some(Ok(g)) => g,
                    Some(Err(e)) => {
                        d.push(err(Code::E0104, &p, e));
                        vec![]
                    }
                    None => {
                        d.push(err(Code::E0103, &p, "a map file needs `grid`"));
                        vec![]
                    }
                },
            }
        }
        Some(v) => match parse_grid(v) {
            Ok(g) => g,
            Err(e) => {
                d.push(err(Code::E0104, path, format!("`map`: {e}")));
                vec![]
            }
        },
    };
    d.into_result(MazeSpec {
        id,
        path: path.to_path_buf(),
        robot,
        robot_overrides: base_overrides,
        grid,
        maze_size_scaling,
        maze_height,
        reward_type,
        continuing_task,
        reset_target,
        max_episode_steps,
        position_noise_range,
        velocity_clip,
        goal_threshold,
    })
}

/// Goal and reset candidates and wall cells, in the reference's order (A4–A6).
#[derive(Clone, Debug, Default)]
pub struct Layout {
    /// Wall blocks as (row, col, x, y).
    pub walls: Vec<(usize, usize, f64, f64)>,
    /// Goal candidates (g cells, then c cells; fallbacks when the map has none).
    pub goals: Vec<[f64; 2]>,
    /// Reset candidates (r cells, then c cells; fallbacks likewise).
    pub resets: Vec<[f64; 2]>,
}

impl MazeSpec {
    pub fn rows(&self) -> usize {
        self.grid.len()
    }
    pub fn cols(&self) -> usize {
        self.grid.first().map_or(0, |r| r.len())
    }
    /// Cell centre, exactly as `Maze.cell_rowcol_to_xy` computes it.
    pub fn cell_xy(&self, i: usize, j: usize) -> [f64; 2] {
        let s = self.maze_size_scaling;
        let x_center = self.cols() as f64 / 2.0 * s;
        let y_center = self.rows() as f64 / 2.0 * s;
        [
            (j as f64 + 0.5) * s - x_center,
            y_center - (i as f64 + 0.5) * s,
        ]
    }
    /// The reference's scan (`Maze.make_maze`): row-major, with its fallback rules.
    pub fn layout(&self) -> Layout {
        let mut l = Layout::default();
        let (mut combined, mut empty) = (vec![], vec![]);
        for (i, row) in self.grid.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                let xy = self.cell_xy(i, j);
                match c {
                    Cell::Wall => l.walls.push((i, j, xy[0], xy[1])),
                    Cell::Reset => l.resets.push(xy),
                    Cell::Goal => l.goals.push(xy),
                    Cell::Combined => combined.push(xy),
                    Cell::Free => empty.push(xy),
                }
            }
        }
        if l.goals.is_empty() && l.resets.is_empty() && combined.is_empty() {
            combined = empty;
        } else if l.resets.is_empty() && combined.is_empty() {
            l.resets = empty;
        } else if l.goals.is_empty() && combined.is_empty() {
            l.goals = empty;
        }
        l.goals.extend(&combined);
        l.resets.extend(&combined);
        l
    }
}

/// A registered family: a maze spec run over several maps and both reward types.
#[derive(Clone, Debug)]
pub struct Registered {
    pub id: String,
    pub spec: PathBuf,
    pub overrides: Vec<Override>,
}

/// Read a maze registry file: `[[family]] spec = "...", id = "PointMaze_{map}{reward}-v3"` with
/// `[family.maps] UMaze = { map = "maps/u_maze.toml", max_episode_steps = 300 }`. `{reward}` is
/// `""` for sparse and `"Dense"` for dense, as Gymnasium-Robotics registers them.
pub fn registry(path: &Path) -> Result<Vec<Registered>, Diagnostics> {
    let t = read_table(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut out = vec![];
    let bad = |m: &str| Diagnostics(vec![err(Code::E0104, path, m.to_string())]);
    let fams = t
        .get("family")
        .and_then(|f| f.as_array())
        .ok_or_else(|| bad("a maze registry needs [[family]] entries"))?;
    for f in fams {
        let (Some(spec), Some(id), Some(maps)) = (
            f.get("spec").and_then(|v| v.as_str()),
            f.get("id").and_then(|v| v.as_str()),
            f.get("maps").and_then(|v| v.as_table()),
        ) else {
            return Err(bad("each [[family]] needs `spec`, `id` and `maps`"));
        };
        for (name, entry) in maps {
            let Some(e) = entry.as_table() else {
                return Err(bad("each map entry must be a table"));
            };
            for (suffix, rt) in [("", "sparse"), ("Dense", "dense")] {
                let mut overrides = vec![Override::text("reward_type", &format!("\"{rt}\""))];
                for (k, v) in e {
                    let text = match (k.as_str(), v) {
                        ("map", toml::Value::String(s)) => {
                            toml::Value::String(dir.join(s).display().to_string()).to_string()
                        }
                        _ => v.to_string(),
                    };
                    overrides.push(Override::text(k, &text));
                }
                out.push(Registered {
                    id: id.replace("{map}", name).replace("{reward}", suffix),
                    spec: dir.join(spec),
                    overrides,
                });
            }
        }
    }
    out.sort_by(|a, b| a.id.cmp(&b.id));
    Ok(out)
}

impl MazeSpec {
    /// The maze's goal task as spec-language terms over the robot's root x, y (`qpos[0:2]` of the
    /// robot's model): `reward_type`, `goal_threshold` and `continuing_task` (docs/maze.md).
    pub fn goal_task(&self, robot: &crate::ModelInfo) -> Result<crate::goal::GoalTask, Diagnostic> {
        crate::goal::GoalTask::reach(
            robot,
            "qpos[0:2]",
            self.reward_type == RewardType::Dense,
            self.goal_threshold,
            !self.continuing_task,
        )
    }
}
