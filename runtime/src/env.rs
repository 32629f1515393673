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

use std::path::Path;
use std::sync::Arc;

use envspec::ir::*;
use envspec::{Field, Override, ResolvedSpec, Selection};
use mujoco_rs::mujoco_c::mjData;
use mujoco_rs::prelude::{MjData, MjModel};

use crate::error::EnvError;
use crate::mj::log as mujoco_log;
use crate::mj::{self, Call};
use crate::numerics::{Profile, clip, default_profile, norm, pairwise_sum, square_pow};
use crate::rng::NumpyRng;

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

/// Where one info key's values sit in the info buffer.
#[derive(Clone, Debug)]
struct InfoSlot {
    key: String,
    offset: usize,
    len: usize,
}

/// Read-only view of an info dict: keys in spec order, each with one or more f64 values.
#[derive(Clone, Copy, Debug)]
pub struct Info<'a> {
    slots: &'a [InfoSlot],
    values: &'a [f64],
}

impl<'a> Info<'a> {
    /// The values of `key`, or None when the spec declares no such key.
    pub fn get(&self, key: &str) -> Option<&'a [f64]> {
        self.slots
            .iter()
            .find(|s| s.key == key)
            .map(|s| &self.values[s.offset..s.offset + s.len])
    }
    /// The value of a scalar key.
    pub fn scalar(&self, key: &str) -> Option<f64> {
        self.get(key).and_then(|v| (v.len() == 1).then(|| v[0]))
    }
    /// Every key with its values, in spec order.
    pub fn iter(&self) -> impl Iterator<Item = (&'a str, &'a [f64])> + 'a {
        let values = self.values;
        self.slots
            .iter()
            .map(move |s| (s.key.as_str(), &values[s.offset..s.offset + s.len]))
    }
    /// The number of keys.
    pub fn len(&self) -> usize {
        self.slots.len()
    }
    /// Whether the dict has no keys.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }
    /// The keys, in spec order.
    pub fn keys(&self) -> impl Iterator<Item = &'a str> + 'a {
        self.slots.iter().map(|s| s.key.as_str())
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

/// The simulation and the values specs can read from it.
struct Sim {
    model: Arc<MjModel>,
    data: MjData<Arc<MjModel>>,
    action: Vec<f64>,
    mass_center: [f64; 3],
    /// The dense tendon Jacobian (ntendon × nv), kept up to date when the model has tendons.
    ten_j: Vec<f64>,
    /// numpy's pairwise `body_mass.sum()`, computed once.
    mass_sum: f64,
    nq: usize,
    nv: usize,
    nu: usize,
    nsite: usize,
    /// Whose arithmetic the CPU-dependent reductions (norms) follow.
    numerics: Profile,
    /// The env-held goal vector (`desired = "goal"`; `spec.goal_dim` entries).
    goal: Vec<f64>,
    /// The `[derived.*]` values (`spec.derived_dim` entries; `runtime/src/derived.rs`).
    derived: Vec<f64>,
    /// Per `[derived.*]` table, the ids a `contact` table watches.
    contact_ids: Vec<Option<crate::derived::ContactIds>>,
    /// Commands, PD actions and legged-term state (`runtime/src/commands.rs`).
    legged: crate::commands::Legged,
    /// `[init]`, `[end_effector]`, `[hold.*]` and the fields they read
    /// (`runtime/src/manipulation.rs`).
    manip: crate::manipulation::Manip,
}

/// Why a reset gave no valid start.
enum ResetFailure {
    /// The reset step (index) whose `resample_until` went unmet.
    Unmet(usize),
    /// A MuJoCo error (`mju_error`) in `mj_resetData` or `mj_forward`.
    Mujoco(String),
}

impl Sim {
    /// A MuJoCo call on this model and data that may raise `mju_error` (which ends the process
    /// unless caught): the error's message comes back as `Err`, and the data is reset so it is
    /// never used in MuJoCo's mid-error state.
    fn call(&mut self, call: Call) -> Result<(), String> {
        mj::call(&mut self.data, call)
    }

    /// Where every reset starts: the `[init]` time (when the spec has `[init]`), `qpos`, `qvel`.
    fn restart(&mut self, init: bool, qpos0: &[f64], qvel0: &[f64]) {
        if init {
            mj::manip::set_time(&mut self.data, self.manip.init_time);
        }
        let [qpos, qvel, ..] = mj::state::state_mut(&mut self.data);
        qpos.copy_from_slice(qpos0);
        qvel.copy_from_slice(qvel0);
    }

    /// A `settle` reset step: whether its check holds (the records it names are read again).
    fn settle(
        &mut self,
        s: &Settle,
        init: Option<&envspec::manipulation::Init>,
        frame_skip: u32,
    ) -> Result<bool, String> {
        for _ in 0..s.steps {
            let ctrl = self.data.ctrl_mut();
            self.legged.write_ctrl_by(|_| 0.0, ctrl);
            self.call(Call::Step {
                n: frame_skip,
                rne: false,
            })?;
        }
        if let Some((watch, above)) = &s.require {
            self.call(Call::Forward)?;
            self.manip.update(&self.data, self.numerics);
            if self.get(watch, 0).partial_cmp(above) != Some(std::cmp::Ordering::Greater) {
                return Ok(false);
            }
        }
        self.manip.update(&self.data, self.numerics);
        if let Some(init) = init {
            self.manip.refresh_records(init, &self.data, &s.records);
        }
        Ok(true)
    }

    fn m(&self) -> &mujoco_rs::mujoco_c::mjModel {
        self.model.ffi()
    }

    /// The current contents of a field, flattened row-major.
    fn field(&self, f: Field) -> &[f64] {
        let d = &self.data;
        match f {
            Field::Qpos => d.qpos(),
            Field::Qvel => d.qvel(),
            Field::Qpos0 => self.model.qpos0(),
            Field::Action => &self.action,
            Field::Ctrl => d.ctrl(),
            Field::QfrcActuator => d.qfrc_actuator(),
            Field::QfrcConstraint => d.qfrc_constraint(),
            Field::CfrcExt => d.cfrc_ext().as_flattened(),
            Field::CfrcInt => d.cfrc_int().as_flattened(),
            Field::Cacc => d.cacc().as_flattened(),
            Field::Cinert => d.cinert().as_flattened(),
            Field::Cvel => d.cvel().as_flattened(),
            Field::Xpos => d.xpos().as_flattened(),
            Field::Xipos => d.xipos().as_flattened(),
            Field::SiteXpos => d.site_xpos().as_flattened(),
            Field::Xquat => d.xquat().as_flattened(),
            Field::SiteXmat => d.site_xmat().as_flattened(),
            Field::Goal => &self.goal,
            Field::Derived => &self.derived,
            Field::SensorData => d.sensordata(),
            Field::MocapPos => d.mocap_pos().as_flattened(),
            Field::MocapQuat => d.mocap_quat().as_flattened(),
            Field::SiteEuler | Field::SiteXvelp | Field::SiteXvelr | Field::BodyEuler => {
                self.manip.field(f).unwrap_or(&[])
            }
            Field::SubtreeLinvel => d.subtree_linvel().as_flattened(),
            Field::SubtreeAngmom => d.subtree_angmom().as_flattened(),
            Field::TenLength => d.ten_length(),
            Field::TenVelocity => d.ten_velocity(),
            Field::MassCenter => &self.mass_center,
            Field::TenJ => &self.ten_j,
            // One force per actuator (MuJoCo sizes the array by force outputs, at least nu).
            Field::ActuatorForce => {
                let f = d.actuator_force();
                &f[..self.nu.min(f.len())]
            }
            other => self.legged.field(other).unwrap_or(&[]),
        }
    }

    fn get(&self, s: &Selection, k: usize) -> f64 {
        self.field(s.field)[s.indices[k]]
    }

    /// `(achievedₖ, desiredₖ)` of a goal distance.
    fn goal_pair(&self, g: &GoalDistance, k: usize) -> (f64, f64) {
        let a = self.field(g.achieved.field)[g.achieved.indices[k]];
        match &g.desired {
            Desired::Select(d) => (a, self.field(d.field)[d.indices[k]]),
            Desired::Goal => (a, self.goal[k]),
        }
    }

    fn goal_reached(&self, c: &GoalCheck) -> bool {
        crate::goal::reached_by(c, self.numerics, &|k| self.goal_pair(&c.distance, k))
    }

    fn goals_reached(&self, cs: &[GoalCheck]) -> bool {
        crate::goal::all_reached(cs, self.numerics, &|i, k| {
            self.goal_pair(&cs[i].distance, k)
        })
    }

    /// Whether `quantity op value` holds on the current state (`only_if`, `condition` info).
    fn condition_holds(&self, c: &Condition) -> bool {
        let x = match &c.quantity {
            Quantity::Value { source, minus } => {
                let x = self.get(source, 0);
                minus.as_ref().map_or(x, |m| x - self.get(m, 0))
            }
            Quantity::Norm { source, minus } => {
                let f = self.field(source.field);
                match minus {
                    Some(m) => {
                        let g = self.field(m.field);
                        norm(self.numerics, source.len(), &|k| {
                            f[source.indices[k]] - g[m.indices[k]]
                        })
                    }
                    None => norm(self.numerics, source.len(), &|k| f[source.indices[k]]),
                }
            }
        };
        c.holds_for(x)
    }

    /// Expand MuJoCo's sparse `ten_J` (rownnz / rowadr / colind) into `ten_j`.
    fn update_ten_j(&mut self) {
        if self.ten_j.is_empty() {
            return;
        }
        let nv = self.nv;
        let (rownnz, rowadr) = (self.model.ten_j_rownnz(), self.model.ten_j_rowadr());
        let (colind, ten_j) = (self.model.ten_j_colind(), self.data.ten_j());
        self.ten_j.fill(0.0);
        for (r, (&adr, &nnz)) in rowadr.iter().zip(rownnz).enumerate() {
            let (adr, nnz) = (adr as usize, nnz as usize);
            for j in adr..adr + nnz {
                let c = colind[j] as usize;
                if c < nv {
                    self.ten_j[r * nv + c] = ten_j[j];
                }
            }
        }
    }

    /// `einsum("b,bj->j", body_mass, xipos) / body_mass.sum()`: sequential products and sums.
    fn update_mass_center(&mut self) {
        let (mass, xipos) = (self.model.body_mass(), self.data.xipos().as_flattened());
        let mut c = [0.0f64; 3];
        for (b, &mb) in mass.iter().enumerate() {
            for (j, cj) in c.iter_mut().enumerate() {
                *cj += mb * xipos[b * 3 + j];
            }
        }
        self.mass_center = c.map(|x| x / self.mass_sum);
    }
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

/// What one env holds beyond the model it shares, in the two measures a process runs out of:
/// `resident`, the memory it writes (what the machine's available memory must hold), and
/// `mapped`, its address space (what `ulimit -v` counts: MuJoCo maps each env's whole arena,
/// 13 MiB for Hopper, and writes a few hundred KiB of it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// Bytes written: the `mjData` buffer, the arena pages stepping touches, the env's vectors.
    pub resident: u64,
    /// Bytes of address space: as `resident`, with the whole arena.
    pub mapped: u64,
}

/// Per-env bytes beyond the vectors [`Env::footprint`] counts (the struct, small vectors,
/// allocator rounding); measured at about 20 KiB for the Gymnasium suite.
const ENV_OVERHEAD_BYTES: u64 = 32 << 10;
/// Arena bytes counted beyond twice what the probe used (pages, the stack's first frames).
const ARENA_SLACK_BYTES: u64 = 64 << 10;
/// Physics steps the arena probe runs from `qpos0` with zero controls.
const PROBE_STEPS: usize = 50;

/// The most arena and stack bytes `mj_forward` and a few zero-control steps use on a scratch
/// `mjData` of `model` (None when MuJoCo fails: the caller counts the whole arena).
fn arena_in_use(model: &Arc<MjModel>) -> Option<u64> {
    let mut d = mujoco_log::guard(|| MjData::try_new(Arc::clone(model)))
        .ok()?
        .ok()?;
    let probe = (|| {
        mj::call(&mut d, Call::Forward)?;
        for _ in 0..PROBE_STEPS {
            mj::call(&mut d, Call::Step { n: 1, rne: false })?;
        }
        Ok::<(), String>(())
    })();
    // The probe's warnings belong to no env.
    mujoco_log::drain_into(&mut Vec::new());
    probe.ok()?;
    let f = d.ffi();
    Some((f.maxuse_arena as u64).saturating_add(f.maxuse_stack as u64))
}

impl Env {
    /// Load a spec file with parameter overrides and build the env.
    pub fn from_spec_file(path: impl AsRef<Path>, overrides: &[Override]) -> Result<Env, EnvError> {
        let spec = envspec::load(path.as_ref(), overrides)?;
        Env::new(Arc::new(spec))
    }

    /// A bundled env by id (e.g. `"Ant-v5"`) or a spec file path, with overrides.
    pub fn make(id_or_path: &str, overrides: &[Override]) -> Result<Env, EnvError> {
        Env::from_spec_file(crate::registry::find(id_or_path)?, overrides)
    }

    /// Build an env from a resolved spec (compiles the model).
    pub fn new(spec: Arc<ResolvedSpec>) -> Result<Env, EnvError> {
        let model = Arc::new(compile(&spec)?);
        Env::with_model(spec, model)
    }

    /// Build an env sharing an already compiled model (vectorized envs share one).
    pub fn with_model(spec: Arc<ResolvedSpec>, model: Arc<MjModel>) -> Result<Env, EnvError> {
        Env::with_world_model(spec, model, 0)
    }

    /// `with_model` for a model that adds `world_sites` sites to the world body of the spec's
    /// model (a maze's goal marker); everything else must match the spec's model.
    pub(crate) fn with_world_model(
        spec: Arc<ResolvedSpec>,
        model: Arc<MjModel>,
        world_sites: usize,
    ) -> Result<Env, EnvError> {
        mujoco_log::install();
        check_model(&spec, &model, world_sites)?;
        crate::model_values::check(&spec.model_path, &model)?;
        // Randomized model fields are written in the env's own copy; envs sharing the compiled
        // model are unaffected.
        let model = if spec.events.iter().any(envspec::events::Event::writes_model) {
            Arc::new(MjModel::clone(&model))
        } else {
            model
        };
        let events = if spec.events.is_empty() {
            None
        } else {
            Some(crate::events::Events::new(
                &spec.id,
                &spec.events,
                model.ffi(),
            )?)
        };
        // mj_makeData raises mju_error when the allocation fails: guarded, it is an error too.
        let data = crate::mj::log::guard(|| MjData::try_new(Arc::clone(&model)))
            .map_err(|e| e.to_string())
            .and_then(|d| d.map_err(|e| e.to_string()))
            .map_err(|e| EnvError::Compile {
                path: spec.model_path.clone(),
                message: format!("cannot allocate mjData: {e}"),
            })?;
        let numerics = default_profile()?;
        let m = model.ffi();
        let render = crate::render::EnvRender::new(&spec.params, m)?;
        let size = |x: i64| x as usize;
        let mut sim = Sim {
            numerics,
            goal: vec![0.0; spec.goal_dim],
            derived: vec![0.0; spec.derived_dim],
            contact_ids: crate::derived::contact_ids(&spec, model.ffi())?,
            nq: size(m.nq),
            nv: size(m.nv),
            nu: size(m.nu),
            nsite: size(m.nsite),
            action: vec![0.0; spec.act_dim()],
            mass_center: [0.0; 3],
            ten_j: vec![0.0; size(m.ntendon) * size(m.nv)],
            mass_sum: 0.0,
            legged: crate::commands::Legged::new(&spec, &model)?,
            manip: crate::manipulation::Manip::new(&spec, &model)?,
            model: Arc::clone(&model),
            data,
        };
        let mass = model.body_mass();
        sim.mass_sum = pairwise_sum(mass.len(), &|i| mass[i]);
        // A trial `mj_forward` at qpos0, so a model MuJoCo cannot run (its arena too small, say)
        // is refused when the env is built (`check --compile`), not at the first reset. Every
        // reset starts with `mj_resetData`, so nothing of it carries over; its warnings are dropped.
        let mut warnings = vec![];
        mujoco_log::drain_into(&mut warnings);
        let trial = sim.call(Call::Forward);
        mujoco_log::drain_into(&mut vec![]);
        if let Err(message) = trial {
            return Err(EnvError::Mujoco {
                env: spec.id.clone(),
                during: "in a trial mj_forward when building the env",
                message,
            });
        }
        // `[init]`: its end state is where every reset starts.
        let mut qpos_init = model.qpos0().to_vec();
        let mut qvel_init = vec![0.0; sim.nv];
        if let Some(init) = &spec.manipulation.init {
            let numerics = sim.numerics;
            if let Err(message) = sim
                .manip
                .run_init(init, &mut sim.data, spec.frame_skip, numerics)
            {
                return Err(EnvError::Mujoco {
                    env: spec.id.clone(),
                    during: "in [init] when building the env",
                    message,
                });
            }
            qpos_init.copy_from_slice(sim.data.qpos());
            qvel_init.copy_from_slice(sim.data.qvel());
            mujoco_log::drain_into(&mut warnings);
        }
        let timestep = m.opt.timestep;
        let dt = timestep * spec.frame_skip as f64;

        let mut velocity_sources = vec![];
        let term_slot = spec
            .reward
            .iter()
            .map(|t| match &t.kind {
                TermKind::Velocity { source } => {
                    velocity_sources.push(source.clone());
                    Some(velocity_sources.len() - 1)
                }
                _ => None,
            })
            .collect();
        let info_slot = spec
            .info
            .iter()
            .map(|i| match &i.kind {
                InfoKind::Velocity { source } => {
                    velocity_sources.push(source.clone());
                    Some(velocity_sources.len() - 1)
                }
                _ => None,
            })
            .collect();
        let uses_mass_center = spec.reads(Field::MassCenter);
        let uses_subtree = spec.reads(Field::SubtreeLinvel) || spec.reads(Field::SubtreeAngmom);

        let layout = |items: &mut dyn Iterator<Item = &InfoItem>| {
            let mut off = 0;
            items
                .map(|i| {
                    let s = InfoSlot {
                        key: i.key.clone(),
                        offset: off,
                        len: i.len,
                    };
                    off += i.len;
                    s
                })
                .collect::<Vec<_>>()
        };
        let step_info = layout(&mut spec.info.iter());
        let reset_info = layout(&mut spec.reset_info());
        let total = |l: &[InfoSlot]| l.iter().map(|s| s.len).sum::<usize>();

        let ctrlrange = model.actuator_ctrlrange().as_flattened();
        // Gymnasium: Box(ctrlrange.astype(float32)); the bounds are the float32-rounded values.
        let mut action_space = BoxSpace {
            low: (0..sim.nu)
                .map(|i| ctrlrange[2 * i] as f32 as f64)
                .collect(),
            high: (0..sim.nu)
                .map(|i| ctrlrange[2 * i + 1] as f32 as f64)
                .collect(),
        };
        // PD actions: the declared action space, not the control range.
        if let Some(a) = &spec.actions {
            action_space.low.fill(a.range.0 as f32 as f64);
            action_space.high.fill(a.range.1 as f32 as f64);
        }
        // End-effector actions: Box(-1, 1) of their own length.
        if spec.manipulation.end_effector.is_some() {
            action_space = BoxSpace {
                low: vec![-1.0; spec.act_dim()],
                high: vec![1.0; spec.act_dim()],
            };
        }
        let observation_space = BoxSpace {
            low: vec![f64::NEG_INFINITY; spec.obs_dim],
            high: vec![f64::INFINITY; spec.obs_dim],
        };
        let max_draw = spec.reset.iter().map(|r| r.target.len()).max().unwrap_or(0);

        let latency =
            crate::latency::ActionLatency::new(spec.corruption.action_latency, spec.act_dim());
        mujoco_log::drain_into(&mut warnings);
        Ok(Env {
            before: vec![0.0; velocity_sources.len()],
            velocity_sources,
            term_slot,
            info_slot,
            term_values: vec![0.0; 2 * spec.reward.len()],
            unweighted_terms: (0..spec.reward.len())
                .map(|i| {
                    spec.info
                        .iter()
                        .any(|it| it.unweighted && matches!(it.kind, InfoKind::Term(j) if j == i))
                })
                .collect(),
            obs: vec![0.0; spec.obs_dim],
            step_info_values: vec![0.0; total(&step_info)],
            reset_info_values: vec![0.0; total(&reset_info)],
            step_info,
            reset_info,
            qvel_init,
            qpos_init,
            draw: vec![0.0; max_draw],
            terrain_origins: terrain_origins(&model),
            sim,
            rng: None,
            dt,
            timestep,
            uses_mass_center,
            uses_subtree,
            elapsed: 0,
            has_reset: false,
            reset_failure: None,
            action_f32: false,
            warnings,
            observation_space,
            action_space,
            obs_noise: crate::obs_noise::ObsNoise::new(&spec),
            latency,
            spec,
            render,
            events,
        })
    }

    /// The resolved spec this env runs.
    pub fn spec(&self) -> &Arc<ResolvedSpec> {
        &self.spec
    }
    /// Bytes of this env's `mjData` as mapped: its buffer and its whole arena.
    pub fn data_bytes(&self) -> u64 {
        let d = self.sim.data.ffi();
        (d.nbuffer as u64).saturating_add(d.narena as u64)
    }
    /// What one more env of this spec holds beyond the shared model (see [`Footprint`]). Runs a
    /// short probe on a scratch `mjData` of the model to see how much of the arena stepping
    /// touches; this env is left as it is.
    pub fn footprint(&self) -> Footprint {
        let d = self.sim.data.ffi();
        let (buffer, arena) = (d.nbuffer as u64, d.narena as u64);
        let rings = self.obs_noise.as_ref().map_or(0, |n| n.bytes())
            + self.latency.as_ref().map_or(0, |l| l.bytes());
        // An env whose events write the model steps its own copy of it.
        let model = if self
            .spec
            .events
            .iter()
            .any(envspec::events::Event::writes_model)
        {
            self.sim.model.ffi().nbuffer as u64
        } else {
            0
        };
        // The vectors sized by the spec: the observation and its two bounds, info values, state
        // copies; plus the allocator's and the struct's own overhead.
        let numbers = 3 * self.spec.obs_dim
            + self.step_info_values.len()
            + self.reset_info_values.len()
            + self.qpos_init.len()
            + self.qvel_init.len()
            + self.sim.ten_j.len()
            + self.sim.action.len()
            + self.term_values.len()
            + self.draw.len();
        let own = (numbers * 8) as u64 + ENV_OVERHEAD_BYTES;
        // MuJoCo maps the arena whole but writes only what the solver and contacts use: the
        // pages a probe touched, twice over for states with more contacts than it met.
        let touched = arena_in_use(&self.sim.model).map_or(arena, |used| {
            used.saturating_mul(2)
                .saturating_add(ARENA_SLACK_BYTES)
                .min(arena)
        });
        // MuJoCo allocates the `mjData` struct itself too: its solver statistics make it
        // about 200 KiB, more than a small model's buffer.
        let header = std::mem::size_of::<mjData>() as u64;
        let common = header + buffer + rings + model + own;
        Footprint {
            resident: common.saturating_add(touched),
            mapped: common.saturating_add(arena),
        }
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
    /// `compute_reward` of a `[goal]` task for rows of `goal_dim` numbers each: the reward sum of
    /// the goal terms, each evaluated on `achieved` against `desired` exactly as `step` does. `Err`
    /// names a reward term that reads anything but the goal distance (no reward from goals
    /// alone), or says the env has no `[goal]`.
    pub fn compute_reward(
        &self,
        achieved: &[f64],
        desired: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        let n = self.spec.goal_dim;
        if self.spec.manipulation.goal.is_none() || n == 0 {
            return Err(format!("{} has no [goal] table", self.spec.id));
        }
        // Where each goal distance's elements lie in a goal row.
        let mut at: Vec<Vec<Vec<usize>>> = vec![];
        for t in &self.spec.reward {
            let found = crate::manipulation::goal_positions(&self.spec, &t.kind);
            let Some(positions) = found else {
                return Err(format!(
                    "[reward.{}] (kind {}) is not a goal term comparing the [goal] achieved values with the goal vector, so the reward is not a function of the goals",
                    t.name,
                    t.kind_name()
                ));
            };
            at.push(positions);
        }
        if achieved.len() != out.len() * n || desired.len() != out.len() * n {
            return Err(format!(
                "{} and {} goal numbers for {} rows of {n}",
                achieved.len(),
                desired.len(),
                out.len()
            ));
        }
        let mut values = vec![0.0; self.spec.reward.len()];
        for (r, o) in out.iter_mut().enumerate() {
            let (a, d) = (&achieved[r * n..(r + 1) * n], &desired[r * n..(r + 1) * n]);
            for ((v, t), at) in values.iter_mut().zip(&self.spec.reward).zip(&at) {
                *v = crate::goal::term_value(t, self.sim.numerics, a, d, &|i, k| at[i][k])
                    .unwrap_or(f64::NAN);
            }
            *o = sum_values(&self.spec.reward_sum, &values);
        }
        Ok(())
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
    /// The info of the last `step` (kept when a later `reset` fills the reset info).
    pub fn step_info(&self) -> Info<'_> {
        Info {
            slots: &self.step_info,
            values: &self.step_info_values,
        }
    }
    /// The info of the last `reset`.
    pub fn reset_info(&self) -> Info<'_> {
        Info {
            slots: &self.reset_info,
            values: &self.reset_info_values,
        }
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

    /// Clip the current qvel to `±limit` and `mj_forward` (Gymnasium's `set_state(qpos, clip(qvel))`).
    pub(crate) fn clip_qvel(&mut self, limit: f64) -> Result<(), EnvError> {
        for v in self.sim.data.qvel_mut() {
            *v = crate::numerics::clip(*v, -limit, limit);
        }
        self.sim.call(Call::Forward).map_err(|message| {
            self.has_reset = false;
            EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in a step (reset before stepping again)",
                message,
            }
        })
    }

    /// Gymnasium's `MujocoEnv.set_state`: `qpos` and `qvel` are written, then `mj_forward`; the
    /// derived fields and the observation follow the new state (`[derived.*]` values measured at
    /// reset keep their values, as the reference's attributes do). E1105 for another length
    /// than the model's `nq` / `nv`.
    pub fn set_state(&mut self, qpos: &[f64], qvel: &[f64]) -> Result<(), EnvError> {
        for (what, got, expected) in [
            ("qpos", qpos.len(), self.sim.nq),
            ("qvel", qvel.len(), self.sim.nv),
        ] {
            if got != expected {
                return Err(EnvError::StateLength {
                    env: self.spec.id.clone(),
                    what,
                    expected,
                    got,
                });
            }
        }
        let (q, v) = mj::state::qpos_qvel_mut(&mut self.sim.data);
        q.copy_from_slice(qpos);
        v.copy_from_slice(qvel);
        if let Err(message) = self.sim.call(Call::Forward) {
            self.has_reset = false;
            return Err(EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in set_state (reset before stepping again)",
                message,
            });
        }
        self.derive_after_physics();
        self.sim.legged.update_sites(&self.sim.data);
        self.write_obs();
        Ok(())
    }

    /// The MuJoCo data, read-only (checks of derived quantities against independent
    /// implementations read `cvel`, `subtree_com`, `site_xmat`, the contact list).
    pub fn data(&self) -> &mjData {
        self.sim.data.ffi()
    }
    /// Current `qpos` and `qvel`.
    pub fn state(&self) -> (&[f64], &[f64]) {
        (self.sim.field(Field::Qpos), self.sim.field(Field::Qvel))
    }
    /// The current contents of a simulation field, flattened row-major (multi-agent
    /// observations read it).
    pub fn field(&self, field: Field) -> &[f64] {
        self.sim.field(field)
    }
    /// Keep the derived fields `sources` read up to date too (a multi-agent env's agents may
    /// observe selections its spec does not). Contact forces are decided by the spec
    /// (`needs_rne_post_constraint`), before the env is built.
    pub(crate) fn read_also<'a>(&mut self, sources: impl Iterator<Item = &'a Selection>) {
        for s in sources {
            self.uses_mass_center |= s.field == Field::MassCenter;
            self.uses_subtree |= s.field.needs_subtree_vel();
            if s.field.is_site_frame() {
                self.sim.legged.enable_site_frames(self.sim.nsite);
            }
            self.sim.manip.read_also(s);
        }
    }

    /// Start an episode. With a seed the RNG restarts from it (numpy `SeedSequence(seed)` →
    /// PCG64); without one the stream continues (the first reset without any seed draws OS entropy).
    pub fn reset(&mut self, seed: Option<u64>) -> (&[f64], Info<'_>) {
        match seed {
            Some(s) => self.rng = Some(NumpyRng::from_seed(s)),
            None if self.rng.is_none() => self.rng = Some(NumpyRng::from_entropy()),
            None => {}
        }
        // Draw order steps 1–2 (docs/spec-reference.md): the events, before `[reset]`.
        let event_error = self.reset_events(seed.is_some());
        let rng = self.rng.as_mut().expect("set above");
        let init = self.spec.manipulation.init.as_ref();
        let mut mujoco_error = if init.is_some_and(|i| !i.reset_data) {
            event_error
        } else {
            self.sim.call(Call::ResetData).err().or(event_error)
        };
        let nq = self.sim.nq;
        let numerics = self.sim.numerics;
        let spec = Arc::clone(&self.spec);
        self.sim
            .restart(init.is_some(), &self.qpos_init, &self.qvel_init);
        self.reset_failure = None;
        let (mut next, mut restarts) = (0, 0);
        while next < spec.reset.len() {
            let (k, step) = (next, &spec.reset[next]);
            next += 1;
            if let Distribution::Settle(s) = &step.dist {
                let init = spec.manipulation.init.as_ref();
                match self.sim.settle(s, init, spec.frame_skip) {
                    Ok(true) => {}
                    Ok(false) if restarts < envspec::limits::MAX_SETTLE_RESTARTS => {
                        // Gymnasium-Robotics' `_reset_sim` until it succeeds: anew from the
                        // start state, the stream continuing.
                        restarts += 1;
                        next = 0;
                        self.sim
                            .restart(init.is_some(), &self.qpos_init, &self.qvel_init);
                    }
                    Ok(false) => {
                        self.reset_failure = Some(ResetFailure::Unmet(k));
                        break;
                    }
                    Err(message) => {
                        mujoco_error = Some(message);
                        break;
                    }
                }
                continue;
            }
            let [qpos, qvel, mocap_pos, mocap_quat] = mj::state::state_mut(&mut self.sim.data);
            let n = step.target.len();
            let draw = &mut self.draw[..n];
            match &step.dist {
                Distribution::Keyframe { index, .. } => {
                    // The resolver checked the index against the model's keyframes and the
                    // env's model check their count.
                    let key = &self.sim.model.key_qpos()[index * nq..(index + 1) * nq];
                    qpos.copy_from_slice(key);
                    continue;
                }
                Distribution::TerrainOrigin { rows } => {
                    // Row first, then column (`integers` draws); the resolver checked the rows
                    // against `[terrain]`, which the model was built with.
                    let Some((adr, tiles)) = self.terrain_origins else {
                        continue;
                    };
                    let cols = tiles / self.spec.model_edits.terrain.as_ref().map_or(1, |t| t.rows);
                    let row = rng.integers(rows.0 as i64, rows.1 as i64 + 1) as usize;
                    let col = rng.integers(0, cols.max(1) as i64) as usize;
                    let o = &self.sim.model.numeric_data()[adr + 3 * (row * cols + col)..][..3];
                    let a = step.target.indices[0];
                    for i in 0..3 {
                        qpos[a + i] += o[i];
                    }
                    continue;
                }
                Distribution::RootPose { ranges } => {
                    let mut x = [0.0; 6];
                    for (v, r) in x.iter_mut().zip(ranges) {
                        *v = rng.uniform(r.0, r.1);
                    }
                    let a = step.target.indices[0];
                    for i in 0..3 {
                        qpos[a + i] += x[i];
                    }
                    let q = [qpos[a + 3], qpos[a + 4], qpos[a + 5], qpos[a + 6]];
                    let d = quat_from_euler_xyz(x[3], x[4], x[5]);
                    qpos[a + 3..a + 7].copy_from_slice(&quat_mul(q, d));
                    continue;
                }
                _ => {}
            }
            // `probability`: one uniform decides whether the step runs at all.
            if let Some(p) = step.probability
                && rng.uniform(0.0, 1.0) >= p
            {
                continue;
            }
            let records = &self.sim.manip.records;
            if let Distribution::Rotation(_) | Distribution::UnitQuaternion = &step.dist {
                let state = [qpos, qvel, mocap_pos, mocap_quat];
                let target = reset_target(step.target.field, state, &mut self.sim.goal);
                crate::manipulation::quaternion_step(step, target, rng, numerics);
                continue;
            }
            if let Distribution::Meet(m) = &step.dist {
                let around = step.around.as_deref().unwrap_or(&[]);
                crate::manipulation::meet(m, around, records, rng, numerics, draw);
                let state = [qpos, qvel, mocap_pos, mocap_quat];
                let target = reset_target(step.target.field, state, &mut self.sim.goal);
                for (k, &i) in step.target.indices.iter().enumerate() {
                    target[i] = draw[k];
                }
                continue;
            }
            // The reference redraws for ever; envc gives up after a bound no real spec reaches.
            for attempt in 1.. {
                match &step.dist {
                    Distribution::Uniform { low, high } => {
                        for i in 0..n {
                            draw[i] = rng.uniform(low[i], high[i]);
                        }
                    }
                    Distribution::Normal { scale } => {
                        for d in draw.iter_mut() {
                            *d = scale * rng.standard_normal();
                        }
                    }
                    Distribution::Constant { value } => draw.fill(*value),
                    Distribution::Values { values } => draw.copy_from_slice(values),
                    Distribution::Keyframe { .. }
                    | Distribution::RootPose { .. }
                    | Distribution::Meet(_)
                    | Distribution::Rotation(_)
                    | Distribution::UnitQuaternion
                    | Distribution::Settle(_)
                    | Distribution::TerrainOrigin { .. } => {}
                }
                let done = match step.resample_until {
                    None => true,
                    Some(Until::NormBelow(x)) => norm(numerics, n, &|i| draw[i]) < x,
                    Some(Until::NormAbove(x)) => norm(numerics, n, &|i| draw[i]) > x,
                    Some(Until::MinDistance(x)) => {
                        let a = step.around.as_deref().unwrap_or(&[]);
                        let at = |i: usize| a.get(i).map_or(0.0, |&j| records[j]);
                        norm(numerics, n, &|i| (at(i) + draw[i]) - at(i)) >= x
                    }
                };
                if done {
                    break;
                }
                if attempt >= envspec::limits::MAX_RESAMPLE_DRAWS {
                    self.reset_failure = Some(ResetFailure::Unmet(k));
                    break;
                }
            }
            let state = [qpos, qvel, mocap_pos, mocap_quat];
            let target = reset_target(step.target.field, state, &mut self.sim.goal);
            for (k, &i) in step.target.indices.iter().enumerate() {
                target[i] = match &step.around {
                    Some(a) => records[a[k]] + draw[k],
                    None if step.set => draw[k],
                    None => target[i] + draw[k],
                };
            }
        }
        self.sim
            .manip
            .place_marker(&self.sim.goal, &mut self.sim.data);
        // Gymnasium's set_state: qpos, qvel, then mj_forward.
        if mujoco_error.is_none() {
            mujoco_error = self.sim.call(Call::Forward).err();
        }
        if let Some(message) = mujoco_error {
            self.reset_failure = Some(ResetFailure::Mujoco(message));
        }
        // Commands are drawn after the `[reset.*]` steps (the design's draw order).
        let rng = self.rng.as_mut().expect("set above");
        self.sim.legged.update_sites(&self.sim.data);
        self.sim.legged.reset(&self.spec, rng);
        self.derive_after_physics();
        self.update_derived(true);
        self.elapsed = 0;
        self.has_reset = self.reset_failure.is_none();
        if let Some(l) = &mut self.latency {
            l.clear();
        }
        self.write_obs_at(true);
        let mut off = 0;
        for item in self.spec.reset_info() {
            let out = &mut self.reset_info_values[off..off + item.len];
            write_info(
                &self.sim,
                &self.before,
                &self.term_values,
                self.dt,
                item,
                None,
                out,
            );
            off += item.len;
        }
        mujoco_log::drain_into(&mut self.warnings);
        (
            &self.obs,
            Info {
                slots: &self.reset_info,
                values: &self.reset_info_values,
            },
        )
    }

    /// Advance one control step. The action is used as given (MuJoCo clamps it to ctrlrange inside
    /// the dynamics; costs see the raw values), as in the reference.
    pub fn step(&mut self, action: &[f64]) -> Result<Step<'_>, EnvError> {
        self.check_action(crate::JointAction::F64(action))?;
        self.sim.action.copy_from_slice(action);
        self.action_f32 = false;
        self.advance()
    }

    /// `step` with a float32 action, as a float32 policy calls the reference: the dynamics are
    /// the same (the conversion to float64 is exact), but costs computed from `action` are
    /// computed in float32 as numpy does (square, pairwise sum and weight in float32; reference
    /// trap T3), so their info values are float32 numbers.
    pub fn step_f32(&mut self, action: &[f32]) -> Result<Step<'_>, EnvError> {
        self.check_action(crate::JointAction::F32(action))?;
        for (a, &x) in self.sim.action.iter_mut().zip(action) {
            *a = x as f64;
        }
        self.action_f32 = true;
        self.advance()
    }

    /// The events' part of a reset (draw order steps 1–2), then what MuJoCo and the env derive
    /// from the changed fields. A MuJoCo error in `mj_setConst` comes back as its message.
    fn reset_events(&mut self, reseed: bool) -> Option<String> {
        let (Some(ev), Some(rng)) = (self.events.as_mut(), self.rng.as_mut()) else {
            return None;
        };
        let mut t = crate::events::Target {
            // The env's own copy of the model when any event writes it (`with_world_model`),
            // shared with nothing but its own data, which MuJoCo does not use meanwhile.
            m: mj::model_edit::ModelValues::env_copy(&self.sim.model),
            qvel: self.sim.data.qvel_mut(),
            rng,
            profile: self.sim.numerics,
        };
        ev.reset(&mut t, reseed);
        let (set_const, mass, timestep) = (ev.set_const, ev.changes_mass, ev.changes_timestep);
        let mut error = None;
        if set_const {
            // Subtree masses, `dof_invweight0`, `body_invweight0`, `actuator_acc0`, ... from the
            // new masses, inertia positions and armature (at qpos0; `mj_resetData` follows).
            error = self.sim.call(Call::SetConst).err();
        }
        self.model_changed(mass, timestep);
        error
    }

    /// Interval events due after this step (draw order step 5); when any fired, `mj_forward` so
    /// what the observation reads agrees with the kicked velocities and new fields.
    fn interval_events(&mut self) -> Result<(), EnvError> {
        let (Some(ev), Some(rng)) = (self.events.as_mut(), self.rng.as_mut()) else {
            return Ok(());
        };
        let mut t = crate::events::Target {
            // As in `reset_events`.
            m: mj::model_edit::ModelValues::env_copy(&self.sim.model),
            qvel: self.sim.data.qvel_mut(),
            rng,
            profile: self.sim.numerics,
        };
        if !ev.step(&mut t, self.dt) {
            return Ok(());
        }
        let timestep = ev.changes_timestep;
        self.model_changed(false, timestep);
        if let Err(message) = self.sim.call(Call::Forward) {
            return Err(self.step_failed(message));
        }
        self.derive_after_physics();
        Ok(())
    }

    /// A MuJoCo error in a step: the state is MuJoCo's mid-error state, so no step before the
    /// next reset.
    fn step_failed(&mut self, message: String) -> EnvError {
        self.has_reset = false;
        EnvError::Mujoco {
            env: self.spec.id.clone(),
            during: "in a step (reset before stepping again)",
            message,
        }
    }

    /// What the env derives from the state after MuJoCo moved it (only what the spec reads).
    fn derive_after_physics(&mut self) {
        if self.uses_mass_center {
            self.sim.update_mass_center();
        }
        if self.uses_subtree {
            // mj_subtreeVel reads only the kinematics the physics just computed and takes stack
            // space mj_step has already used; MuJoCo raises no error from it. A failure would
            // leave the data reset, which the next step reports.
            let _ = self.sim.call(Call::SubtreeVel);
        }
        self.sim.update_ten_j();
        let numerics = self.sim.numerics;
        self.sim.manip.update(&self.sim.data, numerics);
        self.update_derived(false);
    }

    /// `[derived.*]` from the current state (`reset`: the `at = "reset"` ones too).
    fn update_derived(&mut self, reset: bool) {
        if self.spec.derived.is_empty() {
            return;
        }
        let mut out = std::mem::take(&mut self.sim.derived);
        let sim = &self.sim;
        crate::derived::update(
            &self.spec.derived,
            &sim.contact_ids,
            &sim.data,
            |f| sim.field(f),
            sim.numerics,
            reset,
            &mut out,
        );
        self.sim.derived = out;
    }

    /// What the env caches from the model: the mass sum (`mass_center`) and the timestep / dt.
    fn model_changed(&mut self, mass: bool, timestep: bool) {
        if mass {
            let mass = self.sim.model.body_mass();
            self.sim.mass_sum = pairwise_sum(mass.len(), &|i| mass[i]);
        }
        if timestep {
            self.timestep = self.sim.m().opt.timestep;
            self.dt = self.timestep * self.spec.frame_skip as f64;
        }
    }

    /// Why the last reset did not give a valid start (E1104), if it did not.
    pub fn reset_error(&self) -> Option<EnvError> {
        Some(match self.reset_failure.as_ref()? {
            ResetFailure::Unmet(k) => EnvError::ResampleUnmet {
                env: self.spec.id.clone(),
                step: self.spec.reset[*k].name.clone(),
                draws: match self.spec.reset[*k].dist {
                    Distribution::Settle(_) => envspec::limits::MAX_SETTLE_RESTARTS,
                    _ => envspec::limits::MAX_RESAMPLE_DRAWS,
                },
            },
            ResetFailure::Mujoco(message) => EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in reset (reset again, or fix the model)",
                message: message.clone(),
            },
        })
    }

    fn check_action(&self, action: crate::JointAction<'_>) -> Result<(), EnvError> {
        crate::joint_env::check_action(&self.spec.id, self.sim.action.len(), action, || {
            (!self.has_reset).then(|| self.reset_error().unwrap_or(EnvError::NotReset))
        })
    }

    /// The step proper, with the action already in `sim.action`.
    fn advance(&mut self) -> Result<Step<'_>, EnvError> {
        if let Some(l) = &mut self.latency {
            l.apply(&mut self.sim.action);
        }
        for (k, s) in self.velocity_sources.iter().enumerate() {
            self.before[k] = self.sim.get(s, 0);
        }
        let n_terms = self.spec.reward.len();
        // Terms with `at = "before"` see the state the previous step (or the reset) left.
        for (i, t) in self.spec.reward.iter().enumerate() {
            if t.before {
                let v = self.term(i, t, self.term_slot[i], true, t.weight);
                self.term_values[i] = if t.cost { -v } else { v };
                if self.unweighted_terms[i] {
                    let u = self.term(i, t, self.term_slot[i], true, 1.0);
                    self.term_values[n_terms + i] = if t.cost { -u } else { u };
                }
            }
        }
        if let Some(e) = &self.spec.manipulation.end_effector {
            self.sim
                .manip
                .apply_action(e, &self.sim.action, self.action_f32, &mut self.sim.data);
        } else {
            let ctrl = self.sim.data.ctrl_mut();
            self.sim.legged.write_ctrl(&self.sim.action, ctrl);
        }
        let (n, rne) = (self.spec.frame_skip, self.spec.needs_rne_post_constraint);
        let stepped = if self.sim.legged.landings.active() {
            // Substep by substep: mjlab's contact sensors are updated after each one.
            self.sim.legged.landings.begin_step();
            let mut stepped = Ok(());
            for k in 0..n {
                let rne = rne && k + 1 == n;
                stepped = self.sim.call(Call::Step { n: 1, rne });
                if stepped.is_err() {
                    break;
                }
                self.sim.legged.landings.substep(&self.sim.data);
            }
            stepped
        } else {
            self.sim.call(Call::Step { n, rne })
        };
        if let Err(message) = stepped {
            return Err(self.step_failed(message));
        }
        // `[hold.*]`: joints set after the physics, then `mj_forward` (the reference's step
        // callback).
        if !self.spec.manipulation.hold.is_empty() {
            let (qpos, _) = mj::state::qpos_qvel_mut(&mut self.sim.data);
            for h in &self.spec.manipulation.hold {
                for &a in &h.qpos {
                    qpos[a] = h.value;
                }
            }
            if let Err(message) = self.sim.call(Call::Forward) {
                return Err(self.step_failed(message));
            }
        }
        self.derive_after_physics();
        self.sim.legged.update_sites(&self.sim.data);
        self.sim.legged.update_contacts(&self.sim.data, self.dt);
        self.sim.legged.landings.before_reward(&self.sim.data);

        let healthy = self.spec.health.iter().all(|c| self.check(c));
        for (i, t) in self.spec.reward.iter().enumerate() {
            if t.before {
                continue;
            }
            let v = self.term(i, t, self.term_slot[i], healthy, t.weight);
            self.term_values[i] = if t.cost { -v } else { v };
            if self.unweighted_terms[i] {
                let u = self.term(i, t, self.term_slot[i], healthy, 1.0);
                self.term_values[n_terms + i] = if t.cost { -u } else { u };
            }
        }
        let reward = self.sum(&self.spec.reward_sum);
        self.sim.legged.commit_contacts();
        // Draw order step 4: commands due are redrawn (the info below shows the new ones).
        if !self.spec.commands.is_empty() {
            let rng = self.rng.as_mut().expect("a reset came first");
            self.sim.legged.resample(&self.spec, rng);
        }
        let mut off = 0;
        for (j, item) in self.spec.info.iter().enumerate() {
            let out = &mut self.step_info_values[off..off + item.len];
            let slot = self.info_slot[j];
            write_info(
                &self.sim,
                &self.before,
                &self.term_values,
                self.dt,
                item,
                slot,
                out,
            );
            off += item.len;
        }
        self.elapsed += 1;
        let terminated = (!healthy && self.spec.terminate_when_unhealthy)
            || self
                .spec
                .termination
                .iter()
                .any(|t| self.sim.goal_reached(&t.reached));
        let truncated = self
            .spec
            .max_episode_steps
            .is_some_and(|m| self.elapsed >= m);
        // Draw order step 5: interval events after reward, termination and info, before the
        // observation.
        if self.events.is_some() {
            self.interval_events()?;
        }
        // `[physics] forward_before_observation` (mjlab's step): the observation reads the new
        // state's kinematics, where reward and termination read the last substep's.
        if self.spec.model_edits.forward_before_observation {
            if let Err(message) = self.sim.call(Call::Forward) {
                return Err(self.step_failed(message));
            }
            self.derive_after_physics();
            self.sim.legged.update_sites(&self.sim.data);
        }
        // Draw order step 6: the observation (noise, delay); it holds the previous action as
        // `last_action`, which becomes this step's action only after it is written.
        self.write_obs();
        self.sim.legged.end_step(&self.sim.action);
        mujoco_log::drain_into(&mut self.warnings);
        Ok(Step {
            obs: &self.obs,
            reward,
            terminated,
            truncated,
            info: Info {
                slots: &self.step_info,
                values: &self.step_info_values,
            },
        })
    }

    /// Why the current state is unhealthy: the first health check that fails, with the first
    /// element that fails it (None when every check holds). For explaining endings (`envc run`);
    /// not on the step path.
    pub fn unhealthy(&self) -> Option<Unhealthy> {
        let c = self.spec.health.iter().find(|c| !self.check(c))?;
        let (element, value) = c
            .sources
            .iter()
            .flat_map(|s| {
                let f = self.sim.field(s.field);
                s.indices
                    .iter()
                    .zip(&s.names)
                    .map(move |(&i, n)| (n.clone(), f[i]))
            })
            .find(|(_, x)| !check_value(&c.kind, *x))
            .unwrap_or_default();
        Some(Unhealthy {
            check: c.name.clone(),
            rule: envspec::describe::check(c),
            element,
            value,
        })
    }

    fn check(&self, c: &HealthCheck) -> bool {
        c.sources.iter().all(|s| {
            let f = self.sim.field(s.field);
            s.indices.iter().all(|&i| check_value(&c.kind, f[i]))
        })
    }

    /// `weight × kernel` of one term (unsigned); `weight` is the term's, or 1 for `unweighted` info.
    fn term(
        &self,
        i: usize,
        t: &RewardTerm,
        slot: Option<usize>,
        healthy: bool,
        weight: f64,
    ) -> f64 {
        let sim = &self.sim;
        // A gated-off term's signed value is −0.0, which leaves any sum unchanged.
        let unless = !t.unless.is_empty() && t.unless.iter().all(|c| sim.condition_holds(c));
        if unless || !t.only_if.iter().all(|c| sim.condition_holds(c)) {
            return if t.cost { 0.0 } else { -0.0 };
        }
        let kernel = match &t.kind {
            TermKind::Velocity { source } => {
                let k = slot.expect("velocity terms have a slot");
                (sim.get(source, 0) - self.before[k]) / self.dt
            }
            TermKind::Healthy => (healthy || t.paid_when_unhealthy) as u8 as f64,
            TermKind::SumSquares {
                source,
                clip_input: None,
                clip: out_clip,
            } if self.action_f32 && source.field == Field::Action => {
                // numpy: float32 square and pairwise sum; the weight is rounded to float32 (NEP 50).
                let f = sim.field(source.field);
                let s = pairwise_sum(source.len(), &|k| {
                    let x = f[source.indices[k]] as f32;
                    x * x
                });
                let v = ((weight as f32) * s) as f64;
                return match out_clip {
                    Some((lo, hi)) => clip(v, *lo, *hi),
                    None => v,
                };
            }
            TermKind::SumSquares {
                source,
                clip_input,
                clip: out_clip,
            } => {
                let f = sim.field(source.field);
                let s = pairwise_sum(source.len(), &|k| {
                    let x = f[source.indices[k]];
                    let x = match clip_input {
                        Some((lo, hi)) => clip(x, *lo, *hi),
                        None => x,
                    };
                    x * x
                });
                let v = weight * s;
                return match out_clip {
                    Some((lo, hi)) => clip(v, *lo, *hi),
                    None => v,
                };
            }
            TermKind::Norm { source, minus } => {
                let f = sim.field(source.field);
                match minus {
                    Some(m) => {
                        let g = sim.field(m.field);
                        norm(sim.numerics, source.len(), &|k| {
                            f[source.indices[k]] - g[m.indices[k]]
                        })
                    }
                    None => norm(sim.numerics, source.len(), &|k| f[source.indices[k]]),
                }
            }
            TermKind::Quadratic {
                source,
                coefs,
                targets,
            } => {
                let f = sim.field(source.field);
                let mut acc = 0.0;
                for k in 0..source.len() {
                    let q = coefs[k] * square_pow(f[source.indices[k]] - targets[k]);
                    acc = if k == 0 { q } else { acc + q };
                }
                acc
            }
            TermKind::Value { source, divide_by } => {
                let x = sim.get(source, 0);
                match divide_by {
                    Some(Divisor::Timestep) => x / self.timestep,
                    Some(Divisor::Dt) => x / self.dt,
                    None => x,
                }
            }
            TermKind::Constant => return weight,
            TermKind::WeightedSquare { source, target } => {
                let d = sim.get(source, 0) - target;
                return (weight * d) * d;
            }
            TermKind::Legged(l) => {
                sim.legged
                    .kernel(i, l, sim.numerics, &|f| sim.field(f), &sim.action)
            }
            TermKind::GoalSparse(GoalCheck { distance: g, .. })
            | TermKind::GoalMissed(GoalCheck { distance: g, .. })
            | TermKind::GoalDense(g)
            | TermKind::GoalDistance(g) => {
                crate::goal::kernel(&t.kind, sim.numerics, &|_, k| sim.goal_pair(g, k))
                    .expect("a goal kind")
            }
            TermKind::GoalsMissed(cs) => crate::goal::kernel(&t.kind, sim.numerics, &|i, k| {
                sim.goal_pair(&cs[i].distance, k)
            })
            .expect("a goal kind"),
        };
        weight * kernel
    }

    fn sum(&self, node: &SumNode) -> f64 {
        sum_values(node, &self.term_values)
    }

    fn write_obs(&mut self) {
        self.write_obs_at(false);
    }

    /// The observation, with noise and delay where the spec declares them (`reset`: fill the
    /// delay buffers).
    fn write_obs_at(&mut self, reset: bool) {
        let sim = &self.sim;
        match (&mut self.obs_noise, &mut self.rng) {
            (Some(n), Some(rng)) => {
                n.write(&self.spec, |f| sim.field(f), &mut self.obs, rng, reset)
            }
            _ => crate::observe::write_segments(
                &self.spec.observation,
                |f| sim.field(f),
                &mut self.obs,
            ),
        }
    }
}

