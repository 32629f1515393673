//! The resolved spec (the IR): every name turned into indices, every parameter reference into its
//! value, sizes and the observation layout computed. The runtime executes exactly this; the code
//! generator and `envc show` describe exactly this.

use std::path::PathBuf;

pub use crate::commands::{
    ActionKind, Command, DefaultPose, FeetContact, Gate, LeggedTerm, PdActions,
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

/// Elementwise function applied to an observation segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Apply {
    /// `sin(x)`.
    Sin,
    /// `cos(x)`.
    Cos,
    /// `1.0 if x > 0 else 0.0` (numpy's `x > 0.0` in a float array: a touch sensor's contact).
    Positive,
}

/// One named observation segment.
#[derive(Clone, Debug)]
pub struct Segment {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// What it reads.
    pub source: Selection,
    /// What is subtracted elementwise, if anything.
    pub minus: Option<Selection>,
    /// The function applied after the subtraction.
    pub apply: Option<Apply>,
    /// Clipped to `[lo, hi]` last.
    pub clip: Option<(f64, f64)>,
    /// `scale`: `source` and `minus` are each multiplied by it before the subtraction
    /// (Gymnasium-Robotics' velocities `× dt`).
    pub scale: Option<f64>,
    /// Each element replaced by one of two values by a comparison (after `apply`, before `clip`).
    pub indicator: Option<Indicator>,
    /// Start index in the observation vector.
    pub offset: usize,
}

impl Segment {
    /// The selections the segment reads: `source`, then `minus`.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        std::iter::once(&self.source).chain(&self.minus)
    }
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.source.len()
    }
    /// Whether it has no elements.
    pub fn is_empty(&self) -> bool {
        self.source.is_empty()
    }
    /// One readable name per element, e.g. `cos(qpos[hinge])`.
    pub fn element_names(&self) -> Vec<String> {
        (0..self.len())
            .map(|i| {
                let mut n = self.source.names[i].clone();
                if let Some(m) = &self.minus {
                    n = format!("{n} - {}", m.names[i]);
                }
                if let Some(s) = self.scale {
                    n = format!("{}·({n})", crate::value::format_float(s));
                }
                match self.apply {
                    Some(Apply::Sin) => format!("sin({n})"),
                    Some(Apply::Cos) => format!("cos({n})"),
                    Some(Apply::Positive) => format!("({n} > 0)"),
                    None => n,
                }
            })
            .collect()
    }
}

/// Divisor of a `value` term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Divisor {
    /// The model's physics timestep.
    Timestep,
    /// The env's control step `timestep × frame_skip`.
    Dt,
}

/// What a reward term computes (its kernel, before weight and sign).
#[derive(Clone, Debug)]
pub enum TermKind {
    /// `(x_after − x_before) / dt` of one number.
    Velocity {
        /// The number differentiated.
        source: Selection,
    },
    /// 1 when healthy, else 0.
    Healthy,
    /// `Σ clip_input(x)²` with numpy's pairwise summation. The output `clip` applies to the weighted
    /// value: the term's value is `clip(weight × Σ, clip)` (Humanoid's contact cost).
    SumSquares {
        /// The elements `x`.
        source: Selection,
        /// Each element clipped to this range before squaring.
        clip_input: Option<(f64, f64)>,
        /// The weighted value clipped to this range.
        clip: Option<(f64, f64)>,
    },
    /// `‖x − minus‖₂` (OpenBLAS `ddot` as the env's numerics profile sums it).
    Norm {
        /// The elements `x`.
        source: Selection,
        /// What is subtracted (none: zeros).
        minus: Option<Selection>,
    },
    /// `Σᵢ coefᵢ · pow(xᵢ − targetᵢ, 2)`, left to right.
    Quadratic {
        /// The elements `x`.
        source: Selection,
        /// One coefficient per element.
        coefs: Vec<f64>,
        /// One target per element.
        targets: Vec<f64>,
    },
    /// `x / divisor` of one number.
    Value {
        /// The number `x`.
        source: Selection,
        /// What it is divided by (none: 1).
        divide_by: Option<Divisor>,
    },
    /// 1.
    Constant,
    /// `(weight × (x − target)) × (x − target)` of one number, multiplied in that order (numpy's
    /// `w * (x - t) * (x - t)`); spec kind `weighted_square`.
    WeightedSquare {
        /// The number `x`.
        source: Selection,
        /// What is subtracted from it.
        target: f64,
    },
    /// `1.0 if d ≤ threshold else 0.0` of a goal distance `d` (spec kind `goal_sparse`).
    GoalSparse(GoalCheck),
    /// `exp(−d)` of a goal distance `d` (spec kind `goal_dense`; numpy's `np.exp` under the env's
    /// numerics profile).
    GoalDense(GoalDistance),
    /// `1.0 if d > threshold else 0.0` (spec kind `goal_missed`; as a cost, Gymnasium-Robotics'
    /// sparse `-(d > threshold)`).
    GoalMissed(GoalCheck),
    /// `d` itself (spec kind `goal_distance`; as a cost, Gymnasium-Robotics' dense `-d`).
    GoalDistance(GoalDistance),
    /// `(1.0 if every check is reached else 0.0) − 1.0` (spec kind `goals_missed`):
    /// Gymnasium-Robotics' hand manipulation `success − 1`, +0.0 when reached.
    GoalsMissed(Vec<GoalCheck>),
    /// A legged-locomotion kernel (`tracking`, `sum_abs`, `action_rate`, `feet_air_time`,
    /// `feet_slip`, `joint_limits`).
    Legged(LeggedTerm),
}

