//! The core of a vector env: many task envs stepped by Rust threads into numpy batches.
//!
//! The batch buffers are numpy arrays allocated once; every `reset` and `step` fills them in
//! place (no Python object per env), the threads stepping with the GIL released. Infos are laid
//! out key-major for Gymnasium's vector form: `info` is `[L, N]` (key k's values in rows
//! `offset..offset + len`), `info_mask` is `[K, N]` (row k is the `_key` mask), values zero where
//! an env did not report the key. SameStep's `final_obs` / `final_info` have the same layout,
//! valid where `has_final`.

use numpy::ndarray::Dimension;
use numpy::{
    Element, PyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    out: Buffers,
    /// Bumped when a buffer is replaced (`Buffers::renew`): the Python layer then reads
    /// `buffers` again.
    generation: u64,
}

struct InfoKey {
    name: String,
    offset: usize,
    len: usize,
    /// A float32 number when the step's actions are float32 (a float32 action cost, as numpy
    /// computes it in the reference).
    f32_with_f32_actions: bool,
}

struct Buffers {
    obs: Py<PyArray2<f64>>,
    rewards: Py<PyArray1<f64>>,
    terminated: Py<PyArray1<bool>>,
    truncated: Py<PyArray1<bool>>,
    info: Py<PyArray2<f64>>,
    info_mask: Py<PyArray2<bool>>,
    final_obs: Py<PyArray2<f64>>,
    final_info: Py<PyArray2<f64>>,
    has_final: Py<PyArray1<bool>>,
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

/// One vector step with the GIL released, checking for Ctrl-C about every 50 ms between envs: a
/// signal stops the step part-way (the envs not started are skipped), the env needs a reset, and
/// the signal's exception (KeyboardInterrupt) is raised.
fn step_interruptible(
    py: Python<'_>,
    core: &mut VecCore,
    actions: envc::JointAction<'_>,
) -> PyResult<()> {
    let env = core.env.as_mut().ok_or_else(closed)?;
    let mut signal = None;
    let stepped = py.detach(|| {
        let mut check = || match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                signal = Some(e);
                true
            }
        };
        crate::mujoco_timer::without_mujoco_timer(|| env.step_interruptible(actions, &mut check))
    });
    match (stepped.map_err(errors::env_error)?, signal) {
        (envc::Stepped::Done, _) => Ok(()),
        (envc::Stepped::Interrupted, Some(e)) => {
            core.require_reset();
            Err(e)
        }
        (envc::Stepped::Interrupted, None) => {
            core.require_reset();
            Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                "the vector step was interrupted",
            ))
        }
    }
}

fn closed() -> PyErr {
    errors::coded("E1103", "error[E1103]: the vector env is closed".into())
}

