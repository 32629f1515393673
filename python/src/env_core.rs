//! `EnvCore`: the base class of every kind's core, holding what they share through
//! `envc::JointEnv` — reset, step with a float64 or float32 joint action, the joint action's
//! bounds, `dt`, the time limit, numerics, warnings, render and close. Each kind's subclass
//! (`TaskCore`, `MazeCore`, `AgentsCore`: `#[pyclass(extends = EnvCore)]`) adds only what is
//! its own. The observation and info a reset or step returns are the kind's (a flat array, a
//! maze's dict, one array per agent), made in one place, [`EnvCore::observe`].

use envc::maze::MazeEnv;
use envc::multi_agent::MultiAgentEnv;
use envc::{AnyEnv, JointAction, JointEnv, JointStep};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert;
use crate::errors;
use crate::mujoco_timer::without_mujoco_timer;

/// An env of any kind (`envc._envc.open` returns the kind's subclass).
#[pyclass(module = "envc._envc", subclass)]
pub struct EnvCore {
    pub(crate) env: AnyEnv,
}

/// `(obs, reward, terminated, truncated, info)`, the obs in the kind's form.
pub(crate) type StepOut<'py> = (Bound<'py, PyAny>, f64, bool, bool, Bound<'py, PyDict>);
/// `(obs, info)`.
type ResetOut<'py> = (Bound<'py, PyAny>, Bound<'py, PyDict>);

/// Which info the kind reports: the last reset's or the last step's.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum After {
    Reset,
    Step,
}

/// The observation and info of `env` now, in its kind's Python form.
pub(crate) fn observe<'py>(py: Python<'py>, env: &AnyEnv, after: After) -> PyResult<ResetOut<'py>> {
    let physics = env.physics_env();
    let info = match after {
        After::Reset => physics.reset_info(),
        After::Step => physics.step_info(),
    };
    Ok(match env {
        // A `[goal]` task: Gymnasium-Robotics' dict, keys in the reference's insertion order.
        AnyEnv::Task(e) if e.spec().manipulation.goal.is_some() => {
            let d = PyDict::new(py);
            let mut achieved = vec![];
            e.achieved_goal(&mut achieved);
            d.set_item("observation", PyArray1::from_slice(py, e.obs()))?;
            d.set_item("achieved_goal", PyArray1::from_vec(py, achieved))?;
            d.set_item("desired_goal", PyArray1::from_slice(py, e.goal()))?;
            (d.into_any(), convert::info(py, info)?)
        }
        AnyEnv::Task(e) => (
            PyArray1::from_slice(py, e.obs()).into_any(),
            convert::info(py, info)?,
        ),
        AnyEnv::Maze(m) => {
            // The robot's info with `success` added last, as the reference's maze envs do.
            let d = convert::info(py, info)?;
            d.set_item("success", m.success())?;
            (maze_obs(py, m.obs())?.into_any(), d)
        }
        AnyEnv::Agents(a) => (
            PyList::new(
                py,
                a.observations().iter().map(|o| PyArray1::from_slice(py, o)),
            )?
            .into_any(),
            convert::info(py, info)?,
        ),
    })
}

/// A maze's observation dict, keys in the reference's insertion order.
fn maze_obs<'py>(py: Python<'py>, o: &envc::maze::MazeObs) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("observation", PyArray1::from_slice(py, &o.observation))?;
    d.set_item("achieved_goal", PyArray1::from_slice(py, &o.achieved_goal))?;
    d.set_item("desired_goal", PyArray1::from_slice(py, &o.desired_goal))?;
    Ok(d)
}

impl EnvCore {
    pub fn new(env: AnyEnv) -> EnvCore {
        EnvCore { env }
    }

