//! The core of a multi-agent env (a factorization of a task among agents): what `EnvCore`
//! shares (its joint action is the global action), a step with one numpy array per agent, each
//! agent's spaces, the global state and the reference's mappings between local and global
//! actions and observations.

use envc::multi_agent::MultiAgentEnv;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::env_core::{After, EnvCore, StepOut, observe, wrong_kind};
use crate::errors;

/// A multi-agent env (`envc.parallel_env` wraps it as a PettingZoo `ParallelEnv`).
#[pyclass(module = "envc._envc", extends = EnvCore)]
pub struct AgentsCore;

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
    slf: &PyRef<'py, AgentsCore>,
    py: Python<'py>,
    i: usize,
    pick: impl for<'e> Fn(&'e MultiAgentEnv, usize) -> &'e [f64],
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let env = slf.as_super().agents()?;
    Ok(PyArray1::from_slice(py, pick(env, agent(env, i)?)))
}

fn arrays<'py>(py: Python<'py>, vs: &[Vec<f64>]) -> Arrays<'py> {
    vs.iter().map(|v| PyArray1::from_slice(py, v)).collect()
}

fn slices<'a>(xs: &'a [PyReadonlyArray1<'_, f64>]) -> PyResult<Vec<&'a [f64]>> {
    xs.iter().map(|x| Ok(x.as_slice()?)).collect()
}

#[pymethods]
impl AgentsCore {
    /// Step with one float64 action per agent (in agent order): every agent's observation and
    /// the shared reward, terminated, truncated and info.
    fn step_agents<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
        actions: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<StepOut<'py>> {
        let a = slices(&actions)?;
        slf.as_super().guarded(|env| {
            let envc::AnyEnv::Agents(agents) = env else {
                return Err(wrong_kind(env, "multi-agent"));
            };
            let s = crate::mujoco_timer::without_mujoco_timer(|| agents.step(&a))
                .map_err(errors::env_error)?;
            let flags = (s.reward, s.terminated, s.truncated);
            let (obs, info) = observe(py, env, After::Step)?;
            Ok((obs, flags.0, flags.1, flags.2, info))
        })
    }

    /// The global state: the single-agent env's observation.
    fn state<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, slf.as_super().agents()?.state()))
    }

    /// The global action of one local action per agent.
    fn local_actions_to_global<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        actions: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let a = slices(&actions)?;
        let g = slf
            .as_super()
            .agents()?
            .local_actions_to_global(&a)
            .map_err(errors::env_error)?;
        Ok(PyArray1::from_vec(py, g))
    }

    /// Each agent's share of a global action.
    fn global_action_to_local<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arrays<'py>> {
        let l = slf
            .as_super()
            .agents()?
            .global_action_to_local(action.as_slice()?)
            .map_err(errors::env_error)?;
        Ok(arrays(py, &l))
    }

    /// Each agent's observation taken from a global state.
    fn global_state_to_local<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        state: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arrays<'py>> {
        let env = slf.as_super().agents()?;
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
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        obs: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let o = slices(&obs)?;
        let g = slf
            .as_super()
            .agents()?
            .local_observations_to_global(&o)
            .map_err(|e| errors::argument(e.to_string()))?;
        Ok(PyArray1::from_vec(py, g))
    }

    /// The task's id (the single-agent env every agent shares).
    #[getter]
    fn base_id(slf: PyRef<'_, Self>) -> PyResult<String> {
        Ok(slf.as_super().agents()?.spec().base.id.clone())
    }
    #[getter]
    fn conf(slf: PyRef<'_, Self>) -> PyResult<String> {
        Ok(slf.as_super().agents()?.spec().conf.clone())
    }
    #[getter]
    fn confs(slf: PyRef<'_, Self>) -> PyResult<Vec<String>> {
        Ok(slf.as_super().agents()?.spec().confs.clone())
    }
    #[getter]
    fn k(slf: PyRef<'_, Self>) -> PyResult<usize> {
        Ok(slf.as_super().agents()?.spec().k)
    }
    /// Draw each agent's limbs in its own colour in later frames (False: the model's colours).
    fn color_agents(mut slf: PyRefMut<'_, Self>, on: bool) -> PyResult<()> {
        slf.as_super().agents_mut()?.color_agents(on);
        Ok(())
    }
    #[getter]
    fn possible_agents(slf: PyRef<'_, Self>) -> PyResult<Vec<String>> {
        let env = slf.as_super().agents()?;
        Ok(env
            .possible_agents()
            .into_iter()
            .map(String::from)
            .collect())
    }
    /// The agents still acting: all after `reset`, none once the episode has ended.
    #[getter]
    fn agents(slf: PyRef<'_, Self>) -> PyResult<Vec<String>> {
        let env = slf.as_super().agents()?;
        Ok(env.agents().into_iter().map(String::from).collect())
    }
    /// Agent `agent`'s observation bounds.
    fn agent_obs_low<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&slf, py, agent, |e, i| &e.observation_space(i).low)
    }
    fn agent_obs_high<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&slf, py, agent, |e, i| &e.observation_space(i).high)
    }
    /// Agent `agent`'s action bounds.
    fn agent_act_low<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&slf, py, agent, |e, i| &e.action_space(i).low)
    }
    fn agent_act_high<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
        agent: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        agent_bound(&slf, py, agent, |e, i| &e.action_space(i).high)
    }
    /// The global state's bounds (the single-agent observation space).
    #[getter]
    fn state_low<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let env = slf.as_super().agents()?;
        Ok(PyArray1::from_slice(py, &env.env().observation_space().low))
    }
    #[getter]
    fn state_high<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let env = slf.as_super().agents()?;
        Ok(PyArray1::from_slice(
            py,
            &env.env().observation_space().high,
        ))
    }
}