impl TermKind {}

/// How a goal distance adds the squared differences (numpy's two ways to spell the same norm,
/// which differ in the last bit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoalNorm {
    /// `np.linalg.norm(a − b, axis=-1)`: `sqrt` of numpy's pairwise sum of the squares (spec
    /// `norm = "pairwise"`; the default of the reward kinds).
    Pairwise,
    /// `np.linalg.norm(a − b)`: OpenBLAS `ddot` as the env's numerics profile sums it, then
    /// `sqrt` (spec `norm = "blas"`; the default of `goal_reached`).
    Blas,
    /// The angle between two quaternions (w first): `2 · arccos(clip(w(a ⊗ conj(b)), −1, 1))`,
    /// numpy's `arccos` under the numerics profile (spec `norm = "angle"`; 4 elements).
    Angle,
    /// As `Angle`, after the achieved orientation's Z Euler angle is replaced by the desired
    /// one's (`quat2euler`, then `euler2quat`; spec `norm = "angle_ignoring_z"`, Gymnasium-Robotics'
    /// `ignore_z_target_rotation`, the pen's).
    AngleIgnoringZ,
}

impl GoalNorm {
    /// The `norm` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["pairwise", "blas", "angle", "angle_ignoring_z"];
    /// The norm a spec's `norm = "..."` names, if any.
    pub fn parse(s: &str) -> Option<GoalNorm> {
        match s {
            "pairwise" => Some(GoalNorm::Pairwise),
            "blas" => Some(GoalNorm::Blas),
            "angle" => Some(GoalNorm::Angle),
            "angle_ignoring_z" => Some(GoalNorm::AngleIgnoringZ),
            _ => None,
        }
    }
    /// The `norm` a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            GoalNorm::Pairwise => "pairwise",
            GoalNorm::Blas => "blas",
            GoalNorm::Angle => "angle",
            GoalNorm::AngleIgnoringZ => "angle_ignoring_z",
        }
    }
}

/// Where a goal distance's desired quantity comes from.
#[derive(Clone, Debug)]
pub enum Desired {
    /// A selection of the simulation (e.g. the target body's position).
    Select(Selection),
    /// The env-held goal vector (spec `desired = "goal"`), set by whoever drives the env
    /// (`Env::set_goal`; a maze sets it to its goal at every reset and goal change).
    Goal,
}

/// `d = ‖achieved − desired‖₂`, summed as `norm` says.
#[derive(Clone, Debug)]
pub struct GoalDistance {
    /// What the env has reached (e.g. the robot's position).
    pub achieved: Selection,
    /// What it should reach.
    pub desired: Desired,
    /// How the squares are summed.
    pub norm: GoalNorm,
}

impl GoalDistance {
    /// Number of coordinates compared.
    pub fn len(&self) -> usize {
        self.achieved.len()
    }
    /// Whether it compares nothing.
    pub fn is_empty(&self) -> bool {
        self.achieved.is_empty()
    }
    /// What the distance reads: `achieved`, and `desired` unless it is the env-held goal.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        let desired = match &self.desired {
            Desired::Select(s) => Some(s),
            Desired::Goal => None,
        };
        std::iter::once(&self.achieved).chain(desired)
    }
}

/// The goal is reached when `d ≤ threshold`, or `d < threshold` when `strict` (a NaN distance
/// never reaches it).
#[derive(Clone, Debug)]
pub struct GoalCheck {
    /// The distance `d`.
    pub distance: GoalDistance,
    /// The largest distance that counts as reached.
    pub threshold: f64,
    /// Reached only below the threshold (Gymnasium-Robotics' `d < distance_threshold`).
    pub strict: bool,
}

/// `[termination.<name>]`: the episode terminates on a step after which the condition holds.
#[derive(Clone, Debug)]
pub struct Termination {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// Spec kind `goal_reached`.
    pub reached: GoalCheck,
}

