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

/// MuJoCo's message when a panic's payload is an `mju_error` that unwound outside every guard
/// (the Python binding turns it into E1004 rather than a bug report).
pub fn mujoco_error_message(payload: &(dyn std::any::Any + Send)) -> Option<String> {
    payload.downcast_ref::<MujocoError>().map(|e| e.0.clone())
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

/// MuJoCo's entry points that can raise `mju_error`, declared `C-unwind` so the error's
/// unwinding through them is defined (mujoco-rs declares them `C`: unwinding through those is
/// undefined behaviour, which the optimized build turned into a panic escaping to `main`). Every
/// MuJoCo function envc calls directly is either here or in `NO_MJU_ERROR` (the test
/// `every_direct_mujoco_call_can_unwind` reads the sources to check).
pub(crate) mod ffi {
    use mujoco_rs::mujoco_c::{
        mjData, mjModel, mjrContext, mjrRect, mjvCamera, mjvOption, mjvPerturb, mjvScene,
    };

    unsafe extern "C-unwind" {
        pub fn mj_step(m: *const mjModel, d: *mut mjData);
        pub fn mj_forward(m: *const mjModel, d: *mut mjData);
        pub fn mj_resetData(m: *const mjModel, d: *mut mjData);
        pub fn mj_rnePostConstraint(m: *const mjModel, d: *mut mjData);
        pub fn mj_subtreeVel(m: *const mjModel, d: *mut mjData);
        pub fn mj_setConst(m: *mut mjModel, d: *mut mjData);
        pub fn mj_copyModel(dest: *mut mjModel, src: *const mjModel) -> *mut mjModel;
        pub fn mjv_makeScene(m: *const mjModel, scn: *mut mjvScene, maxgeom: i32);
        pub fn mjv_updateScene(
            m: *const mjModel,
            d: *mut mjData,
            opt: *const mjvOption,
            pert: *const mjvPerturb,
            cam: *mut mjvCamera,
            catmask: i32,
            scn: *mut mjvScene,
        );
        pub fn mjv_freeScene(scn: *mut mjvScene);
        pub fn mjr_makeContext(m: *const mjModel, con: *mut mjrContext, fontscale: i32);
        pub fn mjr_setBuffer(framebuffer: i32, con: *mut mjrContext);
        pub fn mjr_render(viewport: mjrRect, scn: *mut mjvScene, con: *const mjrContext);
        pub fn mjr_readPixels(
            rgb: *mut u8,
            depth: *mut f32,
            viewport: mjrRect,
            con: *const mjrContext,
        );
        pub fn mjr_freeContext(con: *mut mjrContext);
    }
}

/// MuJoCo functions envc calls through mujoco-rs's `C` declarations: none can raise `mju_error`
/// as envc calls them (defaults, names and ids, sizes, the version, a model's deletion, and
/// `mj_objectVelocity` with a valid object type). The `C-unwind` list is `ffi` above.
#[cfg(test)]
pub(crate) const NO_MJU_ERROR: &[&str] = &[
    "mjv_defaultCamera",
    "mjv_defaultOption",
    "mjv_defaultPerturb",
    "mjv_defaultScene",
    "mjr_defaultContext",
    "mj_deleteModel",
    "mj_versionString",
    "mj_id2name",
    "mj_name2id",
    "mj_sizeModel",
    "mj_saveModel",
    "mj_objectVelocity",
];

/// Move the warnings raised on this thread since the last call into `out`.
pub fn drain_into(out: &mut Vec<String>) {
    PENDING.with(|p| {
        let mut p = p.borrow_mut();
        if !p.is_empty() {
            out.append(&mut p);
        }
    });
}

#[cfg(test)]
mod tests {
    /// Every MuJoCo function the runtime calls through mujoco-rs's `C` declarations (`c::mj…`,
    /// `mujoco_c::mj…`, or imported from `mujoco_c`) is listed in `NO_MJU_ERROR`; the others go
    /// through `ffi`'s `C-unwind` declarations.
    #[test]
    fn every_direct_mujoco_call_can_unwind() {
        let src = concat!(env!("CARGO_MANIFEST_DIR"), "/src");
        let this = std::fs::read_to_string(format!("{src}/mj/log.rs")).unwrap();
        let ffi_block = this
            .split("unsafe extern \"C-unwind\" {")
            .nth(1)
            .and_then(|s| s.split("\n    }\n").next())
            .unwrap();
        let unwinding: Vec<&str> = ffi_block
            .split("pub fn ")
            .skip(1)
            .map(|s| s.split('(').next().unwrap())
            .collect();
        for f in [
            "mj_step",
            "mjr_makeContext",
            "mjr_render",
            "mjv_updateScene",
        ] {
            assert!(
                unwinding.contains(&f),
                "{f} not declared C-unwind: {unwinding:?}"
            );
        }
        let mut files = vec![];
        let mut dirs = vec![std::path::PathBuf::from(src)];
        while let Some(d) = dirs.pop() {
            for e in std::fs::read_dir(d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    dirs.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    files.push(p);
                }
            }
        }
        let mut called = std::collections::BTreeSet::new();
        for f in &files {
            let text = std::fs::read_to_string(f).unwrap();
            for (i, _) in text.match_indices("mj") {
                let before = &text[..i];
                let via_c = before.ends_with("c::") || before.ends_with("mujoco_c::");
                let imported = before
                    .rfind("use mujoco_rs::mujoco_c::")
                    .is_some_and(|u| !text[u..i].contains(';'));
                if !via_c && !imported {
                    continue;
                }
                let name: String = text[i..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                // Functions only: `mj_…`, `mjv_…`, `mjr_…`, `mju_…` (not types such as `mjModel`).
                if ["mj_", "mjv_", "mjr_"].iter().any(|p| name.starts_with(p)) {
                    called.insert((name, f.display().to_string()));
                }
            }
        }
        assert!(called.iter().any(|(n, _)| n == "mj_id2name"), "{called:?}");
        let unlisted: Vec<_> = called
            .iter()
            .filter(|(n, _)| !super::NO_MJU_ERROR.contains(&n.as_str()))
            .collect();
        assert!(
            unlisted.is_empty(),
            "MuJoCo functions called through a `C` declaration that may raise mju_error; declare \
             them `C-unwind` in mj::log::ffi and call them inside `guard`, or list them in \
             NO_MJU_ERROR with a reason: {unlisted:?}"
        );
    }
}
