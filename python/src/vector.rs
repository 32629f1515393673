//! The core of a vector env: many task envs stepped by Rust threads, their batches handed to
//! Python as numpy arrays and Gymnasium's vector info dicts built here, with no Python loop.
//!
//! `copy=True` (Gymnasium's default) returns fresh arrays each call. `copy=False` returns the
//! same arrays every call, owned by the core and overwritten in place by the next `reset` or
//! `step` (observations, rewards, flags, each info key's values and `_key` mask); a buffer the
//! user made unusable (read-only, resized) is replaced by a fresh one. Infos are gathered
//! key-major in Rust scratch space (key k's values env-major at `offset * N`), zero where an env
//! did not report the key, as Gymnasium's `_add_info` leaves them.

use numpy::ndarray::IxDyn;
use numpy::{Element, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyString, PyTuple};

use crate::convert;
use crate::errors;

/// A vector env (`envc.EnvcVectorEnv` wraps it as a `gymnasium.vector.VectorEnv`).
#[pyclass(module = "envc._envc")]
pub struct VecCore {
    /// `None` once closed.
    env: Option<envc::VecEnv>,
    keys: Vec<InfoKey>,
    /// Info key index of each step-info slot and of each reset-info slot.
    step_map: Vec<usize>,
    reset_map: Vec<usize>,
    /// The last call's infos: values (`[L × N]`, key k env-major from `offset * N`), `_key`
    /// masks (`[K × N]`), and SameStep's final infos (values only: their mask is `has_final`).
    values: Vec<f64>,
    mask: Vec<bool>,
    final_values: Vec<f64>,
    /// A float32 key's values, converted for the call.
    f32_scratch: Vec<f32>,
    /// By `Slot`: `[0]` `copy=False`'s arrays (handed out every call); `[1]` `copy=True`'s
    /// next ones, made while the workers step (`prepare`) and each handed out once.
    f64_slots: [Vec<Kept<f64>>; 2],
    f32_slots: [Vec<Kept<f32>>; 2],
    bool_slots: [Vec<Kept<bool>>; 2],
    final_obs_key: Py<PyString>,
    final_obs_mask_key: Py<PyString>,
    final_info_key: Py<PyString>,
    final_info_mask_key: Py<PyString>,
    /// Env steps taken by `step` and `rust_steps`, NextStep's autoreset steps not counted.
    env_steps: u64,
    /// `step`'s `copy` when the call names none (`EnvcVectorEnv.copy`).
    copy: bool,
}

/// An array the core keeps in a slot (see `Slot`).
type Kept<T> = Option<Py<PyArrayDyn<T>>>;

struct InfoKey {
    name: Py<PyString>,
    /// `"_" + name`: the mask's key.
    mask_name: Py<PyString>,
    offset: usize,
    len: usize,
    /// A float32 number when the step's actions are float32 (a float32 action cost, as numpy
    /// computes it in the reference).
    f32_with_f32_actions: bool,
}

/// Where `copy=False` keeps each array: `f64_slots` holds observations, rewards, then each key's
/// values and final values; `bool_slots` the two flags, `has_final`, then each key's mask;
/// `f32_slots` each key's float32 values and final values.
#[derive(Clone, Copy)]
enum Slot {
    Obs,
    Rewards,
    Terminated,
    Truncated,
    HasFinal,
    Value { key: usize, last: bool },
    Mask(usize),
}

impl Slot {
    fn index(self, nkeys: usize) -> usize {
        match self {
            Slot::Obs | Slot::Terminated => 0,
            Slot::Rewards | Slot::Truncated => 1,
            Slot::HasFinal => 2,
            Slot::Value { key, last } => 2 + key + usize::from(last) * nkeys,
            Slot::Mask(k) => 3 + k,
        }
    }
}

/// `data` as a numpy array of `shape`. `copy`: a fresh array, the one `prepare` made in `slot`
/// (taken out) or a new one. Else written into the array kept in `slot` (made, or remade when
/// the user left it unusable) and that array itself.
fn out_array<'py, T: Element + Copy>(
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

