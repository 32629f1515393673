//! What the one collector needs from an env: its spaces as Minari stores them, its info columns,
//! and reset/step that append the stored observation row. Every task env (typed or dynamic,
//! through [`Environment`]) and the maze env ([`MazeRecording`]) implement it; a multi-agent env
//! does not, as Minari datasets are single-agent. The trait is object safe, so code that records
//! whatever [`envc::open`] gave holds a `Box<dyn Recordable + Send>` ([`recordable`]) and never
//! matches on the kind again.
//!
//! The impls live here, not beside the kinds in the runtime: the runtime does not depend on this
//! crate. That leaves one knot. The task impl is a blanket one over every [`Environment`] (typed
//! envs are types of the user's crate), and beside it an impl for [`MazeEnv`] would be refused:
//! both are `envc`'s, so `envc` could one day make a maze an `Environment` and the two impls
//! would overlap (coherence reasons only about impls the current crate alone could add). So a
//! maze is recorded through this crate's own wrapper, [`MazeRecording`].

use crate::episode::InfoColumn;
use crate::error::DatasetError;
use crate::gym_spec::{env_spec_json, envc_env_spec_json, envc_spec_arg, envc_task_env_spec_json};
use crate::provenance;
use crate::space::{Dtype, Space};
use envc::environment::Environment;
use envc::error::EnvError;
use envc::maze::{MazeEnv, MazeObs};
use envc::multi_agent::MultiAgentEnv;
use envc::{AnyEnv, Info, JointAction, JointEnv, JointStep};

/// An env the collector can record. Object safe: `Box<dyn Recordable + Send>` records any kind.
pub trait Recordable {
    /// The env as every kind drives it (its action space, numerics and warnings).
    fn joint(&self) -> &dyn JointEnv;
    /// The stored observation space (a `Box`, or a `Dict` flattened key by key, keys sorted).
    fn observation_space(&self) -> Space;
    /// The info columns, in stored order (values empty).
    fn info_columns(&self) -> Vec<InfoColumn>;
    /// Gymnasium `EnvSpec` JSON, when the env has a Gymnasium counterpart.
    fn env_spec(&self) -> Option<String>;
    /// What made the env (`envc_provenance`), when it was opened from files; an error when they
    /// cannot be recorded as they were read.
    fn provenance(&self) -> Option<Result<serde_json::Value, DatasetError>>;
    /// The flat observation a policy acts on: a task's. `None` for a maze, whose observation is
    /// a dict: only policies that read no observation drive it ([`policy_fits`]).
    fn flat_obs(&self) -> Option<&[f64]>;
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
    /// Why the env cannot be recorded yet, if it cannot (collectors refuse it, E1205).
    fn unrecordable(&self) -> Option<String> {
        None
    }
}

/// E1205 for an env the collectors cannot record yet.
pub fn check_recordable<E: Recordable + ?Sized>(env: &E) -> Result<(), DatasetError> {
    match env.unrecordable() {
        Some(why) => Err(DatasetError::Unsupported(why)),
        None => Ok(()),
    }
}

