//! Maze specs: a maze layout (a grid of cells) composed with any robot task spec, as in
//! Gymnasium-Robotics' PointMaze/AntMaze (v4 maze logic). No MuJoCo here: this reads and checks
//! the maze file (with locations, like task specs); the runtime builds the world (mjSpec) and runs
//! the goal-conditioned env.
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
//! Modules: [`reader`](mod@reader) (the `[maze]` table and overrides), `grid` (cells with
//! their locations and the layout checks E0701–E0705), [`registry`](mod@registry) (`[[family]]`
//! files expanding into ids).

use std::path::PathBuf;

use crate::diagnostic::Location;
use crate::params::Override;

mod grid;
pub mod reader;
pub mod registry;

pub use reader::{from_document, load_maze};
pub use registry::{Registered, registry};

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

/// The maze's `reward_type`: how the distance to the goal becomes the reward.
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
    /// Env id, e.g. `PointMaze_UMaze-v3`.
    pub id: String,
    /// The maze file.
    pub path: PathBuf,
    /// Every file read to make it (the maze, its map, the robot's spec and model), with hashes:
    /// as [`crate::ResolvedSpec::inputs`].
    pub inputs: Vec<crate::source::FileRead>,
    /// The robot task spec (resolved path).
    pub robot: PathBuf,
    /// Overrides for the robot spec (`robot_params`, then robot parameters given to the maze).
    pub robot_overrides: Vec<Override>,
    /// Rows top to bottom, columns left to right.
    pub grid: Vec<Vec<Cell>>,
    /// Side of one cell in metres.
    pub maze_size_scaling: f64,
    /// Height of the wall blocks in metres.
    pub maze_height: f64,
    /// Sparse or dense reward.
    pub reward_type: RewardType,
    /// Whether reaching the goal leaves the episode running (`terminated` stays false).
    pub continuing_task: bool,
    /// Whether a continuing task draws a new goal once the goal is reached.
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
    /// Where the values were written, for errors found later (the runtime's checks).
    pub locations: MazeLocations,
}

/// Locations of a maze spec's values: in the spec file, the map file, or an override's text.
/// `None` when the value was not written anywhere (a default).
#[derive(Clone, Default)]
pub struct MazeLocations {
    /// The `maze` key of the `[maze]` table.
    pub maze: Option<Location>,
    /// The `robot` key.
    pub robot: Option<Location>,
    /// The grid as written: in the map file when `map` names one.
    pub map: Option<Location>,
    /// The `maze_size_scaling` key.
    pub maze_size_scaling: Option<Location>,
    /// Each `robot_params` entry the robot receives as written (a user's override of the same
    /// name replaces it), for the robot spec's errors about it.
    pub robot_params: Vec<(String, Location)>,
    /// Each cell, `[row][col]` (empty when the grid was not read).
    pub cells: Vec<Vec<Location>>,
}

/// `path:line:col` of each location (not the whole source files they hold).
impl std::fmt::Debug for MazeLocations {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let at = |l: &Option<Location>| l.as_ref().map(Location::position);
        f.debug_struct("MazeLocations")
            .field("maze", &at(&self.maze))
            .field("robot", &at(&self.robot))
            .field("map", &at(&self.map))
            .field("maze_size_scaling", &at(&self.maze_size_scaling))
            .field(
                "robot_params",
                &self
                    .robot_params
                    .iter()
                    .map(|(k, l)| (k, l.position()))
                    .collect::<Vec<_>>(),
            )
            .field("cells", &self.cells.iter().map(Vec::len).sum::<usize>())
            .finish()
    }
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

/// Goal and reset candidates as (row, col), in the reference's order: `Maze.make_maze` scans
/// row-major, then applies its fallbacks (no r/g/c at all: every free cell is both; no r/c: the
/// free cells are resets; no g/c: the free cells are goals) and appends the c cells to both.
pub fn candidates(grid: &[Vec<Cell>]) -> (Vec<[usize; 2]>, Vec<[usize; 2]>) {
    let (mut goals, mut resets, mut combined, mut empty) = (vec![], vec![], vec![], vec![]);
    for (i, row) in grid.iter().enumerate() {
        for (j, c) in row.iter().enumerate() {
            match c {
                Cell::Wall => {}
                Cell::Reset => resets.push([i, j]),
                Cell::Goal => goals.push([i, j]),
                Cell::Combined => combined.push([i, j]),
                Cell::Free => empty.push([i, j]),
            }
        }
    }
    if goals.is_empty() && resets.is_empty() && combined.is_empty() {
        combined = empty;
    } else if resets.is_empty() && combined.is_empty() {
        resets = empty;
    } else if goals.is_empty() && combined.is_empty() {
        goals = empty;
    }
    goals.extend(&combined);
    resets.extend(&combined);
    (goals, resets)
}

impl MazeSpec {
    /// Number of grid rows.
    pub fn rows(&self) -> usize {
        self.grid.len()
    }
    /// Number of grid columns (every row has as many).
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
        for (i, row) in self.grid.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                if *c == Cell::Wall {
                    let [x, y] = self.cell_xy(i, j);
                    l.walls.push((i, j, x, y));
                }
            }
        }
        let (goals, resets) = candidates(&self.grid);
        l.goals = goals.iter().map(|&[i, j]| self.cell_xy(i, j)).collect();
        l.resets = resets.iter().map(|&[i, j]| self.cell_xy(i, j)).collect();
        l
    }
}

impl MazeSpec {
    /// The maze's goal task as spec-language terms over the robot's root x, y (`qpos[0:2]` of the
    /// robot's model): `reward_type`, `goal_threshold` and `continuing_task` (docs/maze.md).
    pub fn goal_task(
        &self,
        robot: &crate::ModelInfo,
    ) -> Result<crate::goal::GoalTask, crate::Diagnostic> {
        crate::goal::GoalTask::reach(
            robot,
            "qpos[0:2]",
            self.reward_type == RewardType::Dense,
            self.goal_threshold,
            !self.continuing_task,
        )
    }
}