/// One info item's values, written into `out` (a free function so the spec can stay borrowed
/// while the env's buffers are written: no per-step `Arc` clone).
/// Whether one element passes a health check.
fn check_value(kind: &CheckKind, x: f64) -> bool {
    match *kind {
        CheckKind::Finite => x.is_finite(),
        CheckKind::InRange {
            lo,
            hi,
            closed: true,
        } => lo <= x && x <= hi,
        CheckKind::InRange {
            lo,
            hi,
            closed: false,
        } => lo < x && x < hi,
        CheckKind::FailsIf { op, value } => !match op {
            CmpOp::Lt => x < value,
            CmpOp::Le => x <= value,
            CmpOp::Gt => x > value,
            CmpOp::Ge => x >= value,
        },
    }
}

/// A failed health check, as [`Env::unhealthy`] reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct Unhealthy {
    /// The check's name in the spec (`[health.<name>]`).
    pub check: String,
    /// What the check requires, in words.
    pub rule: String,
    /// The first element that fails it, e.g. `qpos[1] (rootz)`, and its value.
    pub element: String,
    /// That element's value.
    pub value: f64,
}

fn write_info(
    sim: &Sim,
    before: &[f64],
    term_values: &[f64],
    dt: f64,
    item: &InfoItem,
    slot: Option<usize>,
    out: &mut [f64],
) {
    match &item.kind {
        InfoKind::Value { source, minus } => {
            let f = sim.field(source.field);
            for (k, o) in out.iter_mut().enumerate() {
                *o = f[source.indices[k]];
                if let Some(m) = minus {
                    *o -= sim.field(m.field)[m.indices[k]];
                }
            }
        }
        InfoKind::Norm { source } => {
            let f = sim.field(source.field);
            out[0] = norm(sim.numerics, source.len(), &|k| f[source.indices[k]]);
        }
        InfoKind::Velocity { source } => {
            let k = slot.expect("velocity infos have a slot");
            out[0] = (sim.get(source, 0) - before[k]) / dt;
        }
        InfoKind::Term(i) if item.unweighted => out[0] = term_values[term_values.len() / 2 + *i],
        InfoKind::Term(i) => out[0] = term_values[*i],
        InfoKind::GoalReached(c) => out[0] = sim.goal_reached(c) as u8 as f64,
        InfoKind::GoalsReached(cs) => out[0] = sim.goals_reached(cs) as u8 as f64,
        InfoKind::Condition(cs) => out[0] = cs.iter().all(|c| sim.condition_holds(c)) as u8 as f64,
    }
}

