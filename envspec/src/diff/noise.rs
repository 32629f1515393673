//! Observation noise and delay per segment, action latency: compared on the resolved specs (so
//! a parameter default that changes a scale counts, a rewritten spelling does not), reported in
//! the randomization category with what the change does to the training distribution.

use super::rules::RuleId;
use super::{Change, Ctx, Pos, pos};
use crate::ResolvedSpec;
use crate::noise::Noise;
use crate::syntax::Spec;
use crate::value::format_float;

/// Where a segment's `key` is written (else the segment's name, else nothing).
fn at(spec: &Spec, segment: &str, key: &str) -> Option<Pos> {
    let s = spec.observation.iter().find(|s| s.name == segment)?;
    let loc = s
        .entries
        .iter()
        .find(|e| e.key == key)
        .map_or(&s.name_loc, |e| &e.key_loc);
    Some(pos(loc))
}

fn latency_at(spec: &Spec) -> Option<Pos> {
    let l = spec.latency.as_ref()?;
    let loc = l
        .entries
        .iter()
        .find(|e| e.key == "action")
        .map_or(&l.name_loc, |e| &e.key_loc);
    Some(pos(loc))
}

fn steps(n: usize, dt: f64) -> String {
    let s = if n == 1 { "" } else { "s" };
    format!("{n} step{s} ({} s)", format_float(n as f64 * dt))
}

/// Six decimals are plenty for a reviewer.
fn short(x: f64) -> String {
    format_float((x * 1e6).round() / 1e6)
}

fn std_text(n: Option<&Noise>) -> String {
    n.map_or("0".into(), |n| short(n.std()))
}

/// The segment's noise and delay in `r` (none when the segment declares neither).
fn of<'a>(r: &'a ResolvedSpec, name: &str) -> (Option<&'a Noise>, usize) {
    match r.corruption.segment(name) {
        Some(c) => (c.noise.as_ref(), c.delay),
        None => (None, 0),
    }
}

pub(super) fn noise(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let mut names: Vec<&str> = n.observation.iter().map(|s| s.name.as_str()).collect();
    for s in &o.observation {
        if !names.contains(&s.name.as_str()) {
            names.push(&s.name);
        }
    }
    let mut changes = vec![];
    for name in names {
        let ((na, da), (nb, db)) = (of(o, name), of(n, name));
        let subject = format!("observation.{name}");
        let len = n
            .observation
            .iter()
            .chain(&o.observation)
            .find(|s| s.name == name)
            .map_or(0, |s| s.len());
        let (pa, pb) = (at(cx.old, name, "noise"), at(cx.new, name, "noise"));
        if na != nb {
            let rule = match (na, nb) {
                (None, _) => RuleId::NoiseAdded,
                (_, None) => RuleId::NoiseRemoved,
                _ => RuleId::NoiseChanged,
            };
            let mut witness = format!(
                "noise std {} → {} on {len} elements",
                std_text(na),
                std_text(nb)
            );
            if let (Some(a), Some(b)) = (na, nb)
                && a.std() > 0.0
            {
                witness.push_str(&format!(" (× {})", short(b.std() / a.std())));
            }
            changes.push(
                Change::new(rule, &subject, "noise")
                    .values(na.map(Noise::to_string), nb.map(Noise::to_string))
                    .at(pa, pb)
                    .witness(witness),
            );
        }
        if da != db {
            let (pa, pb) = (at(cx.old, name, "delay"), at(cx.new, name, "delay"));
            changes.push(
                Change::new(RuleId::LatencyObservationChanged, &subject, "delay")
                    .values(Some(steps(da, o.dt())), Some(steps(db, n.dt())))
                    .at(pa, pb)
                    .witness(format!(
                        "the policy sees {len} elements {} s old",
                        format_float(db as f64 * n.dt())
                    )),
            );
        }
    }
    let (la, lb) = (o.corruption.action_latency, n.corruption.action_latency);
    if la != lb {
        changes.push(
            Change::new(RuleId::LatencyActionChanged, "latency", "action")
                .values(Some(steps(la, o.dt())), Some(steps(lb, n.dt())))
                .at(latency_at(cx.old), latency_at(cx.new))
                .witness(format!(
                    "each action takes effect {} s after it is given",
                    format_float(lb as f64 * n.dt())
                )),
        );
    }
    for c in changes {
        cx.add(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_and_amplitudes_in_words() {
        // 3 × 0.25 = 0.75 exactly; 1 × 0.05 is 0.05.
        assert_eq!(steps(3, 0.25), "3 steps (0.75 s)");
        assert_eq!(steps(1, 0.05), "1 step (0.05 s)");
        assert_eq!(steps(0, 0.05), "0 steps (0.0 s)");
        // Six decimals: 0.1234567 → 0.123457; integers keep a `.0`.
        assert_eq!(short(0.1234567), "0.123457");
        assert_eq!(short(2.0), "2.0");
        assert_eq!(std_text(None), "0");
    }
}
