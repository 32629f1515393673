//! Reward terms: each term's value on the current state, the reward sum, and `compute_reward`
//! for goal tasks.

use envspec::ir::*;
use envspec::{Field, Selection};

use super::Env;
use crate::numerics::{clip, norm, pairwise_sum, square_pow};

impl Env {
    /// `weight × kernel` of one term (unsigned); `weight` is the term's, or 1 for `unweighted` info.
    pub(super) fn term(
        &self,
        i: usize,
        t: &RewardTerm,
        slot: Option<usize>,
        healthy: bool,
        weight: f64,
    ) -> f64 {
        let sim = &self.sim;
        // A gated-off term's signed value is −0.0, which leaves any sum unchanged.
        let unless = !t.unless.is_empty() && t.unless.iter().all(|c| sim.condition_holds(c));
        if unless || !t.only_if.iter().all(|c| sim.condition_holds(c)) {
            return if t.cost { 0.0 } else { -0.0 };
        }
        let kernel = match &t.kind {
            TermKind::Velocity { source } => {
                let k = slot.expect("velocity terms have a slot");
                (sim.get(source, 0) - self.before[k]) / self.dt
            }
            TermKind::Healthy => (healthy || t.paid_when_unhealthy) as u8 as f64,
            TermKind::SumSquares {
                source,
                clip_input: None,
                clip: out_clip,
            } if self.action_f32 && source.field == Field::Action => {
                let v = sum_squares_f32(sim.field(source.field), source, weight);
                return clip_output(v, out_clip);
            }
            TermKind::SumSquares {
                source,
                clip_input,
                clip: out_clip,
            } => {
                let v = sum_squares(sim.field(source.field), source, clip_input, weight);
                return clip_output(v, out_clip);
            }
            TermKind::Norm { source, minus } => {
                let f = sim.field(source.field);
                match minus {
                    Some(m) => {
                        let g = sim.field(m.field);
                        norm(sim.numerics, source.len(), &|k| {
                            f[source.indices[k]] - g[m.indices[k]]
                        })
                    }
                    None => norm(sim.numerics, source.len(), &|k| f[source.indices[k]]),
                }
            }
            TermKind::Quadratic {
                source,
                coefs,
                targets,
            } => {
                let f = sim.field(source.field);
                let mut acc = 0.0;
                for k in 0..source.len() {
                    let q = coefs[k] * square_pow(f[source.indices[k]] - targets[k]);
                    acc = if k == 0 { q } else { acc + q };
                }
                acc
            }
            TermKind::Value { source, divide_by } => {
                let x = sim.get(source, 0);
                match divide_by {
                    Some(Divisor::Timestep) => x / self.timestep,
                    Some(Divisor::Dt) => x / self.dt,
                    None => x,
                }
            }
            TermKind::Constant => return weight,
            TermKind::PartsReached => sim.parts.as_ref().map_or(0, |c| c.reached_count()) as f64,
            TermKind::WeightedSquare { source, target } => {
                let d = sim.get(source, 0) - target;
                return (weight * d) * d;
            }
            TermKind::Legged(l) => {
                sim.legged
                    .kernel(i, l, sim.numerics, &|f| sim.field(f), &sim.action)
            }
            TermKind::GoalSparse(GoalCheck { distance: g, .. })
            | TermKind::GoalMissed(GoalCheck { distance: g, .. })
            | TermKind::GoalDense(g)
            | TermKind::GoalDistance(g) => {
                crate::goal::kernel(&t.kind, sim.numerics, &|_, k| sim.goal_pair(g, k))
                    .expect("a goal kind")
            }
            TermKind::GoalsMissed(cs) => crate::goal::kernel(&t.kind, sim.numerics, &|i, k| {
                sim.goal_pair(&cs[i].distance, k)
            })
            .expect("a goal kind"),
        };
        weight * kernel
    }

    /// The reward sum over the current signed term values.
    pub(super) fn sum(&self, node: &SumNode) -> f64 {
        sum_values(node, &self.term_values)
    }