/// A reward term: `value = weight × kernel` (except `SumSquares` with `clip`, see there, and `Constant`,
/// whose value is exactly `weight`); the reward adds `value`, or `−value` for a cost.
#[derive(Clone, Debug)]
pub struct RewardTerm {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// The kernel.
    pub kind: TermKind,
    /// The kernel's multiplier.
    pub weight: f64,
    /// Subtracted from the reward instead of added.
    pub cost: bool,
    /// The info key that reports its value, if any.
    pub info: Option<String>,
    /// Evaluated at the start of `step`, on the state before the action is applied (spec key
    /// `at = "before"`; Gymnasium v4's Reacher and Pusher distances). Never for `velocity` or
    /// `healthy`.
    pub before: bool,
    /// `healthy` terms only: the kernel is 1 also when unhealthy (spec key `paid_when_unhealthy`;
    /// Gymnasium v4's `float(is_healthy or terminate_when_unhealthy)`).
    pub paid_when_unhealthy: bool,
    /// `only_if`: the term counts only on steps where every condition holds; otherwise its
    /// signed value is `−0.0`, which leaves any sum unchanged.
    pub only_if: Vec<Condition>,
    /// `unless`: the term does not count on steps where every one of these conditions holds
    /// (the `else` of an `only_if`, NaN included); its signed value is then `−0.0`.
    pub unless: Vec<Condition>,
}

impl TermKind {
    /// The selections the kernel reads (none for `healthy` and `constant`).
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        let (a, b) = match self {
            TermKind::Velocity { source }
            | TermKind::SumSquares { source, .. }
            | TermKind::Quadratic { source, .. }
            | TermKind::WeightedSquare { source, .. }
            | TermKind::Value { source, .. } => (Some(source), None),
            TermKind::Norm { source, minus } => (Some(source), minus.as_ref()),
            TermKind::GoalSparse(c) | TermKind::GoalMissed(c) => {
                return Either::Goal(c.distance.sources());
            }
            TermKind::GoalDense(g) | TermKind::GoalDistance(g) => return Either::Goal(g.sources()),
            TermKind::GoalsMissed(cs) => {
                return Either::Many(
                    cs.iter()
                        .flat_map(|c| c.distance.sources())
                        .collect::<Vec<_>>()
                        .into_iter(),
                );
            }
            TermKind::Healthy | TermKind::Constant => (None, None),
            TermKind::Legged(l) => return Either::Many(l.sources().into_iter()),
        };
        Either::Pair(a.into_iter().chain(b))
    }
}

impl RewardTerm {
    /// The `kind` a spec writes for this term.
    pub fn kind_name(&self) -> &'static str {
        match &self.kind {
            TermKind::Velocity { .. } => "velocity",
            TermKind::Healthy => "healthy",
            TermKind::SumSquares { .. } => "sum_squares",
            TermKind::Norm { .. } => "norm",
            TermKind::Quadratic { .. } => "quadratic",
            TermKind::Value { .. } => "value",
            TermKind::Constant => "constant",
            TermKind::WeightedSquare { .. } => "weighted_square",
            TermKind::GoalSparse(_) => "goal_sparse",
            TermKind::GoalDense(_) => "goal_dense",
            TermKind::GoalMissed(_) => "goal_missed",
            TermKind::GoalDistance(_) => "goal_distance",
            TermKind::GoalsMissed(_) => "goals_missed",
            TermKind::Legged(l) => l.kind_name(),
        }
    }
}

/// How the signed term values are added: a list is summed left to right, nested lists first.
#[derive(Clone, Debug, PartialEq)]
pub enum SumNode {
    /// The signed value of reward term `i`.
    Term(usize),
    /// A nested list, summed left to right.
    Sum(Vec<SumNode>),
}

/// A comparison of a health check's `fails_if`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CmpOp {
    /// `<`.
    Lt,
    /// `≤`.
    Le,
    /// `>`.
    Gt,
    /// `≥`.
    Ge,
}

/// What a health check tests.
#[derive(Clone, Debug)]
pub enum CheckKind {
    /// Every element is finite.
    Finite,
    /// Every element is in the range: `lo ≤ x ≤ hi` when closed, `lo < x < hi` when open.
    /// NaN is never in range.
    InRange {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
        /// Whether the ends are in range.
        closed: bool,
    },
    /// Unhealthy when `x op value` for any element (a NaN compares false: healthy).
    FailsIf {
        /// The comparison.
        op: CmpOp,
        /// What the element is compared with.
        value: f64,
    },
}

/// `[health.<name>]`: one check of the env's state.
#[derive(Clone, Debug)]
pub struct HealthCheck {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// What it tests.
    pub kind: CheckKind,
    /// The elements it tests, every selection alike.
    pub sources: Vec<Selection>,
}

