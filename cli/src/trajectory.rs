//! What a trajectory file holds of each kind of env: the [`Trajectory`] each kind implements
//! (tasks in `commands/rollout.rs`, mazes and multi-agent specs in `kinds/`), and the info
//! columns they collect.

use std::collections::BTreeMap;

use anyhow::Result;
use envc::JointEnv;
use ndarray::{Array, ArrayD, IxDyn};
use ndarray_npy::NpzWriter;

use crate::output::Sticky;

/// Per-key info values collected over steps.
#[derive(Default)]
pub(crate) struct InfoColumns {
    keys: Vec<(String, usize)>,
    values: BTreeMap<String, Vec<f64>>,
}

impl InfoColumns {
    pub(crate) fn push(&mut self, info: envc::Info<'_>) {
        if self.keys.is_empty() {
            self.keys = info.iter().map(|(k, v)| (k.to_string(), v.len())).collect();
        }
        for (k, v) in info.iter() {
            self.values
                .entry(k.to_string())
                .or_default()
                .extend_from_slice(v);
        }
    }
    /// `prefix.<key>` of every row: `[n]` for scalar keys, `[n, k]` for vector keys.
    pub(crate) fn write(&self, npz: &mut NpzWriter<Sticky>, prefix: &str) -> Result<()> {
        for (name, a) in self.arrays(prefix)? {
            npz.add_array(name.as_str(), &a)?;
        }
        Ok(())
    }
    /// `prefix.<key>` of the first row alone (a reset's info): `[]` for scalars, `[k]` for
    /// vectors.
    pub(crate) fn write_first(&self, npz: &mut NpzWriter<Sticky>, prefix: &str) -> Result<()> {
        for (name, a) in self.arrays(prefix)? {
            npz.add_array(name.as_str(), &a.index_axis_move(ndarray::Axis(0), 0))?;
        }
        Ok(())
    }
    fn arrays(&self, prefix: &str) -> Result<Vec<(String, ArrayD<f64>)>> {
        let mut out = vec![];
        for (k, len) in &self.keys {
            let v = self.values[k].clone();
            let n = v.len() / len;
            let shape = if *len == 1 { vec![n] } else { vec![n, *len] };
            out.push((
                format!("{prefix}.{k}"),
                Array::from_shape_vec(IxDyn(&shape), v)?,
            ));
        }
        Ok(out)
    }
}

/// What a trajectory file holds of one kind of env. The one loop ([`roll`]) resets and steps
/// any kind through [`JointEnv`] and writes the reward and flags; each kind records its own
/// observations and infos (flat, a maze's dict, every agent's) and writes them around those.
pub(crate) trait Trajectory {
    type Env: JointEnv;
    /// After a reset: the first (`at` None) or an auto-reset before step `at`.
    fn reset(&mut self, env: &Self::Env, at: Option<usize>);
    /// After a step.
    fn step(&mut self, env: &Self::Env);
    /// The arrays written before `reward`, `terminated` and `truncated` (the observations).
    fn write_obs(
        &mut self,
        npz: &mut NpzWriter<Sticky>,
        env: &Self::Env,
        n: usize,
        auto_reset: bool,
    ) -> Result<()>;
    /// The arrays written after them (infos, and with `--auto-reset` the resets).
    fn write_rest(
        self,
        npz: &mut NpzWriter<Sticky>,
        env: &Self::Env,
        auto_reset: bool,
    ) -> Result<()>;
    /// How the closing message names the env.
    fn describe(&self, env: &Self::Env) -> String {
        env.id().to_string()
    }
}
