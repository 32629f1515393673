//! Gymnasium's vector info dicts, gathered key-major in the core's scratch space.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use super::arrays::{Slot, out_array};
use super::{InfoKey, VecCore, closed};

/// Whether info item `item` is a float32 action cost under float32 actions (see `Env::step_f32`).
pub(super) fn f32_cost(spec: &envspec::ResolvedSpec, item: &envspec::ir::InfoItem) -> bool {
    use envspec::ir::{InfoKind, TermKind};
    match item.kind {
        InfoKind::Term(t) => matches!(
            &spec.reward[t].kind,
            TermKind::SumSquares { source, clip_input: None, .. } if source.field == envspec::Field::Action
        ),
        _ => false,
    }
}

impl VecCore {
    /// Gather the last call's infos into the scratch space: of the envs in `only` (a masked
    /// reset), else of every env; and SameStep's final infos where an env ended.
    pub(super) fn gather(&mut self) -> PyResult<()> {
        self.gather_only(None)
    }

    pub(super) fn gather_only(&mut self, only: Option<&[bool]>) -> PyResult<()> {
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

    /// Key k's values over envs as Gymnasium gives them: `(N,)` or `(N, len)`; float32 for a
    /// key declared float32, or where `f32` and the key is a float32 action cost; bool for a key
    /// declared bool (as the single env converts them, and `_add_info` batches numpy scalars).
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
        if key.boolean && key.len == 1 {
            return self.flag_objects(py, k, last);
        }
        let (off, len) = (key.offset * n, key.len * n);
        let shape: &[usize] = if key.len == 1 { &[n] } else { &[n, key.len] };
        let src = if last {
            &self.final_values[off..off + len]
        } else {
            &self.values[off..off + len]
        };
        let slot = Slot::Value { key: k, last }.index(self.keys.len());
        if key.boolean {
            self.bool_scratch.clear();
            self.bool_scratch.extend(src.iter().map(|&x| x != 0.0));
            let slot = Slot::Flag { key: k, last }.index(self.keys.len());
            out_array(
                py,
                &mut self.bool_slots[usize::from(copy)][slot],
                shape,
                &self.bool_scratch,
                copy,
            )
        } else if key.float32 || (f32 && key.f32_with_f32_actions) {
            self.f32_scratch.clear();
            // An action cost's is exact (computed in float32); a declared float32 rounds as
            // `np.float32(value)` does.
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

    /// A one-number bool key as `_add_info` batches the single env's `np.bool_` scalars (no
    /// `np.number`, so an object array): `np.True_` or `np.False_` where the env reported the
    /// key (`last`: where it ended), None elsewhere.
    fn flag_objects<'py>(
        &self,
        py: Python<'py>,
        k: usize,
        last: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let env = self.env()?;
        let n = env.num_envs();
        let at = self.keys[k].offset * n;
        let (values, reported) = if last {
            (&self.final_values[at..at + n], env.has_final())
        } else {
            (&self.values[at..at + n], &self.mask[k * n..(k + 1) * n])
        };
        let rows = (0..n)
            .map(|i| {
                if reported[i] {
                    self.np_bools[usize::from(values[i] != 0.0)].clone_ref(py)
                } else {
                    py.None()
                }
            })
            .collect::<Vec<_>>();
        Ok(PyArray1::from_vec(py, rows).into_any())
    }

    /// The last call's infos in Gymnasium's vector form; `finals`: SameStep's `final_obs` and
    /// `final_info` where an env ended.
    pub(super) fn info<'py>(
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
        let has_final = env.has_final();
        let rows = (0..n)
            .map(|i| {
                Ok(if has_final[i] {
                    final_row(py, env, i, &self.goal_keys)?.unbind()
                } else {
                    py.None()
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
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
}

/// Env i's final observation as the single env returned it: an array, or a `[goal]` task's
/// dict in the single env's key order (`observation`, `achieved_goal`, `desired_goal`).
fn final_row<'py>(
    py: Python<'py>,
    env: &envc::VecEnv,
    i: usize,
    [achieved, desired, observation]: &[Py<PyString>; 3],
) -> PyResult<Bound<'py, PyAny>> {
    let (od, gd) = (env.obs_dim(), env.goal_dim());
    let obs = PyArray1::from_slice(py, &env.final_obs()[i * od..(i + 1) * od]).into_any();
    if gd == 0 {
        return Ok(obs);
    }
    let d = PyDict::new(py);
    let g = i * gd..(i + 1) * gd;
    d.set_item(observation.bind(py), obs)?;
    let a = &env.final_achieved_goals()[g.clone()];
    d.set_item(achieved.bind(py), PyArray1::from_slice(py, a))?;
    let w = &env.final_desired_goals()[g];
    d.set_item(desired.bind(py), PyArray1::from_slice(py, w))?;
    Ok(d.into_any())
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