/// What a reset step writes: the state array of its target's field, or the goal vector.
fn reset_target<'a>(field: Field, state: [&'a mut [f64]; 4], goal: &'a mut [f64]) -> &'a mut [f64] {
    let [qpos, qvel, mocap_pos, mocap_quat] = state;
    match field {
        Field::Qpos => qpos,
        Field::Goal => goal,
        Field::MocapPos => mocap_pos,
        Field::MocapQuat => mocap_quat,
        _ => qvel,
    }
}

/// The reward sum over signed term values: each list left to right, nested lists first.
fn sum_values(node: &SumNode, values: &[f64]) -> f64 {
    match node {
        SumNode::Term(i) => values[*i],
        SumNode::Sum(children) => {
            let mut it = children.iter();
            let Some(first) = it.next() else { return 0.0 };
            it.fold(sum_values(first, values), |acc, c| {
                acc + sum_values(c, values)
            })
        }
    }
}

/// Compile the spec's model (MJCF or URDF) with MuJoCo, capturing its messages; `[actuators]` and
/// `[physics]` are applied through mjSpec.
pub fn compile(spec: &ResolvedSpec) -> Result<MjModel, EnvError> {
    mujoco_log::install();
    let path = &spec.model_path;
    let bad = |message: String| EnvError::Compile {
        path: path.clone(),
        message,
    };
    let s = path
        .to_str()
        .ok_or_else(|| bad("the path is not valid UTF-8".into()))?;
    if s.contains('\0') {
        return Err(bad("the path contains a NUL byte".into()));
    }
    // (with no edits, the same parse and compile as `mj_loadXML`)
    let mut model = crate::model_build::compile_edited(path, &spec.model_edits).map_err(bad)?;
    if spec
        .manipulation
        .init
        .as_ref()
        .is_some_and(|i| i.reset_welds)
    {
        mj::manip::reset_welds(&mut model);
    }
    crate::commands::apply_gains(spec, &mut model)?;
    Ok(model)
}