/// What a reset step draws.
#[derive(Clone, Debug)]
pub enum Distribution {
    /// numpy `uniform(low, high)` per element.
    Uniform {
        /// Lower end, per element.
        low: Vec<f64>,
        /// Upper end, per element.
        high: Vec<f64>,
    },
    /// `scale × standard_normal()` per element.
    Normal {
        /// The standard deviation.
        scale: f64,
    },
    /// The same value for every element; no draw.
    Constant {
        /// The value.
        value: f64,
    },
    /// One value per element (`value` as an array); no draw.
    Values {
        /// The values.
        values: Vec<f64>,
    },
    /// The whole `qpos` of keyframe `index` (the model's keyframes, then the spec's); no draw.
    Keyframe {
        /// The keyframe's index.
        index: usize,
        /// The keyframe's name.
        name: String,
    },
    /// Six uniforms in the order x, y, z, roll, pitch, yaw: the position offsets are added to a
    /// free joint's position, and `q ← q ⊗ quat_from_euler_xyz(roll, pitch, yaw)` (mjlab's
    /// `reset_root_state_uniform`). The target is the free joint's 7 `qpos`.
    RootPose {
        /// `(low, high)` of x, y, z, roll, pitch, yaw.
        ranges: [(f64, f64); 6],
    },
    /// Points (3 numbers each, starting from `around`) brought together: a meeting point is
    /// drawn as `center + offset + scale × standard_normal()³`; the points `always` and one of
    /// `one_of` (an `integers` draw, first) each move to `gap` short of it along the line from
    /// where they start; a last uniform below `unchanged` keeps `around` as it is
    /// (Gymnasium-Robotics' HandReach goal: the thumb and one finger meet).
    Meet(Box<Meet>),
    /// A rotation of a quaternion target (4 numbers, w first): `angle` uniform, then the axis
    /// (3 uniforms in [−1, 1] when not given), `r = quat_from_angle_and_axis(angle, axis)`
    /// (axis and quaternion each divided by their OpenBLAS norm); `add`: `q ← q ⊗ r`, `set`:
    /// `q ← r` (Gymnasium-Robotics' hand manipulation draws).
    Rotation(Rotation),
    /// `q ← q / ‖q‖` (OpenBLAS norm) of a quaternion target; no draw.
    UnitQuaternion,
    /// Control steps with action 0 in the middle of the reset, then a check that may start the
    /// reset over (see [`Settle`]).
    Settle(Box<Settle>),
    /// A tile of `[terrain]` drawn uniformly (row in `rows`, any column; `integers` draws, row
    /// first), whose spawn origin is added to a free joint's position (mjlab's env origins). The
    /// target is the free joint's 3 position `qpos`.
    TerrainOrigin {
        /// Inclusive range of rows (difficulty levels) drawn from.
        rows: (usize, usize),
    },
}

/// The keys of a `rotation` reset step (see [`Distribution::Rotation`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Rotation {
    /// The axis; None: drawn.
    pub axis: Option<[f64; 3]>,
    /// The angle's uniform range (radians).
    pub angle: (f64, f64),
    /// Then composed with one of the 24 axis-aligned orientations, drawn uniformly (an
    /// `integers` draw; Gymnasium-Robotics' "parallel" rotations).
    pub parallel: bool,
}

/// A `settle` reset step: `steps` control steps (`frame_skip × mj_step` each) with `ctrl` from
/// action 0, then `mj_forward`; when `watch` is not above `above`, the reset starts over from its
/// first step (drawing anew); otherwise the named `[init] record`s are read again.
#[derive(Clone, Debug, PartialEq)]
pub struct Settle {
    /// Control steps.
    pub steps: u32,
    /// The value checked, and the bound it must exceed.
    pub require: Option<(Selection, f64)>,
    /// Indices into `[init] record` of the records read again after settling.
    pub records: Vec<usize>,
}

/// The keys of a `meet` reset step (see [`Distribution::Meet`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Meet {
    /// Indices into the `[init] record` values of the 3 numbers the meeting point is drawn
    /// around.
    pub center: [usize; 3],
    /// Added to `center`.
    pub offset: [f64; 3],
    /// Standard deviation of the meeting point's normal draws.
    pub scale: f64,
    /// Points that always move.
    pub always: Vec<usize>,
    /// Points of which one, drawn uniformly, moves too.
    pub one_of: Vec<usize>,
    /// How far short of the meeting point each moved point stops.
    pub gap: f64,
    /// Probability that the target keeps `around` unchanged (drawn last).
    pub unchanged: f64,
}

impl Distribution {
    /// The spec's `kind` of the distribution.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Distribution::Uniform { .. } => "uniform",
            Distribution::Normal { .. } => "normal",
            Distribution::Constant { .. } | Distribution::Values { .. } => "constant",
            Distribution::Keyframe { .. } => "keyframe",
            Distribution::RootPose { .. } => "root_pose",
            Distribution::TerrainOrigin { .. } => "terrain_origin",
            Distribution::Meet(_) => "meet",
            Distribution::Rotation(_) => "rotation",
            Distribution::UnitQuaternion => "unit_quaternion",
            Distribution::Settle(_) => "settle",
        }
    }
}

