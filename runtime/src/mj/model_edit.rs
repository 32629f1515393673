//! The model values envc writes after compiling: `[actions]` gains, the spec's keyframes, and
//! `[events]` (domain randomization of an env's own model copy).

use std::marker::PhantomData;

use mujoco_rs::mujoco_c::mjModel;
use mujoco_rs::prelude::MjModel;

/// `mjNGAIN`, `mjNBIAS`: entries per actuator of `gainprm` and `biasprm`.
pub(crate) const NPRM: usize = 10;

/// A model array of doubles envc writes, with MuJoCo's row strides.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum ModelArray {
    GeomFriction,
    BodyMass,
    BodyIpos,
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
            ModelArray::BodyIpos => 3 * n(m.nbody),
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
