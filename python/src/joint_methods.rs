//! `EnvCore`'s methods: what every kind shares through `envc::JointEnv` — reset, step with a
//! float64 or float32 joint action, the joint action's bounds, `dt`, the time limit, numerics,
//! warnings, render and close — on the env of the kind's core they are called on ([`with_env`],
//! the one place that tells the cores' kinds apart). Apart from `env_core.rs`, which the kinds'
//! cores build on, so that no file imports one that imports it.

use envc::JointAction;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert;
use crate::env_core::{After, EnvCore, KindEnv, ResetOut, StepOut, guarded, step_with};
use crate::errors;
use crate::maze::MazeCore;
use crate::mujoco_timer::without_mujoco_timer;
use crate::multi_agent::MultiAgentCore;
use crate::task::TaskCore;

/// `f` on the env of the kind's core `slf` is. The subclasses are the only cores `open` makes;
/// a Python subclass of `EnvCore` itself holds no env (TypeError).
fn with_env<R>(
    slf: &Bound<'_, EnvCore>,
    f: impl FnOnce(&mut dyn KindEnv) -> PyResult<R>,
) -> PyResult<R> {
    if let Ok(c) = slf.cast::<TaskCore>() {
        return f(&mut c.try_borrow_mut()?.env);
    }
    if let Ok(c) = slf.cast::<MazeCore>() {
        return f(&mut *c.try_borrow_mut()?.env);
    }
    if let Ok(c) = slf.cast::<MultiAgentCore>() {
        return f(&mut c.try_borrow_mut()?.env);
    }
    Err(pyo3::exceptions::PyTypeError::new_err(
        "EnvCore holds no env: cores come from envc._envc.open",
    ))
}

#[pymethods]
impl EnvCore {
    /// `reset(seed)`: a seed restarts the env's RNG stream, `None` continues it. A reset that
    /// found no valid start raises (E1104, or a MuJoCo error).
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<ResetOut<'py>> {
        with_env(slf, |env| {
            guarded(env, |env| {
                without_mujoco_timer(|| env.try_reset(seed)).map_err(errors::env_error)?;
                env.observe(py, After::Reset)
            })
        })
    }

    /// Step with a float64 joint action (a multi-agent spec: the global action).
    fn step<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        with_env(slf, |env| step_with(py, env, JointAction::F64(a)))
    }

    /// Step with a float32 joint action (float32 control costs, as numpy computes them).
    fn step_f32<'py>(
        slf: &Bound<'py, Self>,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        with_env(slf, |env| step_with(py, env, JointAction::F32(a)))
    }

    /// A frame in Gymnasium's `render_mode` ("rgb_array", "depth_array", "rgbd_tuple"): a task,
    /// a maze with its goal marker, a multi-agent spec's whole robot.
    fn render(slf: &Bound<'_, Self>, py: Python<'_>, mode: &str) -> PyResult<Py<PyAny>> {
        with_env(slf, |env| {
            errors::no_panic(
                env,
                |env| crate::render::render(py, mode, |m| env.render(m)),
                |env| env.close(),
            )
        })
    }

    /// Free the renderer (Gymnasium's `close()`; the next `render` makes a new one).
    fn close(slf: &Bound<'_, Self>) -> PyResult<()> {
        with_env(slf, |env| {
            env.close();
            Ok(())
        })
    }

    /// `"task"`, `"maze"` or `"agents"`.
    #[getter]
    fn kind(slf: &Bound<'_, Self>) -> PyResult<&'static str> {
        with_env(slf, |env| Ok(crate::kind_name(env.kind())))
    }
    #[getter]
    fn id(slf: &Bound<'_, Self>) -> PyResult<String> {
        with_env(slf, |env| Ok(env.id().to_string()))
    }
    #[getter]
    fn dt(slf: &Bound<'_, Self>) -> PyResult<f64> {
        with_env(slf, |env| Ok(env.dt()))
    }
    /// The time limit (`None` when opened with `max_episode_steps=0`).
    #[getter]
    fn max_episode_steps(slf: &Bound<'_, Self>) -> PyResult<Option<u64>> {
        with_env(slf, |env| Ok(env.max_episode_steps()))
    }
    /// The joint action's bounds (a multi-agent spec: the global action's).
    #[getter]
    fn act_low<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        with_env(slf, |env| {
            Ok(PyArray1::from_slice(slf.py(), &env.action_space().low))
        })
    }
    #[getter]
    fn act_high<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        with_env(slf, |env| {
            Ok(PyArray1::from_slice(slf.py(), &env.action_space().high))
        })
    }
    /// The numerics profile the env computes under (docs/numerics.md).
    #[getter]
    fn numerics(slf: &Bound<'_, Self>) -> PyResult<String> {
        with_env(slf, |env| Ok(env.numerics().to_string()))
    }
    #[setter]
    fn set_numerics(slf: &Bound<'_, Self>, name: &str) -> PyResult<()> {
        let p = convert::profile(name)?;
        with_env(slf, |env| {
            env.set_numerics(p);
            Ok(())
        })
    }
    /// MuJoCo warnings captured so far.
    #[getter]
    fn warnings(slf: &Bound<'_, Self>) -> PyResult<Vec<String>> {
        with_env(slf, |env| Ok(env.warnings().to_vec()))
    }
}
