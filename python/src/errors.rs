//! envc errors as Python exceptions: one hierarchy under `envc.Error` (`python/envc/_errors.py`),
//! every one carrying its stable code as `code` and picklable with it. The class follows from the
//! code (`SpecError` for E0xxx, `ModelError`, `ActionError`, `DatasetError`, ...); each is also
//! the builtin exception envc raised before (`SpecError` a `ValueError`, an unknown parameter a
//! `TypeError`, a step before reset a `RuntimeError`).

use pyo3::PyErr;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;

/// `envc._errors.coded`, which maps a code to its exception class: looked up once.
static CODED: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// The envc exception for `code` with `text`. Should the Python module be missing (it never is
/// in an installed package), a `RuntimeError` still carries the text.
pub fn coded(code: &str, text: String) -> PyErr {
    Python::attach(|py| {
        let made = CODED
            .import(py, "envc._errors", "coded")
            .and_then(|f| f.call1((text.as_str(), code)));
        match made {
            Ok(e) => PyErr::from_value(e),
            Err(_) => pyo3::exceptions::PyRuntimeError::new_err(text),
        }
    })
}

/// The Python exception for an envc error.
pub fn env_error(e: envc::EnvError) -> PyErr {
    coded(&e.code().to_string(), e.to_string())
}

/// A spec diagnostic list as a Python exception.
pub fn diagnostics(d: envspec::Diagnostics) -> PyErr {
    env_error(envc::EnvError::Spec(d))
}

/// A dataset or collection error (E12xx, E1402, E1600, E1601, or the env's own code).
pub fn dataset_error(e: envc_datasets::DatasetError) -> PyErr {
    coded(&e.code(), e.to_string())
}

/// E1105: an argument of a Python call of the wrong type or out of range.
pub fn argument(text: impl std::fmt::Display) -> PyErr {
    coded("E1105", format!("error[E1105]: {text}"))
}

/// Run a binding's body; a panic (a bug) becomes `envc.InternalError` (E1900) instead of
/// PyO3's `PanicException`, which `except Exception` does not catch. `on_panic` leaves the
/// object that panicked needing a reset. An `mju_error` that escaped every guard is E1004.
pub fn no_panic<T: ?Sized, R>(
    target: &mut T,
    f: impl FnOnce(&mut T) -> PyResult<R>,
    on_panic: impl FnOnce(&mut T),
) -> PyResult<R> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&mut *target))) {
        Ok(r) => r,
        Err(payload) => {
            // Should the object itself be beyond repair, its own panic stays contained too.
            let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| on_panic(target)));
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .or_else(|| envc::mujoco_error_message(&*payload))
                .unwrap_or_else(|| "a panic without a message".into());
            if envc::mujoco_error_message(&*payload).is_some() {
                return Err(coded(
                    "E1004",
                    format!("error[E1004]: MuJoCo failed: {what}; reset before stepping again"),
                ));
            }
            Err(coded(
                "E1900",
                format!(
                    "error[E1900]: envc failed internally, a bug (please report it with this \
                     message): {what}; reset before stepping again"
                ),
            ))
        }
    }
}
