//! What the one collector needs from an env beyond [`JointEnv`]: its spaces as Minari stores
//! them, its info columns, and reset/step that append the stored observation row. Every task env
//! (typed or dynamic, through [`Environment`]) and the maze env implement it; a multi-agent env
//! does not, as Minari datasets are single-agent.
//!
//! The impls live here, not beside the kinds in the runtime: the runtime does not depend on this
//! crate. That leaves one knot. The task impl is a blanket one over every [`Environment`] (typed
//! envs are types of the user's crate), and beside it an impl for [`MazeEnv`] would be refused:
//! both are `envc`'s, so `envc` could one day make a maze an `Environment` and the two impls
//! would overlap (coherence reasons only about impls the current crate alone could add). So the
//! trait takes the kind as a marker type, [`TaskKind`] or [`MazeKind`]: the two impls are of
//! different traits and never overlap, and callers never name the marker, as it is inferred from
//! the env (`Collector::new(maze, ..)` is a `Collector<MazeEnv, MazeKind>`).

use crate::episode::InfoColumn;
use crate::error::DatasetError;
use crate::gym_spec::{env_spec_json, envc_env_spec_json, envc_spec_arg, envc_task_env_spec_json};
use crate::provenance;
use crate::space::{Dtype, Space};
use envc::environment::Environment;
use envc::error::EnvError;
use envc::maze::{MazeEnv, MazeObs};
use envc::{Info, JointAction, JointEnv, JointStep};

/// The [`Recordable`] impl of task envs, typed or dynamic (a marker, never a value).
#[derive(Debug)]
pub enum TaskKind {}

/// The [`Recordable`] impl of maze envs (a marker, never a value).
#[derive(Debug)]
pub enum MazeKind {}

