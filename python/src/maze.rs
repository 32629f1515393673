//! The core of a maze env (goal-conditioned, dict observations): reset with goal/reset cells,
//! step with numpy arrays, and the batched goal functions (`compute_reward`, `compute_terminated`,
//! `compute_truncated`) computed by the env's own goal terms.

use envc::maze::{MazeEnv, MazeObs, ResetOptions};
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors;

/// A maze env (`envc.EnvcMazeEnv` wraps it as a Gymnasium-Robotics `GoalEnv`).
#[pyclass(module = "envc._envc")]
pub struct MazeCore {
    env: MazeEnv,
}

impl MazeCore {
    pub fn new(env: MazeEnv) -> MazeCore {
        MazeCore { env }
    }
}

type StepOut<'py> = (Bound<'py, PyDict>, f64, bool, bool, Bound<'py, PyDict>);

/// The observation dict, keys in the reference's insertion order.
fn obs_dict<'py>(py: Python<'py>, o: &MazeObs) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("observation", PyArray1::from_slice(py, &o.observation))?;
    d.set_item("achieved_goal", PyArray1::from_slice(py, &o.achieved_goal))?;
    d.set_item("desired_goal", PyArray1::from_slice(py, &o.desired_goal))?;
    Ok(d)
}

/// The robot's info with `success` added last, as the reference's maze envs do.
fn info_dict<'py>(
    py: Python<'py>,
    robot: envc::Info<'_>,
    success: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let d = convert::info(py, robot)?;
    d.set_item("success", success)?;
    Ok(d)
}

fn step_out<'py>(py: Python<'py>, s: envc::maze::MazeStep<'_>) -> PyResult<StepOut<'py>> {
    Ok((
        obs_dict(py, s.obs)?,
        s.reward,
        s.terminated,
        s.truncated,
        info_dict(py, s.robot_info, s.success)?,
    ))
}

/// Goal (x, y) rows.
type Goals = Vec<[f64; 2]>;

/// `[N, 2]` goal batches as pairs of rows; both must have the same shape.
fn goal_rows(
    achieved: &PyReadonlyArray2<'_, f64>,
    desired: &PyReadonlyArray2<'_, f64>,
) -> PyResult<(Goals, Goals)> {
    let (a, d) = (achieved.as_array(), desired.as_array());
    if a.shape() != d.shape() || a.shape()[1] != 2 {
        return Err(errors::argument(format!(
            "achieved_goal {:?} and desired_goal {:?}: expected two arrays of shape [N, 2]",
            a.shape(),
            d.shape()
        )));
    }
    let rows = |m: numpy::ndarray::ArrayView2<'_, f64>| -> Goals {
        m.outer_iter().map(|r| [r[0], r[1]]).collect()
    };
    Ok((rows(a), rows(d)))
}

