//! Multi-agent specs: the base envs (as task specs), then, for every factorization both declare
//! and k = 0, 1, 2, each agent's actions and observation element by element. Factorizations only
//! one side declares are reported as added or removed.

use std::path::Path;

use super::rules::RuleId;
use super::{Change, Report};
use crate::diagnostic::Diagnostics;
use crate::ir::Segment;
use crate::multi_agent::{Agent, MultiAgentSpec, load};
use crate::params::Override;
use crate::syntax::Spec;

/// How a segment's values are transformed, e.g. `sin, clipped to [-1, 1]`.
fn how(s: &Segment) -> String {
    let mut v = vec![];
    if let Some(a) = s.apply {
        v.push(format!("{a:?}").to_lowercase());
    }
    match s.clip {
        Some((lo, hi)) => v.push(format!("clipped to [{lo}, {hi}]")),
        None => v.push("not clipped".into()),
    }
    v.join(", ")
}

fn actions_text(ag: &Agent) -> String {
    ag.nodes
        .iter()
        .zip(&ag.actions)
        .map(|(n, g)| format!("{n}→action[{g}]"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The base envs' task diff, subjects prefixed with `base`.
fn base_report(old: &MultiAgentSpec, new: &MultiAgentSpec) -> Report {
    match (
        Spec::load(&old.base.spec_path),
        Spec::load(&new.base.spec_path),
    ) {
        (Ok(os), Ok(ns)) => {
            let mut r = super::diff(&os, &old.base, &ns, &new.base);
            for c in &mut r.changes {
                c.subject = format!("base {}", c.subject);
            }
            r
        }
        _ => Report::new("", "", "", ""),
    }
}

/// Two agents of one factorization at one k.
fn agent_changes(x: &Agent, y: &Agent, conf: &str, k: usize, out: &mut Vec<Change>) {
    if k == 0 && x.actions != y.actions {
        out.push(
            Change::new(
                RuleId::AgentsActionsChanged,
                format!("{} (conf `{conf}`)", x.name),
                "actions",
            )
            .values(Some(actions_text(x)), Some(actions_text(y))),
        );
    }
    let subject = format!("{} (conf `{conf}`, k = {k})", x.name);
    let (xn, yn) = (x.obs_names(), y.obs_names());
    if xn != yn {
        let first = xn
            .iter()
            .zip(&yn)
            .position(|(p, q)| p != q)
            .unwrap_or(xn.len().min(yn.len()));
        let differing =
            xn.iter().zip(&yn).filter(|(p, q)| p != q).count() + xn.len().abs_diff(yn.len());
        out.push(
            Change::new(RuleId::AgentsObservationChanged, subject, "observation")
                .values(
                    Some(format!("{} values", xn.len())),
                    Some(format!("{} values, {differing} differ", yn.len())),
                )
                .witness(format!(
                    "obs dim {} → {}; first difference at index {first}: {} → {}",
                    xn.len(),
                    yn.len(),
                    xn.get(first).map(String::as_str).unwrap_or("(none)"),
                    yn.get(first).map(String::as_str).unwrap_or("(none)")
                )),
        );
        return;
    }
    // Same elements: clipping or functions may still differ.
    for (s, t) in x.observation.iter().zip(&y.observation) {
        if s.offset == t.offset && (s.clip != t.clip || s.apply != t.apply) {
            out.push(
                Change::new(
                    RuleId::AgentsObservationValuesChanged,
                    &subject,
                    "observation clip/apply",
                )
                .values(
                    Some(format!("{} {}", s.name, how(s))),
                    Some(format!("{} {}", t.name, how(t))),
                ),
            );
        }
    }
}

/// The line of `key = ...` in a spec file (the first one, as the `[agents]` table holds it).
fn key_line(path: &Path, key: &str) -> Option<super::Pos> {
    let text = crate::source::read_text(path, crate::limits::MAX_SPEC_BYTES).ok()?;
    let line = text.lines().position(|l| {
        l.trim_start()
            .strip_prefix(key)
            .is_some_and(|r| r.trim_start().starts_with('='))
    })?;
    Some(super::Pos {
        file: path.display().to_string(),
        line: line + 1,
    })
}

/// Semantic diff of two multi-agent specs (`[agents]` files).
pub fn diff_multi_agent(old_path: &Path, new_path: &Path) -> Result<Report, Diagnostics> {
    let old = load(old_path, &[])?;
    let new = load(new_path, &[])?;
    let mut report = base_report(&old, &new);
    report.old_id = old.id.clone();
    report.new_id = new.id.clone();
    report.old_file = old_path.display().to_string();
    report.new_file = new_path.display().to_string();
    let mut changes = vec![];
    // What a user who passes neither `agent_conf` nor `agent_obsk` gets.
    let at = |path: &Path, key: &str| key_line(path, key);
    if old.conf != new.conf {
        changes.push(
            Change::new(RuleId::AgentsDefaultConfChanged, "agents", "default agent_conf")
                .values(Some(old.conf.clone()), Some(new.conf.clone()))
                .at(at(old_path, "agent_conf"), at(new_path, "agent_conf"))
                .witness(format!(
                    "without `agent_conf`, users get the `{}` factorization instead of `{}`: {} agents instead of {}; their policies, action splits and observations no longer fit",
                    new.conf,
                    old.conf,
                    new.agents.len(),
                    old.agents.len()
                )),
        );
    }
    if old.k != new.k {
        changes.push(
            Change::new(RuleId::AgentsDefaultObskChanged, "agents", "default agent_obsk")
                .values(Some(old.k.to_string()), Some(new.k.to_string()))
                .at(at(old_path, "agent_obsk"), at(new_path, "agent_obsk"))
                .witness(format!(
                    "without `agent_obsk`, every agent observes its neighbours {} hops away instead of {}: local observations change size and layout",
                    new.k, old.k
                )),
        );
    }
    for c in &old.confs {
        if !new.confs.contains(c) {
            changes.push(
                Change::new(
                    RuleId::AgentsConfRemoved,
                    format!("agents conf `{c}`"),
                    "removed",
                )
                .values(Some(c.clone()), None),
            );
        }
    }
    for c in &new.confs {
        let subject = format!("agents conf `{c}`");
        if !old.confs.contains(c) {
            changes.push(
                Change::new(RuleId::AgentsConfAdded, subject, "added")
                    .values(None, Some(c.clone())),
            );
            continue;
        }
        for k in 0..=2usize {
            let o = [
                Override::text("agent_conf", c),
                Override::text("agent_obsk", &k.to_string()),
            ];
            let (a, b) = (load(old_path, &o)?, load(new_path, &o)?);
            if k == 0 && a.first_element_bounds != b.first_element_bounds {
                let show = |x: bool| if x { "first_element" } else { "per_actuator" }.to_string();
                changes.push(
                    Change::new(RuleId::AgentsActionBoundsChanged, &subject, "action_bounds")
                        .values(
                            Some(show(a.first_element_bounds)),
                            Some(show(b.first_element_bounds)),
                        )
                        .witness("the action space changes only where an actuator's range differs from actuator 0's"),
                );
            }
            if a.agents.len() != b.agents.len() {
                if k == 0 {
                    changes.push(
                        Change::new(RuleId::AgentsCountChanged, &subject, "number of agents")
                            .values(
                                Some(a.agents.len().to_string()),
                                Some(b.agents.len().to_string()),
                            ),
                    );
                }
                continue;
            }
            for (x, y) in a.agents.iter().zip(&b.agents) {
                agent_changes(x, y, c, k, &mut changes);
            }
        }
    }
    // `extend` recomputes the flags for the multi-agent ids.
    report.extend(changes);
    Ok(report)
}
