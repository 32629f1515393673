//! Info entries: what each reports at step (and reset).

use super::{Either, GoalCheck};
use crate::conditions::Condition;
use crate::selector::Selection;

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
    /// One value per `[goal]` part in play (spec kind `goal_parts`), which the Python package
    /// reports as the list of the parts' names whose value is not 0, ordered by value.
    GoalParts(PartSet),
}

/// Which parts a `goal_parts` info entry lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartSet {
    /// Still to complete: 1 or 0 (`which = "remaining"`, Kitchen's `tasks_to_complete`).
    Remaining,
    /// Reached by this step while still to complete: 1 or 0 (`which = "reached"`,
    /// `step_task_completions`).
    Reached,
    /// Reached at least once this episode: the order of completion, 1 for the first, else 0
    /// (`which = "completed"`, `episode_task_completions`).
    Completed,
}

impl PartSet {
    /// The `which` values a spec may write.
    pub const NAMES: &'static [&'static str] = &["remaining", "reached", "completed"];
    /// The set a spec's `which = "..."` names.
    pub fn parse(s: &str) -> Option<PartSet> {
        match s {
            "remaining" => Some(PartSet::Remaining),
            "reached" => Some(PartSet::Reached),
            "completed" => Some(PartSet::Completed),
            _ => None,
        }
    }
    /// The `which` a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            PartSet::Remaining => "remaining",
            PartSet::Reached => "reached",
            PartSet::Completed => "completed",
        }
    }
}

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
            InfoKind::Term(_) | InfoKind::GoalParts(_) => (None, None),
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
