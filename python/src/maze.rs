//! The core of a maze env (goal-conditioned, dict observations).

use pyo3::prelude::*;

/// A maze env (`envc.EnvcMazeEnv` wraps it).
#[pyclass(module = "envc._envc")]
pub struct MazeCore {
    env: envc::maze::MazeEnv,
}

impl MazeCore {
    pub fn new(env: envc::maze::MazeEnv) -> MazeCore {
        MazeCore { env }
    }
}

#[pymethods]
impl MazeCore {
    #[getter]
    fn id(&self) -> String {
        self.env.id().to_string()
    }
}
