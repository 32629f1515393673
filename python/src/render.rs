//! Frames to numpy: `rgb_array` is `(height, width, 3)` uint8, `depth_array` `(height, width)`
//! float32, `rgbd_tuple` the pair, as Gymnasium's `MujocoRenderer` returns them.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors;

/// Render with `f` (a task env, a maze, a multi-agent spec) in the mode named `mode` and convert
/// the frame (copied: the renderer reuses its buffers).
pub fn render<'a>(
    py: Python<'_>,
    mode: &str,
    f: impl FnOnce(envc::render::RenderMode) -> Result<envc::render::Frame<'a>, envc::EnvError>,
) -> PyResult<Py<PyAny>> {
    let mode = envc::render::RenderMode::parse(mode)
        .map_err(|e| errors::env_error(envc::EnvError::Render(e)))?;
    let frame = f(mode).map_err(errors::env_error)?;
    let (h, w) = (frame.height, frame.width);
    let rgb = match frame.rgb {
        Some(px) => Some(PyArray1::from_slice(py, px).reshape([h, w, 3])?.into_any()),
        None => None,
    };
    let depth = match frame.depth {
        Some(px) => Some(PyArray1::from_slice(py, px).reshape([h, w])?.into_any()),
        None => None,
    };
    Ok(match (rgb, depth) {
        (Some(r), Some(d)) => (r, d).into_pyobject(py)?.into_any().unbind(),
        (Some(r), None) => r.unbind(),
        (None, Some(d)) => d.unbind(),
        (None, None) => py.None(),
    })
}
