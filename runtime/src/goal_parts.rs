//! A `[goal]` of named parts, kept as a checklist through an episode (Gymnasium-Robotics' Franka
//! Kitchen): which parts are still to complete, which the last step reached, and in which order
//! the episode completed them. A part is reached when `‖achieved − desired‖ < threshold`.

use envspec::ir::PartSet;
use envspec::manipulation::GoalParts;

use crate::numerics::Profile;

/// The checklist's state.
#[derive(Clone, Debug)]
pub(crate) struct Checklist {
    /// Per part: still to complete.
    remaining: Vec<bool>,
    /// Per part: reached by the last step while still to complete.
    reached: Vec<bool>,
    /// Per part: its place in the episode's order of completion (1 for the first), 0 if never.
    completed: Vec<u32>,
    /// The number of parts completed so far this episode.
    n_completed: u32,
}

impl Checklist {
    pub(crate) fn new(parts: &GoalParts) -> Checklist {
        let n = parts.parts.len();
        Checklist {
            remaining: vec![true; n],
            reached: vec![false; n],
            completed: vec![0; n],
            n_completed: 0,
        }
    }

    /// A new episode: every part to complete, none reached.
    pub(crate) fn reset(&mut self) {
        self.remaining.fill(true);
        self.reached.fill(false);
        self.completed.fill(0);
        self.n_completed = 0;
    }

    /// Which parts still to complete `achieved` reaches (`achieved[k]`: the achieved goal's
    /// element `k`, the parts end to end, against their desired values).
    pub(crate) fn evaluate(
        &mut self,
        parts: &GoalParts,
        profile: Profile,
        achieved: &dyn Fn(usize) -> f64,
    ) {
        for (i, part) in parts.parts.iter().enumerate() {
            self.reached[i] = self.remaining[i]
                && part_reached(parts, i, profile, &|k| achieved(part.offset + k));
        }
    }

    /// How many parts the last `evaluate` found reached.
    pub(crate) fn reached_count(&self) -> usize {
        self.reached.iter().filter(|&&r| r).count()
    }

    /// After the reward: reached parts are completed (in part order within a step), and leave
    /// the list with `remove_done`.
    pub(crate) fn commit(&mut self, parts: &GoalParts) {
        for i in 0..self.reached.len() {
            if !self.reached[i] {
                continue;
            }
            if parts.remove_done {
                self.remaining[i] = false;
            }
            if self.completed[i] == 0 {
                self.n_completed += 1;
                self.completed[i] = self.n_completed;
            }
        }
    }

    /// Every part has been completed at least once this episode.
    pub(crate) fn all_completed(&self) -> bool {
        self.completed.iter().all(|&c| c > 0)
    }

    /// One value per part for a `goal_parts` info entry.
    pub(crate) fn write(&self, which: PartSet, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = match which {
                PartSet::Remaining => self.remaining[i] as u8 as f64,
                PartSet::Reached => self.reached[i] as u8 as f64,
                PartSet::Completed => self.completed[i] as f64,
            };
        }
    }

    /// The number of parts still to complete that one row of goals reaches (a batched
    /// `compute_reward` against the current list, as the reference's is).
    pub(crate) fn count_row(
        &self,
        parts: &GoalParts,
        profile: Profile,
        achieved: &[f64],
        desired: &[f64],
    ) -> usize {
        (0..parts.parts.len())
            .filter(|&i| {
                let off = parts.parts[i].offset;
                self.remaining[i]
                    && part_reached_pairs(parts, i, profile, &|k| {
                        (achieved[off + k], desired[off + k])
                    })
            })
            .count()
    }
}

/// Whether part `i` is reached, its achieved values given and its desired the spec's.
fn part_reached(
    parts: &GoalParts,
    i: usize,
    profile: Profile,
    achieved: &dyn Fn(usize) -> f64,
) -> bool {
    let desired = &parts.parts[i].desired;
    part_reached_pairs(parts, i, profile, &|k| (achieved(k), desired[k]))
}

/// `‖achieved − desired‖ < threshold` over part `i`'s elements (false for a NaN distance).
fn part_reached_pairs(
    parts: &GoalParts,
    i: usize,
    profile: Profile,
    pair: &dyn Fn(usize) -> (f64, f64),
) -> bool {
    let n = parts.parts[i].len();
    crate::goal::distance(parts.norm, profile, n, pair) < parts.threshold
}