/// Whether info item `item` is a float32 action cost under float32 actions (see `Env::step_f32`).
fn f32_cost(spec: &envspec::ResolvedSpec, item: &envspec::ir::InfoItem) -> bool {
    use envspec::ir::{InfoKind, TermKind};
    match item.kind {
        InfoKind::Term(t) => matches!(
            &spec.reward[t].kind,
            TermKind::SumSquares { source, clip_input: None, .. } if source.field == envspec::Field::Action
        ),
        _ => false,
    }
}

/// One vector step with the GIL released (see `detached`). With `copy` and worker threads, the
/// arrays the step will return are made meanwhile (`prepare`), while the workers step envs.
fn step_interruptible(
    py: Python<'_>,
    core: &mut VecCore,
    actions: envc::JointAction<'_>,
    copy: bool,
) -> PyResult<()> {
    let f32 = matches!(actions, envc::JointAction::F32(_));
    let VecCore {
        env,
        keys,
        f64_slots: [_, f64s],
        f32_slots: [_, f32s],
        bool_slots: [_, bools],
        ..
    } = core;
    let env = env.as_mut().ok_or_else(closed)?;
    let (n, od) = (env.num_envs(), env.obs_dim());
    let overlap = copy && env.threads() > 1;
    let mut meanwhile = || {
        if overlap {
            Python::attach(|py| prepare(py, keys, f64s, f32s, bools, (n, od), f32));
        }
    };
    detached(py, env, |env, check| {
        env.step_overlapped(actions, check, &mut meanwhile)
    })
}

/// `copy=True`'s arrays for the coming step, made while the workers step it: observations,
/// rewards, flags, each key's values and mask (a key no env reports keeps its arrays for the
/// next step), in `copy=True`'s slots by `Slot`.
fn prepare(
    py: Python<'_>,
    keys: &[InfoKey],
    f64s: &mut [Kept<f64>],
    f32s: &mut [Kept<f32>],
    bools: &mut [Kept<bool>],
    (n, od): (usize, usize),
    f32: bool,
) {
    let nk = keys.len();
    fresh(py, &mut f64s[Slot::Obs.index(nk)], &[n, od]);
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
        if f32 && key.f32_with_f32_actions {
            fresh(py, &mut f32s[v], shape);
        } else {
            fresh(py, &mut f64s[v], shape);
        }
        fresh(py, &mut bools[Slot::Mask(k).index(nk)], &[n]);
    }
}

/// `steps` run on the env with the GIL released, checking for Ctrl-C about every 50 ms between
/// envs (`steps` hands the check to `VecEnv::step_interruptible`): a signal stops the step
/// part-way (the envs not started are skipped), the env needs a reset, and the signal's
/// exception (KeyboardInterrupt) is raised.
fn detached<F>(py: Python<'_>, env: &mut envc::VecEnv, steps: F) -> PyResult<()>
where
    F: FnOnce(&mut envc::VecEnv, &mut dyn FnMut() -> bool) -> Result<envc::Stepped, envc::EnvError>
        + Send,
{
    let mut signal = None;
    let stepped = py.detach(|| {
        let mut check = || match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                signal = Some(e);
                true
            }
        };
        crate::mujoco_timer::without_mujoco_timer(|| steps(&mut *env, &mut check))
    });
    match (stepped.map_err(errors::env_error)?, signal) {
        (envc::Stepped::Done, _) => Ok(()),
        (envc::Stepped::Interrupted, Some(e)) => {
            env.require_reset();
            Err(e)
        }
        (envc::Stepped::Interrupted, None) => {
            env.require_reset();
            Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                "the vector step was interrupted",
            ))
        }
    }
}

/// The env steps of the last step: every env's, but for NextStep's autoreset steps (an
/// autoreset leaves an env at 0 elapsed steps; a step never does, SameStep's reset aside).
fn real_steps(env: &envc::VecEnv) -> u64 {
    if env.autoreset() == envc::Autoreset::SameStep {
        return env.num_envs() as u64;
    }
    env.envs().iter().filter(|e| e.elapsed_steps() > 0).count() as u64
}

