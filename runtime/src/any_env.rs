//! The one door of the runtime: [`open`] builds the env of any spec kind, [`AnyEnv`] says which
//! one it is. What every kind shares is [`JointEnv`], which `AnyEnv` implements by handing each
//! call to its variant; kind-specific work (`rollout`'s files, `show`) matches on the variant once.

use envspec::{AnySpec, Kind, Override};

use crate::env::Env;
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv, JointStep};
use crate::maze::MazeEnv;
use crate::multi_agent::MultiAgentEnv;
use crate::numerics::Profile;
use crate::render::{Frame, RenderMode};

/// An env of any kind.
pub enum AnyEnv {
    /// A single-agent task (a Gymnasium MuJoCo env or a spec of one robot).
    Task(Env),
    /// A goal-conditioned maze env (boxed: much larger than the others).
    Maze(Box<MazeEnv>),
    /// A multi-agent (MaMuJoCo) env.
    MultiAgent(MultiAgentEnv),
}

/// Open a bundled id or a spec file of any kind (see `envspec::open`) and build its env.
///
/// ```no_run
/// use envc::JointEnv;
/// let env = envc::open("PointMaze_UMaze-v3", &[])?;
/// assert_eq!(env.kind(), envc::Kind::Maze);
/// # Ok::<(), envc::EnvError>(())
/// ```
pub fn open(id_or_path: &str, overrides: &[Override]) -> Result<AnyEnv, EnvError> {
    AnyEnv::new(envspec::open(id_or_path, overrides)?)
}

impl AnyEnv {
    /// Build the env of a resolved spec of any kind.
    pub fn new(spec: AnySpec) -> Result<AnyEnv, EnvError> {
        Ok(match spec {
            AnySpec::Task(s) => AnyEnv::Task(Env::new(std::sync::Arc::new(*s))?),
            AnySpec::Maze(s) => AnyEnv::Maze(Box::new(MazeEnv::new(*s)?)),
            AnySpec::MultiAgent(s) => {
                AnyEnv::MultiAgent(MultiAgentEnv::new(std::sync::Arc::new(*s))?)
            }
        })
    }

    /// The variant as the trait every kind implements.
    pub fn as_joint(&self) -> &dyn JointEnv {
        match self {
            AnyEnv::Task(e) => e,
            AnyEnv::Maze(e) => &**e,
            AnyEnv::MultiAgent(e) => e,
        }
    }
    /// The variant as the trait every kind implements, mutably.
    pub fn as_joint_mut(&mut self) -> &mut dyn JointEnv {
        match self {
            AnyEnv::Task(e) => e,
            AnyEnv::Maze(e) => &mut **e,
            AnyEnv::MultiAgent(e) => e,
        }
    }
}

/// Every call goes to the variant, so a kind's own answer (a maze's time limit, its goal marker
/// in frames) holds through `AnyEnv` too.
impl JointEnv for AnyEnv {
    fn kind(&self) -> Kind {
        self.as_joint().kind()
    }
    fn id(&self) -> &str {
        self.as_joint().id()
    }
    fn physics_env(&self) -> &Env {
        self.as_joint().physics_env()
    }
    fn physics_env_mut(&mut self) -> &mut Env {
        self.as_joint_mut().physics_env_mut()
    }
    fn try_reset(&mut self, seed: Option<u64>) -> Result<(), EnvError> {
        self.as_joint_mut().try_reset(seed)
    }
    fn step_joint(&mut self, action: JointAction<'_>) -> Result<JointStep, EnvError> {
        self.as_joint_mut().step_joint(action)
    }
    fn require_reset(&mut self) {
        self.as_joint_mut().require_reset();
    }
    fn action_space(&self) -> &crate::BoxSpace {
        self.as_joint().action_space()
    }
    fn dt(&self) -> f64 {
        self.as_joint().dt()
    }
    fn max_episode_steps(&self) -> Option<u64> {
        self.as_joint().max_episode_steps()
    }
    fn numerics(&self) -> Profile {
        self.as_joint().numerics()
    }
    fn set_numerics(&mut self, profile: Profile) {
        self.as_joint_mut().set_numerics(profile);
    }
    fn warnings(&self) -> &[String] {
        self.as_joint().warnings()
    }
    fn render(&mut self, mode: RenderMode) -> Result<Frame<'_>, EnvError> {
        self.as_joint_mut().render(mode)
    }
    fn close(&mut self) {
        self.as_joint_mut().close();
    }
}
