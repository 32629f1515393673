//! The core of a multi-agent env (a factorization of a task among agents): what `EnvCore`
//! shares (its joint action is the global action), a step with one numpy array per agent, each
//! agent's spaces, the global state and the reference's mappings between local and global
//! actions and observations.

use envc::multi_agent::MultiAgentEnv;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::env_core::{After, EnvCore, KindEnv, StepOut, guarded};
use crate::errors;

/// A multi-agent env (`envc.parallel_env` wraps it as a PettingZoo `ParallelEnv`).
#[pyclass(module = "envc._envc", extends = EnvCore)]
pub struct MultiAgentCore {
    pub(crate) env: MultiAgentEnv,
}

/// Agent `i`, checked.
fn agent(env: &MultiAgentEnv, i: usize) -> PyResult<usize> {
    if i < env.num_agents() {
        Ok(i)
    } else {
        Err(errors::argument(format!(
            "agent index {i} out of range ({} agents)",
            env.num_agents()
        )))
    }
}

type Arrays<'py> = Vec<Bound<'py, PyArray1<f64>>>;

/// One bound of agent `i`'s spaces, picked by `pick`.
fn agent_bound<'py>(
    env: &MultiAgentEnv,
    py: Python<'py>,
    i: usize,
    pick: impl for<'e> Fn(&'e MultiAgentEnv, usize) -> &'e [f64],
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    Ok(PyArray1::from_slice(py, pick(env, agent(env, i)?)))
}

fn arrays<'py>(py: Python<'py>, vs: &[Vec<f64>]) -> Arrays<'py> {
    vs.iter().map(|v| PyArray1::from_slice(py, v)).collect()
}

fn slices<'a>(xs: &'a [PyReadonlyArray1<'_, f64>]) -> PyResult<Vec<&'a [f64]>> {
    xs.iter().map(|x| Ok(x.as_slice()?)).collect()
}

#[pymethods]
impl MultiAgentCore {
    /// Step with one float64 action per agent (in agent order): every agent's observation and
    /// the shared reward, terminated, truncated and info.
    fn step_agents<'py>(
        &mut self,
        py: Python<'py>,
        actions: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<StepOut<'py>> {
        let a = slices(&actions)?;
        guarded(&mut self.env, |env| {
            let s = crate::mujoco_timer::without_mujoco_timer(|| env.step(&a))
                .map_err(errors::env_error)?;
            let (reward, terminated, truncated) = (s.reward, s.terminated, s.truncated);
            let (obs, info) = env.observe(py, After::Step)?;
            Ok((obs, reward, terminated, truncated, info))
        })
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
        let env = &self.env;
        let s = state.as_slice()?;
        if s.len() != env.spec().state_dim() {
            return Err(errors::argument(format!(
                "state has length {}; expected {}",
                s.len(),
                env.spec().state_dim()
            )));
        }
        match env.global_state_to_local(s) {
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
    #[getter]
    fn possible_agents(&self) -> Vec<String> {
        let names = self.env.possible_agents().into_iter();
        names.map(String::from).collect()
    }
    /// The agents still acting: all after `reset`, none once the episode has ended.
    #[getter]
    fn agents(&self) -> Vec<String> {
        self.env.agents().into_iter().map(String::from).collect()
    }
    /// Agent `agent`'s observation bounds.
    fn agent_obs_low<'py>(
        &self,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&self.env, py, agent, |e, i| &e.observation_space(i).low)
    }
    fn agent_obs_high<'py>(
        &self,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&self.env, py, agent, |e, i| &e.observation_space(i).high)
    }
    /// Agent `agent`'s action bounds.
    fn agent_act_low<'py>(
        &self,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&self.env, py, agent, |e, i| &e.action_space(i).low)
    }
    fn agent_act_high<'py>(
        &self,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&self.env, py, agent, |e, i| &e.action_space(i).high)
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
}
