//! envc errors as Python exceptions: bad specs and parameters are `SpecError` (a `ValueError`)
//! with the stable code as its `code` attribute, an unknown parameter is a `TypeError` (as an unknown keyword
//! argument is in Python), bad actions are `ValueError`, a step before reset a `RuntimeError`.

use envspec::Code;
use pyo3::PyErr;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::PyAnyMethods;

pyo3::create_exception!(
    _envc,
    SpecError,
    PyValueError,
    "A spec, parameter or model that does not check out; `code` is the stable error code (docs/errors.md)."
);

/// The Python exception for an envc error.
pub fn env_error(e: envc::EnvError) -> PyErr {
    let code = e.code();
    let text = e.to_string();
    match (&e, code) {
        // An unknown parameter is an unknown keyword argument.
        (_, Code::E0202) => PyTypeError::new_err(text),
        (envc::EnvError::Spec(_), _) => {
            let err = SpecError::new_err(text);
            pyo3::Python::attach(|py| {
                // `code`: the stable error code; a failure to set it leaves the message intact.
                let _ = err.value(py).setattr("code", code.to_string());
            });
            err
        }
        (envc::EnvError::NotReset, _) => PyRuntimeError::new_err(text),
        // Rendering: a camera name or setting is a spec error; no GL is a runtime error.
        (envc::EnvError::Render(envc::render::RenderError::Spec(_)), _) => {
            let err = SpecError::new_err(text);
            pyo3::Python::attach(|py| {
                let _ = err.value(py).setattr("code", code.to_string());
            });
            err
        }
        (envc::EnvError::Render(_), Code::E1501 | Code::E1502) => PyRuntimeError::new_err(text),
        _ => PyValueError::new_err(text),
    }
}

/// A spec diagnostic list as a Python exception.
pub fn diagnostics(d: envspec::Diagnostics) -> PyErr {
    env_error(envc::EnvError::Spec(d))
}
