//! [`JointEnv`]: what an env of any kind offers — a task ([`Env`], typed or dynamic), a maze
//! ([`MazeEnv`](crate::maze::MazeEnv)) or a multi-agent spec
//! ([`MultiAgentEnv`](crate::multi_agent::MultiAgentEnv)) — stepped with one joint action.
//!
//! Everything that drives envs without caring for their kind is written against this trait:
//! [`AnyEnv`](crate::AnyEnv) (the one door's env), the vector env's workers, the dataset
//! collector (`envc_datasets::Recordable` adds what Minari stores), the CLI's one rollout loop
//! and the Python binding's base class. Kind-specific views (a maze's dict observation, each agent's
//! observation) stay on the concrete types, and each kind's impl lives beside its kind (tasks here,
//! `maze/joint.rs`, `multi_agent/joint.rs`).
//!
//! ```no_run
//! use envc::{JointAction, JointEnv};
//! let mut env = envc::open("PointMaze_UMaze-v3", &[])?;
//! env.try_reset(Some(0))?;
//! let s = env.step_joint(JointAction::F64(&[0.5, 0.5]))?;
//! println!("reward {} after {} s", s.reward, env.dt());
//! # Ok::<(), envc::EnvError>(())
//! ```

use envspec::Kind;

use crate::env::{BoxSpace, Env};
use crate::environment::Environment;
use crate::error::EnvError;
use crate::numerics::Profile;
use crate::render::{Frame, RenderMode};

/// A joint action (every actuator, in the model's order) as the policy gives it: float64, or
/// float32 (action costs then computed in float32, as numpy computes them for a float32 policy).
#[derive(Clone, Copy, Debug)]
pub enum JointAction<'a> {
    /// A float64 action.
    F64(&'a [f64]),
    /// A float32 action.
    F32(&'a [f32]),
}

impl JointAction<'_> {
    /// The number of entries.
    pub fn len(&self) -> usize {
        match self {
            JointAction::F64(a) => a.len(),
            JointAction::F32(a) => a.len(),
        }
    }
    /// Whether the action has no entries.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Entry `i` as float64 (a float32 converts exactly).
    pub fn get(&self, i: usize) -> f64 {
        match self {
            JointAction::F64(a) => a[i],
            JointAction::F32(a) => f64::from(a[i]),
        }
    }
}

/// What every kind's step reports: the (shared) reward and the episode flags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointStep {
    /// The step's reward (every agent's, for a multi-agent env).
    pub reward: f64,
    /// Whether the episode ended in a terminal state.
    pub terminated: bool,
    /// Whether the time limit cut the episode short.
    pub truncated: bool,
}

/// An env of any kind, stepped with a joint action. Implementors give the kind, the id, the
/// single-agent env that steps the physics, a fallible reset and a joint step; the rest is
/// provided from the physics env and may be overridden where a kind differs (a maze's own time
/// limit). Object safe: `&mut dyn JointEnv` drives any kind.
pub trait JointEnv {
    /// Task, maze or multi-agent.
    fn kind(&self) -> Kind;
    /// The spec's id (a multi-agent spec: its own, not its task's).
    fn id(&self) -> &str;
    /// The single-agent env that steps the physics: the task itself, a maze's robot in its
    /// world, a multi-agent spec's factorized task.
    fn physics_env(&self) -> &Env;
    /// The physics env, mutably.
    fn physics_env_mut(&mut self) -> &mut Env;
    /// Gymnasium `reset(seed=...)`: a seed restarts the RNG stream, `None` continues it. A reset
    /// that found no valid start is the error (E1104, or a MuJoCo error), and `step` refuses
    /// until a reset succeeds.
    fn try_reset(&mut self, seed: Option<u64>) -> Result<(), EnvError>;
    /// One step with a joint action (a multi-agent spec: every agent's actions in global order).
    fn step_joint(&mut self, action: JointAction<'_>) -> Result<JointStep, EnvError>;
    /// After a failure: `step` refuses (E1103) until the next `reset`.
    fn require_reset(&mut self);

    /// The joint action's space.
    fn action_space(&self) -> &BoxSpace {
        self.physics_env().action_space()
    }
    /// The joint action's length.
    fn act_dim(&self) -> usize {
        self.action_space().dim()
    }
    /// `timestep × frame_skip` of the compiled model.
    fn dt(&self) -> f64 {
        self.physics_env().dt()
    }
    /// The episode limit (`TimeLimit`), if any.
    fn max_episode_steps(&self) -> Option<u64> {
        self.physics_env().spec().max_episode_steps
    }
    /// The numerics profile the env computes under (stored in datasets it records).
    fn numerics(&self) -> Profile {
        self.physics_env().numerics()
    }
    /// Compute as the reference does under `profile` from now on (e.g. a recording's profile).
    fn set_numerics(&mut self, profile: Profile) {
        self.physics_env_mut().set_numerics(profile);
    }
    /// MuJoCo warnings captured so far.
    fn warnings(&self) -> &[String] {
        self.physics_env().warnings()
    }
    /// A frame in a Gymnasium render mode (docs/rendering.md); the renderer is made on first use.
    fn render(&mut self, mode: RenderMode) -> Result<Frame<'_>, EnvError> {
        self.physics_env_mut().render(mode)
    }
    /// Gymnasium's `close()`: free the renderer (rendering again makes a new one).
    fn close(&mut self) {
        self.physics_env_mut().close_renderer();
    }
}

