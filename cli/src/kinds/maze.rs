//! `envc rollout`, `envc show` and `envc list` for maze envs (a registered maze id such as
//! `PointMaze_UMaze-v3`, or a maze spec: a file with a `[maze]` table).

use std::fmt::Write;
use std::path::Path;

use anyhow::Result;
use envc::maze::MazeEnv;
use ndarray::{Array1, Array2};
use ndarray_npy::NpzWriter;

use crate::Outcome;
use crate::output::Sticky;
use crate::trajectory::{InfoColumns, Trajectory};

struct DictObs {
    observation: Vec<f64>,
    achieved: Vec<f64>,
    desired: Vec<f64>,
    rows: usize,
}

impl DictObs {
    fn new() -> Self {
        DictObs {
            observation: vec![],
            achieved: vec![],
            desired: vec![],
            rows: 0,
        }
    }
    fn push(&mut self, o: &envc::maze::MazeObs) {
        self.observation.extend_from_slice(&o.observation);
        self.achieved.extend_from_slice(&o.achieved_goal);
        self.desired.extend_from_slice(&o.desired_goal);
        self.rows += 1;
    }
    fn write(self, npz: &mut NpzWriter<Sticky>, prefix: &str, dim: usize) -> Result<()> {
        let n = self.rows;
        npz.add_array(
            format!("{prefix}.observation"),
            &Array2::from_shape_vec((n, dim), self.observation)?,
        )?;
        npz.add_array(
            format!("{prefix}.achieved_goal"),
            &Array2::from_shape_vec((n, 2), self.achieved)?,
        )?;
        npz.add_array(
            format!("{prefix}.desired_goal"),
            &Array2::from_shape_vec((n, 2), self.desired)?,
        )?;
        Ok(())
    }
}

/// A maze's trajectory: `obs.observation` [n+1, dim], `obs.achieved_goal` / `obs.desired_goal`
/// [n+1, 2], `info.success` `[n]` and the robot's info as `info.<key>`; `reset_info.success` and
/// the robot's reset info for the first reset; with `--auto-reset` `reset_obs.*` and `reset_at`
/// as for flat envs.
pub struct MazeTrajectory {
    obs: DictObs,
    reset_obs: DictObs,
    reset_at: Vec<i64>,
    success: Vec<bool>,
    /// The robot's info of every step and of the first reset.
    info: InfoColumns,
    first_success: bool,
    first_reset: InfoColumns,
}

impl Default for MazeTrajectory {
    fn default() -> Self {
        MazeTrajectory {
            obs: DictObs::new(),
            reset_obs: DictObs::new(),
            reset_at: vec![],
            success: vec![],
            info: InfoColumns::default(),
            first_success: false,
            first_reset: InfoColumns::default(),
        }
    }
}

impl Trajectory for MazeTrajectory {
    type Env = MazeEnv;
    fn reset(&mut self, env: &MazeEnv, at: Option<usize>) {
        if at.is_none() {
            self.obs.push(env.obs());
            self.first_success = env.success();
            self.first_reset.push(env.robot().reset_info());
        }
        self.reset_obs.push(env.obs());
        self.reset_at.push(at.unwrap_or(0) as i64);
    }
    fn step(&mut self, env: &MazeEnv) {
        self.obs.push(env.obs());
        self.success.push(env.success());
        self.info.push(env.robot().step_info());
    }
    fn write_obs(
        &mut self,
        npz: &mut NpzWriter<Sticky>,
        env: &MazeEnv,
        _n: usize,
        _auto_reset: bool,
    ) -> Result<()> {
        std::mem::replace(&mut self.obs, DictObs::new()).write(npz, "obs", env.observation_dim())
    }
    fn write_rest(
        self,
        npz: &mut NpzWriter<Sticky>,
        env: &MazeEnv,
        auto_reset: bool,
    ) -> Result<()> {
        npz.add_array("info.success", &Array1::from(self.success))?;
        self.info.write(npz, "info")?;
        npz.add_array("reset_info.success", &ndarray::arr0(self.first_success))?;
        self.first_reset.write_first(npz, "reset_info")?;
        if auto_reset {
            self.reset_obs
                .write(npz, "reset_obs", env.observation_dim())?;
            npz.add_array("reset_at", &Array1::from(self.reset_at))?;
        }
        Ok(())
    }
}

/// `envc show` for a maze: the maze parameters, the layout, the candidate cells and the robot.
pub fn show(env: &MazeEnv) -> Result<Outcome> {
    let m = env.spec();
    let cwd = std::env::current_dir().unwrap_or_default();
    let rel = |p: &Path| p.strip_prefix(&cwd).unwrap_or(p).display().to_string();
    let mut o = String::new();
    writeln!(o, "{}  (maze spec {})", m.id, rel(&m.path))?;
    let r = env.robot().spec();
    writeln!(
        o,
        "robot: {} ({}), model {} with the maze added to its world body",
        r.id,
        rel(&m.robot),
        rel(&r.model_path)
    )?;
    let model = env.model().ffi();
    writeln!(
        o,
        "world: {}×{} cells, {} wall blocks (ngeom {}, nbody {}, nq {}, nu {}); dt {}",
        m.rows(),
        m.cols(),
        env.layout().walls.len(),
        model.ngeom,
        model.nbody,
        model.nq,
        model.nu,
        env.dt()
    )?;
    writeln!(
        o,
        "maze_size_scaling {}  maze_height {}  reward_type {:?}  continuing_task {}  reset_target {}  max_episode_steps {}",
        m.maze_size_scaling,
        m.maze_height,
        m.reward_type,
        m.continuing_task,
        m.reset_target,
        m.max_episode_steps
            .map(|x| x.to_string())
            .unwrap_or_else(|| "none".into())
    )?;
    writeln!(o, "\nmap (row 0 at the top, largest y):")?;
    for row in &m.grid {
        let cells: Vec<&str> = row
            .iter()
            .map(|c| match c {
                envspec::maze::Cell::Wall => "1",
                envspec::maze::Cell::Free => "0",
                envspec::maze::Cell::Reset => "r",
                envspec::maze::Cell::Goal => "g",
                envspec::maze::Cell::Combined => "c",
            })
            .collect();
        writeln!(o, "  {}", cells.join(" "))?;
    }
    let xy = |v: &[[f64; 2]]| {
        v.iter()
            .map(|p| format!("({}, {})", p[0], p[1]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    writeln!(
        o,
        "\ngoal candidates (in draw order): {}",
        xy(&env.layout().goals)
    )?;
    writeln!(
        o,
        "reset candidates (in draw order): {}",
        xy(&env.layout().resets)
    )?;
    writeln!(
        o,
        "\nobservation (dict):\n  observation    {} float64  the robot's observation ({})\n  achieved_goal  2 float64  qpos[0:2]\n  desired_goal   2 float64  the goal x, y",
        env.observation_dim(),
        r.id
    )?;
    let task = env.goal_task();
    writeln!(
        o,
        "reward: {} ({}); success: {}; terminates on success: {}",
        envspec::describe::term(&task.reward),
        task.reward.kind_name(),
        envspec::describe::goal_check(&task.reached),
        task.terminate
    )?;
    print!("{o}");
    Ok(Outcome::Ok)
}
