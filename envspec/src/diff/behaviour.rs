//! Behaviour keys: what an IR item computes, built from its fields, without what does not change
//! behaviour (names, docs, how a selector was spelled: `xpos[$main_body]` and `xpos[torso]` select
//! the same elements). Two items behave the same exactly when their keys are equal. Numbers are
//! compared by their bits, as the env's results are.

use crate::ir::*;
use crate::selector::{Field, Selection};

/// A float by its bits (`-0.0` and `0.0` differ; a NaN equals the same NaN).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Bits(u64);

fn bits(x: f64) -> Bits {
    Bits(x.to_bits())
}

fn bits_all(v: &[f64]) -> Vec<Bits> {
    v.iter().copied().map(bits).collect()
}

fn range(r: Option<(f64, f64)>) -> Option<(Bits, Bits)> {
    r.map(|(a, b)| (bits(a), bits(b)))
}

/// The elements a selection reads: field and flat indices (not its text or element names).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Sel {
    field: Field,
    indices: Vec<usize>,
}

pub(crate) fn sel(s: &Selection) -> Sel {
    Sel {
        field: s.field,
        indices: s.indices.clone(),
    }
}

/// An observation segment, wherever it sits in the vector.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SegmentKey {
    source: Sel,
    minus: Option<Sel>,
    apply: Option<Apply>,
    clip: Option<(Bits, Bits)>,
    scale: Option<Bits>,
    /// The indicator, compared by its whole resolved value.
    indicator: Option<String>,
}

pub(crate) fn segment(s: &Segment) -> SegmentKey {
    SegmentKey {
        source: sel(&s.source),
        minus: s.minus.as_ref().map(sel),
        apply: s.apply,
        clip: range(s.clip),
        scale: s.scale.map(bits),
        indicator: s.indicator.map(|i| format!("{i:?}")),
    }
}

#[derive(Clone, Debug, PartialEq)]
enum TermKindKey {
    Velocity(Sel),
    Healthy,
    SumSquares(Sel, Option<(Bits, Bits)>, Option<(Bits, Bits)>),
    Norm(Sel, Option<Sel>),
    Quadratic(Sel, Vec<Bits>, Vec<Bits>),
    Value(Sel, Option<Divisor>),
    Constant,
    WeightedSquare(Sel, Bits),
    GoalSparse(GoalCheckKey),
    GoalDense(GoalDistanceKey),
    GoalMissed(GoalCheckKey),
    GoalDistance(GoalDistanceKey),
    GoalsMissed(Vec<GoalCheckKey>),
    PartsReached,
    /// A legged kernel, compared by its whole resolved value.
    Legged(String),
}

/// A goal distance: what it compares and how it sums.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GoalDistanceKey {
    achieved: Sel,
    /// `None`: the env-held goal vector.
    desired: Option<Sel>,
    norm: GoalNorm,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GoalCheckKey {
    distance: GoalDistanceKey,
    threshold: Bits,
    strict: bool,
}

fn goal_distance(g: &GoalDistance) -> GoalDistanceKey {
    GoalDistanceKey {
        achieved: sel(&g.achieved),
        desired: match &g.desired {
            Desired::Select(s) => Some(sel(s)),
            Desired::Goal => None,
        },
        norm: g.norm,
    }
}

pub(crate) fn goal_check(c: &GoalCheck) -> GoalCheckKey {
    GoalCheckKey {
        distance: goal_distance(&c.distance),
        threshold: bits(c.threshold),
        strict: c.strict,
    }
}

/// A reward term's value (not the info key it is reported under).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TermKey {
    kind: TermKindKey,
    weight: Bits,
    cost: bool,
    before: bool,
    paid_when_unhealthy: bool,
    /// The gating conditions, compared by their whole resolved value.
    only_if: String,
}

