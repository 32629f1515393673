//! Domain randomization (`[events.<name>]`): model fields of named elements redrawn at startup,
//! at every reset or at an interval, and pushes (velocity kicks). The IR here is what the runtime
//! executes (`runtime/src/events.rs`) and what `envc show` / `envc diff` describe; the resolver is
//! `resolve/events.rs`. The draw order is documented in docs/spec-reference.md ("Draw order").

/// A model field an event can write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventField {
    /// `geom_friction[g][k]`: k = 0 sliding, 1 torsional, 2 rolling.
    GeomFriction(usize),
    /// `body_mass`.
    BodyMass,
    /// `body_ipos` (the centre of mass in the body frame): x, y, z.
    BodyIpos,
    /// One axis of `body_ipos` (0 x, 1 y, 2 z): per-axis ranges, as mjlab's `body_com_offset`.
    BodyIposAxis(usize),
    /// `body_pos` (the body's position in its parent's frame): x, y, z. A placement, as
    /// Gymnasium-Robotics' Adroit moves its door, board or object at reset.
    BodyPos,
    /// One axis of `body_pos` (0 x, 1 y, 2 z).
    BodyPosAxis(usize),
    /// `site_pos` (the site's position in its body's frame): x, y, z.
    SitePos,
    /// One axis of `site_pos` (0 x, 1 y, 2 z).
    SitePosAxis(usize),
    /// One Euler angle (0 x, 1 y, 2 z) of the body's orientation in its parent's frame: after the
    /// reset events, `body_quat = euler2quat(angles)` (Gymnasium-Robotics' `rotations`), the
    /// angles no event drew being 0. Reset events only, `operation = "abs"`.
    BodyQuatEuler(usize),
    /// `dof_damping` of every dof of the joint.
    JointDamping,
    /// `dof_armature` of every dof of the joint.
    JointArmature,
    /// `actuator_gainprm[0]`.
    ActuatorGain,
    /// `actuator_biasprm[0..3]`.
    ActuatorBias,
    /// A position servo's kp: `gainprm[0] = kp` and `biasprm[1] = −kp` from one draw.
    ActuatorKp,
    /// `opt.gravity`: x, y, z.
    Gravity,
    /// `opt.timestep`.
    Timestep,
}

/// What an event's `elements` name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementKind {
    /// Geoms, by name.
    Geom,
    /// Bodies, by name.
    Body,
    /// Sites, by name.
    Site,
    /// Joints, by name (their dofs are written).
    Joint,
    /// Actuators, by name.
    Actuator,
    /// Gravity and the timestep: model-wide, no elements.
    Model,
}

impl ElementKind {
    /// The plural for messages, e.g. `geoms`.
    pub fn plural(self) -> &'static str {
        match self {
            ElementKind::Geom => "geoms",
            ElementKind::Body => "bodies",
            ElementKind::Site => "sites",
            ElementKind::Joint => "joints",
            ElementKind::Actuator => "actuators",
            ElementKind::Model => "model",
        }
    }
    /// The singular for messages, e.g. `geom`.
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::Geom => "geom",
            ElementKind::Body => "body",
            ElementKind::Site => "site",
            ElementKind::Joint => "joint",
            ElementKind::Actuator => "actuator",
            ElementKind::Model => "model",
        }
    }
}

/// Every field by the name an event's `field` writes, e.g. `geom_friction`.
pub const FIELDS: &[(&str, EventField)] = &[
    ("geom_friction.sliding", EventField::GeomFriction(0)),
    ("geom_friction.torsional", EventField::GeomFriction(1)),
    ("geom_friction.rolling", EventField::GeomFriction(2)),
    ("body_mass", EventField::BodyMass),
    ("body_ipos", EventField::BodyIpos),
    ("body_ipos.x", EventField::BodyIposAxis(0)),
    ("body_ipos.y", EventField::BodyIposAxis(1)),
    ("body_ipos.z", EventField::BodyIposAxis(2)),
    ("body_pos", EventField::BodyPos),
    ("body_pos.x", EventField::BodyPosAxis(0)),
    ("body_pos.y", EventField::BodyPosAxis(1)),
    ("body_pos.z", EventField::BodyPosAxis(2)),
    ("site_pos", EventField::SitePos),
    ("site_pos.x", EventField::SitePosAxis(0)),
    ("site_pos.y", EventField::SitePosAxis(1)),
    ("site_pos.z", EventField::SitePosAxis(2)),
    ("body_quat_euler.x", EventField::BodyQuatEuler(0)),
    ("body_quat_euler.y", EventField::BodyQuatEuler(1)),
    ("body_quat_euler.z", EventField::BodyQuatEuler(2)),
    ("joint_damping", EventField::JointDamping),
    ("joint_armature", EventField::JointArmature),
    ("actuator_gain", EventField::ActuatorGain),
    ("actuator_bias", EventField::ActuatorBias),
    ("actuator_kp", EventField::ActuatorKp),
    ("gravity", EventField::Gravity),
    ("timestep", EventField::Timestep),
];