/// `count` steps of `env` in Rust, step t over batch `(first + t) % batches` of `rows`
/// (`batches` batches of `num_envs × act_dim`, C order; see `VecCore::rust_steps`), adding the
/// env steps taken to `taken`.
fn rust_loop<'a, T>(
    env: &mut envc::VecEnv,
    check: &mut dyn FnMut() -> bool,
    rows: &'a [T],
    (first, count): (usize, usize),
    action: impl Fn(&'a [T]) -> envc::JointAction<'a>,
    taken: &mut u64,
) -> Result<envc::Stepped, envc::EnvError> {
    let batch = env.num_envs() * env.act_dim();
    let batches = rows.len() / batch.max(1);
    for t in 0..count {
        let at = (first + t) % batches.max(1) * batch;
        let stepped = env.step_interruptible(action(&rows[at..at + batch]), check)?;
        if stepped == envc::Stepped::Interrupted {
            return Ok(stepped);
        }
        *taken += real_steps(env);
    }
    Ok(envc::Stepped::Done)
}

fn closed() -> PyErr {
    errors::coded("E1103", "error[E1103]: the vector env is closed".into())
}

/// The element types a batch of actions is stepped in.
trait ActionElement: Element + Copy {
    fn joint(rows: &[Self]) -> envc::JointAction<'_>;
}
impl ActionElement for f32 {
    fn joint(rows: &[f32]) -> envc::JointAction<'_> {
        envc::JointAction::F32(rows)
    }
}
impl ActionElement for f64 {
    fn joint(rows: &[f64]) -> envc::JointAction<'_> {
        envc::JointAction::F64(rows)
    }
}

/// `envc._gym.as_actions`, for batches that are not float32 or float64 arrays.
static AS_ACTIONS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// The call's hold on the core. The core steps with the GIL released, so a second thread may
/// call while one runs: that call is E1106, not PyO3's borrow error.
fn hold<'py>(slf: &Bound<'py, VecCore>, what: &str) -> PyResult<PyRefMut<'py, VecCore>> {
    slf.try_borrow_mut().map_err(|_| {
        errors::coded(
            "E1106",
            format!(
                "error[E1106]: `{what}` while another thread is in a call of this vector env; \
                 use one vector env per thread, or a lock around its calls"
            ),
        )
    })
}

impl VecCore {
    fn env(&self) -> PyResult<&envc::VecEnv> {
        self.env.as_ref().ok_or_else(closed)
    }

    /// Gather the last call's infos into the scratch space: of the envs in `only` (a masked
    /// reset), else of every env; and SameStep's final infos where an env ended.
    fn gather(&mut self) -> PyResult<()> {
        self.gather_only(None)
    }

    fn gather_only(&mut self, only: Option<&[bool]>) -> PyResult<()> {
        let VecCore {
            env,
            keys,
            step_map,
            reset_map,
            values,
            mask,
            final_values,
            ..
        } = self;
        let env = env.as_ref().ok_or_else(closed)?;
        let n = env.num_envs();
        values.fill(0.0);
        mask.fill(false);
        for (i, e) in env.envs().iter().enumerate() {
            if only.is_some_and(|m| !m[i]) {
                continue;
            }
            // As `VecEnv::info`: an (auto)reset leaves the env at 0 elapsed steps.
            let (info, map) = if e.elapsed_steps() == 0 {
                (e.reset_info(), &*reset_map)
            } else {
                (e.step_info(), &*step_map)
            };
            write_info(keys, info, map, n, i, values, Some(mask));
        }
        let has_final = env.has_final();
        if only.is_none() && has_final.iter().any(|&h| h) {
            final_values.fill(0.0);
            for i in (0..n).filter(|&i| has_final[i]) {
                if let Some(info) = env.final_info(i) {
                    write_info(keys, info, step_map, n, i, final_values, None);
                }
            }
        }
        Ok(())
    }

