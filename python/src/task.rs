//! The core of a single-agent task env: what `EnvCore` shares, plus the observation bounds, the
//! state and the resolved parameters.

use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::env_core::EnvCore;
use crate::errors;

type F64Array<'py> = Bound<'py, PyArray1<f64>>;

/// A task env (`envc.EnvcEnv` wraps it as a `gymnasium.Env`).
#[pyclass(module = "envc._envc", extends = EnvCore)]
pub struct TaskCore {
    pub(crate) env: envc::Env,
}

#[pymethods]
impl TaskCore {
    /// `(qpos, qvel)` now (checks of other executors start from the same state).
    fn state<'py>(&self, py: Python<'py>) -> (F64Array<'py>, F64Array<'py>) {
        let (q, v) = self.env.state();
        (PyArray1::from_slice(py, q), PyArray1::from_slice(py, v))
    }
    #[getter]
    fn obs_low<'py>(&self, py: Python<'py>) -> F64Array<'py> {
        PyArray1::from_slice(py, &self.env.observation_space().low)
    }
    #[getter]
    fn obs_high<'py>(&self, py: Python<'py>) -> F64Array<'py> {
        PyArray1::from_slice(py, &self.env.observation_space().high)
    }
    /// Length of the goal vectors of a `[goal]` task (0 without `[goal]`).
    #[getter]
    fn goal_dim(&self) -> usize {
        let spec = self.env.spec();
        if spec.manipulation.goal.is_some() {
            spec.goal_dim
        } else {
            0
        }
    }
    /// A `[goal]` of parts: each part in play's name and length, in goal-vector order (empty
    /// for a single goal).
    #[getter]
    fn goal_parts(&self) -> Vec<(String, usize)> {
        let goal = self.env.spec().manipulation.goal.as_ref();
        let parts = goal.and_then(|g| g.parts.as_ref());
        parts.map_or(vec![], |p| {
            p.parts.iter().map(|x| (x.name.clone(), x.len())).collect()
        })
    }
    /// The info keys of `goal_parts` entries: one value per part, reported as a list of names.
    #[getter]
    fn parts_info_keys(&self) -> Vec<String> {
        let info = self.env.spec().info.iter();
        info.filter(|i| matches!(i.kind, envspec::ir::InfoKind::GoalParts(_)))
            .map(|i| i.key.clone())
            .collect()
    }
    /// The info keys reported as numpy float32 (`dtype = "float32"`).
    #[getter]
    fn float32_info_keys(&self) -> Vec<String> {
        let info = self.env.spec().info.iter();
        info.filter(|i| i.float32).map(|i| i.key.clone()).collect()
    }
    /// The info keys reported as numpy bool (`dtype = "bool"`).
    #[getter]
    fn bool_info_keys(&self) -> Vec<String> {
        let info = self.env.spec().info.iter();
        info.filter(|i| i.boolean).map(|i| i.key.clone()).collect()
    }
    /// How many `[termination.*]` conditions the task has.
    #[getter]
    fn terminations(&self) -> usize {
        self.env.spec().termination.len()
    }
    /// Whether every reward term is `goal_missed` (the reference computes that reward in
    /// float32: `-(d > threshold).astype(np.float32)`).
    #[getter]
    fn goal_reward_float32(&self) -> bool {
        let spec = self.env.spec();
        !spec.reward.is_empty()
            && spec.reward.iter().all(|t| {
                matches!(
                    t.kind,
                    envspec::ir::TermKind::GoalMissed(_) | envspec::ir::TermKind::GoalsMissed(_)
                )
            })
    }
    /// `compute_reward` of a `[goal]` task over rows of two `[N, goal_dim]` arrays, exactly as the
    /// step reward (E0170 when the reward is not a function of the goals alone).
    fn compute_reward<'py>(
        &self,
        py: Python<'py>,
        achieved: PyReadonlyArray2<'py, f64>,
        desired: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<F64Array<'py>> {
        let env = &self.env;
        let n = env.spec().goal_dim;
        let (a, d) = (achieved.as_array(), desired.as_array());
        if a.shape() != d.shape() || a.shape()[1] != n {
            return Err(errors::argument(format!(
                "achieved_goal {:?} and desired_goal {:?}: expected two arrays of shape [N, {n}]",
                a.shape(),
                d.shape()
            )));
        }
        let mut out = vec![0.0; a.shape()[0]];
        // C-contiguous batches (what Python passes) are read in place.
        let result = match (achieved.as_slice(), desired.as_slice()) {
            (Ok(a), Ok(d)) => env.compute_reward(a, d, &mut out),
            _ => {
                let (a, d): (Vec<f64>, Vec<f64>) =
                    (a.iter().copied().collect(), d.iter().copied().collect());
                env.compute_reward(&a, &d, &mut out)
            }
        };
        result.map_err(|why| {
            errors::coded("E0170", format!("error[E0170]: compute_reward: {why}"))
        })?;
        Ok(PyArray1::from_vec(py, out))
    }
    /// The resolved parameters: `{name: value as TOML text}`.
    #[getter]
    fn params(&self) -> Vec<(String, String)> {
        let params = self.env.spec().params.iter();
        params
            .map(|p| (p.name.clone(), p.value.to_string()))
            .collect()
    }
}

/// `(name, type, default as TOML text, doc)` of every parameter of a spec of any kind.
pub fn parameters(id_or_path: &str) -> PyResult<Vec<(String, String, String, String)>> {
    let spec = envspec::open(id_or_path, &[]).map_err(errors::diagnostics)?;
    let params = match &spec {
        envc::AnySpec::Task(t) => &t.params,
        envc::AnySpec::Maze(_) => return Ok(vec![]),
        envc::AnySpec::MultiAgent(a) => &a.base.params,
    };
    Ok(params
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                p.ty.name().to_string(),
                p.default.to_string(),
                p.doc.clone(),
            )
        })
        .collect())
}
