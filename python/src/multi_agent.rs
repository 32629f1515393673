//! The core of a multi-agent env (a factorization of a task among agents): reset and step with
//! one numpy array per agent, the global state and the reference's mappings between local and
//! global actions and observations.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors;

/// A multi-agent env (`envc.parallel_env` wraps it as a PettingZoo `ParallelEnv`).
#[pyclass(module = "envc._envc")]
pub struct AgentsCore {
    env: envc::multi_agent::MultiAgentEnv,
}

impl AgentsCore {
    pub fn new(env: envc::multi_agent::MultiAgentEnv) -> AgentsCore {
        AgentsCore { env }
    }

    fn agent(&self, i: usize) -> PyResult<usize> {
        if i < self.env.num_agents() {
            Ok(i)
        } else {
            Err(errors::argument(format!(
                "agent index {i} out of range ({} agents)",
                self.env.num_agents()
            )))
        }
    }
}

type Arrays<'py> = Vec<Bound<'py, PyArray1<f64>>>;
type StepOut<'py> = (Arrays<'py>, f64, bool, bool, Bound<'py, PyDict>);

fn arrays<'py>(py: Python<'py>, vs: &[Vec<f64>]) -> Arrays<'py> {
    vs.iter().map(|v| PyArray1::from_slice(py, v)).collect()
}

