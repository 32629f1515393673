//! The core of a maze env (goal-conditioned, dict observations): what `EnvCore` shares, a reset
//! that takes goal and reset cells, and the batched goal functions (`compute_reward`,
//! `compute_terminated`, `compute_truncated`) computed by the env's own goal terms.

use envc::maze::{MazeEnv, ResetOptions};
use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::env_core::{After, EnvCore, KindEnv, ResetOut, guarded};
use crate::errors;

/// A maze env (`envc.EnvcMazeEnv` wraps it as a Gymnasium-Robotics `GoalEnv`).
#[pyclass(module = "envc._envc", extends = EnvCore)]
pub struct MazeCore {
    /// Boxed: much larger than the other kinds' envs.
    pub(crate) env: Box<MazeEnv>,
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

/// A goal function's flag for every row of two `[N, 2]` goal batches.
fn goal_flags<'py>(
    py: Python<'py>,
    achieved: &PyReadonlyArray2<'py, f64>,
    desired: &PyReadonlyArray2<'py, f64>,
    f: impl Fn([f64; 2], [f64; 2]) -> bool,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let (a, d) = goal_rows(achieved, desired)?;
    let out: Vec<bool> = a.iter().zip(&d).map(|(a, d)| f(*a, *d)).collect();
    Ok(PyArray1::from_vec(py, out))
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
    ) -> PyResult<ResetOut<'py>> {
        let options = (goal_cell.is_some() || reset_cell.is_some()).then_some(ResetOptions {
            goal_cell,
            reset_cell,
        });
        guarded(&mut *self.env, |maze| {
            crate::mujoco_timer::without_mujoco_timer(|| {
                maze.reset(seed, options)?;
                maze.robot().reset_error().map_or(Ok(()), Err)
            })
            .map_err(errors::env_error)?;
            maze.observe(py, After::Reset)
        })
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
        let maze = &self.env;
        goal_flags(py, &achieved, &desired, |a, d| {
            maze.compute_terminated(a, d)
        })
    }

    /// The env's truncation of every row (never: the time limit truncates).
    fn compute_truncated<'py>(
        &self,
        py: Python<'py>,
        achieved: PyReadonlyArray2<'py, f64>,
        desired: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let maze = &self.env;
        goal_flags(py, &achieved, &desired, |a, d| maze.compute_truncated(a, d))
    }

    /// Size of the `observation` entry (the goals have 2 entries).
    #[getter]
    fn observation_dim(&self) -> usize {
        self.env.observation_dim()
    }
    /// The current goal (the next step's `desired_goal`).
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.goal())
    }
    /// `(rows, cols)` of the maze grid.
    #[getter]
    fn map_shape(&self) -> (usize, usize) {
        let m = self.env.spec();
        (m.rows(), m.cols())
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
}