/// A boxed recordable env is one too (what [`recordable`] gives, to every generic collector).
impl Recordable for Box<dyn Recordable + Send> {
    fn joint(&self) -> &dyn JointEnv {
        (**self).joint()
    }
    fn observation_space(&self) -> Space {
        (**self).observation_space()
    }
    fn info_columns(&self) -> Vec<InfoColumn> {
        (**self).info_columns()
    }
    fn env_spec(&self) -> Option<String> {
        (**self).env_spec()
    }
    fn provenance(&self) -> Option<Result<serde_json::Value, DatasetError>> {
        (**self).provenance()
    }
    fn flat_obs(&self) -> Option<&[f64]> {
        (**self).flat_obs()
    }
    fn record_reset(
        &mut self,
        seed: u64,
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<(), EnvError> {
        (**self).record_reset(seed, obs, infos)
    }
    fn record_step(
        &mut self,
        action: &[f32],
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<JointStep, EnvError> {
        (**self).record_step(action, obs, infos)
    }
    fn unrecordable(&self) -> Option<String> {
        (**self).unrecordable()
    }
}

/// The env [`envc::open`] gave, as the collector records it: a task or a maze. A multi-agent env
/// is handed back (Minari datasets are single-agent), for the caller's own refusal.
pub fn recordable(env: AnyEnv) -> Result<Box<dyn Recordable + Send>, Box<MultiAgentEnv>> {
    match env {
        AnyEnv::Task(e) => Ok(Box::new(e)),
        AnyEnv::Maze(e) => Ok(Box::new(MazeRecording(e))),
        AnyEnv::MultiAgent(e) => Err(Box::new(e)),
    }
}

/// Whether a policy can drive `env`: one that reads observations (a callable, a spec's MLP)
/// needs a flat one, which a maze has not.
pub fn policy_fits<E: Recordable + ?Sized>(env: &E, reads_obs: bool) -> Result<(), DatasetError> {
    if reads_obs && env.flat_obs().is_none() {
        return Err(DatasetError::Unsupported(
            "a callable policy needs a task env (flat observations); mazes take 'zero', 'random' or 'replay'".into(),
        ));
    }
    Ok(())
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

impl<E: Environment> Recordable for E {
    fn joint(&self) -> &dyn JointEnv {
        self
    }
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
    fn flat_obs(&self) -> Option<&[f64]> {
        Some(Environment::obs(self))
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
    /// A goal of named parts is a dict of dicts, and its `goal_parts` info entries are lists of
    /// names: neither is stored yet.
    fn unrecordable(&self) -> Option<String> {
        let goal = self.spec().manipulation.goal.as_ref()?;
        goal.parts.as_ref().map(|_| {
            format!(
                "`{}` has a [goal] of named parts (nested dict observations, info lists of names), which envc's datasets do not store yet",
                self.spec().id
            )
        })
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

/// A maze env as the collector records it (this crate's own type: see the module doc).
pub struct MazeRecording(pub Box<MazeEnv>);

impl Recordable for MazeRecording {
    fn joint(&self) -> &dyn JointEnv {
        &*self.0
    }
    fn observation_space(&self) -> Space {
        Space::Dict(vec![
            ("achieved_goal".into(), unbounded(2)),
            ("desired_goal".into(), unbounded(2)),
            ("observation".into(), unbounded(self.0.observation_dim())),
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
            .chain(columns(self.0.robot().spec()))
            .collect()
    }
    /// envc's own registration (`envc/<id>`, a `GoalEnv`): the maze id, or its spec file.
    fn env_spec(&self) -> Option<String> {
        let m = self.0.spec();
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
        let m = self.0.spec();
        if m.inputs.is_empty() {
            return None;
        }
        let mut inputs = m.inputs.clone();
        for f in &self.0.robot().spec().inputs {
            if !inputs.iter().any(|i| i.path == f.path) {
                inputs.push(f.clone());
            }
        }
        let arg = envc_spec_arg(&m.id, &m.path);
        Some(provenance::record("maze", &arg, &m.path, &inputs))
    }
    fn flat_obs(&self) -> Option<&[f64]> {
        None
    }
    fn record_reset(
        &mut self,
        seed: u64,
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<(), EnvError> {
        let (o, success) = self.0.reset(Some(seed), None)?;
        push_maze_obs(obs, o);
        push_info(infos, Some(success), self.0.robot().reset_info());
        Ok(())
    }
    fn record_step(
        &mut self,
        action: &[f32],
        obs: &mut Vec<f64>,
        infos: &mut [InfoColumn],
    ) -> Result<JointStep, EnvError> {
        let s = self.0.step_joint(JointAction::F32(action))?;
        push_info(infos, Some(self.0.success()), self.0.robot().step_info());
        push_maze_obs(obs, self.0.obs());
        Ok(s)
    }
}
