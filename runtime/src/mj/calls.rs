//! The MuJoCo calls that may raise `mju_error`, made through envc's `C-unwind` declarations
//! inside [`crate::mujoco_log::guard`], so an error comes back as `Err(message)` instead of
//! ending the process.

use mujoco_rs::mujoco_c::{mjData, mjModel};
use mujoco_rs::prelude::MjData;
use mujoco_rs::wrappers::mj_model::traits::ModelType;

use crate::mujoco_log::{self, ffi};

/// One MuJoCo computation on a model and its data.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Call {
    /// `mj_forward`.
    Forward,
    /// `mj_resetData`.
    ResetData,
    /// `mj_setConst`: the model's derived constants from its current values (it writes the
    /// model: only for a model copy that belongs to this data's env).
    SetConst,
    /// `n × mj_step`, then `mj_rnePostConstraint` when `rne`: one env step of physics.
    Step { n: u32, rne: bool },
}

/// Run `call` on `data` and its own model. After an error the data is reset
/// (`mj_resetData`), so it is never used in MuJoCo's mid-error state.
pub(crate) fn call<M: ModelType>(data: &mut MjData<M>, call: Call) -> Result<(), String> {
    let m: *const mjModel = data.model().ffi();
    // SAFETY: the data's own model and the data, borrowed exclusively here; only MuJoCo uses
    // the pointers, and only for the duration of this function.
    let d: *mut mjData = unsafe { data.ffi_mut() };
    let result = match call {
        // SAFETY: `m` and `d` as above, a live model and data of that model.
        Call::Forward => mujoco_log::guard(|| unsafe { ffi::mj_forward(m, d) }),
        // SAFETY: as above.
        Call::ResetData => mujoco_log::guard(|| unsafe { ffi::mj_resetData(m, d) }),
        // SAFETY: as above; mj_setConst also writes the model's constants, which
        // `Call::SetConst`'s contract allows.
        Call::SetConst => mujoco_log::guard(|| unsafe { ffi::mj_setConst(m.cast_mut(), d) }),
        Call::Step { n, rne } => mujoco_log::guard(|| {
            for _ in 0..n {
                // SAFETY: as above.
                unsafe { ffi::mj_step(m, d) };
            }
            if rne {
                // SAFETY: as above.
                unsafe { ffi::mj_rnePostConstraint(m, d) };
            }
        }),
    };
    result.inspect_err(|_| {
        // SAFETY: as above; resetting clears the arena and stack an error left marked.
        unsafe { ffi::mj_resetData(m, d) };
    })
}