fn slices<'a>(xs: &'a [PyReadonlyArray1<'_, f64>]) -> PyResult<Vec<&'a [f64]>> {
    xs.iter().map(|x| Ok(x.as_slice()?)).collect()
}

fn step_out<'py>(py: Python<'py>, s: envc::multi_agent::MultiStep<'_>) -> PyResult<StepOut<'py>> {
    Ok((
        arrays(py, s.obs),
        s.reward,
        s.terminated,
        s.truncated,
        convert::info(py, s.info)?,
    ))
}

#[pymethods]
impl AgentsCore {
    /// `reset(seed)`: every agent's observation (in agent order) and the shared info. A seed
    /// restarts the env's RNG stream, `None` continues it.
    #[pyo3(signature = (seed = None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<(Arrays<'py>, Bound<'py, PyDict>)> {
        errors::no_panic(
            &mut self.env,
            |env| {
                let (obs, info) = crate::mujoco_timer::without_mujoco_timer(|| env.reset(seed));
                Ok((arrays(py, obs), convert::info(py, info)?))
            },
            |env| env.require_reset(),
        )
    }

    /// Step with one float64 action per agent (in agent order): every agent's observation and
    /// the shared reward, terminated, truncated and info.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<StepOut<'py>> {
        let a = slices(&actions)?;
        errors::no_panic(
            &mut self.env,
            |env| {
                let s = crate::mujoco_timer::without_mujoco_timer(|| env.step(&a))
                    .map_err(errors::env_error)?;
                step_out(py, s)
            },
            |env| env.require_reset(),
        )
    }

    /// Step with the global (single-agent) action.
    fn step_global<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                let s = crate::mujoco_timer::without_mujoco_timer(|| env.step_global(a))
                    .map_err(errors::env_error)?;
                step_out(py, s)
            },
            |env| env.require_reset(),
        )
    }

    /// Step with a float32 global action (float32 control costs, as numpy computes them).
    fn step_global_f32<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<StepOut<'py>> {
        let a = action.as_slice()?;
        errors::no_panic(
            &mut self.env,
            |env| {
                let s = crate::mujoco_timer::without_mujoco_timer(|| env.step_global_f32(a))
                    .map_err(errors::env_error)?;
                step_out(py, s)
            },
            |env| env.require_reset(),
        )
    }

    /// The global state: the single-agent env's observation.
    fn state<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.env.state())
    }

    /// The global action of one local action per agent.
    fn local_actions_to_global<'py>(
        &self,
        py: Python<'py>,
        actions: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let a = slices(&actions)?;
        let g = self
            .env
            .local_actions_to_global(&a)
            .map_err(errors::env_error)?;
        Ok(PyArray1::from_vec(py, g))
    }

    /// Each agent's share of a global action.
    fn global_action_to_local<'py>(
        &self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arrays<'py>> {
        let l = self
            .env
            .global_action_to_local(action.as_slice()?)
            .map_err(errors::env_error)?;
        Ok(arrays(py, &l))
    }

    /// Each agent's observation taken from a global state.
    fn global_state_to_local<'py>(
        &self,
        py: Python<'py>,
        state: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arrays<'py>> {
        let s = state.as_slice()?;
        if s.len() != self.env.spec().state_dim() {
            return Err(errors::argument(format!(
                "state has length {}; expected {}",
                s.len(),
                self.env.spec().state_dim()
            )));
        }
        match self.env.global_state_to_local(s) {
            Some(l) => Ok(arrays(py, &l)),
            None => Err(errors::argument(
                "some agent observes values that are not in the state: no mapping from the state",
            )),
        }
    }

    /// The global state rebuilt from every agent's observation.
    fn local_observations_to_global<'py>(
        &self,
        py: Python<'py>,
        obs: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let o = slices(&obs)?;
        let g = self
            .env
            .local_observations_to_global(&o)
            .map_err(|e| errors::argument(e.to_string()))?;
        Ok(PyArray1::from_vec(py, g))
    }

    #[getter]
    fn id(&self) -> String {
        self.env.spec().id.clone()
    }
    /// The task's id (the single-agent env every agent shares).
    #[getter]
    fn base_id(&self) -> String {
        self.env.spec().base.id.clone()
    }
    #[getter]
    fn conf(&self) -> String {
        self.env.spec().conf.clone()
    }
    #[getter]
    fn confs(&self) -> Vec<String> {
        self.env.spec().confs.clone()
    }
    #[getter]
    fn k(&self) -> usize {
        self.env.spec().k
    }
    /// Draw each agent's limbs in its own colour in later frames (False: the model's colours).
    fn color_agents(&mut self, on: bool) {
        self.env.color_agents(on);
    }
    /// A frame of the whole robot in Gymnasium's `render_mode` (MaMuJoCo renders its single-agent env).
    fn render(&mut self, py: Python<'_>, mode: &str) -> PyResult<Py<PyAny>> {
        crate::render::render(py, mode, |m| self.env.render(m))
    }
    #[getter]
    fn dt(&self) -> f64 {
        self.env.env().dt()
    }
    #[getter]
    fn max_episode_steps(&self) -> Option<u64> {
        self.env.spec().base.max_episode_steps
    }
    #[getter]
    fn possible_agents(&self) -> Vec<String> {
        self.env
            .possible_agents()
            .into_iter()
            .map(String::from)
            .collect()
    }
    /// The agents still acting: all after `reset`, none once the episode has ended.
    #[getter]
    fn agents(&self) -> Vec<String> {
        self.env.agents().into_iter().map(String::from).collect()
    }
    fn obs_low<'py>(&self, py: Python<'py>, agent: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env.observation_space(self.agent(agent)?).low,
        ))
    }
    fn obs_high<'py>(&self, py: Python<'py>, agent: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env.observation_space(self.agent(agent)?).high,
        ))
    }
    fn act_low<'py>(&self, py: Python<'py>, agent: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env.action_space(self.agent(agent)?).low,
        ))
    }
    fn act_high<'py>(&self, py: Python<'py>, agent: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env.action_space(self.agent(agent)?).high,
        ))
    }
    /// The global state's bounds (the single-agent observation space).
    #[getter]
    fn state_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.env().observation_space().low)
    }
    #[getter]
    fn state_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.env().observation_space().high)
    }
    /// The global action's bounds (the single-agent action space).
    #[getter]
    fn global_act_low<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.env().action_space().low)
    }
    #[getter]
    fn global_act_high<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.env.env().action_space().high)
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
        self.env.env().warnings().to_vec()
    }
}