/// The compiled model must have the numbering envspec derived from the MJCF (otherwise names in
/// the spec would point at the wrong elements).
fn check_model(spec: &ResolvedSpec, model: &MjModel, world_sites: usize) -> Result<(), EnvError> {
    let m = model.ffi();
    let info = &spec.model;
    let mismatch = |what: String| EnvError::ModelMismatch {
        path: spec.model_path.clone(),
        what,
    };
    let sizes = [
        ("nq", m.nq as usize, info.nq),
        ("nv", m.nv as usize, info.nv),
        ("nu", m.nu as usize, info.nu()),
        ("nbody", m.nbody as usize, info.nbody()),
        ("njnt", m.njnt as usize, info.joints.len()),
        ("nsite", m.nsite as usize, info.sites.len() + world_sites),
        ("ntendon", m.ntendon as usize, info.tendons.len()),
    ];
    for (name, compiled, read) in sizes {
        if compiled != read {
            return Err(mismatch(format!(
                "{name} is {compiled} compiled but {read} from the MJCF"
            )));
        }
    }
    // njnt entries each, checked equal to the joints read from the MJCF above.
    let (qadr, dadr) = (model.jnt_qposadr(), model.jnt_dofadr());
    for (j, joint) in info.joints.iter().enumerate() {
        if qadr[j] as usize != joint.qposadr || dadr[j] as usize != joint.dofadr {
            return Err(mismatch(format!(
                "joint {j} (`{}`) has different addresses",
                joint.name
            )));
        }
    }
    if m.opt.timestep != info.timestep {
        return Err(mismatch(format!(
            "timestep is {} compiled but {} from the MJCF",
            m.opt.timestep, info.timestep
        )));
    }
    // `sensordata[...]` indices come from the sizes read in the MJCF: each sensor read must sit
    // where MuJoCo put it.
    if spec.reads(Field::SensorData) {
        let (adr, dim) = (model.sensor_adr(), model.sensor_dim());
        let mut at = 0;
        for (s, (name, size)) in info.sensors.iter().enumerate() {
            let Some(size) = size else { break };
            let same = adr.get(s).is_some_and(|&a| a as usize == at)
                && dim.get(s).is_some_and(|&d| d as usize == *size);
            if !same {
                return Err(mismatch(format!(
                    "sensor {s} (`{name}`) has another address or size than the MJCF says"
                )));
            }
            at += size;
        }
    }
    Ok(())
}

