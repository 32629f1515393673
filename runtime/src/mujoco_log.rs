//! MuJoCo's warnings, captured. By default MuJoCo prints warnings to stdout and appends them to
//! `MUJOCO_LOG.TXT` in the working directory; envc installs a handler once per process that keeps
//! them in a per-thread buffer, from which each env moves them into its own list.

use std::cell::RefCell;
use std::ffi::{CStr, c_char};
use std::sync::Once;

thread_local! {
    static PENDING: RefCell<Vec<String>> = const { RefCell::new(Vec::new()) };
}

unsafe extern "C" fn on_warning(msg: *const c_char) {
    if msg.is_null() {
        return;
    }
    // SAFETY: MuJoCo passes a NUL-terminated message that lives for the duration of the call.
    let text = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    // A warning raised while the buffer is borrowed (cannot happen: we never call MuJoCo while
    // holding it) would be dropped rather than panic across the C boundary.
    PENDING.with(|p| {
        if let Ok(mut p) = p.try_borrow_mut() {
            p.push(text);
        }
    });
}

/// Route MuJoCo's warnings into envc (idempotent).
pub fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // SAFETY: a process-wide function pointer written once, before any env calls MuJoCo.
        unsafe {
            mujoco_rs::mujoco_c::mju_user_warning = Some(on_warning);
        }
    });
}

/// Move the warnings raised on this thread since the last call into `out`.
pub fn drain_into(out: &mut Vec<String>) {
    PENDING.with(|p| {
        let mut p = p.borrow_mut();
        if !p.is_empty() {
            out.append(&mut p);
        }
    });
}
