//! The env's identity and its parameters: added, removed, default changed (categorised by the
//! places that read the parameter), constructor argument or fixed, documentation.

use super::rules::{Category, RuleId};
use super::{Change, Ctx, pos};
use crate::ir::ResolvedSpec;
use crate::syntax::{Section, Spec};
use crate::value::{Val, ValKind};

pub(super) fn env_section(cx: &mut Ctx) {
    let (o, n) = (cx.old, cx.new);
    if o.id != n.id {
        cx.add(
            Change::new(RuleId::EnvIdChanged, "env", "id")
                .values(Some(o.id.clone()), Some(n.id.clone()))
                .at(Some(pos(&o.id_loc)), Some(pos(&n.id_loc))),
        );
    }
    if o.description != n.description {
        cx.add(
            Change::new(RuleId::EnvDescriptionChanged, "env", "description")
                .values(Some(o.description.clone()), Some(n.description.clone())),
        );
    }
    if o.reward_threshold != n.reward_threshold {
        let f = |x: Option<f64>| x.map(|v| v.to_string()).unwrap_or_else(|| "none".into());
        cx.add(
            Change::new(RuleId::EnvRewardThresholdChanged, "env", "reward_threshold")
                .values(Some(f(o.reward_threshold)), Some(f(n.reward_threshold))),
        );
    }
    if o.entry_point != n.entry_point {
        let f = |x: &Option<String>| x.clone().unwrap_or_else(|| "none".into());
        cx.add(
            Change::new(RuleId::EnvEntryPointChanged, "env", "entry_point")
                .values(Some(f(&o.entry_point)), Some(f(&n.entry_point))),
        );
    }
}

/// The behavioural categories of the places a parameter is referenced from.
fn uses(spec: &Spec, param: &str) -> Vec<(Category, String)> {
    fn refers(v: &Val, p: &str) -> bool {
        match &v.kind {
            ValKind::Str(s) => {
                let s = s.trim_start_matches('!');
                s == p || s.contains(&format!("${p}]"))
            }
            ValKind::Array(a) => a.iter().any(|x| refers(x, p)),
            ValKind::Table(t) => t.iter().any(|e| refers(&e.value, p)),
            _ => false,
        }
    }
    let mut out = vec![];
    let groups: [(&[Section], Category, &str); 6] = [
        (&spec.observation, Category::Observation, "observation"),
        (&spec.reward, Category::Reward, "reward"),
        (&spec.health, Category::Termination, "health"),
        (&spec.termination, Category::Termination, "termination"),
        (&spec.reset, Category::Reset, "reset"),
        (&spec.info, Category::Info, "info"),
    ];
    for (secs, cat, kind) in groups {
        for s in secs {
            // Observation noise and delay read it for the training distribution, not the layout.
            let noise = |k: &str| kind == "observation" && matches!(k, "noise" | "delay");
            let refs = |e: &&crate::value::Entry| e.key != "doc" && refers(&e.value, param);
            if s.entries.iter().filter(refs).any(|e| !noise(&e.key)) {
                out.push((cat, format!("{kind}.{}", s.name)));
            }
            if s.entries.iter().filter(refs).any(|e| noise(&e.key)) {
                out.push((Category::Randomization, format!("noise.{}", s.name)));
            }
        }
    }
    if let Some(l) = &spec.latency
        && l.entries
            .iter()
            .any(|e| e.key != "doc" && refers(&e.value, param))
    {
        out.push((Category::Randomization, "latency.action".into()));
    }
    if spec
        .health_terminate
        .as_ref()
        .is_some_and(|v| refers(v, param))
    {
        out.push((Category::Termination, "health.terminate".into()));
    }
    match param {
        "xml_file" | "frame_skip" => {
            out.push((Category::Dynamics, format!("the built-in `{param}`")))
        }
        "max_episode_steps" => out.push((Category::Termination, "the time limit".into())),
        _ => {}
    }
    out
}

/// The rule of a changed default: that of its most harmful use.
fn default_rule(used: &[(Category, String)]) -> RuleId {
    match used.iter().map(|(c, _)| *c).min() {
        None => RuleId::ParamDefaultUnused,
        Some(Category::Observation) => RuleId::ParamDefaultObservation,
        Some(Category::Reward) => RuleId::ParamDefaultReward,
        Some(Category::Termination) => RuleId::ParamDefaultTermination,
        Some(Category::Reset) => RuleId::ParamDefaultReset,
        Some(Category::Randomization) => RuleId::ParamDefaultRandomization,
        Some(Category::Dynamics) => RuleId::ParamDefaultDynamics,
        // `uses` reports no other categories; info is the mildest behavioural one.
        Some(_) => RuleId::ParamDefaultInfo,
    }
}