impl EventField {
    /// The name a spec writes for it.
    pub fn name(self) -> &'static str {
        FIELDS
            .iter()
            .find(|(_, f)| *f == self)
            .map(|(n, _)| *n)
            .unwrap_or("?")
    }
    /// The field a spec's `field = "..."` names, if any.
    pub fn parse(s: &str) -> Option<EventField> {
        FIELDS.iter().find(|(n, _)| *n == s).map(|(_, f)| *f)
    }
    /// What kind of element its `elements` name.
    pub fn elements(self) -> ElementKind {
        match self {
            EventField::GeomFriction(_) => ElementKind::Geom,
            EventField::BodyMass
            | EventField::BodyIpos
            | EventField::BodyIposAxis(_)
            | EventField::BodyPos
            | EventField::BodyPosAxis(_)
            | EventField::BodyQuatEuler(_) => ElementKind::Body,
            EventField::SitePos | EventField::SitePosAxis(_) => ElementKind::Site,
            EventField::JointDamping | EventField::JointArmature => ElementKind::Joint,
            EventField::ActuatorGain | EventField::ActuatorBias | EventField::ActuatorKp => {
                ElementKind::Actuator
            }
            EventField::Gravity | EventField::Timestep => ElementKind::Model,
        }
    }
    /// Values of one element that the field holds when it is not per dof (ipos, bias and
    /// gravity: 3; joint fields: the joint's dof count, see [`Event::components`]).
    pub fn width(self) -> usize {
        match self {
            EventField::BodyIpos
            | EventField::BodyPos
            | EventField::SitePos
            | EventField::ActuatorBias
            | EventField::Gravity => 3,
            _ => 1,
        }
    }
    /// The smallest value the field may take (results are clamped to it): friction, mass,
    /// damping, armature and kp are ≥ 0; the timestep is > 0 (and ≤ `limits::MAX_TIMESTEP`).
    pub fn lower_bound(self) -> Option<f64> {
        match self {
            EventField::GeomFriction(_)
            | EventField::BodyMass
            | EventField::JointDamping
            | EventField::JointArmature
            | EventField::ActuatorKp => Some(0.0),
            EventField::Timestep => Some(MIN_TIMESTEP),
            _ => None,
        }
    }
    /// The largest value the field may take (results are clamped to it), if any.
    pub fn upper_bound(self) -> Option<f64> {
        match self {
            EventField::Timestep => Some(crate::limits::MAX_TIMESTEP),
            _ => None,
        }
    }
    /// Whether MuJoCo's derived constants (`mj_setConst`: subtree masses, `dof_invweight0`,
    /// `body_invweight0`, `actuator_acc0`, ...) depend on the field, so they are recomputed after
    /// it changes.
    pub fn needs_set_const(self) -> bool {
        matches!(
            self,
            EventField::BodyMass
                | EventField::BodyIpos
                | EventField::BodyIposAxis(_)
                | EventField::JointArmature
        )
    }
}

/// The smallest timestep a randomized timestep is clamped to (a Gaussian draw may go below 0).
pub const MIN_TIMESTEP: f64 = 1e-6;

/// When an event draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventMode {
    /// At the first reset and at every reset with a seed (from the compiled values).
    Startup,
    /// At every reset.
    Reset,
    /// Every `interval` seconds of simulated time; a range draws each interval uniformly.
    Interval {
        /// Shortest interval in seconds.
        low: f64,
        /// Longest interval in seconds (equal to `low`: a fixed interval).
        high: f64,
    },
}

impl EventMode {
    /// The `mode` a spec writes for it.
    pub fn name(&self) -> &'static str {
        match self {
            EventMode::Startup => "startup",
            EventMode::Reset => "reset",
            EventMode::Interval { .. } => "interval",
        }
    }
}

/// The distribution an event draws from, on the env's stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventDist {
    /// numpy `uniform(low, high)`.
    Uniform {
        /// Lower end.
        low: f64,
        /// Upper end.
        high: f64,
    },
    /// `exp(uniform(ln low, ln high))` (numpy's `np.exp` under the env's numerics profile).
    LogUniform {
        /// Lower end (> 0).
        low: f64,
        /// Upper end.
        high: f64,
    },
    /// `mean + std × standard_normal()`, numpy's `normal(mean, std)`.
    Gaussian {
        /// The mean.
        mean: f64,
        /// The standard deviation.
        std: f64,
    },
}