pub(crate) fn term(t: &RewardTerm) -> TermKey {
    let kind = match &t.kind {
        TermKind::Velocity { source } => TermKindKey::Velocity(sel(source)),
        TermKind::Healthy => TermKindKey::Healthy,
        TermKind::SumSquares {
            source,
            clip_input,
            clip,
        } => TermKindKey::SumSquares(sel(source), range(*clip_input), range(*clip)),
        TermKind::Norm { source, minus } => TermKindKey::Norm(sel(source), minus.as_ref().map(sel)),
        TermKind::Quadratic {
            source,
            coefs,
            targets,
        } => TermKindKey::Quadratic(sel(source), bits_all(coefs), bits_all(targets)),
        TermKind::Value { source, divide_by } => TermKindKey::Value(sel(source), *divide_by),
        TermKind::Constant => TermKindKey::Constant,
        TermKind::WeightedSquare { source, target } => {
            TermKindKey::WeightedSquare(sel(source), bits(*target))
        }
        TermKind::GoalSparse(c) => TermKindKey::GoalSparse(goal_check(c)),
        TermKind::GoalDense(g) => TermKindKey::GoalDense(goal_distance(g)),
        TermKind::GoalMissed(c) => TermKindKey::GoalMissed(goal_check(c)),
        TermKind::GoalDistance(g) => TermKindKey::GoalDistance(goal_distance(g)),
        TermKind::GoalsMissed(cs) => TermKindKey::GoalsMissed(cs.iter().map(goal_check).collect()),
        TermKind::PartsReached => TermKindKey::PartsReached,
        TermKind::Legged(l) => TermKindKey::Legged(format!("{l:?}")),
    };
    TermKey {
        kind,
        weight: bits(t.weight),
        cost: t.cost,
        before: t.before,
        paid_when_unhealthy: t.paid_when_unhealthy,
        only_if: format!("{:?} unless {:?}", t.only_if, t.unless),
    }
}