/// The one action check of every kind, before anything moves: a reset first (`not_reset` says
/// why there is none: E1103, or the failed reset's error), then the length, then finite values.
pub(crate) fn check_action(
    id: &str,
    expected: usize,
    action: JointAction<'_>,
    not_reset: impl FnOnce() -> Option<EnvError>,
) -> Result<(), EnvError> {
    if let Some(e) = not_reset() {
        return Err(e);
    }
    if action.len() != expected {
        return Err(EnvError::ActionLength {
            env: id.to_string(),
            expected,
            got: action.len(),
        });
    }
    if let Some(index) = (0..action.len()).find(|&i| !action.get(i).is_finite()) {
        return Err(EnvError::NonFiniteAction {
            index,
            value: action.get(index),
        });
    }
    Ok(())
}

/// The physics env's reset error, if its last reset found no valid start.
pub(crate) fn reset_result(env: &Env) -> Result<(), EnvError> {
    env.reset_error().map_or(Ok(()), Err)
}

/// Every task env, dynamic or typed (through [`Environment`]).
impl<E: Environment> JointEnv for E {
    fn kind(&self) -> Kind {
        Kind::Task
    }
    fn id(&self) -> &str {
        &self.env().spec().id
    }
    fn physics_env(&self) -> &Env {
        self.env()
    }
    fn physics_env_mut(&mut self) -> &mut Env {
        self.env_mut()
    }
    fn try_reset(&mut self, seed: Option<u64>) -> Result<(), EnvError> {
        self.env_mut().reset(seed);
        reset_result(self.env())
    }
    fn step_joint(&mut self, action: JointAction<'_>) -> Result<JointStep, EnvError> {
        let s = match action {
            JointAction::F64(a) => self.env_mut().step(a)?,
            JointAction::F32(a) => self.env_mut().step_f32(a)?,
        };
        Ok(JointStep {
            reward: s.reward,
            terminated: s.terminated,
            truncated: s.truncated,
        })
    }
    fn require_reset(&mut self) {
        self.env_mut().require_reset();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_action_refuses_in_order_not_reset_length_non_finite() {
        let ok = JointAction::F64(&[0.0, 1.0]);
        let not_reset = check_action("E", 2, ok, || Some(EnvError::NotReset));
        assert!(matches!(not_reset, Err(EnvError::NotReset)));
        let short = check_action("E", 3, JointAction::F64(&[f64::NAN]), || None);
        assert!(matches!(
            short,
            Err(EnvError::ActionLength {
                expected: 3,
                got: 1,
                ..
            })
        ));
        let nan = check_action("E", 2, JointAction::F32(&[0.5, f32::INFINITY]), || None);
        assert!(matches!(
            nan,
            Err(EnvError::NonFiniteAction { index: 1, value }) if value == f64::INFINITY
        ));
        assert!(check_action("E", 2, ok, || None).is_ok());
    }

    #[test]
    fn a_float32_action_reads_as_its_exact_float64() {
        let a = JointAction::F32(&[0.1, -3.0]);
        assert_eq!((a.len(), a.get(0), a.get(1)), (2, f64::from(0.1f32), -3.0));
    }
}