    /// Key k's values over envs as Gymnasium gives them: `(N,)` or `(N, len)`, float32 where
    /// `f32` and the key is a float32 action cost.
    fn value_array<'py>(
        &mut self,
        py: Python<'py>,
        k: usize,
        last: bool,
        f32: bool,
        copy: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.mask.len() / self.keys.len().max(1);
        let key = &self.keys[k];
        let (off, len) = (key.offset * n, key.len * n);
        let shape: &[usize] = if key.len == 1 { &[n] } else { &[n, key.len] };
        let src = if last {
            &self.final_values[off..off + len]
        } else {
            &self.values[off..off + len]
        };
        let slot = Slot::Value { key: k, last }.index(self.keys.len());
        if f32 && key.f32_with_f32_actions {
            self.f32_scratch.clear();
            // Exact: the value was computed in float32.
            self.f32_scratch.extend(src.iter().map(|&x| x as f32));
            out_array(
                py,
                &mut self.f32_slots[usize::from(copy)][slot],
                shape,
                &self.f32_scratch,
                copy,
            )
        } else {
            out_array(
                py,
                &mut self.f64_slots[usize::from(copy)][slot],
                shape,
                src,
                copy,
            )
        }
    }

    /// The last call's infos in Gymnasium's vector form; `finals`: SameStep's `final_obs` and
    /// `final_info` where an env ended.
    fn info<'py>(
        &mut self,
        py: Python<'py>,
        f32: bool,
        copy: bool,
        finals: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let info = PyDict::new(py);
        let nkeys = self.keys.len();
        let n = self.env()?.num_envs();
        for k in 0..nkeys {
            let m = &self.mask[k * n..(k + 1) * n];
            if !m.iter().any(|&b| b) {
                continue;
            }
            let v = self.value_array(py, k, false, f32, copy)?;
            info.set_item(self.keys[k].name.bind(py), v)?;
            let slot = &mut self.bool_slots[usize::from(copy)][Slot::Mask(k).index(nkeys)];
            let m = out_array(py, slot, &[n], &self.mask[k * n..(k + 1) * n], copy)?;
            info.set_item(self.keys[k].mask_name.bind(py), m)?;
        }
        let env = self.env.as_ref().ok_or_else(closed)?;
        if !finals
            || env.autoreset() != envc::Autoreset::SameStep
            || !env.has_final().iter().any(|&h| h)
        {
            return Ok(info);
        }
        // Gymnasium's form: an object array with each ended env's observation, None elsewhere.
        let od = env.obs_dim();
        let (has_final, final_obs) = (env.has_final(), env.final_obs());
        let rows = (0..n)
            .map(|i| {
                if has_final[i] {
                    PyArray1::from_slice(py, &final_obs[i * od..(i + 1) * od])
                        .into_any()
                        .unbind()
                } else {
                    py.None()
                }
            })
            .collect::<Vec<_>>();
        let ended = has_final.to_vec();
        let final_obs = PyArray1::from_vec(py, rows);
        let slot = Slot::HasFinal.index(nkeys);
        let ended_array = |core: &mut VecCore| {
            out_array(
                py,
                &mut core.bool_slots[usize::from(copy)][slot],
                &[n],
                &ended,
                copy,
            )
        };
        let final_info = PyDict::new(py);
        for k in 0..nkeys {
            let v = self.value_array(py, k, true, f32, copy)?;
            let (name, mask_name) = (
                self.keys[k].name.clone_ref(py),
                self.keys[k].mask_name.clone_ref(py),
            );
            final_info.set_item(name, v)?;
            final_info.set_item(mask_name, ended_array(self)?)?;
        }
        info.set_item(self.final_obs_key.bind(py), final_obs)?;
        let mask_key = self.final_obs_mask_key.clone_ref(py);
        info.set_item(mask_key, ended_array(self)?)?;
        info.set_item(self.final_info_key.bind(py), final_info)?;
        let mask_key = self.final_info_mask_key.clone_ref(py);
        info.set_item(mask_key, ended_array(self)?)?;
        Ok(info)
    }

    /// The observation batch as numpy (`copy`: a fresh array, else the kept one).
    fn obs<'py>(&mut self, py: Python<'py>, copy: bool) -> PyResult<Bound<'py, PyAny>> {
        let env = self.env.as_ref().ok_or_else(closed)?;
        let shape = [env.num_envs(), env.obs_dim()];
        let slot = &mut self.f64_slots[usize::from(copy)][Slot::Obs.index(self.keys.len())];
        out_array(py, slot, &shape, env.obs(), copy)
    }

    /// `(obs, rewards, terminated, truncated, info)` of the last step.
    fn step_result<'py>(
        &mut self,
        py: Python<'py>,
        f32: bool,
        copy: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        self.gather()?;
        self.env_steps += real_steps(self.env()?);
        let nkeys = self.keys.len();
        let obs = self.obs(py, copy)?;
        let env = self.env.as_ref().ok_or_else(closed)?;
        let n = env.num_envs();
        let rewards = out_array(
            py,
            &mut self.f64_slots[usize::from(copy)][Slot::Rewards.index(nkeys)],
            &[n],
            env.rewards(),
            copy,
        )?;
        let terminated = out_array(
            py,
            &mut self.bool_slots[usize::from(copy)][Slot::Terminated.index(nkeys)],
            &[n],
            env.terminated(),
            copy,
        )?;
        let truncated = out_array(
            py,
            &mut self.bool_slots[usize::from(copy)][Slot::Truncated.index(nkeys)],
            &[n],
            env.truncated(),
            copy,
        )?;
        let info = self.info(py, f32, copy, true)?;
        PyTuple::new(py, [obs, rewards, terminated, truncated, info.into_any()])
    }

    /// After a panic: every env needs a reset before the next step.
    fn require_reset(&mut self) {
        if let Some(env) = self.env.as_mut() {
            env.require_reset();
        }
    }

    /// `step` over a 2-D float32 or float64 array; `None` for anything else.
    fn step_array<'py>(
        &mut self,
        py: Python<'py>,
        actions: &Bound<'py, PyAny>,
        copy: bool,
    ) -> Option<PyResult<Bound<'py, PyTuple>>> {
        if let Ok(a) = actions.cast::<PyArray2<f32>>() {
            return Some(self.step_rows(py, a, copy));
        }
        if let Ok(a) = actions.cast::<PyArray2<f64>>() {
            return Some(self.step_rows(py, a, copy));
        }
        None
    }

    fn step_rows<'py, T: ActionElement>(
        &mut self,
        py: Python<'py>,
        a: &Bound<'py, PyArray2<T>>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let a = a.try_readonly().map_err(errors::argument)?;
        self.check_batch(a.shape())?;
        // `as_slice` takes Fortran order too: only a C-ordered batch is read in place.
        match a.as_slice() {
            Ok(s) if a.is_c_contiguous() => self.step_batch(py, T::joint(s), copy),
            _ => {
                let rows = a.as_array().iter().copied().collect::<Vec<T>>();
                self.step_batch(py, T::joint(&rows), copy)
            }
        }
    }

    fn check_batch(&self, shape: &[usize]) -> PyResult<()> {
        let env = self.env()?;
        let want = [env.num_envs(), env.act_dim()];
        if shape != want {
            return Err(errors::coded(
                "E1101",
                format!(
                    "error[E1101]: actions have shape {shape:?}; expected (num_envs, act_dim) = ({}, {})",
                    want[0], want[1]
                ),
            ));
        }
        Ok(())
    }

    /// One step over a checked batch, with the GIL released; the result tuple.
    fn step_batch<'py>(
        &mut self,
        py: Python<'py>,
        actions: envc::JointAction<'_>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let f32 = matches!(actions, envc::JointAction::F32(_));
        errors::no_panic(
            self,
            |core| {
                step_interruptible(py, core, actions, copy)?;
                core.step_result(py, f32, copy)
            },
            VecCore::require_reset,
        )
    }
}