/// Redraw the whole block until its norm satisfies the condition.
#[derive(Clone, Copy, Debug)]
pub enum Until {
    /// Until the norm is below the bound.
    NormBelow(f64),
    /// Until the norm is above the bound.
    NormAbove(f64),
    /// Until `‖(around + draw) − around‖ ≥ x` (OpenBLAS norm): redraw while the point is closer
    /// than `x` to where it is drawn around (Gymnasium-Robotics' object placement).
    MinDistance(f64),
}

/// `[reset.<name>]`: one draw applied to the initial state.
#[derive(Clone, Debug)]
pub struct ResetStep {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// A selection of `qpos` or `qvel`.
    pub target: Selection,
    /// What is drawn.
    pub dist: Distribution,
    /// true: the draw replaces the value; false: it is added to the initial value.
    pub set: bool,
    /// Redraw until the block's norm satisfies this, if set.
    pub resample_until: Option<Until>,
    /// `around`: indices into the `[init] record` values; the step writes `around + draw`
    /// (`set`) instead of the draw.
    pub around: Option<Vec<usize>>,
    /// `probability`: one uniform is drawn first, and the step runs only when it is below this.
    pub probability: Option<f64>,
}

/// What an info entry reports.
#[derive(Clone, Debug)]
pub enum InfoKind {
    /// The selected values, minus another selection if given.
    Value {
        /// The values.
        source: Selection,
        /// What is subtracted elementwise.
        minus: Option<Selection>,
    },
    /// The Euclidean norm of the selection.
    Norm {
        /// The elements.
        source: Selection,
    },
    /// `(x_after − x_before) / dt` of the selection.
    Velocity {
        /// The elements.
        source: Selection,
    },
    /// The signed value of reward term `i` (see [`InfoItem::unweighted`]).
    Term(usize),
    /// 1.0 when the goal is reached, else 0.0 (spec kind `goal_reached`; e.g. `success`).
    GoalReached(GoalCheck),
    /// 1.0 when every check is reached, else 0.0 (spec kind `goals_reached`; the float32
    /// product of Gymnasium-Robotics' hand manipulation `is_success`).
    GoalsReached(Vec<GoalCheck>),
    /// 1.0 when every condition holds, else 0.0 (spec kind `condition`).
    Condition(Vec<Condition>),
}

impl InfoKind {}

impl InfoKind {
    /// The selections the entry reads (none for a reward term's value).
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        let (a, b) = match self {
            InfoKind::Value { source, minus } => (Some(source), minus.as_ref()),
            InfoKind::Norm { source } | InfoKind::Velocity { source } => (Some(source), None),
            InfoKind::GoalReached(c) => return Either::Goal(c.distance.sources()),
            InfoKind::GoalsReached(cs) => {
                return Either::Many(
                    cs.iter()
                        .flat_map(|c| c.distance.sources())
                        .collect::<Vec<_>>()
                        .into_iter(),
                );
            }
            InfoKind::Condition(cs) => {
                return Either::Many(
                    cs.iter()
                        .flat_map(|c| c.quantity.sources())
                        .collect::<Vec<_>>()
                        .into_iter(),
                );
            }
            InfoKind::Term(_) => (None, None),
        };
        Either::Pair(a.into_iter().chain(b))
    }
}

/// `[info.<name>]` (or a reward term's `info` key): one entry of the step info.
#[derive(Clone, Debug)]
pub struct InfoItem {
    /// The key in the info dict.
    pub key: String,
    /// The `doc` text.
    pub doc: String,
    /// What it reports.
    pub kind: InfoKind,
    /// Number of values (1 for scalars).
    pub len: usize,
    /// Whether the key is also in the reset info.
    pub at_reset: bool,
    /// `Term` items only: report the term's signed value computed with weight 1 (spec key
    /// `unweighted = true`).
    pub unweighted: bool,
    /// `dtype = "float32"`: Python reports the value as a numpy float32 (the reference's
    /// `is_success`); the value itself is the same.
    pub float32: bool,
    /// `dtype = "bool"`: Python reports the value as a numpy bool (0.0 is `False`), as
    /// Gymnasium-Robotics' Adroit `success`.
    pub boolean: bool,
}

