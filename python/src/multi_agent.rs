//! The core of a multi-agent env (a factorization of a task among agents).

use pyo3::prelude::*;

/// A multi-agent env (`envc.parallel_env` wraps it as a PettingZoo `ParallelEnv`).
#[pyclass(module = "envc._envc")]
pub struct AgentsCore {
    env: envc::multi_agent::MultiAgentEnv,
}

impl AgentsCore {
    pub fn new(env: envc::multi_agent::MultiAgentEnv) -> AgentsCore {
        AgentsCore { env }
    }
}

#[pymethods]
impl AgentsCore {
    #[getter]
    fn id(&self) -> String {
        self.env.spec().id.clone()
    }
}