#[derive(Clone, Debug, PartialEq)]
enum CheckKindKey {
    Finite,
    InRange(Bits, Bits, bool),
    FailsIf(CmpOp, Bits),
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CheckKey {
    kind: CheckKindKey,
    sources: Vec<Sel>,
}

pub(crate) fn check(c: &HealthCheck) -> CheckKey {
    let kind = match c.kind {
        CheckKind::Finite => CheckKindKey::Finite,
        CheckKind::InRange { lo, hi, closed } => CheckKindKey::InRange(bits(lo), bits(hi), closed),
        CheckKind::FailsIf { op, value } => CheckKindKey::FailsIf(op, bits(value)),
    };
    CheckKey {
        kind,
        sources: c.sources.iter().map(sel).collect(),
    }
}

#[derive(Clone, Debug, PartialEq)]
enum DistKey {
    Uniform(Vec<Bits>, Vec<Bits>),
    Normal(Bits),
    Constant(Bits),
    Values(Vec<Bits>),
    Keyframe(usize),
    RootPose(Vec<Bits>),
    TerrainOrigin(usize, usize),
    Meet(Vec<usize>, Vec<Bits>, Vec<usize>, Vec<usize>),
    Rotation(Option<Vec<Bits>>, Bits, Bits, bool),
    UnitQuaternion,
    Settle(u32, Option<(Sel, Bits)>, Vec<usize>),
}

#[derive(Clone, Debug, PartialEq)]
enum UntilKey {
    NormBelow(Bits),
    NormAbove(Bits),
    MinDistance(Bits),
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ResetKey {
    target: Sel,
    dist: DistKey,
    set: bool,
    resample_until: Option<UntilKey>,
    around: Option<Vec<usize>>,
    probability: Option<Bits>,
}

pub(crate) fn reset_step(r: &ResetStep) -> ResetKey {
    let dist = match &r.dist {
        Distribution::Uniform { low, high } => DistKey::Uniform(bits_all(low), bits_all(high)),
        Distribution::Normal { scale } => DistKey::Normal(bits(*scale)),
        Distribution::Constant { value } => DistKey::Constant(bits(*value)),
        Distribution::Values { values } => DistKey::Values(bits_all(values)),
        Distribution::Keyframe { index, .. } => DistKey::Keyframe(*index),
        Distribution::RootPose { ranges } => {
            DistKey::RootPose(ranges.iter().flat_map(|r| [bits(r.0), bits(r.1)]).collect())
        }
        Distribution::TerrainOrigin { rows } => DistKey::TerrainOrigin(rows.0, rows.1),
        Distribution::Rotation(r) => DistKey::Rotation(
            r.axis.map(|a| bits_all(&a)),
            bits(r.angle.0),
            bits(r.angle.1),
            r.parallel,
        ),
        Distribution::UnitQuaternion => DistKey::UnitQuaternion,
        Distribution::Settle(s) => DistKey::Settle(
            s.steps,
            s.require.as_ref().map(|(sel_, x)| (sel(sel_), bits(*x))),
            s.records.clone(),
        ),
        Distribution::Meet(m) => DistKey::Meet(
            m.center.to_vec(),
            bits_all(&[m.offset.as_slice(), &[m.scale, m.gap, m.unchanged]].concat()),
            m.always.clone(),
            m.one_of.clone(),
        ),
    };
    ResetKey {
        target: sel(&r.target),
        dist,
        set: r.set,
        resample_until: r.resample_until.map(|u| match u {
            Until::NormBelow(x) => UntilKey::NormBelow(bits(x)),
            Until::NormAbove(x) => UntilKey::NormAbove(bits(x)),
            Until::MinDistance(x) => UntilKey::MinDistance(bits(x)),
        }),
        around: r.around.clone(),
        probability: r.probability.map(bits),
    }
}

/// An info entry's value (not its key, nor whether it is also reported at reset).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum InfoKey {
    Value(Sel, Option<Sel>, usize),
    Norm(Sel, usize),
    Velocity(Sel, usize),
    /// The reported term's value (none when the index is out of range) and `unweighted`.
    Term(Option<TermKey>, bool),
    GoalReached(GoalCheckKey),
    GoalsReached(Vec<GoalCheckKey>),
    /// The conditions, compared by their whole resolved value.
    Condition(String),
    GoalParts(PartSet, usize),
}

pub(crate) fn info(r: &ResolvedSpec, i: &InfoItem) -> InfoKey {
    match &i.kind {
        InfoKind::Value { source, minus } => {
            InfoKey::Value(sel(source), minus.as_ref().map(sel), i.len)
        }
        InfoKind::Norm { source } => InfoKey::Norm(sel(source), i.len),
        InfoKind::Velocity { source } => InfoKey::Velocity(sel(source), i.len),
        InfoKind::Term(t) => InfoKey::Term(r.reward.get(*t).map(term), i.unweighted),
        InfoKind::GoalReached(c) => InfoKey::GoalReached(goal_check(c)),
        InfoKind::GoalsReached(cs) => InfoKey::GoalsReached(cs.iter().map(goal_check).collect()),
        InfoKind::Condition(cs) => InfoKey::Condition(format!("{cs:?}")),
        InfoKind::GoalParts(which) => InfoKey::GoalParts(*which, i.len),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn selection(text: &str, names: &[&str], indices: &[usize]) -> Selection {
        Selection {
            field: Field::Xpos,
            indices: indices.to_vec(),
            names: names.iter().map(|s| s.to_string()).collect(),
            text: text.into(),
        }
    }

    fn seg(name: &str, doc: &str, source: Selection) -> Segment {
        Segment {
            name: name.into(),
            doc: doc.into(),
            source,
            minus: None,
            apply: None,
            clip: None,
            scale: None,
            indicator: None,
            offset: 0,
        }
    }

    #[test]
    fn keys_ignore_names_docs_and_selector_spelling() {
        let a = seg(
            "a",
            "say \"hi\"",
            selection("xpos[$b]", &["xpos[torso]"], &[3]),
        );
        let b = seg("b", "", selection("xpos[torso]", &["xpos[body1]"], &[3]));
        assert_eq!(segment(&a), segment(&b));
        let c = seg("a", "", selection("xpos[$b]", &["xpos[torso]"], &[4]));
        assert_ne!(segment(&a), segment(&c));
        let mut d = a.clone();
        d.source.field = Field::Xipos;
        assert_ne!(segment(&a), segment(&d));
        let mut e = a.clone();
        e.clip = Some((-0.0, 1.0));
        let mut f = a.clone();
        f.clip = Some((0.0, 1.0));
        assert_ne!(segment(&e), segment(&f), "compared by bits");
    }

    #[test]
    fn term_keys_ignore_the_info_key_but_not_the_weight() {
        let t = RewardTerm {
            name: "forward".into(),
            doc: String::new(),
            kind: TermKind::Velocity {
                source: selection("xpos[torso][0]", &["x"], &[3]),
            },
            weight: 1.0,
            cost: false,
            info: Some("reward_forward".into()),
            before: false,
            paid_when_unhealthy: false,
            only_if: vec![],
            unless: vec![],
        };
        let u = RewardTerm {
            name: "run".into(),
            info: None,
            ..t.clone()
        };
        assert_eq!(term(&t), term(&u));
        let w = RewardTerm {
            weight: 2.0,
            ..t.clone()
        };
        assert_ne!(term(&t), term(&w));
    }
}
