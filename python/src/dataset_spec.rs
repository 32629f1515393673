//! Dataset specs for `envc.datasets` and the scripts: read by envspec (E1801 at the line and
//! column, the same reader `envc dataset build` uses) and handed over as plain data, and the
//! structural rewrite of their reference scores.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors;

/// A dataset spec file, or a bundled dataset's id, checked as a build checks it and returned as
/// its TOML data (the tables as written, `[train]` included; paths not resolved).
#[pyfunction]
pub fn read_dataset_spec<'py>(py: Python<'py>, spec: &str) -> PyResult<Bound<'py, PyDict>> {
    let read = errors::no_panic(
        &mut (),
        |_| envc_datasets::open_spec(spec).map_err(errors::dataset_error),
        |_| {},
    )?;
    table(py, &read.document)
}

/// The text of the dataset spec at `path` with its `[reference_scores]` set: the values replaced
/// where the table is, else a new table before `[train]`; comments and layout kept.
#[pyfunction]
pub fn with_reference_scores(
    path: std::path::PathBuf,
    ref_min_score: f64,
    ref_max_score: f64,
    num_episodes_average_score: u64,
) -> PyResult<String> {
    let scores = envc_datasets::RefScores {
        ref_min_score,
        ref_max_score,
        num_episodes_average_score,
    };
    envspec::dataset_spec::edit::with_reference_scores(&path, &scores)
        .map_err(|d| errors::diagnostics(d.into()))
}

fn table<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, value(py, v)?)?;
    }
    Ok(d)
}

/// As `tomllib` gives it, but a date or time as its TOML text (no dataset spec holds one).
fn value<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(t) => t.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for e in a {
                l.append(value(py, e)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => table(py, t)?.into_any(),
    })
}
