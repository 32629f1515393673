//! The env core: executes a [`ResolvedSpec`] over MuJoCo with Gymnasium semantics.
//!
//! `reset(seed)`: reseed (or continue the stream) → `mj_resetData` → reset draws in spec order →
//! write qpos/qvel → `mj_forward` → observation and reset info.
//! `step(action)`: action latency (`latency`: the action given N steps ago) → read "before"
//! values → ctrl = action → `frame_skip × mj_step` →
//! `mj_rnePostConstraint` when contact forces are read → health, reward terms, observation
//! (noise and delay: `obs_noise`, also at reset), info,
//! termination (health and `[termination.*]`), TimeLimit truncation. Goal terms read the env-held
//! goal vector (`goal_mut`) where they say `desired = "goal"`. No `mj_forward` after stepping: derived quantities are "lagged", exactly
//! as in the reference. Nothing allocates after construction.
//!
//! One file per concern: `build` (construction and model checks), `sim` (the simulation and its
//! field readers), `reset`, `step`, `reward` (terms and sums), `health`, `info`, `state` (reading,
//! setting and deriving from the state) and `footprint` (memory).

use std::sync::Arc;

use envspec::ir::*;
use envspec::{ResolvedSpec, Selection};
use mujoco_rs::prelude::{MjData, MjModel};

use crate::error::EnvError;
use crate::numerics::Profile;
use crate::rng::NumpyRng;

mod build;
mod footprint;
mod health;
mod info;
mod reset;
mod reward;
mod sim;
mod state;
mod step;

pub use build::compile;
pub use footprint::Footprint;
pub use health::Unhealthy;
pub use info::Info;

use info::InfoSlot;
use reset::ResetFailure;
use sim::Sim;

/// A box space: per-element bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct BoxSpace {
    /// Lower bounds, one per element (`-inf` where unbounded).
    pub low: Vec<f64>,
    /// Upper bounds, one per element (`inf` where unbounded).
    pub high: Vec<f64>,
}

impl BoxSpace {
    /// The number of elements.
    pub fn dim(&self) -> usize {
        self.low.len()
    }
    /// Whether `x` has the space's size and lies within its bounds.
    pub fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.low.len()
            && x.iter()
                .zip(&self.low)
                .zip(&self.high)
                .all(|((v, l), h)| l <= v && v <= h)
    }
}

/// What `step` returns; borrows the env's buffers (no allocation per step).
#[derive(Clone, Copy, Debug)]
pub struct Step<'a> {
    /// The observation after the step.
    pub obs: &'a [f64],
    /// The step's reward (the spec's reward sum).
    pub reward: f64,
    /// Whether the episode ended in a terminal state (unhealthy, or a `[termination.*]` rule).
    pub terminated: bool,
    /// Whether the time limit cut the episode short.
    pub truncated: bool,
    /// The step's info dict.
    pub info: Info<'a>,
}

/// An environment built from a spec.
pub struct Env {
    spec: Arc<ResolvedSpec>,
    sim: Sim,
    rng: Option<NumpyRng>,
    dt: f64,
    timestep: f64,
    uses_mass_center: bool,
    /// A source reads `subtree_linvel` or `subtree_angmom` (`mj_subtreeVel` after the physics).
    uses_subtree: bool,
    /// One scalar source per velocity term / velocity info entry.
    velocity_sources: Vec<Selection>,
    before: Vec<f64>,
    term_slot: Vec<Option<usize>>,
    info_slot: Vec<Option<usize>>,
    /// Signed term values, then (at `reward.len() + i`) the signed values computed with weight 1
    /// for the terms an `unweighted` info entry reports.
    term_values: Vec<f64>,
    /// Per term: whether its weight-1 value is needed.
    unweighted_terms: Vec<bool>,
    obs: Vec<f64>,
    step_info: Vec<InfoSlot>,
    step_info_values: Vec<f64>,
    reset_info: Vec<InfoSlot>,
    reset_info_values: Vec<f64>,
    qpos_init: Vec<f64>,
    qvel_init: Vec<f64>,
    draw: Vec<f64>,
    /// Where the terrain tiles' spawn origins are in the model's `numeric_data` (address, count
    /// of tiles): `[terrain]` puts them there (`model_build::TERRAIN_ORIGINS`).
    terrain_origins: Option<(usize, usize)>,
    elapsed: u64,
    has_reset: bool,
    /// Why the last reset gave no valid start (E1104, E1004): `step` refuses until a reset
    /// succeeds.
    reset_failure: Option<ResetFailure>,
    /// The current step's action came as float32 (numpy then computes action costs in float32).
    action_f32: bool,
    warnings: Vec<String>,
    observation_space: BoxSpace,
    action_space: BoxSpace,
    /// Rendering settings and the renderer, made on the first frame: an env never rendered
    /// never opens a GL context.
    render: crate::render::EnvRender,
    /// Observation noise and delay (None: the spec declares neither).
    obs_noise: Option<crate::obs_noise::ObsNoise>,
    /// Action latency (None: none declared).
    latency: Option<crate::latency::ActionLatency>,
    /// `[events]` (None: the spec has none and nothing is drawn for them).
    events: Option<crate::events::Events>,
}