/// Replace `slot` with a fresh zeroed array of `shape` when the user made it unusable: read-only,
/// resized, or no longer contiguous (`copy=False` hands the observation buffer itself out).
/// Returns whether it was replaced.
fn renew<T: Element, D: Dimension>(
    py: Python<'_>,
    slot: &mut Py<PyArray<T, D>>,
    shape: &[usize],
    fresh: impl FnOnce(Python<'_>) -> Bound<'_, PyArray<T, D>>,
) -> bool {
    let a = slot.bind(py);
    let usable = a.shape() == shape && a.is_c_contiguous() && a.try_readwrite().is_ok();
    if !usable {
        *slot = fresh(py).unbind();
    }
    !usable
}

impl Buffers {
    /// Every buffer usable for writing (see `renew`); true when one was replaced.
    fn renew(&mut self, py: Python<'_>, n: usize, od: usize, nval: usize, nkeys: usize) -> bool {
        let mut r = false;
        r |= renew(py, &mut self.obs, &[n, od], |py| {
            PyArray2::zeros(py, [n, od], false)
        });
        r |= renew(py, &mut self.rewards, &[n], |py| {
            PyArray1::zeros(py, n, false)
        });
        r |= renew(py, &mut self.terminated, &[n], |py| {
            PyArray1::zeros(py, n, false)
        });
        r |= renew(py, &mut self.truncated, &[n], |py| {
            PyArray1::zeros(py, n, false)
        });
        r |= renew(py, &mut self.info, &[nval, n], |py| {
            PyArray2::zeros(py, [nval, n], false)
        });
        r |= renew(py, &mut self.info_mask, &[nkeys, n], |py| {
            PyArray2::zeros(py, [nkeys, n], false)
        });
        r |= renew(py, &mut self.final_obs, &[n, od], |py| {
            PyArray2::zeros(py, [n, od], false)
        });
        r |= renew(py, &mut self.final_info, &[nval, n], |py| {
            PyArray2::zeros(py, [nval, n], false)
        });
        r |= renew(py, &mut self.has_final, &[n], |py| {
            PyArray1::zeros(py, n, false)
        });
        r
    }
}

impl VecCore {
    fn env(&self) -> PyResult<&envc::VecEnv> {
        self.env.as_ref().ok_or_else(closed)
    }

    /// Copy the batch of the last reset or step into the numpy buffers; infos only of the envs
    /// in `only` (a masked reset), else of every env.
    fn fill(&mut self, py: Python<'_>, only: Option<&[bool]>) -> PyResult<()> {
        let (n, od) = {
            let env = self.env()?;
            (env.num_envs(), env.obs_dim())
        };
        let nval = self.keys.iter().map(|k| k.len).sum();
        if self.out.renew(py, n, od, nval, self.keys.len()) {
            self.generation += 1;
        }
        let env = self.env()?;
        let b = &self.out;
        let mut obs = b.obs.bind(py).readwrite();
        obs.as_slice_mut()?.copy_from_slice(env.obs());
        b.rewards
            .bind(py)
            .readwrite()
            .as_slice_mut()?
            .copy_from_slice(env.rewards());
        b.terminated
            .bind(py)
            .readwrite()
            .as_slice_mut()?
            .copy_from_slice(env.terminated());
        b.truncated
            .bind(py)
            .readwrite()
            .as_slice_mut()?
            .copy_from_slice(env.truncated());
        let mut values = b.info.bind(py).readwrite();
        let mut mask = b.info_mask.bind(py).readwrite();
        let (values, mask) = (values.as_slice_mut()?, mask.as_slice_mut()?);
        values.fill(0.0);
        mask.fill(false);
        for (i, e) in env.envs().iter().enumerate() {
            if only.is_some_and(|m| !m[i]) {
                continue;
            }
            // As `VecEnv::info`: an (auto)reset leaves the env at 0 elapsed steps.
            let (info, map) = if e.elapsed_steps() == 0 {
                (e.reset_info(), &self.reset_map)
            } else {
                (e.step_info(), &self.step_map)
            };
            self.write_info(info, map, n, i, values, Some(mask));
        }
        let has_final = env.has_final();
        b.has_final
            .bind(py)
            .readwrite()
            .as_slice_mut()?
            .copy_from_slice(has_final);
        if has_final.iter().any(|&h| h) {
            let od = env.obs_dim();
            let mut fo = b.final_obs.bind(py).readwrite();
            let mut fi = b.final_info.bind(py).readwrite();
            let (fo, fi) = (fo.as_slice_mut()?, fi.as_slice_mut()?);
            fi.fill(0.0);
            for i in (0..n).filter(|&i| has_final[i]) {
                fo[i * od..(i + 1) * od].copy_from_slice(&env.final_obs()[i * od..(i + 1) * od]);
                if let Some(info) = env.final_info(i) {
                    self.write_info(info, &self.step_map, n, i, fi, None);
                }
            }
        }
        Ok(())
    }

    fn write_info(
        &self,
        info: envc::Info<'_>,
        map: &[usize],
        n: usize,
        i: usize,
        values: &mut [f64],
        mut mask: Option<&mut [bool]>,
    ) {
        for ((_, v), &k) in info.iter().zip(map) {
            let key = &self.keys[k];
            for (t, &x) in v.iter().enumerate().take(key.len) {
                values[(key.offset + t) * n + i] = x;
            }
            if let Some(m) = mask.as_deref_mut() {
                m[k * n + i] = true;
            }
        }
    }

    /// After a panic: every env needs a reset before the next step.
    fn require_reset(&mut self) {
        if let Some(env) = self.env.as_mut() {
            env.require_reset();
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
        let spec = env.spec().expect("num_envs ≥ 1").clone();
        let mut keys = Vec::new();
        let mut offset = 0;
        for item in &spec.info {
            keys.push(InfoKey {
                name: item.key.clone(),
                offset,
                len: item.len,
                f32_with_f32_actions: f32_cost(&spec, item),
            });
            offset += item.len;
        }
        let index = |name: &str| {
            keys.iter()
                .position(|k| k.name == name)
                .expect("a spec info key")
        };
        let e0 = &env.envs()[0];
        let step_map = e0.step_info().keys().map(index).collect();
        let reset_map = e0.reset_info().keys().map(index).collect();
        let (n, od) = (num_envs, env.obs_dim());
        let out = Buffers {
            obs: PyArray2::zeros(py, [n, od], false).unbind(),
            rewards: PyArray1::zeros(py, n, false).unbind(),
            terminated: PyArray1::zeros(py, n, false).unbind(),
            truncated: PyArray1::zeros(py, n, false).unbind(),
            info: PyArray2::zeros(py, [offset, n], false).unbind(),
            info_mask: PyArray2::zeros(py, [keys.len(), n], false).unbind(),
            final_obs: PyArray2::zeros(py, [n, od], false).unbind(),
            final_info: PyArray2::zeros(py, [offset, n], false).unbind(),
            has_final: PyArray1::zeros(py, n, false).unbind(),
        };
        Ok(VecCore {
            env: Some(env),
            keys,
            step_map,
            reset_map,
            out,
            generation: 0,
        })
    }

    /// Reset every env, or those where `mask` is true: `seeds` is one seed (or `None`) per
    /// env, or `None` to continue every env's stream. Fills the buffers.
    #[pyo3(signature = (seeds = None, mask = None))]
    fn reset(
        &mut self,
        py: Python<'_>,
        seeds: Option<Vec<Option<u64>>>,
        mask: Option<Vec<bool>>,
    ) -> PyResult<()> {
        let n = self.env()?.num_envs();
        let seeds = seeds.unwrap_or_else(|| vec![None; n]);
        if seeds.len() != n || mask.as_ref().is_some_and(|m| m.len() != n) {
            return Err(errors::argument(format!(
                "{} seeds and {:?} mask entries for {n} envs",
                seeds.len(),
                mask.as_ref().map(Vec::len)
            )));
        }
        errors::no_panic(
            self,
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
                core.fill(py, mask.as_deref())
            },
            VecCore::require_reset,
        )
    }

    /// Step with a float64 `(num_envs, act_dim)` C-contiguous batch; fills the buffers.
    fn step(&mut self, py: Python<'_>, actions: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        self.check_batch(actions.shape())?;
        let a = actions.as_slice()?;
        errors::no_panic(
            self,
            |core| {
                step_interruptible(py, core, envc::JointAction::F64(a))?;
                core.fill(py, None)
            },
            VecCore::require_reset,
        )
    }

    /// Step with a float32 batch (float32 action costs, as numpy computes them).
    fn step_f32(&mut self, py: Python<'_>, actions: PyReadonlyArray2<'_, f32>) -> PyResult<()> {
        self.check_batch(actions.shape())?;
        let a = actions.as_slice()?;
        errors::no_panic(
            self,
            |core| {
                step_interruptible(py, core, envc::JointAction::F32(a))?;
                core.fill(py, None)
            },
            VecCore::require_reset,
        )
    }

    /// A frame of env `index` in Gymnasium's `render_mode` (each env has its own renderer).
    fn render(&mut self, py: Python<'_>, index: usize, mode: &str) -> PyResult<Py<PyAny>> {
        let env = self.env.as_mut().ok_or_else(closed)?;
        if index >= env.num_envs() {
            return Err(errors::argument(format!(
                "env index {index} out of range for {} envs",
                env.num_envs()
            )));
        }
        crate::render::render(py, mode, |m| env.render(index, m))
    }

    /// Stop the threads and drop the envs; later calls raise `RuntimeError`.
    fn close(&mut self) {
        self.env = None;
    }

    /// The numpy buffers the batches are written into, by name: `obs`, `rewards`,
    /// `terminated`, `truncated`, `info`, `info_mask`, `final_obs`, `final_info`, `has_final`.
    #[getter]
    fn buffers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let b = &self.out;
        d.set_item("obs", b.obs.bind(py))?;
        d.set_item("rewards", b.rewards.bind(py))?;
        d.set_item("terminated", b.terminated.bind(py))?;
        d.set_item("truncated", b.truncated.bind(py))?;
        d.set_item("info", b.info.bind(py))?;
        d.set_item("info_mask", b.info_mask.bind(py))?;
        d.set_item("final_obs", b.final_obs.bind(py))?;
        d.set_item("final_info", b.final_info.bind(py))?;
        d.set_item("has_final", b.has_final.bind(py))?;
        Ok(d)
    }

    /// Bumped whenever a buffer the user made read-only or resized is replaced by a fresh one:
    /// read `buffers` again then.
    #[getter]
    fn generation(&self) -> u64 {
        self.generation
    }

    /// The info keys: `(name, offset, len, float32 under float32 actions)`, in spec order.
    #[getter]
    fn info_keys(&self) -> Vec<(String, usize, usize, bool)> {
        self.keys
            .iter()
            .map(|k| (k.name.clone(), k.offset, k.len, k.f32_with_f32_actions))
            .collect()
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
