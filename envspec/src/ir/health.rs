//! Whether an episode goes on: health checks and `[termination.*]` conditions.

use super::GoalCheck;
use crate::conditions::CmpOp;
use crate::selector::Selection;

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
