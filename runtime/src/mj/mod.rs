//! MuJoCo's raw model and data, behind safe functions: the runtime's one place that dereferences
//! `mjModel` / `mjData` pointers or calls MuJoCo's C API directly (rendering aside: `render/`).
//!
//! Arrays with a safe accessor in mujoco-rs (`MjData::qpos`, `MjModel::body_mass`, ...) are read
//! through it where they are used; this module holds what mujoco-rs leaves `unsafe` or does not
//! wrap the way envc needs:
//! - [`calls`]: the MuJoCo calls that may raise `mju_error` (`mj_forward`, `mj_step`, ...),
//!   through envc's `C-unwind` declarations and [`crate::mj::log::guard`];
//! - [`names`]: names and ids (no panic on a name MuJoCo cannot hold);
//! - [`model_edit`]: the model values `[actions]` gains and `[events]` write;
//! - [`state`]: borrows mujoco-rs cannot split (qpos and qvel at once);
//! - [`manip`]: what manipulation tasks read and write (site Jacobians, mocap poses, the
//!   simulation time, weld poses);
//! - [`stat`]: the `mjStatistic` of a spec and of a compiled model (`settotalmass`, [`total_mass`]);
//! - [`without_mujoco_timer`]: MuJoCo's process-wide profiling clock, cleared while envc steps.

pub(crate) mod log;
pub(crate) mod total_mass;

pub(crate) use calls::{Call, call};

/// MuJoCo's version string (`mj_versionString`, e.g. `"3.17.0"`).
pub(crate) fn version() -> String {
    // SAFETY: MuJoCo returns a static NUL-terminated string.
    unsafe { std::ffi::CStr::from_ptr(mujoco_rs::mujoco_c::mj_versionString()) }
        .to_string_lossy()
        .into_owned()
}

pub(crate) mod calls {
    //! The MuJoCo calls that may raise `mju_error`, made through envc's `C-unwind` declarations
    //! inside [`crate::mj::log::guard`], so an error comes back as `Err(message)` instead of
    //! ending the process.

    use mujoco_rs::mujoco_c::{mjData, mjModel};
    use mujoco_rs::prelude::MjData;
    use mujoco_rs::wrappers::mj_model::traits::ModelType;

    use crate::mj::log::{self as mujoco_log, ffi};

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
        /// `mj_subtreeVel`: `subtree_linvel` and `subtree_angmom` from the current kinematics.
        SubtreeVel,
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
            // SAFETY: as above.
            Call::SubtreeVel => mujoco_log::guard(|| unsafe { ffi::mj_subtreeVel(m, d) }),
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
}

pub(crate) mod names {
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
}

pub(crate) mod model_edit {
    //! The model values envc writes after compiling: `[actions]` gains and `[events]` (domain
    //! randomization of an env's own model copy).

    use std::marker::PhantomData;

    use mujoco_rs::mujoco_c::mjModel;
    use mujoco_rs::prelude::MjModel;

    /// `mjNGAIN` (= `mjNBIAS`): entries per actuator of `gainprm` and `biasprm`.
    pub(crate) const NPRM: usize = mujoco_rs::mujoco_c::mjNGAIN as usize;
    const _: () = assert!(mujoco_rs::mujoco_c::mjNBIAS as usize == NPRM);