impl Env {
    /// The resolved spec this env runs.
    pub fn spec(&self) -> &Arc<ResolvedSpec> {
        &self.spec
    }
    /// After a failure the env's state cannot be trusted: `step` refuses (E1103) until the next
    /// `reset`.
    pub fn require_reset(&mut self) {
        self.has_reset = false;
    }
    /// The compiled model, shared by every env built from it.
    pub fn model(&self) -> &Arc<MjModel> {
        &self.sim.model
    }
    /// Render the current state as Gymnasium's `render()` does with this `render_mode`; the
    /// renderer is made on the first call (docs/rendering.md).
    pub fn render(
        &mut self,
        mode: crate::render::RenderMode,
    ) -> Result<crate::render::Frame<'_>, EnvError> {
        // `[goal] marker_site`: the reference's render callback, which also leaves the data
        // forwarded (what the next step's end-effector action reads).
        if self.sim.manip.renders_marker_site()
            && let Err(message) = self
                .sim
                .manip
                .render_marker_site(&self.sim.goal, &mut self.sim.data)
        {
            self.has_reset = false;
            return Err(EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in a render's mj_forward (reset before stepping again)",
                message,
            });
        }
        self.render_with(mode, |_| {})
    }
    /// `render` after `prep` adjusts visual-only state (a maze's goal marker).
    pub(crate) fn render_with(
        &mut self,
        mode: crate::render::RenderMode,
        prep: impl FnOnce(&mut MjData<Arc<MjModel>>),
    ) -> Result<crate::render::Frame<'_>, EnvError> {
        prep(&mut self.sim.data);
        Ok(self
            .render
            .frame_of(&self.sim.model, &mut self.sim.data, mode)?)
    }
    /// Draw geom `g` in `tint[g]` where given, in every later frame (empty: the model's own
    /// colours). Visual only: the model, shared with other envs, is not changed.
    pub fn set_render_tint(&mut self, tint: Vec<Option<[f32; 4]>>) {
        self.render.set_tint(tint);
    }
    /// Free the renderer (Gymnasium's `close()`); rendering again makes a new one.
    pub fn close_renderer(&mut self) {
        self.render.close();
    }
    /// The observation space (unbounded, as Gymnasium's MuJoCo envs declare it).
    pub fn observation_space(&self) -> &BoxSpace {
        &self.observation_space
    }
    /// The action space: the actuators' control ranges in float32, or `[actions]`'s range.
    pub fn action_space(&self) -> &BoxSpace {
        &self.action_space
    }
    /// The observation's length.
    pub fn obs_dim(&self) -> usize {
        self.spec.obs_dim
    }
    /// The action's length (the model's actuator count).
    pub fn act_dim(&self) -> usize {
        self.sim.action.len()
    }
    /// `timestep × frame_skip` of the compiled model.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Steps taken since the last reset.
    pub fn elapsed_steps(&self) -> u64 {
        self.elapsed
    }
    /// The numerics profile this env's CPU-dependent reductions follow (see `envc::numerics`).
    pub fn numerics(&self) -> Profile {
        self.sim.numerics
    }
    /// Compute as the reference does under `profile` from now on (e.g. a recording's profile).
    pub fn set_numerics(&mut self, profile: Profile) {
        self.sim.numerics = profile;
    }
    /// `[goal]`: the achieved goal now (what the observation dict reports as `achieved_goal`).
    /// Empty for an env without `[goal]`.
    pub fn achieved_goal(&self, out: &mut Vec<f64>) {
        out.clear();
        if let Some(g) = &self.spec.manipulation.goal {
            out.extend((0..g.achieved.len()).map(|k| self.sim.get(&g.achieved, k)));
        }
    }
    /// [`Env::achieved_goal`] written into `out` (`spec().goal_dim` entries: a vector env's
    /// batch row), allocating nothing; `out` is left as it is for an env without `[goal]`.
    pub fn write_achieved_goal(&self, out: &mut [f64]) {
        if let Some(g) = &self.spec.manipulation.goal {
            for (k, x) in out.iter_mut().enumerate().take(g.achieved.len()) {
                *x = self.sim.get(&g.achieved, k);
            }
        }
    }
    /// MuJoCo warnings raised while loading or running this env (never printed or logged to a file).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
    /// Forget the warnings collected so far (after the caller has reported them).
    pub fn clear_warnings(&mut self) {
        self.warnings.clear();
    }
    /// The current observation (after the last reset or step).
    pub fn obs(&self) -> &[f64] {
        &self.obs
    }
    /// The env-held goal vector that goal terms with `desired = "goal"` read (`spec().goal_dim`
    /// entries, zero until set).
    pub fn goal(&self) -> &[f64] {
        &self.sim.goal
    }
    /// Set the goal vector (e.g. at every reset, or when an outer env changes the goal).
    pub fn goal_mut(&mut self) -> &mut [f64] {
        &mut self.sim.goal
    }
    /// Whether the current state reaches the goal under `c` (a `goal_reached` check).
    pub fn goal_reached(&self, c: &GoalCheck) -> bool {
        self.sim.goal_reached(c)
    }
    /// The `init_qpos` resets start from (Gymnasium's `env.init_qpos`; a maze moves its xy).
    pub(crate) fn init_qpos_mut(&mut self) -> &mut [f64] {
        &mut self.qpos_init
    }
}
