//! Python ↔ envc values: overrides arrive as `(name, TOML literal)` pairs (the Python layer writes
//! the literals), infos leave as dicts of floats and float64 arrays.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pub fn overrides(pairs: &[(String, String)]) -> Vec<envc::Override> {
    pairs
        .iter()
        .map(|(k, v)| envc::Override::text(k, v))
        .collect()
}

/// An info as Gymnasium envs return it: a scalar entry as a float, a vector entry as an array.
pub fn info<'py>(py: Python<'py>, info: envc::Info<'_>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in info.iter() {
        if v.len() == 1 {
            d.set_item(k, v[0])?;
        } else {
            d.set_item(k, PyArray1::from_slice(py, v))?;
        }
    }
    Ok(d)
}

/// A numerics profile by name (`auto` or e.g. `openblas-haswell+svml`), as every core's
/// `numerics` setter takes it; an unknown name is the envc error E1301.
pub fn profile(name: &str) -> PyResult<envc::numerics::Profile> {
    envc::numerics::Profile::resolve(name, "numerics")
        .map_err(|e| crate::errors::env_error(e.into()))
}