/// Changes the runtime makes to the model when it loads it, before compiling (spec sections
/// `[actuators]` and `[physics]`). Empty for most specs: the model is then compiled as is.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelEdits {
    /// Added after the model's own actuators, in this order (they are the last action entries).
    pub actuators: Vec<AddedActuator>,
    /// `mjOption.timestep`, when the spec sets it.
    pub timestep: Option<f64>,
    /// `mjOption.integrator`, when the spec sets it.
    pub integrator: Option<Integrator>,
    /// Solver options `[physics]` sets (`cone`, `iterations`, `impratio`, …), in the order of
    /// [`SOLVER_OPTIONS`]; `cone` as MuJoCo's number (0 pyramidal, 1 elliptic).
    pub solver: Vec<(SolverOption, f64)>,
    /// Elements added to the model (`[bodies]`, `[sites]`, `[geoms]`, `[cameras]`, `[lights]`).
    pub added: Vec<AddedElement>,
    /// Joint properties set by `[joint_properties]` rows (resolved per joint, model order).
    pub joints: Vec<JointEdit>,
    /// Each `[joint_properties]` row resolved: its pattern, the joints it matches and the values
    /// it sets (parameters resolved), for `envc diff`.
    pub joint_rows: Vec<JointRow>,
    /// Contact properties set by `[geom_properties]` rows (resolved per geom, model order).
    pub geoms: Vec<GeomEdit>,
    /// Each `[geom_properties]` row resolved: its pattern, the geoms it matches and the values it
    /// sets, for `envc diff`.
    pub geom_rows: Vec<JointRow>,
    /// Keyframes added after the model's own (`[keyframes.*]`).
    pub keyframes: Vec<SpecKeyframe>,
    /// `[terrain]`: a grid of generated tiles added to the world body.
    pub terrain: Option<Terrain>,
    /// `[physics] forward_before_observation`: not a model change but a step option: `mj_forward`
    /// runs after the reward and termination, so the observation reads the state's own
    /// kinematics rather than the last physics substep's (mjlab's step).
    pub forward_before_observation: bool,
}

/// `[terrain]`: a grid of `rows × cols` square tiles centred on the world origin, each made by
/// one generator at a difficulty, with a border around the grid (mjlab's `TerrainGenerator`,
/// whose geometry it reproduces). The runtime generates the geoms and each tile's spawn origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// A tile's size along x and y, in metres.
    pub tile_size: [f64; 2],
    /// Tiles along x (difficulty grows along x in the curriculum layout).
    pub rows: usize,
    /// Tiles along y.
    pub cols: usize,
    /// Width of the flat border around the grid, in metres (0: none).
    pub border_width: f64,
    /// Depth of the border boxes below z = 0.
    pub border_height: f64,
    /// The layout's draws (`default_rng(seed)`): which generator and difficulty each tile gets in
    /// the random layout. Part of the model: the terrain is the same in every episode.
    pub seed: u64,
    /// Curriculum layout: column `c` is generator `c`, difficulty rises with the row, no draws.
    /// Otherwise each tile draws its generator (by proportion) and its difficulty.
    pub curriculum: bool,
    /// `(low, high)` of the difficulty in [0, 1].
    pub difficulty: (f64, f64),
    /// The generators, in declaration order.
    pub tiles: Vec<TerrainTile>,
}

/// One `[terrain.<name>]` generator.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainTile {
    /// The table's name.
    pub name: String,
    /// Its share of the tiles in the random layout.
    pub proportion: f64,
    /// What it builds.
    pub kind: TileKind,
}

/// The tile generators (each mjlab's of the same name; `difficulty` interpolates its ranges).
#[derive(Clone, Debug, PartialEq)]
pub enum TileKind {
    /// A flat 1 m thick box with its top at z = 0.
    Flat,
    /// Square stairs up to a central platform (`inverted`: down into a pit), from boxes.
    PyramidStairs {
        /// Step height at difficulty 0 and 1.
        step_height: (f64, f64),
        /// Depth of each step.
        step_width: f64,
        /// Side of the central platform.
        platform_width: f64,
        /// Flat frame around the stairs.
        border_width: f64,
        /// Down instead of up.
        inverted: bool,
    },
    /// A pyramid slope up to a flat top (`inverted`: down into a pit), as a heightfield.
    PyramidSlope {
        /// Slope (rise over run) at difficulty 0 and 1.
        slope: (f64, f64),
        /// Side of the flat platform.
        platform_width: f64,
        /// Flat frame around the slope.
        border_width: f64,
        /// Down instead of up.
        inverted: bool,
        /// Metres per heightfield cell.
        horizontal_scale: f64,
        /// Metres per height unit.
        vertical_scale: f64,
    },
    /// Heights drawn uniformly from `noise` in steps of `noise_step`, one per cell, as a
    /// heightfield (the difficulty scales the range when `scale_with_difficulty`).
    RandomUniform {
        /// `(low, high)` height, metres.
        noise: (f64, f64),
        /// Height quantum, metres.
        noise_step: f64,
        /// Flat frame around the noise.
        border_width: f64,
        /// Metres per heightfield cell.
        horizontal_scale: f64,
        /// Metres per height unit.
        vertical_scale: f64,
        /// Scale the noise range by the difficulty.
        scale_with_difficulty: bool,
    },
}

/// A `[joint_properties]` row resolved: (pattern, matched joints, (key, values) it sets).
pub type JointRow = (String, Vec<String>, Vec<(String, Vec<f64>)>);

