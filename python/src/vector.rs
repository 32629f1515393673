//! The core of a vector env: many task envs stepped by Rust threads into numpy batches.

use pyo3::prelude::*;

/// A vector env (`envc.EnvcVectorEnv` wraps it as a `gymnasium.vector.VectorEnv`).
#[pyclass(module = "envc._envc")]
pub struct VecCore {
    env: envc::VecEnv,
}

#[pymethods]
impl VecCore {
    #[getter]
    fn num_envs(&self) -> usize {
        self.env.envs().len()
    }
}
