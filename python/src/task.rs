//! The core of a single-agent task env: reset and step with numpy arrays, the spaces' bounds.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors;
use crate::mujoco_timer::without_mujoco_timer;

/// A task env (`envc.EnvcEnv` wraps it as a `gymnasium.Env`).
#[pyclass(module = "envc._envc")]
pub struct TaskCore {
    env: envc::Env,
}

impl TaskCore {
    pub fn new(env: envc::Env) -> TaskCore {
        TaskCore { env }
    }
}

type StepOut<'py> = (
    Bound<'py, PyArray1<f64>>,
    f64,
    bool,
    bool,
    Bound<'py, PyDict>,
);

fn step_out<'py>(py: Python<'py>, s: envc::Step<'_>) -> PyResult<StepOut<'py>> {
    Ok((
        PyArray1::from_slice(py, s.obs),
        s.reward,
        s.terminated,
        s.truncated,
        convert::info(py, s.info)?,
    ))
}

#[pymethods]
impl TaskCore {
    /// `reset(seed)`: a seed restarts the env's RNG stream, `None` continues it.
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
        errors::no_panic(
            &mut self.env,
            |env| {
                let (obs, info) = without_mujoco_timer(|| env.reset(seed));
                Ok((PyArray1::from_slice(py, obs), convert::info(py, info)?))
            },
            envc::Env::require_reset,
        )
    }

    /// Step with a float64 action.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepOut<'py>> {
        let action = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                step_out(
                    py,
                    without_mujoco_timer(|| env.step(action)).map_err(errors::env_error)?,
                )
            },
            envc::Env::require_reset,
        )
    }

    /// Step with a float32 action (float32 control costs, as numpy computes them).
    fn step_f32<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<StepOut<'py>> {
        let action = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                step_out(
                    py,
                    without_mujoco_timer(|| env.step_f32(action)).map_err(errors::env_error)?,
                )
            },
            envc::Env::require_reset,
        )
    }

    /// A frame in Gymnasium's `render_mode` ("rgb_array", "depth_array", "rgbd_tuple").
    fn render(&mut self, py: Python<'_>, mode: &str) -> PyResult<Py<PyAny>> {
        errors::no_panic(
            &mut self.env,
            |env| crate::render::render(py, mode, |m| env.render(m)),
            |env| env.close_renderer(),
        )
    }
    /// Free the renderer (made again by the next `render`).
    fn close_renderer(&mut self) {
        self.env.close_renderer();
    }

    /// `(qpos, qvel)` now (checks of other executors start from the same state).
    fn state<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let (q, v) = self.env.state();
        (PyArray1::from_slice(py, q), PyArray1::from_slice(py, v))
    }
    #[getter]
    fn id(&self) -> String {
        self.env.spec().id.clone()
    }
    #[getter]
    fn dt(&self) -> f64 {
        self.env.dt()
    }
    #[getter]
    fn max_episode_steps(&self) -> Option<u64> {
        self.env.spec().max_episode_steps
    }
    #[getter]
    fn obs_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.observation_space().low)
    }
    #[getter]
    fn obs_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.observation_space().high)
    }
    #[getter]
    fn act_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.action_space().low)
    }
    #[getter]
    fn act_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.action_space().high)
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
    /// The resolved parameters: `{name: value as TOML text}`.
    #[getter]
    fn params(&self) -> Vec<(String, String)> {
        self.env
            .spec()
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value.to_string()))
            .collect()
    }
}

/// `(name, type, default as TOML text, doc)` of every parameter of a spec of any kind.
pub fn parameters(id_or_path: &str) -> PyResult<Vec<(String, String, String, String)>> {
    let spec = envspec::open(id_or_path, &[]).map_err(errors::diagnostics)?;
    let params = match &spec {
        envc::AnySpec::Task(t) => &t.params,
        envc::AnySpec::Maze(_) => return Ok(vec![]),
        envc::AnySpec::Agents(a) => &a.base.params,
    };
    Ok(params
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                p.ty.name().to_string(),
                p.default.to_string(),
                p.doc.clone(),
            )
        })
        .collect())
}