/// Properties of one joint set by the spec (`None`: the model's value stays).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointEdit {
    /// The joint's name.
    pub joint: String,
    /// `dof_armature`.
    pub armature: Option<f64>,
    /// `dof_damping`.
    pub damping: Option<f64>,
    /// `dof_frictionloss`.
    pub frictionloss: Option<f64>,
    /// The `[joint_properties]` row (pattern) that set each value last, for `envc show`.
    pub rows: Vec<String>,
}

/// Contact properties of one geom set by the spec (`None`: the model's value stays). Arrays set
/// their first entries only (`friction = [0.6]` sets the sliding friction).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeomEdit {
    /// The geom's name.
    pub geom: String,
    /// `contype`, `conaffinity`, `condim`, `priority`.
    pub ints: [Option<i32>; 4],
    /// `solmix`, `margin`, `gap`.
    pub reals: [Option<f64>; 3],
    /// `friction` (up to 3), `solref` (up to 2), `solimp` (up to 5): the leading entries set.
    pub friction: Vec<f64>,
    /// See `friction`.
    pub solref: Vec<f64>,
    /// See `friction`.
    pub solimp: Vec<f64>,
    /// The `[geom_properties]` rows (patterns) that set one of its values, in order.
    pub rows: Vec<String>,
}

impl GeomEdit {
    /// The integer keys, in the order of `ints`.
    pub const INTS: [&'static str; 4] = ["contype", "conaffinity", "condim", "priority"];
    /// The real keys, in the order of `reals`.
    pub const REALS: [&'static str; 3] = ["solmix", "margin", "gap"];
    /// The array keys with their most entries.
    pub const ARRAYS: [(&'static str, usize); 3] = [("friction", 3), ("solref", 2), ("solimp", 5)];
}

/// A keyframe a spec declares (`[keyframes.<name>]`): the compiled model's `qpos0` (or the
/// model keyframe it starts `from`), with the spec's values written at their `qpos` addresses.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecKeyframe {
    /// The table's name (the keyframe's name in the model).
    pub name: String,
    /// A model keyframe to start from (its index), else `qpos0`.
    pub from: Option<usize>,
    /// (qpos address, value), in the order written.
    pub values: Vec<(usize, f64)>,
}

/// A model element a spec adds. Bodies hang from the world, after the model's own bodies, so
/// every existing index stays; sites, geoms and cameras attach to any body (`world` by default).
#[derive(Clone, Debug, PartialEq)]
pub enum AddedElement {
    /// `[bodies]`: a body child of the world, with its joints and an optional marker geom.
    Body {
        /// Its name.
        name: String,
        /// Position in the world frame.
        pos: [f64; 3],
        /// (name, kind, axis): slide or hinge joints along or about a world axis, or a free or
        /// ball joint (axis unused), in order.
        joints: Vec<(String, crate::mjcf::JointKind, [f64; 3])>,
        /// A marker geom (no contacts): type, size, rgba.
        geom: Option<(AddedGeomType, [f64; 3], [f32; 4])>,
        /// A mocap body: placed by `mocap_pos` / `mocap_quat`, never moved by the physics.
        mocap: bool,
        /// Gravity compensation (0: none, 1: the body floats).
        gravcomp: f64,
        /// The marker geom's mass (None: MuJoCo's default density).
        mass: Option<f64>,
        /// A mocap body's weld partner: a weld equality ties that body to this one.
        weld: Option<String>,
    },
    /// `[sites]`: a site on a body.
    Site {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Radius of its sphere.
        size: f64,
        /// Colour.
        rgba: [f32; 4],
    },
    /// `[geoms]`: a geom on a body.
    Geom {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Its shape.
        kind: AddedGeomType,
        /// Position in the body frame.
        pos: [f64; 3],
        /// MuJoCo's `size` for the shape.
        size: [f64; 3],
        /// Colour.
        rgba: [f32; 4],
        /// Whether it collides (false: `contype = conaffinity = 0`).
        contact: bool,
        /// Its mass (None: from the density).
        mass: Option<f64>,
        /// Its density (None: MuJoCo's 1000).
        density: Option<f64>,
    },
    /// `[cameras]`: a camera on a body.
    Camera {
        /// Its name (render with it by `camera_name`).
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Orientation as MJCF's `xyaxes`, if given.
        xyaxes: Option<[f64; 6]>,
        /// Vertical field of view in degrees, if given.
        fovy: Option<f64>,
    },
    /// `[lights]`: a light on a body.
    Light {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Direction it shines in.
        dir: [f64; 3],
    },
}

/// The shapes an added geom may have (MuJoCo's geom types).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AddedGeomType {
    /// A sphere.
    Sphere,
    /// A box.
    Box,
    /// A capsule.
    Capsule,
    /// A cylinder.
    Cylinder,
    /// An infinite collision plane (size: half-lengths drawn, 0 = infinite, and grid spacing);
    /// MuJoCo takes planes on static bodies only (the world or a body without joints).
    Plane,
}

impl AddedGeomType {
    /// The `type` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["sphere", "box", "capsule", "cylinder", "plane"];
    /// The shape a spec's `type = "..."` names, if any.
    pub fn parse(s: &str) -> Option<AddedGeomType> {
        Some(match s {
            "sphere" => AddedGeomType::Sphere,
            "box" => AddedGeomType::Box,
            "capsule" => AddedGeomType::Capsule,
            "cylinder" => AddedGeomType::Cylinder,
            "plane" => AddedGeomType::Plane,
            _ => return None,
        })
    }
}

impl ModelEdits {
    /// Whether the spec changes nothing in the model (it is then compiled as is).
    pub fn is_empty(&self) -> bool {
        self.actuators.is_empty()
            && self.timestep.is_none()
            && self.integrator.is_none()
            && self.solver.is_empty()
            && self.added.is_empty()
            && self.joints.is_empty()
            && self.geoms.is_empty()
            && self.keyframes.is_empty()
    }
}

/// An actuator on one hinge or slide joint (MuJoCo's `<motor>`, `<position>`, `<velocity>`).
#[derive(Clone, Debug, PartialEq)]
pub struct AddedActuator {
    /// Its name in the model.
    pub name: String,
    /// The `[actuators.<section>]` table that added it.
    pub section: String,
    /// The joint it drives.
    pub joint: String,
    /// Motor or servo.
    pub kind: ActuatorKind,
    /// Transmission gear.
    pub gear: f64,
    /// Always limited: the action space is the control range.
    pub ctrlrange: (f64, f64),
    /// Limits of the force it applies, if limited.
    pub forcerange: Option<(f64, f64)>,
}

/// How an added actuator turns `ctrl` into force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActuatorKind {
    /// Force (torque) = gear × ctrl.
    Motor,
    /// Position servo: force = kp × (ctrl − q) − kv × q̇.
    Position {
        /// Position gain.
        kp: f64,
        /// Velocity damping of the servo, if any.
        kv: Option<f64>,
    },
    /// Velocity servo: force = kv × (ctrl − q̇).
    Velocity {
        /// Velocity gain.
        kv: f64,
    },
}

/// A numeric `mjOption` field `[physics]` may set (MJCF's `<option>` attribute of that name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverOption {
    /// `cone`: 0 pyramidal (MuJoCo's default), 1 elliptic.
    Cone,
    /// `iterations`: main solver iterations.
    Iterations,
    /// `ls_iterations`: line-search iterations.
    LsIterations,
    /// `noslip_iterations`: no-slip solver iterations.
    NoslipIterations,
    /// `ccd_iterations`: convex collision iterations.
    CcdIterations,
    /// `tolerance`: main solver tolerance.
    Tolerance,
    /// `ls_tolerance`: line-search tolerance.
    LsTolerance,
    /// `impratio`: frictional-to-normal impedance ratio.
    Impratio,
}

