//! Goal distances and the goal-reaching kernels (`goal_sparse`, `goal_dense`, `goal_missed`,
//! `goal_distance`, `goals_missed`, `goal_reached`, `goals_reached`), as numpy computes them.
//! `Env` evaluates them on the simulation and the env-held goal; the functions taking vectors
//! evaluate the same kernels on given achieved / desired goals (batched `compute_reward` for
//! hindsight relabelling). Elements come as pairs `(achievedₖ, desiredₖ)`.

use envspec::ir::{GoalCheck, GoalNorm, RewardTerm, TermKind};

use crate::numerics::{Profile, acos, clip, exp, norm, pairwise_sum};

/// One goal distance's elements: `pair(k) = (achievedₖ, desiredₖ)`.
pub(crate) type Pairs<'a> = &'a dyn Fn(usize) -> (f64, f64);

/// The distance of `n` elements under `kind`.
pub(crate) fn distance(kind: GoalNorm, profile: Profile, n: usize, pair: Pairs) -> f64 {
    let diff = |k: usize| {
        let (a, d) = pair(k);
        a - d
    };
    match kind {
        // np.linalg.norm(x, axis=-1): sqrt(add.reduce(x * x)), numpy's pairwise sum.
        GoalNorm::Pairwise => pairwise_sum(n, &|k| {
            let x = diff(k);
            x * x
        })
        .sqrt(),
        // np.linalg.norm(x): OpenBLAS ddot under the profile, then sqrt.
        GoalNorm::Blas => norm(profile, n, &diff),
        // Gymnasium-Robotics' `_goal_distance`: w of quat_mul(a, quat_conjugate(b)), clipped,
        // then 2 · arccos.
        GoalNorm::Angle | GoalNorm::AngleIgnoringZ => {
            let (mut a, b) = (
                [0, 1, 2, 3].map(|k| pair(k).0),
                [0, 1, 2, 3].map(|k| pair(k).1),
            );
            if kind == GoalNorm::AngleIgnoringZ {
                use crate::manipulation::{euler2quat, quat2euler};
                let mut e = quat2euler(a, profile);
                e[2] = quat2euler(b, profile)[2];
                a = euler2quat(e);
            }
            let w = a[0] * b[0] - a[1] * -b[1] - a[2] * -b[2] - a[3] * -b[3];
            2.0 * acos(profile, clip(w, -1.0, 1.0))
        }
    }
}

/// `d ≤ threshold`, or `d < threshold` when strict (false for a NaN distance).
pub(crate) fn reached_by(c: &GoalCheck, profile: Profile, pair: Pairs) -> bool {
    let d = distance(c.distance.norm, profile, c.distance.len(), pair);
    if c.strict {
        d < c.threshold
    } else {
        d <= c.threshold
    }
}

/// Whether every check is reached; `pair(i, k)` gives check `i`'s elements.
pub(crate) fn all_reached(
    checks: &[GoalCheck],
    profile: Profile,
    pair: &dyn Fn(usize, usize) -> (f64, f64),
) -> bool {
    checks
        .iter()
        .enumerate()
        .all(|(i, c)| reached_by(c, profile, &|k| pair(i, k)))
}

/// The kernel of a goal reward term (`None` for other kinds); `pair(i, k)` gives the elements
/// of the term's distance `i` (0 for the single-distance kinds).
pub(crate) fn kernel(
    kind: &TermKind,
    profile: Profile,
    pair: &dyn Fn(usize, usize) -> (f64, f64),
) -> Option<f64> {
    let one = |k| pair(0, k);
    match kind {
        TermKind::GoalSparse(c) => Some(if reached_by(c, profile, &one) {
            1.0
        } else {
            0.0
        }),
        TermKind::GoalDense(g) => Some(exp(profile, -distance(g.norm, profile, g.len(), &one))),
        // `d > threshold` (false for a NaN distance, as numpy's comparison).
        TermKind::GoalMissed(c) => Some(
            if distance(c.distance.norm, profile, c.distance.len(), &one) > c.threshold {
                1.0
            } else {
                0.0
            },
        ),
        TermKind::GoalDistance(g) => Some(distance(g.norm, profile, g.len(), &one)),
        // float32(success) − 1.0: +0.0 when reached.
        TermKind::GoalsMissed(cs) => Some(
            if all_reached(cs, profile, pair) {
                1.0
            } else {
                0.0
            } - 1.0,
        ),
        _ => None,
    }
}

/// The signed value of a goal reward term for one row of achieved and desired goals, exactly as
/// `Env::step` computes it: `±weight × kernel`. `at(i, k)` is where element `k` of distance `i`
/// lies in the row. `None` when `t` is not a goal term, or a position is outside the row.
pub fn term_value(
    t: &RewardTerm,
    profile: Profile,
    achieved: &[f64],
    desired: &[f64],
    at: &dyn Fn(usize, usize) -> usize,
) -> Option<f64> {
    let fits =
        |i: usize, n: usize| (0..n).all(|k| at(i, k) < achieved.len() && at(i, k) < desired.len());
    let fit = match &t.kind {
        TermKind::GoalSparse(c) | TermKind::GoalMissed(c) => fits(0, c.distance.len()),
        TermKind::GoalDense(g) | TermKind::GoalDistance(g) => fits(0, g.len()),
        TermKind::GoalsMissed(cs) => cs
            .iter()
            .enumerate()
            .all(|(i, c)| fits(i, c.distance.len())),
        _ => return None,
    };
    if !fit {
        return None;
    }
    let v = t.weight
        * kernel(&t.kind, profile, &|i, k| {
            (achieved[at(i, k)], desired[at(i, k)])
        })?;
    Some(if t.cost { -v } else { v })
}

/// Whether `achieved` reaches `desired` under the check. `None` when a vector does not have the
/// check's length.
pub fn reached(c: &GoalCheck, profile: Profile, achieved: &[f64], desired: &[f64]) -> Option<bool> {
    let n = c.distance.len();
    (achieved.len() == n && desired.len() == n)
        .then(|| reached_by(c, profile, &|k| (achieved[k], desired[k])))
}
