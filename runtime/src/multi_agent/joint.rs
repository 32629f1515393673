//! The multi-agent kind's [`JointEnv`]: the joint action of every agent steps the one robot.

use envspec::Kind;

use super::MultiAgentEnv;
use crate::env::Env;
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv, JointStep, reset_result};
use crate::render::{Frame, RenderMode};

impl JointEnv for MultiAgentEnv {
    fn kind(&self) -> Kind {
        Kind::MultiAgent
    }
    fn id(&self) -> &str {
        &self.spec().id
    }
    fn physics_env(&self) -> &Env {
        self.env()
    }
    fn physics_env_mut(&mut self) -> &mut Env {
        self.env_mut()
    }
    fn try_reset(&mut self, seed: Option<u64>) -> Result<(), EnvError> {
        self.reset(seed);
        reset_result(self.env())
    }
    fn step_joint(&mut self, action: JointAction<'_>) -> Result<JointStep, EnvError> {
        let s = match action {
            JointAction::F64(a) => self.step_global(a)?,
            JointAction::F32(a) => self.step_global_f32(a)?,
        };
        Ok(JointStep {
            reward: s.reward,
            terminated: s.terminated,
            truncated: s.truncated,
        })
    }
    fn require_reset(&mut self) {
        MultiAgentEnv::require_reset(self);
    }
    /// The whole robot, each agent's limbs in its colour when `color_agents` is on.
    fn render(&mut self, mode: RenderMode) -> Result<Frame<'_>, EnvError> {
        MultiAgentEnv::render(self, mode)
    }
}