/// The `[physics]` solver options: (key, option, whole number, smallest value). `cone` is read as
/// a name (`"pyramidal"`, `"elliptic"`); the others as numbers.
pub const SOLVER_OPTIONS: &[(&str, SolverOption, bool, f64)] = &[
    ("cone", SolverOption::Cone, true, 0.0),
    ("iterations", SolverOption::Iterations, true, 1.0),
    ("ls_iterations", SolverOption::LsIterations, true, 1.0),
    (
        "noslip_iterations",
        SolverOption::NoslipIterations,
        true,
        0.0,
    ),
    ("ccd_iterations", SolverOption::CcdIterations, true, 1.0),
    ("tolerance", SolverOption::Tolerance, false, 0.0),
    ("ls_tolerance", SolverOption::LsTolerance, false, 0.0),
    ("impratio", SolverOption::Impratio, false, f64::MIN_POSITIVE),
];

/// MuJoCo's integrators, spelt as in MJCF's `<option integrator>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// `Euler` (MuJoCo's default): semi-implicit Euler.
    Euler,
    /// `RK4`: fourth-order Runge-Kutta.
    Rk4,
    /// `implicit`: implicit in velocity.
    Implicit,
    /// `implicitfast`: implicit in velocity, without the Coriolis terms.
    ImplicitFast,
}

impl Integrator {
    /// The `integrator` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["Euler", "RK4", "implicit", "implicitfast"];
    /// The integrator a spec's `integrator = "..."` names, if any.
    pub fn parse(s: &str) -> Option<Integrator> {
        match s {
            "Euler" => Some(Integrator::Euler),
            "RK4" => Some(Integrator::Rk4),
            "implicit" => Some(Integrator::Implicit),
            "implicitfast" => Some(Integrator::ImplicitFast),
            _ => None,
        }
    }
    /// The name as MJCF and specs write it.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "Euler",
            Integrator::Rk4 => "RK4",
            Integrator::Implicit => "implicit",
            Integrator::ImplicitFast => "implicitfast",
        }
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
