//! Changes made to the model at load time: joint and geom properties, keyframes, and the
//! added elements, actuators, terrain and options (in their own modules) they collect.

use super::{AddedActuator, AddedElement, Integrator, SolverOption, Terrain};

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
    /// [`SOLVER_OPTIONS`](super::SOLVER_OPTIONS); `cone` as MuJoCo's number (0 pyramidal, 1 elliptic).
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