fn used_by(used: &[(Category, String)]) -> String {
    format!(
        "used by {}",
        used.iter()
            .map(|(_, s)| s.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    )
}

pub(super) fn params(cx: &mut Ctx) {
    let (o, n) = (cx.old, cx.new);
    for p in &o.params {
        let subject = format!("param {}", p.name);
        let at = Some(pos(&p.name_loc));
        let Some(q) = n.param(&p.name) else {
            cx.add(
                Change::new(RuleId::ParamRemoved, subject, "removed")
                    .values(Some(p.default.to_toml()), None)
                    .at(at, None),
            );
            continue;
        };
        let new_at = Some(pos(&q.name_loc));
        if p.default.to_toml() != q.default.to_toml() {
            let used = uses(n, &q.name);
            // Every use switched off under the default parameters, before and after: the new
            // default changes nothing a default env computes.
            let dormant = !used.is_empty()
                && used
                    .iter()
                    .all(|(_, u)| !active(cx.old_r, u) && !active(cx.new_r, u));
            let witness = if used.is_empty() {
                "not used by the env's behaviour".into()
            } else if dormant {
                format!(
                    "{}, switched off under the default parameters before and after",
                    used_by(&used)
                )
            } else {
                used_by(&used)
            };
            let mut change = Change::new(default_rule(&used), &subject, "default")
                .values(Some(p.default.to_toml()), Some(q.default.to_toml()))
                .at(at.clone(), new_at.clone())
                .witness(witness);
            if dormant {
                change = change.breaking(false);
            }
            cx.add(change);
        }
        if p.fixed != q.fixed {
            let f = |fixed: bool| if fixed { "no (fixed)" } else { "yes" }.to_string();
            let rule = if q.fixed {
                RuleId::ParamNowFixed
            } else {
                RuleId::ParamNowArgument
            };
            cx.add(
                Change::new(rule, &subject, "constructor argument")
                    .values(Some(f(p.fixed)), Some(f(q.fixed)))
                    .at(at.clone(), new_at.clone()),
            );
        }
        if p.doc != q.doc {
            cx.add(
                Change::new(RuleId::DocChanged, &subject, "doc")
                    .values(Some(p.doc.clone()), Some(q.doc.clone()))
                    .at(at, new_at),
            );
        }
    }
    for q in &n.params {
        if o.param(&q.name).is_none() {
            let used = uses(n, &q.name);
            let mut c = Change::new(RuleId::ParamAdded, format!("param {}", q.name), "added")
                .values(None, Some(q.default.to_toml()))
                .at(None, Some(pos(&q.name_loc)));
            if !used.is_empty() {
                c = c.witness(used_by(&used));
            }
            cx.add(c);
        }
    }
}

/// Whether a use named `kind.name` (as [`uses`] names it) is switched on in a resolved spec. Uses
/// that are not sections (the time limit, built-ins) always are.
fn active(r: &ResolvedSpec, use_name: &str) -> bool {
    let Some((kind, name)) = use_name.split_once('.') else {
        return true;
    };
    match kind {
        "reward" => r.reward.iter().any(|t| t.name == name),
        "observation" => r.observation.iter().any(|s| s.name == name),
        "health" if name == "terminate" => true,
        "health" => r.health.iter().any(|c| c.name == name),
        "termination" => r.termination.iter().any(|t| t.name == name),
        "reset" => r.reset.iter().any(|x| x.name == name),
        "info" => r.info.iter().any(|i| i.key == name),
        "noise" => r.observation.iter().any(|s| s.name == name),
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_default_takes_the_rule_of_its_most_harmful_use() {
        let uses = |cats: &[Category]| -> Vec<(Category, String)> {
            cats.iter().map(|c| (*c, c.key().to_string())).collect()
        };
        assert_eq!(default_rule(&[]), RuleId::ParamDefaultUnused);
        // Categories order most harmful first: observation, action, reward, termination, reset,
        // randomization, dynamics, parameters, info, documentation.
        for (cats, rule) in [
            (
                &[Category::Info, Category::Observation, Category::Reward][..],
                RuleId::ParamDefaultObservation,
            ),
            (
                &[Category::Info, Category::Reward],
                RuleId::ParamDefaultReward,
            ),
            (
                &[Category::Reset, Category::Termination],
                RuleId::ParamDefaultTermination,
            ),
            (
                &[Category::Dynamics, Category::Reset],
                RuleId::ParamDefaultReset,
            ),
            (
                &[Category::Dynamics, Category::Randomization],
                RuleId::ParamDefaultRandomization,
            ),
            (&[Category::Dynamics], RuleId::ParamDefaultDynamics),
            (&[Category::Info], RuleId::ParamDefaultInfo),
        ] {
            assert_eq!(default_rule(&uses(cats)), rule, "{cats:?}");
            // The rule's category is that of the use (docs/diff-rules.md's param-default-* rows).
            assert_eq!(rule.category(), *cats.iter().min().unwrap());
        }
        assert_eq!(
            used_by(&[
                (Category::Reward, "reward.healthy".into()),
                (Category::Info, "info.x".into())
            ]),
            "used by reward.healthy, info.x"
        );
    }
}
