//! The one door of the runtime: [`open`] builds the env of any spec kind, [`AnyEnv`] says which
//! one it is and offers what every kind shares (spaces of the joint action, time step, episode
//! limit, numerics, warnings, and a joint-action step for commands such as `run` and `bench`).
//! Kind-specific work (`rollout`'s files, `show`) matches on the variant once.

use envspec::{AnySpec, Kind, Override};

use crate::env::{BoxSpace, Env};
use crate::error::EnvError;
use crate::maze::MazeEnv;
use crate::multi_agent::MultiAgentEnv;
use crate::numerics::Profile;

/// An env of any kind.
pub enum AnyEnv {
    Task(Env),
    Maze(Box<MazeEnv>),
    Agents(MultiAgentEnv),
}

/// What every kind's step reports: the (shared) reward and the episode flags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointStep {
    pub reward: f64,
    pub terminated: bool,
    pub truncated: bool,
}

/// Open a bundled id or a spec file of any kind (see `envspec::open`) and build its env.
///
/// ```no_run
/// let env = envc::open("PointMaze_UMaze-v3", &[])?;
/// assert_eq!(env.kind(), envc::Kind::Maze);
/// # Ok::<(), envc::EnvError>(())
/// ```
pub fn open(id_or_path: &str, overrides: &[Override]) -> Result<AnyEnv, EnvError> {
    AnyEnv::new(envspec::open(id_or_path, overrides)?)
}

impl AnyEnv {
    pub fn new(spec: AnySpec) -> Result<AnyEnv, EnvError> {
        Ok(match spec {
            AnySpec::Task(s) => AnyEnv::Task(Env::new(std::sync::Arc::new(*s))?),
            AnySpec::Maze(s) => AnyEnv::Maze(Box::new(MazeEnv::new(*s)?)),
            AnySpec::Agents(s) => AnyEnv::Agents(MultiAgentEnv::new(std::sync::Arc::new(*s))?),
        })
    }

    pub fn kind(&self) -> Kind {
        match self {
            AnyEnv::Task(_) => Kind::Task,
            AnyEnv::Maze(_) => Kind::Maze,
            AnyEnv::Agents(_) => Kind::Agents,
        }
    }

    pub fn id(&self) -> &str {
        match self {
            AnyEnv::Task(e) => &e.spec().id,
            AnyEnv::Maze(e) => e.id(),
            AnyEnv::Agents(e) => &e.spec().id,
        }
    }

    /// The single-agent env that steps the physics (a maze's robot in its world, the
    /// factorized task of a multi-agent spec).
    pub fn physics_env(&self) -> &Env {
        match self {
            AnyEnv::Task(e) => e,
            AnyEnv::Maze(e) => e.robot(),
            AnyEnv::Agents(e) => e.env(),
        }
    }

    /// Render a frame of any kind of env: a task, a maze with its goal marker, a multi-agent
    /// spec's whole robot.
    pub fn render(
        &mut self,
        mode: crate::render::RenderMode,
    ) -> Result<crate::render::Frame<'_>, EnvError> {
        match self {
            AnyEnv::Task(e) => e.render(mode),
            AnyEnv::Maze(e) => e.render(mode),
            AnyEnv::Agents(e) => e.render(mode),
        }
    }

    /// The joint action's space (a multi-agent spec: every agent's actions in global order).
    pub fn action_space(&self) -> &BoxSpace {
        match self {
            AnyEnv::Maze(e) => e.action_space(),
            _ => self.physics_env().action_space(),
        }
    }

    pub fn act_dim(&self) -> usize {
        self.action_space().dim()
    }

    pub fn dt(&self) -> f64 {
        self.physics_env().dt()
    }

    /// The episode limit (`TimeLimit`), if any.
    pub fn max_episode_steps(&self) -> Option<u64> {
        match self {
            AnyEnv::Maze(e) => e.max_episode_steps(),
            _ => self.physics_env().spec().max_episode_steps,
        }
    }

    pub fn numerics(&self) -> Profile {
        self.physics_env().numerics()
    }

    pub fn set_numerics(&mut self, profile: Profile) {
        match self {
            AnyEnv::Task(e) => e.set_numerics(profile),
            AnyEnv::Maze(e) => e.set_numerics(profile),
            AnyEnv::Agents(e) => e.set_numerics(profile),
        }
    }

    /// MuJoCo warnings captured so far.
    pub fn warnings(&self) -> &[String] {
        self.physics_env().warnings()
    }

    /// `reset(seed)` of whichever kind this is.
    pub fn reset(&mut self, seed: Option<u64>) -> Result<(), EnvError> {
        match self {
            AnyEnv::Task(e) => {
                e.reset(seed);
            }
            AnyEnv::Maze(e) => {
                e.reset(seed, None)?;
            }
            AnyEnv::Agents(e) => {
                e.reset(seed);
            }
        }
        match self.physics_env().reset_error() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// One step with a joint action (float64).
    pub fn step(&mut self, action: &[f64]) -> Result<JointStep, EnvError> {
        let (reward, terminated, truncated) = match self {
            AnyEnv::Task(e) => {
                let s = e.step(action)?;
                (s.reward, s.terminated, s.truncated)
            }
            AnyEnv::Maze(e) => {
                let s = e.step(action)?;
                (s.reward, s.terminated, s.truncated)
            }
            AnyEnv::Agents(e) => {
                let s = e.step_global(action)?;
                (s.reward, s.terminated, s.truncated)
            }
        };
        Ok(JointStep {
            reward,
            terminated,
            truncated,
        })
    }
}