/// Write env i's `info` (its slots mapped to keys by `map`) into the key-major `values`, and
/// mark the keys in `mask`.
fn write_info(
    keys: &[InfoKey],
    info: envc::Info<'_>,
    map: &[usize],
    n: usize,
    i: usize,
    values: &mut [f64],
    mut mask: Option<&mut [bool]>,
) {
    for ((_, v), &k) in info.iter().zip(map) {
        let key = &keys[k];
        let at = key.offset * n + i * key.len;
        let len = key.len.min(v.len());
        values[at..at + len].copy_from_slice(&v[..len]);
        if let Some(m) = mask.as_deref_mut() {
            m[k * n + i] = true;
        }
    }
}

#[pymethods]
impl VecCore {
    /// `VecCore(id_or_path, overrides, num_envs, threads, autoreset)`: `num_envs` envs of one
    /// task spec stepped on `threads` threads; autoreset `"NextStep"` or `"SameStep"`.
    #[new]
    fn new(
        py: Python<'_>,
        id_or_path: &str,
        overrides: Vec<(String, String)>,
        num_envs: usize,
        threads: usize,
        autoreset: &str,
    ) -> PyResult<VecCore> {
        let mode = match autoreset {
            "NextStep" => envc::Autoreset::NextStep,
            "SameStep" => envc::Autoreset::SameStep,
            other => {
                return Err(errors::argument(format!(
                    "autoreset mode {other:?}: envc vector envs support \"NextStep\" and \"SameStep\""
                )));
            }
        };
        if num_envs == 0 {
            return Err(errors::argument("num_envs must be at least 1"));
        }
        let o = convert::overrides(&overrides);
        let id = id_or_path.to_string();
        let env = errors::no_panic(
            &mut (),
            |_| {
                py.detach(move || envc::VecEnv::make(&id, &o, num_envs, threads.max(1), mode))
                    .map_err(errors::env_error)
            },
            |_| {},
        )?;
        let spec = env.spec().ok_or_else(closed)?.clone();
        let mut keys = Vec::new();
        let mut offset = 0;
        for item in &spec.info {
            keys.push(InfoKey {
                name: PyString::intern(py, &item.key).unbind(),
                mask_name: PyString::new(py, &format!("_{}", item.key)).unbind(),
                offset,
                len: item.len,
                f32_with_f32_actions: f32_cost(&spec, item),
            });
            offset += item.len;
        }
        let index = |name: &str| {
            keys.iter()
                .position(|k| k.name.bind(py).to_str().is_ok_and(|s| s == name))
                .ok_or_else(|| {
                    errors::argument(format!("info key {name:?} is not among the spec's"))
                })
        };
        let e0 = &env.envs()[0];
        let step_map = e0.step_info().keys().map(index).collect::<PyResult<_>>()?;
        let reset_map = e0.reset_info().keys().map(index).collect::<PyResult<_>>()?;
        let n = num_envs;
        let nkeys = keys.len();
        Ok(VecCore {
            env: Some(env),
            step_map,
            reset_map,
            values: vec![0.0; offset * n],
            mask: vec![false; nkeys * n],
            final_values: vec![0.0; offset * n],
            f32_scratch: Vec::with_capacity(keys.iter().map(|k| k.len).max().unwrap_or(0) * n),
            f64_slots: [0, 1].map(|_| (0..2 + 2 * nkeys).map(|_| None).collect()),
            f32_slots: [0, 1].map(|_| (0..2 + 2 * nkeys).map(|_| None).collect()),
            bool_slots: [0, 1].map(|_| (0..3 + nkeys).map(|_| None).collect()),
            keys,
            final_obs_key: PyString::intern(py, "final_obs").unbind(),
            final_obs_mask_key: PyString::intern(py, "_final_obs").unbind(),
            final_info_key: PyString::intern(py, "final_info").unbind(),
            final_info_mask_key: PyString::intern(py, "_final_info").unbind(),
            env_steps: 0,
            copy: true,
        })
    }

