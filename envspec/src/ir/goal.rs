//! Goal distances and checks, shared by goal reward terms, terminations and info entries.

pub use crate::goal_norm::GoalNorm;
use crate::selector::Selection;

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
