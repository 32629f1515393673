//! `envc rollout`, `envc show` and `envc list` for maze envs (a registered maze id such as
//! `PointMaze_UMaze-v3`, or a maze spec: a file with a `[maze]` table).

use std::fmt::Write;
use std::path::Path;

use anyhow::{Context, Result};
use envc::maze::MazeEnv;
use ndarray::{Array1, Array2, ArrayD, IxDyn};
use ndarray_npy::NpzWriter;

use crate::Outcome;

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
    fn write(
        self,
        npz: &mut NpzWriter<crate::output::Sticky>,
        prefix: &str,
        dim: usize,
    ) -> Result<()> {
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

/// Writes `obs.observation` [n+1, dim], `obs.achieved_goal` / `obs.desired_goal` [n+1, 2],
/// `reward`, `terminated`, `truncated`, `info.success` `[n]` and the robot's info as `info.<key>`;
/// `reset_info.success` and the robot's reset info for the first reset; with `--auto-reset`
/// `reset_obs.*` and `reset_at` as for flat envs.
pub fn rollout(
    mut env: MazeEnv,
    seed: Option<u64>,
    a: &Array2<f64>,
    out: &Path,
    auto_reset: bool,
) -> Result<Outcome> {
    let t_max = a.dim().0;
    let dim = env.observation_dim();
    let mut obs = DictObs::new();
    let mut reset_obs = DictObs::new();
    let mut reset_at: Vec<i64> = vec![0];
    let (mut reward, mut terminated, mut truncated, mut success) = (vec![], vec![], vec![], vec![]);
    let mut info: Vec<(String, usize, Vec<f64>)> = vec![];
    let (o, s0) = env.reset(seed, None).map_err(|e| anyhow::anyhow!("{e}"))?;
    obs.push(o);
    reset_obs.push(o);
    let first_reset: Vec<(String, Vec<f64>)> = env
        .robot()
        .reset_info()
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_vec()))
        .collect();
    for t in 0..t_max {
        let row = a.row(t);
        let act = row.as_slice().context("actions must be in C order")?;
        let s = env
            .step(act)
            .map_err(|e| anyhow::anyhow!("step {t}: {e}"))?;
        obs.push(s.obs);
        reward.push(s.reward);
        terminated.push(s.terminated);
        truncated.push(s.truncated);
        success.push(s.success);
        if info.is_empty() {
            info = s
                .robot_info
                .iter()
                .map(|(k, v)| (k.to_string(), v.len(), vec![]))
                .collect();
        }
        for ((_, _, col), (_, v)) in info.iter_mut().zip(s.robot_info.iter()) {
            col.extend_from_slice(v);
        }
        if s.terminated || s.truncated {
            if !auto_reset {
                break;
            }
            if t + 1 < t_max {
                let (o, _) = env.reset(None, None).map_err(|e| anyhow::anyhow!("{e}"))?;
                reset_obs.push(o);
                reset_at.push(t as i64 + 1);
            }
        }
    }
    let n = reward.len();
    let (dest, f) = crate::output::Output::create(out)?;
    let mut npz = NpzWriter::new(f);
    obs.write(&mut npz, "obs", dim)?;
    npz.add_array("reward", &Array1::from(reward))?;
    npz.add_array("terminated", &Array1::from(terminated))?;
    npz.add_array("truncated", &Array1::from(truncated))?;
    npz.add_array("info.success", &Array1::from(success))?;
    for (k, len, v) in info {
        let shape = if len == 1 { vec![n] } else { vec![n, len] };
        npz.add_array(
            format!("info.{k}"),
            &ArrayD::from_shape_vec(IxDyn(&shape), v)?,
        )?;
    }
    npz.add_array("reset_info.success", &ndarray::arr0(s0))?;
    for (k, v) in first_reset {
        if v.len() == 1 {
            npz.add_array(format!("reset_info.{k}"), &ndarray::arr0(v[0]))?;
        } else {
            npz.add_array(format!("reset_info.{k}"), &Array1::from(v))?;
        }
    }
    if auto_reset {
        reset_obs.write(&mut npz, "reset_obs", dim)?;
        npz.add_array("reset_at", &Array1::from(reset_at))?;
    }
    dest.commit(npz.finish()?)?;
    for w in env.warnings() {
        eprintln!("MuJoCo warning: {w}");
    }
    eprintln!("{}: {n} steps written to {}", env.id(), out.display());
    Ok(Outcome::Ok)
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
