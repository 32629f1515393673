//! The core of a vector env: many task envs stepped by Rust threads, their batches handed to
//! Python as numpy arrays and Gymnasium's vector info dicts built here, with no Python loop.
//!
//! `copy=True` (Gymnasium's default) returns fresh arrays each call. `copy=False` returns the
//! same arrays every call, owned by the core and overwritten in place by the next `reset` or
//! `step` (observations, rewards, flags, each info key's values and `_key` mask; not a one-number
//! bool key's object array); a buffer the user made unusable (read-only, resized) is replaced by
//! a fresh one. Infos are gathered
//! key-major in Rust scratch space (key k's values env-major at `offset * N`), zero where an env
//! did not report the key, as Gymnasium's `_add_info` leaves them.
//!
//! A goal-conditioned task's (`[goal]`) observations are dicts of three batches, as
//! `SyncVectorEnv` concatenates them over the single env's `Dict` space (its sorted keys):
//! `achieved_goal`, `desired_goal`, `observation`. A goal of named parts is refused (E0602).

use numpy::{Element, PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyString, PyTuple};

use crate::convert;
use crate::errors;

mod arrays;
mod infos;
mod stepping;

use arrays::Kept;
use infos::f32_cost;
use stepping::{detached, rust_loop};

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
    /// A bool key's values, converted for the call.
    bool_scratch: Vec<bool>,
    /// `np.False_` and `np.True_`: a one-number bool key's values (see `flag_objects`).
    np_bools: [Py<PyAny>; 2],
    /// By `Slot`: `[0]` `copy=False`'s arrays (handed out every call); `[1]` `copy=True`'s
    /// next ones, made while the workers step (`prepare`) and each handed out once.
    f64_slots: [Vec<Kept<f64>>; 2],
    f32_slots: [Vec<Kept<f32>>; 2],
    bool_slots: [Vec<Kept<bool>>; 2],
    final_obs_key: Py<PyString>,
    final_obs_mask_key: Py<PyString>,
    final_info_key: Py<PyString>,
    final_info_mask_key: Py<PyString>,
    /// The observation dict's keys (`[goal]`), in `SyncVectorEnv`'s order.
    goal_keys: [Py<PyString>; 3],
    /// Env steps taken by `step` and `rust_steps`, NextStep's autoreset steps not counted.
    env_steps: u64,
    /// `step`'s `copy` when the call names none (`EnvcVectorEnv.copy`).
    copy: bool,
}

struct InfoKey {
    name: Py<PyString>,
    /// `"_" + name`: the mask's key.
    mask_name: Py<PyString>,
    offset: usize,
    len: usize,
    /// A float32 number when the step's actions are float32 (a float32 action cost, as numpy
    /// computes it in the reference).
    f32_with_f32_actions: bool,
    /// Declared `dtype = "float32"`: always float32, as the single env reports it.
    float32: bool,
    /// Declared `dtype = "bool"`: numpy bools (`value != 0`), as the single env reports them
    /// (batched as `_add_info` batches them: an object array for one number, else bools).
    boolean: bool,
}

fn closed() -> PyErr {
    errors::coded("E1103", "error[E1103]: the vector env is closed".into())
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
                py.detach(move || {
                    envc::VecEnv::make_checked(
                        &id,
                        &o,
                        num_envs,
                        threads.max(1),
                        mode,
                        refuse_parts,
                    )
                })
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
                float32: item.float32,
                boolean: item.boolean,
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
        let np = py.import("numpy")?;
        Ok(VecCore {
            env: Some(env),
            step_map,
            reset_map,
            values: vec![0.0; offset * n],
            mask: vec![false; nkeys * n],
            final_values: vec![0.0; offset * n],
            f32_scratch: Vec::with_capacity(keys.iter().map(|k| k.len).max().unwrap_or(0) * n),
            np_bools: [
                np.getattr("False_")?.unbind(),
                np.getattr("True_")?.unbind(),
            ],
            bool_scratch: Vec::with_capacity(keys.iter().map(|k| k.len).max().unwrap_or(0) * n),
            f64_slots: [0, 1].map(|_| (0..4 + 2 * nkeys).map(|_| None).collect()),
            f32_slots: [0, 1].map(|_| (0..2 + 2 * nkeys).map(|_| None).collect()),
            bool_slots: [0, 1].map(|_| (0..3 + 3 * nkeys).map(|_| None).collect()),
            keys,
            final_obs_key: PyString::intern(py, "final_obs").unbind(),
            final_obs_mask_key: PyString::intern(py, "_final_obs").unbind(),
            final_info_key: PyString::intern(py, "final_info").unbind(),
            final_info_mask_key: PyString::intern(py, "_final_info").unbind(),
            goal_keys: ["achieved_goal", "desired_goal", "observation"]
                .map(|k| PyString::intern(py, k).unbind()),
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
    /// The length of a `[goal]` task's goal vectors (0 without `[goal]`: plain observations).
    #[getter]
    fn goal_dim(&self) -> PyResult<usize> {
        Ok(self.env()?.goal_dim())
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

/// A goal of named parts is refused before the vector env builds its envs: its goals are dicts
/// of named parts and its infos lists of names, which the batches do not hold.
fn refuse_parts(first: &envc::Env) -> Result<(), envc::EnvError> {
    let spec = first.spec();
    let parts = spec
        .manipulation
        .goal
        .as_ref()
        .and_then(|g| g.parts.as_ref());
    if parts.is_none() {
        return Ok(());
    }
    Err(envc::EnvError::Spec(
        envspec::Diagnostic::new(
            envspec::Code::E0602,
            format!(
                "`{}` has a goal of named parts ([goal.parts]): envc.make_vec does not batch dicts of parts; use gymnasium.vector.SyncVectorEnv over envc.make",
                spec.id
            ),
        )
        .into(),
    ))
}
