//! The maze kind's [`JointEnv`]: its robot steps the physics, the maze keeps its own time limit
//! and renders its world with the goal marker.

use envspec::Kind;

use super::MazeEnv;
use crate::env::Env;
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv, JointStep, reset_result};
use crate::render::{Frame, RenderMode};

impl JointEnv for MazeEnv {
    fn kind(&self) -> Kind {
        Kind::Maze
    }
    fn id(&self) -> &str {
        MazeEnv::id(self)
    }
    fn physics_env(&self) -> &Env {
        self.robot()
    }
    fn physics_env_mut(&mut self) -> &mut Env {
        self.robot_mut()
    }
    fn try_reset(&mut self, seed: Option<u64>) -> Result<(), EnvError> {
        self.reset(seed, None)?;
        reset_result(self.robot())
    }
    fn step_joint(&mut self, action: JointAction<'_>) -> Result<JointStep, EnvError> {
        let s = match action {
            JointAction::F64(a) => self.step(a)?,
            JointAction::F32(a) => self.step_f32(a)?,
        };
        Ok(JointStep {
            reward: s.reward,
            terminated: s.terminated,
            truncated: s.truncated,
        })
    }
    fn require_reset(&mut self) {
        MazeEnv::require_reset(self);
    }
    /// The maze's own time limit (its robot's is not used).
    fn max_episode_steps(&self) -> Option<u64> {
        MazeEnv::max_episode_steps(self)
    }
    /// The maze world with its goal marker.
    fn render(&mut self, mode: RenderMode) -> Result<Frame<'_>, EnvError> {
        MazeEnv::render(self, mode)
    }
}
