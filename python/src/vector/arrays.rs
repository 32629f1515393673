//! The numpy arrays the core hands out: made fresh (`copy=True`, some made while the workers
//! step) or kept in a slot and overwritten in place (`copy=False`).

use numpy::ndarray::IxDyn;
use numpy::{Element, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

use super::InfoKey;

/// An array the core keeps in a slot (see `Slot`).
pub(super) type Kept<T> = Option<Py<PyArrayDyn<T>>>;

/// Where `copy=False` keeps each array: `f64_slots` holds observations, rewards, each key's
/// values and final values, then the achieved and desired goals (`[goal]`); `bool_slots` the two
/// flags, `has_final`, each key's mask, then a bool key's values and final values (`Flag`);
/// `f32_slots` each key's float32 values and final values.
#[derive(Clone, Copy)]
pub(super) enum Slot {
    Obs,
    Rewards,
    Terminated,
    Truncated,
    HasFinal,
    Value { key: usize, last: bool },
    Mask(usize),
    Flag { key: usize, last: bool },
    Achieved,
    Desired,
}

impl Slot {
    pub(super) fn index(self, nkeys: usize) -> usize {
        match self {
            Slot::Obs | Slot::Terminated => 0,
            Slot::Rewards | Slot::Truncated => 1,
            Slot::HasFinal => 2,
            Slot::Value { key, last } => 2 + key + usize::from(last) * nkeys,
            Slot::Mask(k) => 3 + k,
            Slot::Flag { key, last } => 3 + nkeys + key + usize::from(last) * nkeys,
            Slot::Achieved => 2 + 2 * nkeys,
            Slot::Desired => 3 + 2 * nkeys,
        }
    }
}

/// `data` as a numpy array of `shape`. `copy`: a fresh array, the one `prepare` made in `slot`
/// (taken out) or a new one. Else written into the array kept in `slot` (made, or remade when
/// the user left it unusable) and that array itself.
pub(super) fn out_array<'py, T: Element + Copy>(
    py: Python<'py>,
    slot: &mut Option<Py<PyArrayDyn<T>>>,
    shape: &[usize],
    data: &[T],
    copy: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if copy && let Some(a) = slot.take() {
        let a = a.into_bound(py);
        if a.shape() == shape {
            // SAFETY: made by `prepare` (C-contiguous, of this shape) and never handed out: the
            // core holds its only reference, and the GIL is held.
            unsafe { a.as_slice_mut() }?.copy_from_slice(data);
            return Ok(a.into_any());
        }
    }
    if !copy && let Some(a) = slot.as_ref() {
        let a = a.bind(py);
        if a.shape() == shape
            && let Ok(mut w) = a.try_readwrite()
            && let Ok(dst) = w.as_slice_mut()
        {
            dst.copy_from_slice(data);
            return Ok(a.clone().into_any());
        }
    }
    // SAFETY: a fresh array of `shape`, C-contiguous, written here before anyone else sees it.
    let a = unsafe { PyArrayDyn::<T>::new(py, IxDyn(shape), false) };
    // SAFETY: as above; nothing else holds it.
    unsafe { a.as_slice_mut() }?.copy_from_slice(data);
    if !copy {
        *slot = Some(a.clone().unbind());
    }
    Ok(a.into_any())
}

/// An uninitialized array of `shape` in `slot` for `out_array` to fill, unless one is there.
fn fresh<T: Element>(py: Python<'_>, slot: &mut Option<Py<PyArrayDyn<T>>>, shape: &[usize]) {
    if slot.is_none() {
        // SAFETY: uninitialized, but `out_array` writes it whole before it is handed out, and
        // nothing reads it before.
        *slot = Some(unsafe { PyArrayDyn::<T>::new(py, IxDyn(shape), false) }.unbind());
    }
}

/// `copy=True`'s arrays for the coming step, made while the workers step it: observations (and
/// goals), rewards, flags, each key's values and mask (a key no env reports keeps its arrays for
/// the next step), in `copy=True`'s slots by `Slot`.
pub(super) fn prepare(
    py: Python<'_>,
    keys: &[InfoKey],
    f64s: &mut [Kept<f64>],
    f32s: &mut [Kept<f32>],
    bools: &mut [Kept<bool>],
    (n, od, gd): (usize, usize, usize),
    f32: bool,
) {
    let nk = keys.len();
    fresh(py, &mut f64s[Slot::Obs.index(nk)], &[n, od]);
    if gd > 0 {
        fresh(py, &mut f64s[Slot::Achieved.index(nk)], &[n, gd]);
        fresh(py, &mut f64s[Slot::Desired.index(nk)], &[n, gd]);
    }
    fresh(py, &mut f64s[Slot::Rewards.index(nk)], &[n]);
    fresh(py, &mut bools[Slot::Terminated.index(nk)], &[n]);
    fresh(py, &mut bools[Slot::Truncated.index(nk)], &[n]);
    for (k, key) in keys.iter().enumerate() {
        let shape: &[usize] = if key.len == 1 { &[n] } else { &[n, key.len] };
        let v = Slot::Value {
            key: k,
            last: false,
        }
        .index(nk);
        if key.boolean {
            // A one-number bool key is an object array, made when it is handed out.
            let at = Slot::Flag {
                key: k,
                last: false,
            };
            if key.len > 1 {
                fresh(py, &mut bools[at.index(nk)], shape);
            }
        } else if key.float32 || (f32 && key.f32_with_f32_actions) {
            fresh(py, &mut f32s[v], shape);
        } else {
            fresh(py, &mut f64s[v], shape);
        }
        fresh(py, &mut bools[Slot::Mask(k).index(nk)], &[n]);
    }
}