/// An env the collector can record (its action space, numerics and warnings are the
/// [`JointEnv`]'s); `K` says which kind's impl (see the module doc), inferred from the env.
pub trait Recordable<K = TaskKind>: JointEnv {
    /// What the policy sees: the flat observation, or a maze's dict observation.
    type Obs: ?Sized;
    /// The stored observation space (a `Box`, or a `Dict` flattened key by key, keys sorted).
    fn observation_space(&self) -> Space;
    /// The info columns, in stored order (values empty).
    fn info_columns(&self) -> Vec<InfoColumn>;
    /// Gymnasium `EnvSpec` JSON, when the env has a Gymnasium counterpart.
    fn env_spec(&self) -> Option<String>;
    /// What made the env (`envc_provenance`), when it was opened from files; an error when they
    /// cannot be recorded as they were read.
    fn provenance(&self) -> Option<Result<serde_json::Value, DatasetError>>;
    /// The observation the policy acts on.
    fn policy_obs(&self) -> &Self::Obs;
    /// `reset(seed)`; appends the observation row to `obs` and one value per info column.
    fn record_reset(
        &mut self,
        seed: u64,
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<(), EnvError>;
    /// `step` with a float32 action; appends the observation row and the info values.
    fn record_step(
        &mut self,
        action: &[f32],
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<JointStep, EnvError>;
}

/// Append each column's value from `info` (zeros when a key is absent, e.g. step-only keys in a
/// reset row); `success` is the maze's own column.
fn push_info(infos: &mut [InfoColumn], success: Option<bool>, info: Info<'_>) {
    for c in infos.iter_mut() {
        if let (Some(s), "success") = (success, c.key.as_str()) {
            c.values.push(if s { 1.0 } else { 0.0 });
            continue;
        }
        match info.get(&c.key) {
            Some(v) if v.len() == c.width => c.values.extend_from_slice(v),
            _ => c.values.extend(std::iter::repeat_n(0.0, c.width)),
        }
    }
}

fn columns(spec: &envspec::ResolvedSpec) -> impl Iterator<Item = InfoColumn> + '_ {
    spec.info.iter().map(|i| InfoColumn {
        key: i.key.clone(),
        width: i.len.max(1),
        values: vec![],
    })
}

impl<E: Environment> Recordable<TaskKind> for E {
    type Obs = [f64];
    /// A `[goal]` task's is the reference's dict (keys sorted), as a maze's.
    fn observation_space(&self) -> Space {
        let o = Environment::observation_space(self);
        let flat = Space::box1(Dtype::F64, &o.low, &o.high);
        let spec = self.spec();
        if spec.manipulation.goal.is_none() {
            return flat;
        }
        Space::Dict(vec![
            ("achieved_goal".into(), unbounded(spec.goal_dim)),
            ("desired_goal".into(), unbounded(spec.goal_dim)),
            ("observation".into(), flat),
        ])
    }
    fn info_columns(&self) -> Vec<InfoColumn> {
        columns(self.spec()).collect()
    }
    /// The reference's class when the spec names one (`[env] entry_point`), else envc's own
    /// registration (`envc/<id>`).
    fn env_spec(&self) -> Option<String> {
        let spec = self.spec();
        match spec.entry_point {
            Some(_) => env_spec_json(spec).ok(),
            None => envc_task_env_spec_json(spec).ok(),
        }
    }
    fn provenance(&self) -> Option<Result<serde_json::Value, DatasetError>> {
        let spec = self.spec();
        (!spec.inputs.is_empty()).then(|| {
            let arg = envc_spec_arg(&spec.id, &spec.spec_path);
            provenance::record("task", &arg, &spec.spec_path, &spec.inputs)
        })
    }
    fn policy_obs(&self) -> &[f64] {
        Environment::obs(self)
    }
    fn record_reset(
        &mut self,
        seed: u64,
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<(), EnvError> {
        self.reset(Some(seed));
        push_task_obs(obs, self.env());
        push_info(infos, None, self.env().reset_info());
        Ok(())
    }
    fn record_step(
        &mut self,
        action: &[f32],
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<JointStep, EnvError> {
        let s = self.step_joint(JointAction::F32(action))?;
        push_task_obs(obs, self.env());
        push_info(infos, None, self.env().step_info());
        Ok(s)
    }
}

/// A task's row: the flat observation, or a `[goal]` task's dict in sorted key order.
fn push_task_obs(buf: &mut Vec<f64>, env: &envc::Env) {
    if env.spec().manipulation.goal.is_some() {
        let mut achieved = vec![];
        env.achieved_goal(&mut achieved);
        buf.extend_from_slice(&achieved);
        buf.extend_from_slice(env.goal());
    }
    buf.extend_from_slice(env.obs());
}

fn unbounded(n: usize) -> Space {
    Space::box1(
        Dtype::F64,
        &vec![f64::NEG_INFINITY; n],
        &vec![f64::INFINITY; n],
    )
}

/// A maze row in the reference's `spaces.Dict` key order (sorted).
fn push_maze_obs(buf: &mut Vec<f64>, o: &MazeObs) {
    buf.extend_from_slice(&o.achieved_goal);
    buf.extend_from_slice(&o.desired_goal);
    buf.extend_from_slice(&o.observation);
}

impl Recordable<MazeKind> for MazeEnv {
    type Obs = MazeObs;
    fn observation_space(&self) -> Space {
        Space::Dict(vec![
            ("achieved_goal".into(), unbounded(2)),
            ("desired_goal".into(), unbounded(2)),
            ("observation".into(), unbounded(self.observation_dim())),
        ])
    }
    /// `success`, then every key the robot reports.
    fn info_columns(&self) -> Vec<InfoColumn> {
        let success = InfoColumn {
            key: "success".into(),
            width: 1,
            values: vec![],
        };
        std::iter::once(success)
            .chain(columns(self.robot().spec()))
            .collect()
    }
    /// envc's own registration (`envc/<id>`, a `GoalEnv`): the maze id, or its spec file.
    fn env_spec(&self) -> Option<String> {
        let m = self.spec();
        Some(envc_env_spec_json(
            &m.id,
            "envc._maze:EnvcMazeEnv",
            &envc_spec_arg(&m.id, &m.path),
            m.max_episode_steps,
            vec![],
        ))
    }
    /// The maze's files, then its robot's.
    fn provenance(&self) -> Option<Result<serde_json::Value, DatasetError>> {
        let m = self.spec();
        if m.inputs.is_empty() {
            return None;
        }
        let mut inputs = m.inputs.clone();
        for f in &self.robot().spec().inputs {
            if !inputs.iter().any(|i| i.path == f.path) {
                inputs.push(f.clone());
            }
        }
        let arg = envc_spec_arg(&m.id, &m.path);
        Some(provenance::record("maze", &arg, &m.path, &inputs))
    }
    fn policy_obs(&self) -> &MazeObs {
        self.obs()
    }
    fn record_reset(
        &mut self,
        seed: u64,
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<(), EnvError> {
        let (o, success) = self.reset(Some(seed), None)?;
        push_maze_obs(obs, o);
        push_info(infos, Some(success), self.robot().reset_info());
        Ok(())
    }
    fn record_step(
        &mut self,
        action: &[f32],
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<JointStep, EnvError> {
        let s = self.step_joint(JointAction::F32(action))?;
        push_info(infos, Some(self.success()), self.robot().step_info());
        push_maze_obs(obs, self.obs());
        Ok(s)
    }
}
