//! Goal tasks: the goal-reaching terms of the spec language (`goal_sparse`, `goal_dense`,
//! `goal_reached`) that an outer env puts over a task spec. A maze is one: its `reward_type`,
//! `goal_threshold` and `continuing_task` become a reward term, a reached check (`success`) and,
//! for an episodic task, a `[termination.*]` condition over the robot's `qpos[0:2]` and the
//! env-held goal vector (docs/maze.md shows them as spec text).

use crate::diagnostic::{Code, Diagnostic, SourceFile};
use crate::ir::*;
use crate::mjcf::ModelInfo;
use crate::selector::{self, Selection};

/// A goal-reaching task over the env-held goal vector.
#[derive(Clone, Debug)]
pub struct GoalTask {
    /// The reward: one `goal_sparse` or `goal_dense` term.
    pub reward: RewardTerm,
    /// When the goal counts as reached: the `success` value, and the termination when `terminate`.
    pub reached: GoalCheck,
    /// Whether reaching the goal ends the episode.
    pub terminate: bool,
}

impl GoalTask {
    /// Gymnasium-Robotics' maze task: `achieved` (a selector of `model`, e.g. `qpos[0:2]`) against
    /// the goal vector. Reward: sparse `1.0 if d ≤ threshold else 0.0` or dense `exp(−d)`, both
    /// with the pairwise norm (`np.linalg.norm(a - b, axis=-1)` in `compute_reward`); reached:
    /// `d ≤ threshold` with the BLAS norm (`np.linalg.norm(a - b)` in `compute_terminated` and
    /// `info["success"]`).
    pub fn reach(
        model: &ModelInfo,
        achieved: &str,
        dense: bool,
        threshold: f64,
        terminate: bool,
    ) -> Result<GoalTask, Diagnostic> {
        if !(threshold.is_finite() && threshold >= 0.0) {
            return Err(Diagnostic::new(
                Code::E0803,
                format!("goal threshold {threshold} is not a finite distance ≥ 0"),
            ));
        }
        let achieved = select(model, achieved)?;
        if achieved.is_empty() {
            return Err(Diagnostic::new(
                Code::E0804,
                format!("the goal's achieved `{}` selects no element", achieved.text),
            ));
        }
        let distance = |norm| GoalDistance {
            achieved: achieved.clone(),
            desired: Desired::Goal,
            norm,
        };
        let kind = if dense {
            TermKind::GoalDense(distance(GoalNorm::Pairwise))
        } else {
            TermKind::GoalSparse(GoalCheck {
                distance: distance(GoalNorm::Pairwise),
                threshold,
                strict: false,
            })
        };
        Ok(GoalTask {
            reward: RewardTerm {
                name: "goal".into(),
                doc: "the goal reward".into(),
                kind,
                weight: 1.0,
                cost: false,
                info: None,
                before: false,
                paid_when_unhealthy: false,
                only_if: vec![],
                unless: vec![],
            },
            reached: GoalCheck {
                distance: distance(GoalNorm::Blas),
                threshold,
                strict: false,
            },
            terminate,
        })
    }

    /// The task spec with this goal task in place of its own reward and termination: the goal term
    /// is appended and is the whole reward sum (the spec's own terms are still computed, for the
    /// info entries that report them), health no longer terminates, and the only termination is
    /// reaching the goal (when `terminate`). The goal vector gets the task's length.
    pub fn apply(&self, mut spec: ResolvedSpec) -> Result<ResolvedSpec, Diagnostic> {
        let n = self.reached.distance.len();
        if spec.goal_dim != 0 && spec.goal_dim != n {
            return Err(Diagnostic::new(
                Code::E0801,
                format!(
                    "the goal task reads {n} elements but the spec `{}` uses a goal vector of {}",
                    spec.id, spec.goal_dim
                ),
            ));
        }
        spec.goal_dim = n;
        spec.needs_rne_post_constraint |= self
            .reward
            .kind
            .sources()
            .any(|s| s.field.needs_rne_post_constraint());
        spec.reward.push(self.reward.clone());
        spec.reward_sum = SumNode::Sum(vec![SumNode::Term(spec.reward.len() - 1)]);
        spec.terminate_when_unhealthy = false;
        spec.termination = if self.terminate {
            vec![Termination {
                name: "goal_reached".into(),
                doc: "reaching the goal ends the episode".into(),
                reached: self.reached.clone(),
            }]
        } else {
            vec![]
        };
        Ok(spec)
    }
}

fn select(model: &ModelInfo, text: &str) -> Result<Selection, Diagnostic> {
    let file = SourceFile::new("<goal task>", text.to_string());
    let loc = crate::Location::new(&file, 0..text.len());
    selector::resolve(text, &loc, model, &|name| {
        Err(Diagnostic::new(
            Code::E0201,
            format!("`${name}`: a goal task's selector takes no parameters"),
        ))
    })
}
