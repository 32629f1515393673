//! `[events.*]` (domain randomization): what a change does to the distribution the policy trains
//! on. Events are matched by name and compared resolved (ranges, elements by their model names).

use super::{Ctx, pos};
use crate::diff::{Change, Pos, RuleId};
use crate::events::{Event, EventDist, EventKind, EventMode};

const NOT_COMPARABLE: &str = "returns are not comparable";

fn fmt_range((lo, hi): (f64, f64)) -> String {
    format!("[{lo}, {hi}]")
}

fn mode_text(m: &EventMode) -> String {
    match *m {
        EventMode::Interval { low, high } if low == high => format!("interval every {low} s"),
        EventMode::Interval { low, high } => format!("interval every {low}–{high} s"),
        _ => m.name().to_string(),
    }
}

/// When an event draws, in words; an interval says its period, so two intervals read apart.
fn mode_effect(m: &EventMode) -> String {
    match *m {
        EventMode::Startup => "drawn once per seed".into(),
        EventMode::Reset => "drawn every episode".into(),
        EventMode::Interval { low, high } if low == high => {
            format!("drawn every {low} s during episodes")
        }
        EventMode::Interval { low, high } => {
            format!("drawn every {low}–{high} s during episodes")
        }
    }
}

/// The ranges of an event as (label, interval) pairs: a distribution's support, a push's x, y.
fn ranges(e: &Event) -> Vec<(&'static str, (f64, f64), String)> {
    match &e.kind {
        EventKind::Model { dist, .. } => {
            let text = match *dist {
                EventDist::Uniform { low, high } | EventDist::LogUniform { low, high } => {
                    fmt_range((low, high))
                }
                EventDist::Gaussian { mean, std } => format!("mean {mean}, std {std}"),
            };
            vec![("range", dist.support(), text)]
        }
        EventKind::Push { x, y, .. } => vec![("x", *x, fmt_range(*x)), ("y", *y, fmt_range(*y))],
    }
}

/// Widened, narrowed or shifted, and what that does to training.
fn range_effect(what: &str, old: (f64, f64), new: (f64, f64), was: &str, now: &str) -> String {
    let contains = |a: (f64, f64), b: (f64, f64)| a.0 <= b.0 && b.1 <= a.1;
    let (verb, effect) = if contains(new, old) {
        ("widened", "the policy trains on a wider distribution")
    } else if contains(old, new) {
        (
            "narrowed",
            "the policy trains on a narrower distribution and may not cover what it met before",
        )
    } else {
        ("shifted", "the policy trains on other values")
    };
    format!("{what} {verb} from {was} to {now}: {effect}; {NOT_COMPARABLE}")
}

fn names(e: &Event) -> Vec<String> {
    match &e.kind {
        EventKind::Model { elements, .. } => elements.iter().map(|x| x.name.clone()).collect(),
        EventKind::Push { joints, .. } => joints.iter().map(|x| x.name.clone()).collect(),
    }
}

/// One event present on both sides, with where each side writes it.
struct Pair<'a> {
    o: &'a Event,
    n: &'a Event,
    subject: String,
    oa: Option<Pos>,
    na: Option<Pos>,
}

impl Pair<'_> {
    fn change(&self, rule: RuleId, aspect: &str, was: String, now: String) -> Change {
        Change::new(rule, self.subject.clone(), aspect)
            .values(Some(was), Some(now))
            .at(self.oa.clone(), self.na.clone())
    }
}

pub(super) fn events(cx: &mut Ctx) {
    let (old, new) = (&cx.old_r.events, &cx.new_r.events);
    let at = |spec: &crate::syntax::Spec, name: &str| {
        spec.events
            .iter()
            .find(|s| s.name == name)
            .map(|s| pos(&s.name_loc))
    };
    let mut out = vec![];
    for o in old {
        let (oa, subject) = (at(cx.old, &o.name), format!("events.{}", o.name));
        let Some(n) = new.iter().find(|n| n.name == o.name) else {
            out.push(removed(o, subject, oa));
            continue;
        };
        let na = at(cx.new, &n.name);
        let p = Pair {
            o,
            n,
            subject,
            oa,
            na,
        };
        matched(&p, &mut out);
    }
    for n in new {
        if old.iter().any(|o| o.name == n.name) {
            continue;
        }
        out.push(added(n, at(cx.new, &n.name)));
    }
    for c in out {
        cx.add(c);
    }
}

