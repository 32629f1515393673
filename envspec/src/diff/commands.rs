//! Diff of `[commands.*]` (category randomization) and `[actions]` (category action), on the
//! resolved specs.

use super::change::Change;
use super::rules::RuleId;
use super::{Ctx, Pos, pos};
use crate::ir::{Command, PdActions, ResolvedSpec};

fn at(cx: &Ctx, old: bool, name: &str) -> Option<Pos> {
    let spec = if old { cx.old } else { cx.new };
    spec.commands
        .iter()
        .find(|s| s.name == name)
        .map(|s| pos(&s.name_loc))
}

fn range(c: &Command, k: usize) -> String {
    format!("[{}, {}]", c.low[k], c.high[k])
}

pub(super) fn commands(cx: &mut Ctx) {
    let (old, new) = (&cx.old_r.commands, &cx.new_r.commands);
    let mut out = vec![];
    for c in old.iter().filter(|c| !new.iter().any(|n| n.name == c.name)) {
        out.push(
            Change::new(
                RuleId::CommandsRemoved,
                format!("commands.{}", c.name),
                "removed",
            )
            .values(Some(c.describe()), None)
            .at(at(cx, true, &c.name), None),
        );
    }
    for n in new {
        let (old_at, new_at) = (at(cx, true, &n.name), at(cx, false, &n.name));
        let subject = format!("commands.{}", n.name);
        let Some(o) = old.iter().find(|o| o.name == n.name) else {
            out.push(
                Change::new(RuleId::CommandsAdded, subject, "added")
                    .values(None, Some(n.describe()))
                    .at(None, new_at),
            );
            continue;
        };
        if o.components != n.components {
            out.push(
                Change::new(
                    RuleId::CommandsComponentsChanged,
                    subject.clone(),
                    "components",
                )
                .values(Some(o.components.join(", ")), Some(n.components.join(", ")))
                .at(old_at.clone(), new_at.clone()),
            );
        } else {
            for k in 0..n.len() {
                if (o.low[k], o.high[k]) == (n.low[k], n.high[k]) {
                    continue;
                }
                let (ow, nw) = (o.high[k] - o.low[k], n.high[k] - n.low[k]);
                let how = if n.low[k] <= o.low[k] && n.high[k] >= o.high[k] {
                    "widened: the policy is trained on commands it never saw"
                } else if n.low[k] >= o.low[k] && n.high[k] <= o.high[k] {
                    "narrowed: commands outside the new range are no longer trained"
                } else {
                    "moved"
                };
                out.push(
                    Change::new(
                        RuleId::CommandsRangeChanged,
                        subject.clone(),
                        n.components[k].clone(),
                    )
                    .values(Some(range(o, k)), Some(range(n, k)))
                    .at(old_at.clone(), new_at.clone())
                    .witness(format!("{how} (width {ow} → {nw})")),
                );
            }
        }
        for (aspect, was, now) in [
            (
                "resample_seconds",
                o.resample_seconds.unwrap_or(0.0),
                n.resample_seconds.unwrap_or(0.0),
            ),
            (
                "standing_probability",
                o.standing_probability,
                n.standing_probability,
            ),
        ] {
            if was != now {
                out.push(
                    Change::new(RuleId::CommandsScheduleChanged, subject.clone(), aspect)
                        .values(Some(was.to_string()), Some(now.to_string()))
                        .at(old_at.clone(), new_at.clone()),
                );
            }
        }
    }
    for c in out {
        cx.add(c);
    }
}

pub(super) fn actions(cx: &mut Ctx) {
    let at = |cx: &Ctx, old: bool| {
        let spec = if old { cx.old } else { cx.new };
        spec.actions.as_ref().map(|s| pos(&s.name_loc))
    };
    let (o, n) = (&cx.old_r.actions, &cx.new_r.actions);
    let (old_at, new_at) = (at(cx, true), at(cx, false));
    let change = match (o, n) {
        (None, None) => return,
        (Some(o), None) => {
            let c = Change::new(RuleId::ActionsRemoved, "actions", "removed")
                .values(Some(o.describe()), None)
                .at(old_at, None);
            cx.add(c);
            return;
        }
        (None, Some(n)) => {
            let c = Change::new(RuleId::ActionsAdded, "actions", "added")
                .values(None, Some(n.describe()))
                .at(None, new_at);
            cx.add(c);
            return;
        }
        (Some(o), Some(n)) => (o.clone(), n.clone()),
    };
    let (o, n): (PdActions, PdActions) = change;
    let f = |x: Option<f64>| x.map_or("the model's".to_string(), |v| v.to_string());
    let mut out = vec![];
    let mapping = [
        scale_change(&o.scale, &n.scale, cx.new_r),
        (
            "default_pose",
            format!("{:?}", o.default_pose),
            format!("{:?}", n.default_pose),
        ),
        ("range", format!("{:?}", o.range), format!("{:?}", n.range)),
        ("kind", o.kind.name().to_string(), n.kind.name().to_string()),
    ];
    for (aspect, was, now) in mapping {
        if was != now {
            out.push((RuleId::ActionsMappingChanged, aspect, was, now));
        }
    }
    for (aspect, was, now) in [
        ("kp", o.kp, n.kp),
        ("kd", o.kd, n.kd),
        ("damping", o.damping, n.damping),
    ] {
        if was != now {
            out.push((RuleId::ActionsGainsChanged, aspect, f(was), f(now)));
        }
    }
    for (rule, aspect, was, now) in out {
        let c = Change::new(rule, "actions", aspect)
            .values(Some(was), Some(now))
            .at(old_at.clone(), new_at.clone());
        cx.add(c);
    }
}

/// The scale aspect: one number when each side has one, else only the actuators whose scale
/// differs, by name (a per-joint table changes a few of many).
fn scale_change(o: &[f64], n: &[f64], r: &ResolvedSpec) -> (&'static str, String, String) {
    let uniform = |s: &[f64]| s.windows(2).all(|w| w[0] == w[1]);
    if o.len() != n.len() || (uniform(o) && uniform(n)) {
        let text = |s: &[f64]| match s.first() {
            Some(x) if uniform(s) => x.to_string(),
            _ => format!("{s:?}"),
        };
        return ("scale", text(o), text(n));
    }
    let name = |i: usize| {
        r.model
            .actuators
            .get(i)
            .map_or_else(|| format!("actuator {i}"), |a| a.name.clone())
    };
    let (mut was, mut now) = (vec![], vec![]);
    for i in (0..o.len()).filter(|&i| o[i].to_bits() != n[i].to_bits()) {
        was.push(format!("{} {}", name(i), o[i]));
        now.push(format!("{} {}", name(i), n[i]));
    }
    ("scale", was.join(", "), now.join(", "))
}