impl EventDist {
    /// The `distribution` a spec writes for it.
    pub fn name(&self) -> &'static str {
        match self {
            EventDist::Uniform { .. } => "uniform",
            EventDist::LogUniform { .. } => "log_uniform",
            EventDist::Gaussian { .. } => "gaussian",
        }
    }
    /// The interval the draws fall in (a Gaussian: mean ± 3 std, which holds 99.7 %).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            EventDist::Uniform { low, high } | EventDist::LogUniform { low, high } => (low, high),
            EventDist::Gaussian { mean, std } => (mean - 3.0 * std, mean + 3.0 * std),
        }
    }
    /// `uniform[0.8, 1.2]`, `gaussian(mean 0, std 0.1)`.
    pub fn describe(&self) -> String {
        match *self {
            EventDist::Uniform { low, high } => format!("uniform[{low}, {high}]"),
            EventDist::LogUniform { low, high } => format!("log_uniform[{low}, {high}]"),
            EventDist::Gaussian { mean, std } => format!("gaussian(mean {mean}, std {std})"),
        }
    }
}

/// How a draw combines with the compiled value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// `value = base + draw`.
    Add,
    /// `value = base × draw`.
    Scale,
    /// `value = draw`.
    Abs,
}

impl Operation {
    /// The `operation` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["add", "scale", "abs"];
    /// The operation a spec's `operation = "..."` names, if any.
    pub fn parse(s: &str) -> Option<Operation> {
        match s {
            "add" => Some(Operation::Add),
            "scale" => Some(Operation::Scale),
            "abs" => Some(Operation::Abs),
            _ => None,
        }
    }
    /// The `operation` a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            Operation::Add => "add",
            Operation::Scale => "scale",
            Operation::Abs => "abs",
        }
    }
    /// The range of `op(base, draw)` for draws in `[lo, hi]`.
    pub fn apply_range(self, base: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
        let (a, b) = match self {
            Operation::Add => (base + lo, base + hi),
            Operation::Scale => (base * lo, base * hi),
            Operation::Abs => (lo, hi),
        };
        (a.min(b), a.max(b))
    }
    /// `op(base, draw)`: the value written.
    pub fn apply(self, base: f64, draw: f64) -> f64 {
        match self {
            Operation::Add => base + draw,
            Operation::Scale => base * draw,
            Operation::Abs => draw,
        }
    }
}

/// A named model element an event writes: its name and its index in the model's numbering
/// (geoms: in `ModelInfo::geoms`; the runtime looks geom ids up by name).
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Its name in the model.
    pub name: String,
    /// Its index in the model's numbering of its kind.
    pub index: usize,
    /// Joints: the first dof and the dof count (the values a joint field writes).
    pub dofs: (usize, usize),
}

/// What an event does.
#[derive(Clone, Debug, PartialEq)]
pub enum EventKind {
    /// A model field of each element: `value = operation(base, draw)`.
    Model {
        /// The field written.
        field: EventField,
        /// Empty for gravity and the timestep.
        elements: Vec<Element>,
        /// What is drawn.
        dist: EventDist,
        /// How the draw combines with the compiled value.
        operation: Operation,
        /// One draw for every value the event writes (else one per value).
        shared: bool,
    },
    /// `qvel[x] += uniform(x)`, `qvel[y] += uniform(y)` of each free joint.
    Push {
        /// The free joints pushed.
        joints: Vec<Element>,
        /// Range of the x velocity kick.
        x: (f64, f64),
        /// Range of the y velocity kick.
        y: (f64, f64),
    },
}

/// `[events.<name>]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// When it draws.
    pub mode: EventMode,
    /// What it writes.
    pub kind: EventKind,
    /// The elements as written (names and patterns), for `show` and `diff`.
    pub elements_text: Vec<String>,
}

impl Event {
    /// Values written per element (joint fields: the joint's dofs).
    pub fn components(&self, e: &Element) -> usize {
        match &self.kind {
            EventKind::Model { field, .. } => match field.elements() {
                ElementKind::Joint => e.dofs.1,
                _ => field.width(),
            },
            EventKind::Push { .. } => 2,
        }
    }
    /// The field's name (`push` for pushes).
    pub fn field_name(&self) -> &'static str {
        match &self.kind {
            EventKind::Model { field, .. } => field.name(),
            EventKind::Push { .. } => "push",
        }
    }
    /// Whether the event changes the model (pushes change the state only).
    pub fn writes_model(&self) -> bool {
        matches!(self.kind, EventKind::Model { .. })
    }
}

#[cfg(test)]
mod tests {
    use crate::selector::glob;

    #[test]
    fn globs() {
        assert!(glob("*", "trunk"));
        assert!(glob("*_calf", "FR_calf"));
        assert!(!glob("*_calf", "FR_thigh"));
        assert!(glob("F?_hip", "FL_hip"));
        assert!(glob("trunk", "trunk"));
        assert!(!glob("trunk", "trunk2"));
        assert!(glob("a*b*c", "axxbyyc"));
        assert!(!glob("a*b*c", "axxbyy"));
    }
}
