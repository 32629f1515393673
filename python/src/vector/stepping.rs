//! Stepping the envs with the GIL released (Ctrl-C checked meanwhile), and the step's result
//! as numpy.

use numpy::{Element, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use super::arrays::{Slot, out_array, prepare};
use super::{VecCore, closed};
use crate::errors;

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
    let dims = (env.num_envs(), env.obs_dim(), env.goal_dim());
    let overlap = copy && env.threads() > 1;
    let mut meanwhile = || {
        if overlap {
            Python::attach(|py| prepare(py, keys, f64s, f32s, bools, dims, f32));
        }
    };
    detached(py, env, |env, check| {
        env.step_overlapped(actions, check, &mut meanwhile)
    })
}

/// `steps` run on the env with the GIL released, checking for Ctrl-C about every 50 ms between
/// envs (`steps` hands the check to `VecEnv::step_interruptible`): a signal stops the step
/// part-way (the envs not started are skipped), the env needs a reset, and the signal's
/// exception (KeyboardInterrupt) is raised.
pub(super) fn detached<F>(py: Python<'_>, env: &mut envc::VecEnv, steps: F) -> PyResult<()>
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
pub(super) fn rust_loop<'a, T>(
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

/// The element types a batch of actions is stepped in.
pub(super) trait ActionElement: Element + Copy {
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

impl VecCore {
    /// The observation batch as numpy (`copy`: a fresh array, else the kept one); a `[goal]`
    /// task's is a dict of three such batches (`SyncVectorEnv`'s keys and order).
    pub(super) fn obs<'py>(&mut self, py: Python<'py>, copy: bool) -> PyResult<Bound<'py, PyAny>> {
        let env = self.env.as_ref().ok_or_else(closed)?;
        let (n, gd, nkeys) = (env.num_envs(), env.goal_dim(), self.keys.len());
        let slots = &mut self.f64_slots[usize::from(copy)];
        let obs = out_array(
            py,
            &mut slots[Slot::Obs.index(nkeys)],
            &[n, env.obs_dim()],
            env.obs(),
            copy,
        )?;
        if gd == 0 {
            return Ok(obs);
        }
        let d = PyDict::new(py);
        let achieved = (Slot::Achieved, env.achieved_goals());
        let desired = (Slot::Desired, env.desired_goals());
        for (key, (slot, rows)) in self.goal_keys[..2].iter().zip([achieved, desired]) {
            let a = out_array(py, &mut slots[slot.index(nkeys)], &[n, gd], rows, copy)?;
            d.set_item(key.bind(py), a)?;
        }
        d.set_item(self.goal_keys[2].bind(py), obs)?;
        Ok(d.into_any())
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
    pub(super) fn require_reset(&mut self) {
        if let Some(env) = self.env.as_mut() {
            env.require_reset();
        }
    }

    /// `step` over a 2-D float32 or float64 array; `None` for anything else.
    pub(super) fn step_array<'py>(
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

    pub(super) fn check_batch(&self, shape: &[usize]) -> PyResult<()> {
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
