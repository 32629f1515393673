//! The resolved spec (the IR): every name turned into indices, every parameter reference into its
//! value, sizes and the observation layout computed. The runtime executes exactly this; the code
//! generator and `envc show` describe exactly this.

mod added;
mod goal;
mod health;
mod info;
mod model_edits;
mod observation;
mod physics;
mod reset;
mod reward;
mod terrain;

use std::path::PathBuf;

pub use crate::conditions::CmpOp;
pub use added::{ActuatorKind, AddedActuator, AddedElement, AddedGeomType};
pub use goal::{Desired, GoalCheck, GoalDistance, GoalNorm};
pub use health::{CheckKind, HealthCheck, Termination};
pub use info::{InfoItem, InfoKind, PartSet};
pub use model_edits::{GeomEdit, JointEdit, JointRow, ModelEdits, SpecKeyframe};
pub use observation::{Apply, Segment};
pub use physics::{Integrator, SOLVER_OPTIONS, SolverOption};
pub use reset::{Distribution, Meet, ResetStep, Rotation, Settle, Until};
pub use reward::{Divisor, RewardTerm, SumNode, TermKind};
pub use terrain::{Terrain, TerrainTile, TileKind};

pub use crate::commands::{
    ActionKind, Command, DefaultPose, FeetContact, Gate, LeggedTerm, PdActions, PositionDelta,
};
pub use crate::conditions::{Condition, Indicator, Quantity};
use crate::mjcf::ModelInfo;
use crate::params::{Param, ParamValue};
use crate::selector::{Field, Selection};

/// A spec resolved against its model: what the runtime executes, `envc show` prints and
/// `envc diff` compares.
#[derive(Clone, Debug)]
pub struct ResolvedSpec {
    /// `[env] id`, e.g. `Ant-v5`.
    pub id: String,
    /// `[env] description`.
    pub description: String,
    /// The spec file it was read from.
    pub spec_path: PathBuf,
    /// Every file read to make it (the spec first, then its model, includes, meshes), with the
    /// hash of the bytes read: what a dataset records of the spec that made it. Empty for a spec
    /// not opened from files (a typed env's embedded spec).
    pub inputs: Vec<crate::source::FileRead>,
    /// `[env] reward_threshold` (Gymnasium's `EnvSpec.reward_threshold`).
    pub reward_threshold: Option<f64>,
    /// The Python class that builds the same env (`[env] entry_point`, `module.path:Class`);
    /// dataset metadata names it so Python can recover the env.
    pub entry_point: Option<String>,
    /// Every parameter with its final value.
    pub params: Vec<Param>,
    /// The model file (absolute or relative to the current directory).
    pub model_path: PathBuf,
    /// Names and numbering of the model, the spec's additions included.
    pub model: ModelInfo,
    /// Physics steps per env step.
    pub frame_skip: u32,
    /// None: no time limit.
    pub max_episode_steps: Option<u64>,
    /// The enabled observation segments, in order.
    pub observation: Vec<Segment>,
    /// Length of the observation.
    pub obs_dim: usize,
    /// The enabled reward terms (terms switched off by `when` are left out, also from the sum).
    pub reward: Vec<RewardTerm>,
    /// How term values are added up (the grouping decides the last bit).
    pub reward_sum: SumNode,
    /// The health checks; the env is healthy when every one passes.
    pub health: Vec<HealthCheck>,
    /// Whether an unhealthy state ends the episode.
    pub terminate_when_unhealthy: bool,
    /// Conditions that end the episode when they hold (`[termination.*]`), beside health.
    pub termination: Vec<Termination>,
    /// Length of the env-held goal vector that goal terms with `desired = "goal"` read (0: none).
    pub goal_dim: usize,
    /// Applied in order at reset (the order is the RNG draw order).
    pub reset: Vec<ResetStep>,
    /// Info entries in order (switched-off entries left out); reward terms with an `info` key come
    /// after the `[info]` entries.
    pub info: Vec<InfoItem>,
    /// Whether `mj_rnePostConstraint` must run after the physics steps (contact forces are read).
    pub needs_rne_post_constraint: bool,
    /// Actuators and options added to the model at load time (`[actuators]`, `[physics]`); they
    /// are already accounted for in `model` (its actuators and timestep).
    pub model_edits: ModelEdits,
    /// `[commands.*]` in declared order (the draw order); their components are the env's
    /// command buffer (`command_dim` entries).
    pub commands: Vec<Command>,
    /// Total length of the command buffer.
    pub command_dim: usize,
    /// `[derived.*]` in document order (the order they are computed in).
    pub derived: Vec<crate::derived::Derived>,
    /// Total length of the derived buffer (`derived[...]` reads it).
    pub derived_dim: usize,
    /// `[actions]`: PD position targets (None: `ctrl = action`).
    pub actions: Option<PdActions>,
    /// Observation noise and delay, action latency (`envspec::noise`; empty: none declared).
    pub corruption: crate::noise::Corruption,
    /// `[events.*]` in spec order (domain randomization and pushes; empty: nothing is drawn).
    pub events: Vec<crate::events::Event>,
    /// What the spec may not mean (`warning[W…]`): printed by `envc check`, never fatal.
    pub warnings: Vec<crate::diagnostic::Diagnostic>,
    /// `[init]`, `[end_effector]`, `[hold.*]`, `[goal]` (`envspec::manipulation`).
    pub manipulation: crate::manipulation::Manipulation,
}