    /// A model array of doubles envc writes, with MuJoCo's row strides.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub(crate) enum ModelArray {
        GeomFriction,
        BodyMass,
        BodyIpos,
        BodyPos,
        BodyQuat,
        SitePos,
        DofDamping,
        DofArmature,
        GainPrm,
        BiasPrm,
        Gravity,
        Timestep,
    }

    impl ModelArray {
        /// The number of doubles the array holds in `m`.
        fn len(self, m: &mjModel) -> usize {
            let n = |x: i64| usize::try_from(x).unwrap_or(0);
            match self {
                ModelArray::GeomFriction => 3 * n(m.ngeom),
                ModelArray::BodyMass => n(m.nbody),
                ModelArray::BodyIpos | ModelArray::BodyPos => 3 * n(m.nbody),
                ModelArray::SitePos => 3 * n(m.nsite),
                ModelArray::BodyQuat => 4 * n(m.nbody),
                ModelArray::DofDamping | ModelArray::DofArmature => n(m.nv),
                ModelArray::GainPrm | ModelArray::BiasPrm => NPRM * n(m.nu),
                ModelArray::Gravity => 3,
                ModelArray::Timestep => 1,
            }
        }

        /// The address of value `idx`. Panics (a bug: slots are checked when they are built) when
        /// `idx` is outside the array.
        fn addr(self, m: *mut mjModel, idx: usize) -> *mut f64 {
            // SAFETY: `m` is a live model (both callers hold a borrow of it); reading its sizes and
            // array pointers does not touch the arrays.
            let len = self.len(unsafe { &*m });
            assert!(
                idx < len,
                "{self:?}[{idx}] outside the model's {len} values"
            );
            // SAFETY: as above; `idx` is within the array, checked just now.
            unsafe {
                match self {
                    ModelArray::GeomFriction => (*m).geom_friction.add(idx),
                    ModelArray::BodyMass => (*m).body_mass.add(idx),
                    ModelArray::BodyIpos => (*m).body_ipos.add(idx),
                    ModelArray::BodyPos => (*m).body_pos.add(idx),
                    ModelArray::SitePos => (*m).site_pos.add(idx),
                    ModelArray::BodyQuat => (*m).body_quat.add(idx),
                    ModelArray::DofDamping => (*m).dof_damping.add(idx),
                    ModelArray::DofArmature => (*m).dof_armature.add(idx),
                    ModelArray::GainPrm => (*m).actuator_gainprm.add(idx),
                    ModelArray::BiasPrm => (*m).actuator_biasprm.add(idx),
                    ModelArray::Gravity => (&raw mut (*m).opt.gravity).cast::<f64>().add(idx),
                    ModelArray::Timestep => &raw mut (*m).opt.timestep,
                }
            }
        }

        /// Value `idx` of this array in `m`.
        pub(crate) fn get(self, m: &mjModel, idx: usize) -> f64 {
            // SAFETY: an address within the array of a live model, read while it is borrowed.
            unsafe { *self.addr((m as *const mjModel).cast_mut(), idx) }
        }
    }

    /// Writes into one model's values.
    pub(crate) struct ModelValues<'a> {
        m: *mut mjModel,
        _model: PhantomData<&'a MjModel>,
    }

    impl<'a> ModelValues<'a> {
        /// Writes into a model no env or data uses yet.
        pub(crate) fn owned(model: &'a mut MjModel) -> ModelValues<'a> {
            // SAFETY: the model is borrowed exclusively; the pointer is used only while it is.
            let m: *mut mjModel = unsafe { model.ffi_mut() };
            ModelValues {
                m,
                _model: PhantomData,
            }
        }

        /// Writes into an env's own model copy (an env whose `[events]` write the model compiles
        /// one for itself), shared only with that env's data. The env calls this only while it uses
        /// neither its model nor its data otherwise, and never from two threads at once (an env is
        /// stepped by one thread at a time).
        pub(crate) fn env_copy(model: &'a MjModel) -> ModelValues<'a> {
            ModelValues {
                m: (model.ffi() as *const mjModel).cast_mut(),
                _model: PhantomData,
            }
        }

        pub(crate) fn get(&self, arr: ModelArray, idx: usize) -> f64 {
            // SAFETY: an address within the array (checked by `addr`) of a live model.
            unsafe { *arr.addr(self.m, idx) }
        }

        pub(crate) fn set(&mut self, arr: ModelArray, idx: usize, v: f64) {
            // SAFETY: as in `get`; writes go to the model's arrays, which nothing else reads or
            // writes meanwhile (the constructors' contracts).
            unsafe { *arr.addr(self.m, idx) = v };
        }
    }
}

pub(crate) mod state {
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

    /// `mocap_pos` and `mocap_quat` (3 and 4 doubles per mocap body), beside `qpos` and `qvel`:
    /// what a reset writes.
    pub(crate) fn state_mut<M: ModelType>(data: &mut MjData<M>) -> [&mut [f64]; 4] {
        let m = data.model().ffi();
        let n = |x: i64| usize::try_from(x).unwrap_or(0);
        let (nq, nv, nmocap) = (n(m.nq), n(m.nv), n(m.nmocap));
        // SAFETY: the data's own arrays, of these sizes (MuJoCo allocates each, even empty);
        // they do not overlap, and every borrow ends with the exclusive borrow of `data`.
        unsafe {
            let d = data.ffi_mut();
            [
                slice_mut(d.qpos, nq),
                slice_mut(d.qvel, nv),
                slice_mut(d.mocap_pos, 3 * nmocap),
                slice_mut(d.mocap_quat, 4 * nmocap),
            ]
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
}

pub(crate) mod manip {
    //! Site Jacobians, mocap poses, the simulation time and weld poses (`runtime::manipulation`).

    use mujoco_rs::mujoco_c as ffi;
    use mujoco_rs::prelude::{MjData, MjModel};
    use mujoco_rs::wrappers::mj_model::traits::ModelType;

    fn count(x: i64) -> usize {
        usize::try_from(x).unwrap_or(0)
    }

    /// `mj_jacSite`: the site's translational (`jacp`) and rotational (`jacr`) Jacobians, 3 × nv
    /// each, row-major. Does nothing when the site or a buffer does not fit.
    pub(crate) fn jac_site<M: ModelType>(
        data: &MjData<M>,
        site: usize,
        jacp: &mut [f64],
        jacr: &mut [f64],
    ) {
        let m = data.model().ffi();
        let nv = count(m.nv);
        if site >= count(m.nsite) || jacp.len() < 3 * nv || jacr.len() < 3 * nv || nv == 0 {
            return;
        }
        // SAFETY: a live model and its data; the two buffers hold 3 × nv doubles each, which is
        // all mj_jacSite writes; the site id is in range.
        unsafe {
            ffi::mj_jacSite(
                m,
                data.ffi(),
                jacp.as_mut_ptr(),
                jacr.as_mut_ptr(),
                site as i32,
            );
        }
    }

    /// The simulation time.
    pub(crate) fn set_time<M: ModelType>(data: &mut MjData<M>, t: f64) {
        // SAFETY: a plain double of the data, borrowed exclusively.
        unsafe { data.ffi_mut().time = t };
    }

    /// `mocap_pos` (3 × nmocap) and `mocap_quat` (4 × nmocap), both writable at once, with
    /// `xpos` and `xquat` (3 and 4 × nbody) to read from.
    pub(crate) fn mocap_mut<M: ModelType>(
        data: &mut MjData<M>,
    ) -> (&mut [f64], &mut [f64], &[f64], &[f64]) {
        let m = data.model().ffi();
        let (nmocap, nbody) = (count(m.nmocap), count(m.nbody));
        // SAFETY: four arrays of the data, of the sizes MuJoCo allocates them with; none
        // overlaps another, and all borrows end with the exclusive borrow of `data`.
        unsafe {
            let d = data.ffi_mut();
            let part = |p: *mut f64, n: usize| -> &mut [f64] {
                if n == 0 || p.is_null() {
                    &mut []
                } else {
                    std::slice::from_raw_parts_mut(p, n)
                }
            };
            (
                part(d.mocap_pos, 3 * nmocap),
                part(d.mocap_quat, 4 * nmocap),
                part(d.xpos, 3 * nbody),
                part(d.xquat, 4 * nbody),
            )
        }
    }

    /// Every weld constraint's relative pose becomes the identity: anchor and offset 0, the
    /// quaternion's w 1 (`eq_data[:7] = [0, 0, 0, 0, 0, 0, 1]`, as Gymnasium-Robotics'
    /// `reset_mocap_welds`, which leaves the quaternion's other entries as they were).
    pub(crate) fn reset_welds(model: &mut MjModel) {
        const WELD: i32 = ffi::mjtEq::mjEQ_WELD as i32;
        let n = ffi::mjNEQDATA as usize;
        // SAFETY: the model is borrowed exclusively; eq_type and eq_data hold neq and
        // neq × mjNEQDATA entries; only values change, no size or address.
        unsafe {
            let m = model.ffi_mut();
            for i in 0..count(m.neq) {
                if *m.eq_type.add(i) == WELD {
                    let row = m.eq_data.add(i * n);
                    for (k, v) in [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0].into_iter().enumerate() {
                        *row.add(k) = v;
                    }
                }
            }
        }
    }
}

pub(crate) mod stat {
    use mujoco_rs::mujoco_c::mjStatistic;
    use mujoco_rs::prelude::{MjModel, MjSpec};

    /// The spec's `<statistic>` values, to edit.
    pub(crate) fn of_spec(spec: &mut MjSpec) -> &mut mjStatistic {
        // SAFETY: plain fields of the spec, borrowed mutably with it.
        unsafe { &mut spec.ffi_mut().stat }
    }

    /// The compiled model's statistics, to edit.
    pub(crate) fn of_model(model: &mut MjModel) -> &mut mjStatistic {
        // SAFETY: plain fields of the model, borrowed mutably with it.
        unsafe { &mut model.ffi_mut().stat }
    }
}

/// Run `f` with MuJoCo's process-wide timer callback `mjcb_time` cleared, and put it back after.
///
/// `import mujoco` (MuJoCo's Python bindings, which Gymnasium's MuJoCo envs import) installs a
/// clock there, and every `mj_step` then reads it for each of its profiling timers (`mjData.timer`):
/// about 2.5 µs per `mj_step` on the benchmark machine, +60 % on InvertedPendulum's physics
/// (docs/PERFORMANCE.md). envc never reads `mjData.timer`, and timers do not change the physics.
/// Safe to nest and to call from threads that released the GIL: the first caller in clears the
/// callback, the last one out puts it back. Meanwhile a `mujoco.mj_step` on another thread runs
/// without the clock (its timer statistics miss those steps, nothing else).
pub fn without_mujoco_timer<T>(f: impl FnOnce() -> T) -> T {
    use std::sync::{Mutex, MutexGuard};
    type Clock = Option<unsafe extern "C" fn() -> f64>;
    unsafe extern "C" {
        /// `mjfTime mjcb_time` (mujoco.h): the clock MuJoCo's profiling timers read, or null.
        static mut mjcb_time: Option<unsafe extern "C" fn() -> f64>;
    }
    // Callers inside, and the callback they found.
    static INSIDE: Mutex<(usize, Clock)> = Mutex::new((0, None));
    fn lock() -> MutexGuard<'static, (usize, Clock)> {
        INSIDE.lock().unwrap_or_else(|e| e.into_inner())
    }
    struct Leave;
    impl Drop for Leave {
        fn drop(&mut self) {
            let mut inside = lock();
            inside.0 -= 1;
            if inside.0 == 0 {
                // SAFETY: a pointer-sized global of libmujoco, written back as the first caller
                // found it; every writer from envc holds the lock.
                unsafe { mjcb_time = inside.1 };
            }
        }
    }
    {
        let mut inside = lock();
        if inside.0 == 0 {
            // SAFETY: as above; MuJoCo calls the callback only when it is non-null.
            inside.1 = unsafe {
                let found = mjcb_time;
                mjcb_time = None;
                found
            };
        }
        inside.0 += 1;
    }
    let _leave = Leave;
    f()
}

pub(crate) mod catch {
    //! Every model envc parses or compiles goes through here: MuJoCo's parser and compiler called
    //! from the C++ shim `csrc/mujoco_catch.cc`, so a C++ exception escaping them (MuJoCo catches
    //! only its own errors; a `std::bad_alloc` when a model needs more memory than the process may
    //! have) or an `mju_error` becomes an `Err` with a message, instead of ending the process
    //! (mujoco-rs calls them `extern "C"`, where an exception aborts). docs/limits.md.

    use mujoco_rs::mujoco_c::{mjModel, mjSpec};
    use mujoco_rs::prelude::*;
    use std::ffi::{CString, c_char, c_int};
    use std::path::Path;

    // `C`, not `C-unwind`: the shim lets nothing escape. (It runs MuJoCo with a thread log handler
    // of its own, so envc's `mju_error` handler — a Rust panic — is never entered beneath it.)
    unsafe extern "C" {
        fn envc_check_parse(path: *const c_char, error: *mut c_char, n: c_int) -> c_int;
        fn envc_compile(s: *mut mjSpec, into: *mut mjModel, error: *mut c_char, n: c_int) -> c_int;
        #[cfg(test)]
        fn envc_raise_mju_error(message: *const c_char, error: *mut c_char, n: c_int) -> c_int;
    }

    /// The shim's answer as a message: 1 MuJoCo's own refusal, 2 a C++ exception ("<type>: <what>"),
    /// 3 an `mju_error`.
    fn message(status: c_int, buf: &[c_char]) -> String {
        // SAFETY: the shim always NUL-terminates within the buffer (snprintf / MuJoCo's own copy).
        let text = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) }
            .to_string_lossy()
            .trim()
            .to_string();
        match status {
            2 if text.starts_with("std::bad_alloc")
                || text.starts_with("std::bad_array_new_length") =>
            {
                format!(
                    "MuJoCo threw {text}: the model needs more memory than is available to envc \
                     (the machine's memory or a limit such as `ulimit -v`); make the model smaller \
                     (its <size> numbers, textures, meshes, element counts) or allow more memory"
                )
            }
            2 => format!("MuJoCo threw a C++ exception, {text}"),
            _ => text,
        }
    }

    /// Parse a model file (MJCF or URDF) into an mjSpec; MuJoCo's message on failure.
    pub(crate) fn parse(path: &Path) -> Result<MjSpec, String> {
        crate::mj::log::install();
        let s = path.to_str().ok_or("the path is not valid UTF-8")?;
        let c = CString::new(s).map_err(|_| "the path contains a NUL byte".to_string())?;
        let mut buf = [0 as c_char; 1024];
        // SAFETY: a NUL-terminated path and a writable buffer of the length given.
        let status = unsafe { envc_check_parse(c.as_ptr(), buf.as_mut_ptr(), buf.len() as c_int) };
        if status != 0 {
            return Err(message(status, &buf));
        }
        // mujoco-rs has no constructor from a raw mjSpec, so the file the shim has just parsed
        // without incident is parsed again by mujoco-rs (a few per cent of a compile; docs/limits.md).
        MjSpec::from_xml(path).map_err(|e| e.to_string())
    }

    /// Compile an mjSpec; MuJoCo's message on failure. The model is byte for byte what
    /// `MjSpec::compile` makes (the shim moves mj_compile's result into a model mujoco-rs owns).
    pub(crate) fn compile(spec: &mut MjSpec) -> Result<MjModel, String> {
        // `<compiler settotalmass>` is deprecated in MuJoCo: envc applies it (`total_mass`).
        let Some(taken) = super::total_mass::take(spec) else {
            return compile_as_is(spec);
        };
        let compiled = compile_as_is(spec);
        super::total_mass::restore(spec, &taken);
        let mut model = compiled?;
        super::total_mass::apply(spec, &mut model, &taken)?;
        Ok(model)
    }

    /// [`compile`] of the spec exactly as it is.
    fn compile_as_is(spec: &mut MjSpec) -> Result<MjModel, String> {
        crate::mj::log::install();
        // An empty model owned by mujoco-rs, whose contents the shim replaces.
        let mut model = MjSpec::new().compile().map_err(|e| e.to_string())?;
        let mut buf = [0 as c_char; 1024];
        // SAFETY: live spec and model pointers, used by nothing else during the call; the shim
        // replaces the model's contents only with a whole compiled model (and frees the old ones).
        let status = unsafe {
            envc_compile(
                spec.ffi_mut(),
                model.ffi_mut(),
                buf.as_mut_ptr(),
                buf.len() as c_int,
            )
        };
        if status != 0 {
            return Err(message(status, &buf));
        }
        Ok(model)
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        /// Every bundled model (and the URDF fixtures) compiled through the shim is byte for byte
        /// the model mujoco-rs's own `mj_loadXML` makes: its mjb file and its whole buffer.
        #[test]
        fn shim_models_are_mujoco_rs_models_byte_for_byte() {
            let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
            let mut files = vec![];
            let mut dirs = vec![root.join("assets"), root.join("tests/fixtures/urdf")];
            while let Some(d) = dirs.pop() {
                for e in std::fs::read_dir(&d).unwrap() {
                    let p = e.unwrap().path();
                    if p.is_dir() {
                        dirs.push(p);
                    } else if matches!(p.extension().and_then(|x| x.to_str()), Some("xml" | "urdf"))
                    {
                        files.push(p);
                    }
                }
            }
            files.sort();
            let mut compared = 0;
            for p in &files {
                let Ok(reference) = MjModel::from_xml(p) else {
                    continue; // an include fragment, or a fixture that is meant to fail
                };
                let ours = compile(&mut parse(p).unwrap()).unwrap();
                let mjb = |m: &MjModel| {
                    let mut b = vec![0u8; m.size()];
                    m.save_to_buffer(&mut b).unwrap();
                    b
                };
                assert!(
                    mjb(&reference) == mjb(&ours),
                    "{}: mjb differs",
                    p.display()
                );
                let buffer = |m: &MjModel| {
                    // SAFETY: `buffer` holds `nbuffer` bytes for as long as the model lives.
                    unsafe {
                        std::slice::from_raw_parts(
                            m.ffi().buffer as *const u8,
                            m.ffi().nbuffer as usize,
                        )
                    }
                    .to_vec()
                };
                assert!(
                    buffer(&reference) == buffer(&ours),
                    "{}: buffer differs",
                    p.display()
                );
                compared += 1;
            }
            assert!(compared >= 40, "only {compared} models compared");
        }

        /// An `mju_error` beneath the shim comes back as status 3 with its message, without
        /// entering envc's Rust handler; MuJoCo works as before afterwards, on the same thread.
        #[test]
        fn an_mju_error_beneath_the_shim_is_returned() {
            crate::mj::log::install();
            for _ in 0..3 {
                let mut buf = [0 as c_char; 1024];
                let msg = CString::new("a test error").unwrap();
                // SAFETY: a NUL-terminated message and a writable buffer of the length given.
                let status = unsafe {
                    envc_raise_mju_error(msg.as_ptr(), buf.as_mut_ptr(), buf.len() as c_int)
                };
                assert_eq!(status, 3);
                assert_eq!(message(status, &buf), "a test error");
            }
            let hopper =
                Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium/hopper.xml");
            assert!(compile(&mut parse(&hopper).unwrap()).is_ok());
        }

        /// MuJoCo's own refusals keep their message (now whole: mujoco-rs cut it at 99 bytes).
        #[test]
        fn refusals_carry_mujocos_message() {
            let dir = std::env::temp_dir().join(format!("envc-catch-{}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            let bad = dir.join("bad.xml");
            std::fs::write(
                &bad,
                "<mujoco><worldbody><geom size=\"0\"/></worldbody></mujoco>",
            )
            .unwrap();
            let e = compile(&mut parse(&bad).unwrap()).unwrap_err();
            assert!(e.contains("size 0 must be positive in geom"), "{e}");
            std::fs::write(&bad, "<mujoco><worldbody><bogus/></worldbody></mujoco>").unwrap();
            let e = parse(&bad).err().unwrap();
            assert!(e.contains("Schema violation: unrecognized element"), "{e}");
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }
}