#[pymethods]
impl MazeCore {
    /// `reset(seed, goal_cell, reset_cell)`: a seed restarts the env's RNG stream, `None`
    /// continues it; cells are `(row, col)` of free cells. Returns `(obs dict, info)`.
    #[pyo3(signature = (seed = None, goal_cell = None, reset_cell = None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        goal_cell: Option<[usize; 2]>,
        reset_cell: Option<[usize; 2]>,
    ) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
        let options = (goal_cell.is_some() || reset_cell.is_some()).then_some(ResetOptions {
            goal_cell,
            reset_cell,
        });
        errors::no_panic(
            &mut self.env,
            |env| {
                let (_, success) =
                    crate::mujoco_timer::without_mujoco_timer(|| env.reset(seed, options))
                        .map_err(errors::env_error)?;
                Ok((
                    obs_dict(py, env.obs())?,
                    info_dict(py, env.robot().reset_info(), success)?,
                ))
            },
            |env| env.require_reset(),
        )
    }

    /// Step with a float64 action.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                let s = crate::mujoco_timer::without_mujoco_timer(|| env.step(a))
                    .map_err(errors::env_error)?;
                step_out(py, s)
            },
            |env| env.require_reset(),
        )
    }

    /// Step with a float32 action (float32 control costs in the robot's info, as numpy computes them).
    fn step_f32<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                let s = crate::mujoco_timer::without_mujoco_timer(|| env.step_f32(a))
                    .map_err(errors::env_error)?;
                step_out(py, s)
            },
            |env| env.require_reset(),
        )
    }

    /// The goal reward term of every row: `achieved[k]` against `desired[k]` (`[N, 2]` each),
    /// exactly as the step reward.
    fn compute_reward<'py>(
        &self,
        py: Python<'py>,
        achieved: PyReadonlyArray2<'py, f64>,
        desired: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (a, d) = goal_rows(&achieved, &desired)?;
        let mut out = vec![0.0; a.len()];
        self.env.compute_reward(&a, &d, &mut out);
        Ok(PyArray1::from_vec(py, out))
    }

    /// The env's termination of every row (reaching the goal, unless the task is continuing).
    fn compute_terminated<'py>(
        &self,
        py: Python<'py>,
        achieved: PyReadonlyArray2<'py, f64>,
        desired: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let (a, d) = goal_rows(&achieved, &desired)?;
        let out: Vec<bool> = a
            .iter()
            .zip(&d)
            .map(|(a, d)| self.env.compute_terminated(*a, *d))
            .collect();
        Ok(PyArray1::from_vec(py, out))
    }

    /// The env's truncation of every row (never: the time limit truncates).
    fn compute_truncated<'py>(
        &self,
        py: Python<'py>,
        achieved: PyReadonlyArray2<'py, f64>,
        desired: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let (a, d) = goal_rows(&achieved, &desired)?;
        let out: Vec<bool> = a
            .iter()
            .zip(&d)
            .map(|(a, d)| self.env.compute_truncated(*a, *d))
            .collect();
        Ok(PyArray1::from_vec(py, out))
    }

    /// A frame of the maze world with its goal marker, in Gymnasium's `render_mode`.
    fn render(&mut self, py: Python<'_>, mode: &str) -> PyResult<Py<PyAny>> {
        crate::render::render(py, mode, |m| self.env.render(m))
    }

    #[getter]
    fn id(&self) -> String {
        self.env.id().to_string()
    }
    #[getter]
    fn dt(&self) -> f64 {
        self.env.dt()
    }
    /// The maze's own time limit (`None` when opened with `max_episode_steps=0`).
    #[getter]
    fn max_episode_steps(&self) -> Option<u64> {
        self.env.max_episode_steps()
    }
    /// Size of the `observation` entry (the goals have 2 entries).
    #[getter]
    fn observation_dim(&self) -> usize {
        self.env.observation_dim()
    }
    #[getter]
    fn act_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.action_space().low)
    }
    #[getter]
    fn act_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.action_space().high)
    }
    /// The current goal (the next step's `desired_goal`).
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.goal())
    }
    /// `(rows, cols)` of the maze grid.
    #[getter]
    fn map_shape(&self) -> (usize, usize) {
        (self.env.spec().rows(), self.env.spec().cols())
    }
    #[getter]
    fn continuing_task(&self) -> bool {
        self.env.spec().continuing_task
    }
    #[getter]
    fn reset_target(&self) -> bool {
        self.env.spec().reset_target
    }
    #[getter]
    fn reward_type(&self) -> &'static str {
        match self.env.spec().reward_type {
            envspec::maze::RewardType::Sparse => "sparse",
            envspec::maze::RewardType::Dense => "dense",
        }
    }
    /// The numerics profile the env computes under (docs/numerics.md).
    #[getter]
    fn numerics(&self) -> String {
        self.env.numerics().to_string()
    }
    #[setter]
    fn set_numerics(&mut self, name: &str) -> PyResult<()> {
        let p = crate::convert::profile(name)?;
        self.env.set_numerics(p);
        Ok(())
    }
    /// MuJoCo warnings captured so far.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.env.warnings().to_vec()
    }
}