    /// The env of a task core (each subclass holds its own kind).
    pub(crate) fn task(&self) -> PyResult<&envc::Env> {
        match &self.env {
            AnyEnv::Task(e) => Ok(e),
            other => Err(wrong_kind(other, "task")),
        }
    }
    pub(crate) fn maze(&self) -> PyResult<&MazeEnv> {
        match &self.env {
            AnyEnv::Maze(e) => Ok(e),
            other => Err(wrong_kind(other, "maze")),
        }
    }
    pub(crate) fn agents(&self) -> PyResult<&MultiAgentEnv> {
        match &self.env {
            AnyEnv::Agents(e) => Ok(e),
            other => Err(wrong_kind(other, "multi-agent")),
        }
    }
    pub(crate) fn agents_mut(&mut self) -> PyResult<&mut MultiAgentEnv> {
        match &mut self.env {
            AnyEnv::Agents(e) => Ok(e),
            other => Err(wrong_kind(other, "multi-agent")),
        }
    }

    /// Run `f` on the env; a panic leaves it needing a reset (see `errors::no_panic`).
    pub(crate) fn guarded<R>(&mut self, f: impl FnOnce(&mut AnyEnv) -> PyResult<R>) -> PyResult<R> {
        errors::no_panic(&mut self.env, f, |env| env.require_reset())
    }

    /// One step with a joint action, returned in the kind's form.
    pub(crate) fn step_with<'py>(
        &mut self,
        py: Python<'py>,
        action: JointAction<'_>,
    ) -> PyResult<StepOut<'py>> {
        self.guarded(|env| {
            let JointStep {
                reward,
                terminated,
                truncated,
            } = without_mujoco_timer(|| env.step_joint(action)).map_err(errors::env_error)?;
            let (obs, info) = observe(py, env, After::Step)?;
            Ok((obs, reward, terminated, truncated, info))
        })
    }
}

/// The error of a subclass method reached with another kind's env (never, short of a bug).
pub(crate) fn wrong_kind(env: &AnyEnv, want: &str) -> PyErr {
    errors::coded(
        "E1900",
        format!(
            "error[E1900]: envc failed internally, a bug (please report it with this message): \
             a {want} core holds a {} env",
            env.kind()
        ),
    )
}

#[pymethods]
impl EnvCore {
    /// `reset(seed)`: a seed restarts the env's RNG stream, `None` continues it. A reset that
    /// found no valid start raises (E1104, or a MuJoCo error).
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<ResetOut<'py>> {
        self.guarded(|env| {
            without_mujoco_timer(|| env.try_reset(seed)).map_err(errors::env_error)?;
            observe(py, env, After::Reset)
        })
    }

    /// Step with a float64 joint action (a multi-agent spec: the global action).
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepOut<'py>> {
        self.step_with(py, JointAction::F64(action.as_slice()?))
    }

    /// Step with a float32 joint action (float32 control costs, as numpy computes them).
    fn step_f32<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<StepOut<'py>> {
        self.step_with(py, JointAction::F32(action.as_slice()?))
    }

    /// A frame in Gymnasium's `render_mode` ("rgb_array", "depth_array", "rgbd_tuple"): a task,
    /// a maze with its goal marker, a multi-agent spec's whole robot.
    fn render(&mut self, py: Python<'_>, mode: &str) -> PyResult<Py<PyAny>> {
        errors::no_panic(
            &mut self.env,
            |env| crate::render::render(py, mode, |m| env.render(m)),
            |env| env.close(),
        )
    }

    /// Free the renderer (Gymnasium's `close()`; the next `render` makes a new one).
    fn close(&mut self) {
        self.env.close();
    }

    /// `"task"`, `"maze"` or `"agents"`.
    #[getter]
    fn kind(&self) -> &'static str {
        crate::kind_name(self.env.kind())
    }
    #[getter]
    fn id(&self) -> String {
        self.env.id().to_string()
    }
    #[getter]
    fn dt(&self) -> f64 {
        self.env.dt()
    }
    /// The time limit (`None` when opened with `max_episode_steps=0`).
    #[getter]
    fn max_episode_steps(&self) -> Option<u64> {
        self.env.max_episode_steps()
    }
    /// The joint action's bounds (a multi-agent spec: the global action's).
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
        let p = convert::profile(name)?;
        self.env.set_numerics(p);
        Ok(())
    }
    /// MuJoCo warnings captured so far.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.env.warnings().to_vec()
    }
}
