//! `EnvCore`: the base class of every kind's core. Each kind's subclass (`TaskCore`, `MazeCore`,
//! `MultiAgentCore`: `#[pyclass(extends = EnvCore)]`) holds its own env, typed, and adds only what is
//! its own; the base holds nothing, and its methods (`joint_methods.rs`) reach the env of the
//! subclass they are called on. What a kind's env must offer for them is [`KindEnv`]: `JointEnv`,
//! and the observation and info a reset or step returns in the kind's form (a flat array, a
//! maze's dict, one array per agent).

use envc::maze::MazeEnv;
use envc::multi_agent::MultiAgentEnv;
use envc::{JointAction, JointEnv, JointStep};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert;
use crate::errors;
use crate::mujoco_timer::without_mujoco_timer;

/// An env of any kind (`envc._envc.open` returns the kind's subclass, which holds the env).
#[pyclass(module = "envc._envc", subclass)]
pub struct EnvCore;

/// `(obs, reward, terminated, truncated, info)`, the obs in the kind's form.
pub(crate) type StepOut<'py> = (Bound<'py, PyAny>, f64, bool, bool, Bound<'py, PyDict>);
/// `(obs, info)`.
pub(crate) type ResetOut<'py> = (Bound<'py, PyAny>, Bound<'py, PyDict>);

/// Which info the kind reports: the last reset's or the last step's.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum After {
    Reset,
    Step,
}

/// The env a kind's core holds: driven as every kind is, observed in its kind's Python form.
pub(crate) trait KindEnv: JointEnv {
    /// The observation and info now.
    fn observe<'py>(&self, py: Python<'py>, after: After) -> PyResult<ResetOut<'py>>;
}

fn info<'py>(py: Python<'py>, env: &dyn JointEnv, after: After) -> PyResult<Bound<'py, PyDict>> {
    let physics = env.physics_env();
    convert::info(
        py,
        match after {
            After::Reset => physics.reset_info(),
            After::Step => physics.step_info(),
        },
    )
}

impl KindEnv for envc::Env {
    /// A `[goal]` task's is Gymnasium-Robotics' dict, keys in the reference's insertion order.
    fn observe<'py>(&self, py: Python<'py>, after: After) -> PyResult<ResetOut<'py>> {
        let info = info(py, self, after)?;
        if self.spec().manipulation.goal.is_none() {
            return Ok((PyArray1::from_slice(py, self.obs()).into_any(), info));
        }
        let d = PyDict::new(py);
        let mut achieved = vec![];
        self.achieved_goal(&mut achieved);
        d.set_item("observation", PyArray1::from_slice(py, self.obs()))?;
        d.set_item("achieved_goal", PyArray1::from_vec(py, achieved))?;
        d.set_item("desired_goal", PyArray1::from_slice(py, self.goal()))?;
        Ok((d.into_any(), info))
    }
}

impl KindEnv for MazeEnv {
    /// The robot's info with `success` added last, as the reference's maze envs do.
    fn observe<'py>(&self, py: Python<'py>, after: After) -> PyResult<ResetOut<'py>> {
        let d = info(py, self, after)?;
        d.set_item("success", self.success())?;
        Ok((maze_obs(py, self.obs())?.into_any(), d))
    }
}

impl KindEnv for MultiAgentEnv {
    /// One array per agent.
    fn observe<'py>(&self, py: Python<'py>, after: After) -> PyResult<ResetOut<'py>> {
        let obs = self
            .observations()
            .iter()
            .map(|o| PyArray1::from_slice(py, o));
        Ok((PyList::new(py, obs)?.into_any(), info(py, self, after)?))
    }
}

/// A maze's observation dict, keys in the reference's insertion order.
fn maze_obs<'py>(py: Python<'py>, o: &envc::maze::MazeObs) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("observation", PyArray1::from_slice(py, &o.observation))?;
    d.set_item("achieved_goal", PyArray1::from_slice(py, &o.achieved_goal))?;
    d.set_item("desired_goal", PyArray1::from_slice(py, &o.desired_goal))?;
    Ok(d)
}

/// Run `f` on an env; a panic leaves it needing a reset (see `errors::no_panic`).
pub(crate) fn guarded<E: KindEnv + ?Sized, R>(
    env: &mut E,
    f: impl FnOnce(&mut E) -> PyResult<R>,
) -> PyResult<R> {
    errors::no_panic(env, f, |env| env.require_reset())
}

/// One step with a joint action, returned in the kind's form.
pub(crate) fn step_with<'py>(
    py: Python<'py>,
    env: &mut dyn KindEnv,
    action: JointAction<'_>,
) -> PyResult<StepOut<'py>> {
    guarded(env, |env| {
        let JointStep {
            reward,
            terminated,
            truncated,
        } = without_mujoco_timer(|| env.step_joint(action)).map_err(errors::env_error)?;
        let (obs, info) = env.observe(py, After::Step)?;
        Ok((obs, reward, terminated, truncated, info))
    })
}
