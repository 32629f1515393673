//! Names and ids of model elements (`mj_name2id`, `mj_id2name`).

use std::ffi::{CStr, CString};

use mujoco_rs::mujoco_c::{mj_id2name, mj_name2id, mjModel, mjtObj};

/// The id of the element of kind `obj` named `name`; `None` when the model has none (or the name
/// holds a NUL, which no MuJoCo name can).
pub(crate) fn id(m: &mjModel, obj: mjtObj, name: &str) -> Option<usize> {
    let c = CString::new(name).ok()?;
    // SAFETY: a live model and a NUL-terminated name; MuJoCo only reads both.
    let i = unsafe { mj_name2id(m, obj as i32, c.as_ptr()) };
    usize::try_from(i).ok()
}

/// The name of element `id` of kind `obj`; `None` when it is unnamed (or `id` is out of range).
pub(crate) fn name(m: &mjModel, obj: mjtObj, id: usize) -> Option<String> {
    let id = i32::try_from(id).ok()?;
    // SAFETY: a live model; MuJoCo checks the id and returns NULL for an unnamed element.
    let p = unsafe { mj_id2name(m, obj as i32, id) };
    if p.is_null() {
        return None;
    }
    // SAFETY: a NUL-terminated string in the model's names buffer, which outlives this call.
    Some(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}
