//! Borrows of an `mjData` that mujoco-rs's accessors cannot split.

use mujoco_rs::prelude::MjData;
use mujoco_rs::wrappers::mj_model::traits::ModelType;

/// `qpos` (nq) and `qvel` (nv), both writable at once (a reset draws into either).
pub(crate) fn qpos_qvel_mut<M: ModelType>(data: &mut MjData<M>) -> (&mut [f64], &mut [f64]) {
    let m = data.model().ffi();
    let (nq, nv) = (
        usize::try_from(m.nq).unwrap_or(0),
        usize::try_from(m.nv).unwrap_or(0),
    );
    // SAFETY: the data's own arrays, nq and nv doubles (MuJoCo allocates both, even empty);
    // they do not overlap, and both borrows end with the exclusive borrow of `data`.
    unsafe {
        let d = data.ffi_mut();
        (slice_mut(d.qpos, nq), slice_mut(d.qvel, nv))
    }
}

/// # Safety
/// `ptr` points to `len` initialised doubles, borrowed by nothing else for `'a`.
unsafe fn slice_mut<'a>(ptr: *mut f64, len: usize) -> &'a mut [f64] {
    if len == 0 || ptr.is_null() {
        &mut []
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(ptr, len) }
    }
}