    /// Reset every env, or those where `mask` is true: `seeds` is one seed (or `None`) per
    /// env, or `None` to continue every env's stream. Returns `(obs, info)`; `copy=False`
    /// returns the core's own arrays, overwritten by the next call.
    #[pyo3(signature = (seeds = None, mask = None, copy = true))]
    fn reset<'py>(
        slf: &Bound<'py, Self>,
        seeds: Option<Vec<Option<u64>>>,
        mask: Option<Vec<bool>>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let mut this = hold(slf, "reset")?;
        let n = this.env()?.num_envs();
        let seeds = seeds.unwrap_or_else(|| vec![None; n]);
        if seeds.len() != n || mask.as_ref().is_some_and(|m| m.len() != n) {
            return Err(errors::argument(format!(
                "{} seeds and {:?} mask entries for {n} envs",
                seeds.len(),
                mask.as_ref().map(Vec::len)
            )));
        }
        errors::no_panic(
            &mut *this,
            |core| {
                let env = core.env.as_mut().ok_or_else(closed)?;
                match &mask {
                    None => {
                        crate::mujoco_timer::without_mujoco_timer(|| env.reset_each(seeds));
                    }
                    Some(m) => {
                        crate::mujoco_timer::without_mujoco_timer(|| env.reset_masked(seeds, m))
                            .map_err(errors::env_error)?;
                    }
                }
                core.gather_only(Some(mask.as_deref().unwrap_or(&vec![true; n])))?;
                let obs = core.obs(py, copy)?;
                let info = core.info(py, false, copy, false)?;
                PyTuple::new(py, [obs, info.into_any()])
            },
            VecCore::require_reset,
        )
    }

    /// Step with a `(num_envs, act_dim)` batch: `(obs, rewards, terminated, truncated, info)`.
    /// A C-contiguous float32 or float64 batch is read in place; float32 steps with float32
    /// action costs, as numpy computes them. Anything else is converted as `envc.make`'s
    /// actions are (`envc._gym.as_actions`). `copy` as for `reset`; `None` takes `self.copy`.
    /// `EnvcVectorEnv.step` is this method itself: its checks are all here.
    #[pyo3(signature = (actions, copy = None))]
    fn step<'py>(
        slf: &Bound<'py, Self>,
        actions: &Bound<'py, PyAny>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let mut this = hold(slf, "step")?;
        let copy = copy.unwrap_or(this.copy);
        if let Some(result) = this.step_array(py, actions, copy) {
            return result;
        }
        let converted = AS_ACTIONS
            .import(py, "envc._gym", "as_actions")?
            .call1((actions,))?;
        match this.step_array(py, &converted, copy) {
            Some(result) => result,
            None => Err(errors::coded(
                "E1101",
                format!(
                    "error[E1101]: actions have shape {:?}; expected (num_envs, act_dim) = ({}, {})",
                    converted.getattr("shape")?,
                    this.env()?.num_envs(),
                    this.env()?.act_dim()
                ),
            )),
        }
    }

    /// `step`'s `copy` when the call names none.
    #[getter]
    fn copy(&self) -> bool {
        self.copy
    }
    #[setter]
    fn set_copy(&mut self, copy: bool) {
        self.copy = copy;
    }

    /// The Rust `VecEnv` alone, for benchmarks (`benches/python_overhead.py` pairs it with
    /// `step` on the same envs): `count` steps over the batches of `actions` (`(k, num_envs,
    /// act_dim)`, float32 or float64, C-contiguous; step t takes batch `(first + t) % k`) with
    /// the GIL released throughout and nothing built for Python in between; the results stay in
    /// the env (the next `step` or `reset` returns its own). The steps count in `env_steps`.
    fn rust_steps(
        &mut self,
        py: Python<'_>,
        actions: &Bound<'_, PyAny>,
        first: usize,
        count: usize,
    ) -> PyResult<()> {
        fn rows<'a, T: Element>(
            core: &VecCore,
            a: &'a numpy::PyReadonlyArray3<'_, T>,
        ) -> PyResult<&'a [T]> {
            let shape = a.shape();
            core.check_batch(&shape[1..])?;
            match a.as_slice() {
                Ok(s) if a.is_c_contiguous() && shape[0] > 0 => Ok(s),
                _ => Err(errors::argument(
                    "actions must be a C-contiguous (k, num_envs, act_dim) array with k >= 1",
                )),
            }
        }
        let run = |core: &mut VecCore| -> PyResult<()> {
            let mut taken = 0;
            let done = if let Ok(a) = actions.cast::<numpy::PyArray3<f32>>() {
                let a = a.try_readonly().map_err(errors::argument)?;
                let r = rows(core, &a)?;
                let env = core.env.as_mut().ok_or_else(closed)?;
                detached(py, env, |env, check| {
                    let f32 = |s| envc::JointAction::F32(s);
                    rust_loop(env, check, r, (first, count), f32, &mut taken)
                })
            } else if let Ok(a) = actions.cast::<numpy::PyArray3<f64>>() {
                let a = a.try_readonly().map_err(errors::argument)?;
                let r = rows(core, &a)?;
                let env = core.env.as_mut().ok_or_else(closed)?;
                detached(py, env, |env, check| {
                    let f64 = |s| envc::JointAction::F64(s);
                    rust_loop(env, check, r, (first, count), f64, &mut taken)
                })
            } else {
                Err(errors::coded(
                    "E1101",
                    "error[E1101]: actions must be a 3-D float32 or float64 numpy array".into(),
                ))
            };
            core.env_steps += taken;
            done
        };
        errors::no_panic(self, run, VecCore::require_reset)
    }

    /// Env steps taken by `step` and `rust_steps` since the env was made, NextStep's autoreset
    /// steps (reward 0, both flags false) not counted.
    #[getter]
    fn env_steps(&self) -> u64 {
        self.env_steps
    }

    /// A frame of env `index` in Gymnasium's `render_mode` (each env has its own renderer).
    fn render(slf: &Bound<'_, Self>, index: usize, mode: &str) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let mut this = hold(slf, "render")?;
        let env = this.env.as_mut().ok_or_else(closed)?;
        if index >= env.num_envs() {
            return Err(errors::argument(format!(
                "env index {index} out of range for {} envs",
                env.num_envs()
            )));
        }
        crate::render::render(py, mode, |m| env.render(index, m))
    }

    /// Stop the threads and drop the envs; later calls raise `RuntimeError`. A call running in
    /// another thread is waited for.
    fn close(slf: &Bound<'_, Self>) {
        loop {
            if let Ok(mut this) = slf.try_borrow_mut() {
                this.env = None;
                return;
            }
            slf.py()
                .detach(|| std::thread::sleep(std::time::Duration::from_millis(1)));
        }
    }

    /// What each env costs in memory as envc estimated it before making them (error E1403):
    /// `(resident bytes, mapped bytes)`.
    #[getter]
    fn bytes_per_env(&self) -> PyResult<(u64, u64)> {
        let f = self.env()?.footprint_per_env();
        Ok((f.resident, f.mapped))
    }
    #[getter]
    fn num_envs(&self) -> PyResult<usize> {
        Ok(self.env()?.num_envs())
    }
    /// Threads stepping envs (the calling thread included).
    #[getter]
    fn threads(&self) -> PyResult<usize> {
        Ok(self.env()?.threads())
    }
    #[getter]
    fn autoreset(&self) -> PyResult<&'static str> {
        Ok(match self.env()?.autoreset() {
            envc::Autoreset::NextStep => "NextStep",
            envc::Autoreset::SameStep => "SameStep",
        })
    }
    #[getter]
    fn id(&self) -> PyResult<String> {
        Ok(self.env()?.envs()[0].spec().id.clone())
    }
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        Ok(self.env()?.envs()[0].dt())
    }
    #[getter]
    fn max_episode_steps(&self) -> PyResult<Option<u64>> {
        Ok(self.env()?.envs()[0].spec().max_episode_steps)
    }
    #[getter]
    fn obs_low<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env()?.envs()[0].observation_space().low,
        ))
    }
    #[getter]
    fn obs_high<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env()?.envs()[0].observation_space().high,
        ))
    }
    #[getter]
    fn act_low<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env()?.envs()[0].action_space().low,
        ))
    }
    #[getter]
    fn act_high<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(
            py,
            &self.env()?.envs()[0].action_space().high,
        ))
    }
    /// The numerics profile every sub-env computes under (docs/numerics.md).
    #[getter]
    fn numerics(&self) -> PyResult<String> {
        Ok(self.env()?.envs()[0].numerics().to_string())
    }
    #[setter]
    fn set_numerics(&mut self, name: &str) -> PyResult<()> {
        let p = crate::convert::profile(name)?;
        self.env.as_mut().ok_or_else(closed)?.set_numerics(p);
        Ok(())
    }
}