/// The terrain origins in the model's numerics (see `Env::terrain_origins`).
fn terrain_origins(model: &MjModel) -> Option<(usize, usize)> {
    let id = model.name_to_id(
        mujoco_rs::prelude::MjtObjBase::mjOBJ_NUMERIC,
        crate::model_build::TERRAIN_ORIGINS,
    )?;
    let adr = *model.numeric_adr().get(id)? as usize;
    let size = *model.numeric_size().get(id)? as usize;
    Some((adr, size / 3))
}

/// mjlab's `quat_from_euler_xyz` (w, x, y, z), term for term in its order of operations.
fn quat_from_euler_xyz(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (cy, sy) = ((yaw * 0.5).cos(), (yaw * 0.5).sin());
    let (cr, sr) = ((roll * 0.5).cos(), (roll * 0.5).sin());
    let (cp, sp) = ((pitch * 0.5).cos(), (pitch * 0.5).sin());
    [
        cy * cr * cp + sy * sr * sp,
        cy * sr * cp - sy * cr * sp,
        cy * cr * sp + sy * sr * cp,
        sy * cr * cp - cy * sr * sp,
    ]
}

/// The Hamilton product `a ⊗ b` (w, x, y, z).
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [w1, x1, y1, z1] = a;
    let [w2, x2, y2, z2] = b;
    [
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ]
}