fn removed(o: &Event, subject: String, oa: Option<Pos>) -> Change {
    Change::new(RuleId::EventsRemoved, subject, "removed")
        .values(Some(summary(o)), None)
        .at(oa, None)
        .witness(format!(
            "`{}` is no longer randomized ({}): the policy trains on the compiled values; {NOT_COMPARABLE}",
            o.field_name(),
            mode_effect(&o.mode)
        ))
}

fn added(n: &Event, na: Option<Pos>) -> Change {
    Change::new(RuleId::EventsAdded, format!("events.{}", n.name), "added")
        .values(None, Some(summary(n)))
        .at(None, na)
        .witness(if n.writes_model() {
            format!(
                "`{}` is now randomized ({}): the policy trains on a distribution of models where it saw one; {NOT_COMPARABLE}",
                n.field_name(),
                mode_effect(&n.mode)
            )
        } else {
            format!(
                "the robot is now pushed ({}): the policy trains on disturbed episodes; {NOT_COMPARABLE}",
                mode_text(&n.mode)
            )
        })
}

/// The changes of an event kept by name; another field makes the rest moot.
fn matched(p: &Pair, out: &mut Vec<Change>) {
    let (o, n) = (p.o, p.n);
    if o.field_name() != n.field_name() {
        out.push(
            p.change(
                RuleId::EventsFieldChanged,
                "field",
                o.field_name().into(),
                n.field_name().into(),
            )
            .witness(format!(
                "randomizes `{}` instead of `{}`: the policy trains on another distribution of models; {NOT_COMPARABLE}",
                n.field_name(),
                o.field_name()
            )),
        );
        return;
    }
    if o.mode != n.mode {
        out.push(
            p.change(
                RuleId::EventsModeChanged,
                "mode",
                mode_text(&o.mode),
                mode_text(&n.mode),
            )
            .witness(format!(
                "{} instead of {}: the policy sees the randomization at another rate; {NOT_COMPARABLE}",
                mode_effect(&n.mode),
                mode_effect(&o.mode)
            )),
        );
    }
    if let Some(c) = elements(p) {
        out.push(c);
    }
    model(p, out);
    for ((label, or, ot), (_, nr, nt)) in ranges(o).into_iter().zip(ranges(n)) {
        if ot != nt {
            let what = if label == "range" {
                format!("`{}` range", n.field_name())
            } else {
                format!("push {label} range")
            };
            out.push(
                p.change(RuleId::EventsRangeChanged, label, ot.clone(), nt.clone())
                    .witness(range_effect(&what, or, nr, &ot, &nt)),
            );
        }
    }
}

/// The matched elements: a rewritten pattern that matches the same names has no effect.
fn elements(p: &Pair) -> Option<Change> {
    let (o, n) = (p.o, p.n);
    let (on, nn) = (names(o), names(n));
    if on == nn && o.elements_text == n.elements_text {
        return None;
    }
    let added: Vec<&String> = nn.iter().filter(|x| !on.contains(x)).collect();
    let removed: Vec<&String> = on.iter().filter(|x| !nn.contains(x)).collect();
    let list = |v: &[&String]| v.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ");
    let c = p.change(
        RuleId::EventsElementsChanged,
        "elements",
        format!("{:?}", o.elements_text),
        format!("{:?}", n.elements_text),
    );
    Some(if on == nn {
        c.breaking(false)
            .witness("the same elements are matched: no effect")
    } else {
        c.witness(format!(
            "randomized now: {}; no longer: {}; {NOT_COMPARABLE}",
            if added.is_empty() {
                "-".into()
            } else {
                list(&added)
            },
            if removed.is_empty() {
                "-".into()
            } else {
                list(&removed)
            },
        ))
    })
}

