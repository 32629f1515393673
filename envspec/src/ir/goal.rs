//! Goal distances and checks, shared by goal reward terms, terminations and info entries.

use crate::selector::Selection;

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