    /// `compute_reward` of a `[goal]` task for rows of `goal_dim` numbers each: the reward sum of
    /// the goal terms, each evaluated on `achieved` against `desired` exactly as `step` does. `Err`
    /// names a reward term that reads anything but the goal distance (no reward from goals
    /// alone), or says the env has no `[goal]`.
    pub fn compute_reward(
        &self,
        achieved: &[f64],
        desired: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        let n = self.spec.goal_dim;
        if self.spec.manipulation.goal.is_none() || n == 0 {
            return Err(format!("{} has no [goal] table", self.spec.id));
        }
        // Where each goal distance's elements lie in a goal row (a parts count reads the
        // parts' own positions).
        let mut at: Vec<Vec<Vec<usize>>> = vec![];
        for t in &self.spec.reward {
            if matches!(t.kind, TermKind::PartsReached) {
                at.push(vec![]);
                continue;
            }
            let found = crate::manipulation::goal_positions(&self.spec, &t.kind);
            let Some(positions) = found else {
                return Err(format!(
                    "[reward.{}] (kind {}) is not a goal term comparing the [goal] achieved values with the goal vector, so the reward is not a function of the goals",
                    t.name,
                    t.kind_name()
                ));
            };
            at.push(positions);
        }
        if achieved.len() != out.len() * n || desired.len() != out.len() * n {
            return Err(format!(
                "{} and {} goal numbers for {} rows of {n}",
                achieved.len(),
                desired.len(),
                out.len()
            ));
        }
        let mut values = vec![0.0; self.spec.reward.len()];
        for (r, o) in out.iter_mut().enumerate() {
            let (a, d) = (&achieved[r * n..(r + 1) * n], &desired[r * n..(r + 1) * n]);
            for ((v, t), at) in values.iter_mut().zip(&self.spec.reward).zip(&at) {
                *v = match (&t.kind, self.parts_and_checklist()) {
                    (TermKind::PartsReached, Some((parts, c))) => {
                        let x = t.weight * c.count_row(parts, self.sim.numerics, a, d) as f64;
                        if t.cost { -x } else { x }
                    }
                    _ => crate::goal::term_value(t, self.sim.numerics, a, d, &|i, k| at[i][k])
                        .unwrap_or(f64::NAN),
                };
            }
            *o = sum_values(&self.spec.reward_sum, &values);
        }
        Ok(())
    }
}

impl Env {
    /// A `[goal]` of parts and its checklist.
    fn parts_and_checklist(
        &self,
    ) -> Option<(
        &envspec::manipulation::GoalParts,
        &crate::goal_parts::Checklist,
    )> {
        let parts = self.spec.manipulation.goal.as_ref()?.parts.as_ref()?;
        Some((parts, self.sim.parts.as_ref()?))
    }

    /// After the physics: which parts still to complete the state reaches.
    pub(super) fn evaluate_parts(&mut self) {
        let Some(parts) = self
            .spec
            .manipulation
            .goal
            .as_ref()
            .and_then(|g| g.parts.as_ref())
        else {
            return;
        };
        let achieved = &self
            .spec
            .manipulation
            .goal
            .as_ref()
            .expect("parts")
            .achieved;
        // Taken out while the simulation is read (no allocation).
        let mut c = self.sim.parts.take().expect("built with the parts");
        let sim = &self.sim;
        c.evaluate(parts, sim.numerics, &|k| sim.get(achieved, k));
        self.sim.parts = Some(c);
    }

    /// After the reward: the reached parts are completed; whether every part now is.
    pub(super) fn commit_parts(&mut self) -> bool {
        let Some(parts) = self
            .spec
            .manipulation
            .goal
            .as_ref()
            .and_then(|g| g.parts.as_ref())
        else {
            return false;
        };
        let c = self.sim.parts.as_mut().expect("built with the parts");
        c.commit(parts);
        parts.terminate_when_done && c.all_completed()
    }
}

/// The reward sum over signed term values: each list left to right, nested lists first.
fn sum_values(node: &SumNode, values: &[f64]) -> f64 {
    match node {
        SumNode::Term(i) => values[*i],
        SumNode::Sum(children) => {
            let mut it = children.iter();
            let Some(first) = it.next() else { return 0.0 };
            it.fold(sum_values(first, values), |acc, c| {
                acc + sum_values(c, values)
            })
        }
    }
}

/// `weight × Σ x²` of a float32 action as numpy computes it: float32 squares and pairwise sum,
/// the weight rounded to float32 (NEP 50).
fn sum_squares_f32(f: &[f64], source: &Selection, weight: f64) -> f64 {
    let s = pairwise_sum(source.len(), &|k| {
        let x = f[source.indices[k]] as f32;
        x * x
    });
    ((weight as f32) * s) as f64
}

/// `weight × Σ x²` (pairwise sum), each `x` first clipped to `clip_input` where given.
fn sum_squares(f: &[f64], source: &Selection, clip_input: &Option<(f64, f64)>, weight: f64) -> f64 {
    let s = pairwise_sum(source.len(), &|k| {
        let x = f[source.indices[k]];
        let x = match clip_input {
            Some((lo, hi)) => clip(x, *lo, *hi),
            None => x,
        };
        x * x
    });
    weight * s
}

/// A weighted value clipped to the term's output range, where it has one.
fn clip_output(v: f64, range: &Option<(f64, f64)>) -> f64 {
    match range {
        Some((lo, hi)) => clip(v, *lo, *hi),
        None => v,
    }
}
