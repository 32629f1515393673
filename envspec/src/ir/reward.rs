//! Reward terms: their kernels, weights and gates, and how their values are summed.

use super::{Either, GoalCheck, GoalDistance};
use crate::commands::LeggedTerm;
use crate::conditions::Condition;
use crate::selector::Selection;

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
    /// The number of `[goal]` parts still to complete that are reached now (spec kind
    /// `parts_reached`; Franka Kitchen's reward, `len(step_task_completions)`).
    PartsReached,
    /// A legged-locomotion kernel (`tracking`, `sum_abs`, `action_rate`, `feet_air_time`,
    /// `feet_slip`, `joint_limits`).
    Legged(LeggedTerm),
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
            TermKind::Healthy | TermKind::Constant | TermKind::PartsReached => (None, None),
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
            TermKind::PartsReached => "parts_reached",
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
