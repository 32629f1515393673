//! MuJoCo's raw model and data, behind safe functions: the runtime's one place that dereferences
//! `mjModel` / `mjData` pointers or calls MuJoCo's C API directly (rendering aside: `render/`).
//!
//! Arrays with a safe accessor in mujoco-rs (`MjData::qpos`, `MjModel::body_mass`, ...) are read
//! through it where they are used; this module holds what mujoco-rs leaves `unsafe` or does not
//! wrap the way envc needs:
//! - [`calls`]: the MuJoCo calls that may raise `mju_error` (`mj_forward`, `mj_step`, ...),
//!   through envc's `C-unwind` declarations and [`crate::mujoco_log::guard`];
//! - [`names`]: names and ids (no panic on a name MuJoCo cannot hold);
//! - [`model_edit`]: the model values `[actions]` gains and `[events]` write;
//! - [`state`]: borrows mujoco-rs cannot split (qpos and qvel at once) and the arrays it only
//!   hands out mutably through `unsafe`.

pub(crate) mod calls;
pub(crate) mod model_edit;
pub(crate) mod names;
pub(crate) mod state;

pub(crate) use calls::{Call, call};

/// MuJoCo's version string (`mj_versionString`, e.g. `"3.17.0"`).
pub(crate) fn version() -> String {
    // SAFETY: MuJoCo returns a static NUL-terminated string.
    unsafe { std::ffi::CStr::from_ptr(mujoco_rs::mujoco_c::mj_versionString()) }
        .to_string_lossy()
        .into_owned()
}
