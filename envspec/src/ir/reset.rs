//! Reset steps: the target each writes, the distribution it draws and when it redraws.

use crate::selector::Selection;

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
