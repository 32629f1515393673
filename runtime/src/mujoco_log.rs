//! MuJoCo's warnings and errors, captured. By default MuJoCo prints both to stdout and appends
//! them to `MUJOCO_LOG.TXT` in the working directory, and an error (`mju_error`: an arena or stack
//! overflow in `mj_step`, say) then ends the process with `exit(1)`. envc installs handlers once
//! per process: warnings go to a per-thread buffer, from which each env moves them into its own
//! list; an error unwinds out of MuJoCo as a Rust panic (the `C-unwind` ABI; MuJoCo's own Python
//! bindings throw a C++ exception the same way) and [`guard`] turns it into an `Err` with the
//! message. Only the calls made through [`guard`] with the `C-unwind` declarations below may
//! raise one; after an error the `mjData` is reset before it is used again.

use std::cell::RefCell;
use std::ffi::{CStr, c_char};
use std::sync::Once;

thread_local! {
    static PENDING: RefCell<Vec<String>> = const { RefCell::new(Vec::new()) };
    /// How many `guard`s are running on this thread: an error outside every guard is a bug to
    /// report, not a value in flight.
    static GUARDED: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
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

/// The payload of the panic an `mju_error` becomes.
struct MujocoError(String);

unsafe extern "C-unwind" fn on_error(msg: *const c_char) {
    let text = if msg.is_null() {
        "MuJoCo error".to_string()
    } else {
        // SAFETY: as in `on_warning`.
        unsafe { CStr::from_ptr(msg) }
            .to_string_lossy()
            .into_owned()
    };
    std::panic::panic_any(MujocoError(text));
}

/// Route MuJoCo's warnings and errors into envc (idempotent).
pub fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        type Handler = unsafe extern "C" fn(*const c_char);
        // SAFETY: process-wide function pointers written once, before any env calls MuJoCo. The
        // error handler has the `C-unwind` ABI (same calling convention as `C`): it is only ever
        // reached from calls declared `C-unwind` in `ffi` below, inside `guard`.
        unsafe {
            mujoco_rs::mujoco_c::mju_user_warning = Some(on_warning);
            mujoco_rs::mujoco_c::mju_user_error = Some(std::mem::transmute::<
                unsafe extern "C-unwind" fn(*const c_char),
                Handler,
            >(on_error));
        }
        // The panic is an error value in flight, not a bug: keep it off stderr.
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            match info.payload().downcast_ref::<MujocoError>() {
                Some(_) if GUARDED.with(|g| g.get()) > 0 => {}
                // A MuJoCo call envc does not guard yet: say what MuJoCo said, not nothing.
                Some(e) => eprintln!(
                    "envc: error[E1004]: MuJoCo failed outside a guarded call: {}",
                    e.0
                ),
                None => previous(info),
            }
        }));
    });
}

/// Run MuJoCo calls that may raise `mju_error`; the error's message comes back as `Err`. Other
/// panics pass through.
pub(crate) fn guard<R>(f: impl FnOnce() -> R) -> Result<R, String> {
    GUARDED.with(|g| g.set(g.get() + 1));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(g.get() - 1));
    r.map_err(|payload| match payload.downcast::<MujocoError>() {
        Ok(e) => e.0,
        Err(other) => std::panic::resume_unwind(other),
    })
}

/// MuJoCo's entry points that can raise `mju_error` while stepping, declared `C-unwind` so the
/// error's unwinding through them is defined (mujoco-rs declares them `C`, which would abort).
pub(crate) mod ffi {
    use mujoco_rs::mujoco_c::{mjData, mjModel};

    unsafe extern "C-unwind" {
        pub fn mj_step(m: *const mjModel, d: *mut mjData);
        pub fn mj_forward(m: *const mjModel, d: *mut mjData);
        pub fn mj_resetData(m: *const mjModel, d: *mut mjData);
        pub fn mj_rnePostConstraint(m: *const mjModel, d: *mut mjData);
        pub fn mj_setConst(m: *mut mjModel, d: *mut mjData);
    }
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

/// `n × mj_step`, then `mj_rnePostConstraint` when `rne`: one env step of physics, with MuJoCo's
/// errors returned. The caller resets the data after an error.
///
/// # Safety
/// `m` and `d` are a live model and data of that model, used by nothing else meanwhile.
pub(crate) unsafe fn physics_step(
    m: *const mujoco_rs::mujoco_c::mjModel,
    d: *mut mujoco_rs::mujoco_c::mjData,
    n: u32,
    rne: bool,
) -> Result<(), String> {
    guard(|| {
        for _ in 0..n {
            // SAFETY: the caller's contract.
            unsafe { ffi::mj_step(m, d) };
        }
        if rne {
            // SAFETY: as above.
            unsafe { ffi::mj_rnePostConstraint(m, d) };
        }
    })
}
