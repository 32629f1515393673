//! Goal distances and the goal-reaching kernels (`goal_sparse`, `goal_dense`, `goal_reached`),
//! as numpy computes them. `Env` evaluates them on the simulation and the env-held goal; the
//! functions taking vectors evaluate the same kernels on given achieved / desired goals (a maze's
//! batched `compute_reward` for hindsight relabelling).

use envspec::ir::{GoalCheck, GoalNorm, RewardTerm, TermKind};

use crate::numerics::{Profile, exp, norm, pairwise_sum};

/// `‖a − d‖₂` of `n` elements given as `diff(k) = aₖ − dₖ`.
pub(crate) fn distance(
    kind: GoalNorm,
    profile: Profile,
    n: usize,
    diff: &dyn Fn(usize) -> f64,
) -> f64 {
    match kind {
        // np.linalg.norm(x, axis=-1): sqrt(add.reduce(x * x)), numpy's pairwise sum.
        GoalNorm::Pairwise => pairwise_sum(n, &|k| {
            let x = diff(k);
            x * x
        })
        .sqrt(),
        // np.linalg.norm(x): OpenBLAS ddot under the profile, then sqrt.
        GoalNorm::Blas => norm(profile, n, diff),
    }
}

/// `d ≤ threshold`, or `d < threshold` when strict (false for a NaN distance).
pub(crate) fn reached_by(c: &GoalCheck, profile: Profile, diff: &dyn Fn(usize) -> f64) -> bool {
    let d = distance(c.distance.norm, profile, c.distance.len(), diff);
    if c.strict {
        d < c.threshold
    } else {
        d <= c.threshold
    }
}

/// The kernel of a goal reward term (`None` for other kinds).
pub(crate) fn kernel(
    kind: &TermKind,
    profile: Profile,
    diff: &dyn Fn(usize) -> f64,
) -> Option<f64> {
    match kind {
        TermKind::GoalSparse(c) => Some(if reached_by(c, profile, diff) {
            1.0
        } else {
            0.0
        }),
        TermKind::GoalDense(g) => Some(exp(profile, -distance(g.norm, profile, g.len(), diff))),
        // `d > threshold` (false for a NaN distance, as numpy's comparison).
        TermKind::GoalMissed(c) => Some(
            if distance(c.distance.norm, profile, c.distance.len(), diff) > c.threshold {
                1.0
            } else {
                0.0
            },
        ),
        TermKind::GoalDistance(g) => Some(distance(g.norm, profile, g.len(), diff)),
        _ => None,
    }
}

/// The signed value of a goal reward term for `achieved` against `desired`, exactly as
/// `Env::step` computes it: `±weight × kernel`. `None` when `t` is not a goal term or a vector
/// does not have the term's length.
pub fn term_value(
    t: &RewardTerm,
    profile: Profile,
    achieved: &[f64],
    desired: &[f64],
) -> Option<f64> {
    let n = match &t.kind {
        TermKind::GoalSparse(c) | TermKind::GoalMissed(c) => c.distance.len(),
        TermKind::GoalDense(g) | TermKind::GoalDistance(g) => g.len(),
        _ => return None,
    };
    if achieved.len() != n || desired.len() != n {
        return None;
    }
    let v = t.weight * kernel(&t.kind, profile, &|k| achieved[k] - desired[k])?;
    Some(if t.cost { -v } else { v })
}

/// Whether `achieved` reaches `desired` under the check. `None` when a vector does not have the
/// check's length.
pub fn reached(c: &GoalCheck, profile: Profile, achieved: &[f64], desired: &[f64]) -> Option<bool> {
    let n = c.distance.len();
    (achieved.len() == n && desired.len() == n)
        .then(|| reached_by(c, profile, &|k| achieved[k] - desired[k]))
}