/// Distribution, operation and sharing of a model event (pushes have none).
fn model(p: &Pair, out: &mut Vec<Change>) {
    let (
        EventKind::Model {
            dist: od,
            operation: oo,
            shared: os,
            ..
        },
        EventKind::Model {
            dist: nd,
            operation: no,
            shared: ns,
            ..
        },
    ) = (&p.o.kind, &p.n.kind)
    else {
        return;
    };
    if od.name() != nd.name() {
        out.push(
            p.change(
                RuleId::EventsDistributionChanged,
                "distribution",
                od.describe(),
                nd.describe(),
            )
            .witness(format!(
                "`{}` is drawn {} instead of {}: other values are likely; {NOT_COMPARABLE}",
                p.n.field_name(),
                nd.name(),
                od.name()
            )),
        );
    }
    if oo != no {
        out.push(
            p.change(
                RuleId::EventsOperationChanged,
                "operation",
                oo.name().into(),
                no.name().into(),
            )
            .witness(format!(
                "draws are applied by {} instead of {}: the resulting values differ; {NOT_COMPARABLE}",
                no.name(),
                oo.name()
            )),
        );
    }
    if os != ns {
        out.push(
            p.change(
                RuleId::EventsSharedChanged,
                "shared",
                os.to_string(),
                ns.to_string(),
            )
            .witness(if *ns {
                "one draw for every element: the elements vary together (correlated)"
            } else {
                "one draw per element: the elements vary independently"
            }),
        );
    }
}

/// `startup geom_friction.sliding of FR, FL: uniform[0.4, 1] abs`.
fn summary(e: &Event) -> String {
    let els = names(e).join(", ");
    let of = if els.is_empty() {
        String::new()
    } else {
        format!(" of {els}")
    };
    match &e.kind {
        EventKind::Model {
            dist, operation, ..
        } => format!(
            "{} {}{of}: {} {}",
            mode_text(&e.mode),
            e.field_name(),
            dist.describe(),
            operation.name()
        ),
        EventKind::Push { x, y, .. } => format!(
            "{} push{of}: vx += uniform{}, vy += uniform{}",
            mode_text(&e.mode),
            fmt_range(*x),
            fmt_range(*y)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_widen_narrow_or_shift() {
        // new ⊇ old: widened; old ⊇ new: narrowed; neither: shifted.
        assert_eq!(
            range_effect("`geom_friction` range", (0.5, 1.0), (0.25, 1.5), "a", "b"),
            "`geom_friction` range widened from a to b: the policy trains on a wider distribution; returns are not comparable"
        );
        assert_eq!(
            range_effect("push x range", (-1.0, 1.0), (-0.5, 1.0), "a", "b"),
            "push x range narrowed from a to b: the policy trains on a narrower distribution and may not cover what it met before; returns are not comparable"
        );
        assert_eq!(
            range_effect("r", (0.0, 1.0), (0.5, 1.5), "a", "b"),
            "r shifted from a to b: the policy trains on other values; returns are not comparable"
        );
        // A Gaussian is compared on mean ± 3 std: std 0.1 → 0.2 around 0 is (-0.3, 0.3) →
        // (-0.6, 0.6), wider.
        let (g1, g2) = (
            EventDist::Gaussian {
                mean: 0.0,
                std: 0.1,
            },
            EventDist::Gaussian {
                mean: 0.0,
                std: 0.2,
            },
        );
        assert!(range_effect("r", g1.support(), g2.support(), "", "").contains("widened"));
    }

    #[test]
    fn modes_and_ranges_in_words() {
        let fixed = EventMode::Interval {
            low: 2.0,
            high: 2.0,
        };
        let drawn = EventMode::Interval {
            low: 1.0,
            high: 3.5,
        };
        assert_eq!(mode_text(&fixed), "interval every 2 s");
        assert_eq!(mode_text(&drawn), "interval every 1–3.5 s");
        assert_eq!(mode_text(&EventMode::Reset), "reset");
        assert_eq!(mode_effect(&EventMode::Startup), "drawn once per seed");
        assert_eq!(mode_effect(&EventMode::Reset), "drawn every episode");
        assert_eq!(mode_effect(&fixed), "drawn every 2 s during episodes");
        assert_eq!(mode_effect(&drawn), "drawn every 1–3.5 s during episodes");
        // Rust's shortest float display: 1.0 is `1`.
        assert_eq!(fmt_range((0.5, 1.0)), "[0.5, 1]");
    }
}
