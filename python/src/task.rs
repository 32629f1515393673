//! The core of a single-agent task env: what `EnvCore` shares, plus the observation bounds, the
//! state and the resolved parameters.

use numpy::PyArray1;
use pyo3::prelude::*;

use crate::env_core::EnvCore;
use crate::errors;

type F64Array<'py> = Bound<'py, PyArray1<f64>>;

/// A task env (`envc.EnvcEnv` wraps it as a `gymnasium.Env`).
#[pyclass(module = "envc._envc", extends = EnvCore)]
pub struct TaskCore;

#[pymethods]
impl TaskCore {
    /// `(qpos, qvel)` now (checks of other executors start from the same state).
    fn state<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<(F64Array<'py>, F64Array<'py>)> {
        let (q, v) = slf.as_super().task()?.state();
        Ok((PyArray1::from_slice(py, q), PyArray1::from_slice(py, v)))
    }
    #[getter]
    fn obs_low<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &slf.as_super().task()?.observation_space().low,
        ))
    }
    #[getter]
    fn obs_high<'py>(
        slf: PyRef<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &slf.as_super().task()?.observation_space().high,
        ))
    }
    /// The resolved parameters: `{name: value as TOML text}`.
    #[getter]
    fn params(slf: PyRef<'_, Self>) -> PyResult<Vec<(String, String)>> {
        Ok(slf
            .as_super()
            .task()?
            .spec()
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value.to_string()))
            .collect())
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