impl ResolvedSpec {
    /// The final value of parameter `name`.
    pub fn param(&self, name: &str) -> Option<&ParamValue> {
        self.params
            .iter()
            .find(|p| p.name == name)
            .map(|p| &p.value)
    }
    /// Length of the action: the model's actuators, the spec's included; with
    /// `[end_effector]`, its Cartesian action.
    pub fn act_dim(&self) -> usize {
        match &self.manipulation.end_effector {
            Some(e) => e.act_dim(),
            None => self.model.nu(),
        }
    }
    /// `timestep × frame_skip`, as Gymnasium computes it (from the XML timestep).
    pub fn dt(&self) -> f64 {
        self.model.timestep * self.frame_skip as f64
    }
    /// Names of the observation elements, in order.
    pub fn obs_names(&self) -> Vec<String> {
        self.observation
            .iter()
            .flat_map(|s| s.element_names())
            .collect()
    }
    /// Info entries present after `reset` (no velocities, no reward terms).
    pub fn reset_info(&self) -> impl Iterator<Item = &InfoItem> {
        self.info.iter().filter(|i| i.at_reset)
    }
    /// Every selection the env reads from the simulation (observation, reward terms, health
    /// checks, info), in spec order. Reset targets are written, not read, so they are not here.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        let obs = self.observation.iter().flat_map(Segment::sources);
        let terms = self.reward.iter().flat_map(|t| {
            let gates = t
                .only_if
                .iter()
                .chain(&t.unless)
                .flat_map(|c| c.quantity.sources());
            t.kind.sources().chain(gates)
        });
        let health = self.health.iter().flat_map(|h| &h.sources);
        let info = self.info.iter().flat_map(|i| i.kind.sources());
        let termination = self
            .termination
            .iter()
            .flat_map(|t| t.reached.distance.sources());
        let achieved = self.manipulation.goal.iter().map(|g| &g.achieved);
        let derived = self.derived.iter().flat_map(|d| d.sources());
        obs.chain(terms)
            .chain(health)
            .chain(info)
            .chain(termination)
            .chain(achieved)
            .chain(derived)
    }
    /// Whether anything the env computes reads `field`.
    pub fn reads(&self, field: Field) -> bool {
        self.sources().any(|s| s.field == field)
    }
}

/// One of two iterators over the selections a term reads (a plain term's one or two, or a goal
/// distance's), so `sources` allocates nothing.
enum Either<'a, A, B> {
    Pair(A),
    Goal(B),
    Many(std::vec::IntoIter<&'a Selection>),
}

impl<'a, A: Iterator<Item = &'a Selection>, B: Iterator<Item = &'a Selection>> Iterator
    for Either<'a, A, B>
{
    type Item = &'a Selection;
    fn next(&mut self) -> Option<&'a Selection> {
        match self {
            Either::Pair(a) => a.next(),
            Either::Goal(b) => b.next(),
            Either::Many(m) => m.next(),
        }
    }
}
