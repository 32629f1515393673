//! Named sections (`[observation.*]`, `[reward.*]`, `[health.*]`, `[reset.*]`) matched by name,
//! renames detected by equal content, every key reported as "was X, now Y". Whether a change
//! alters behaviour is decided on the resolved items' behaviour keys.

use super::rules::RuleId;
use super::{Change, Ctx, Pos, pos};
use crate::describe;
use crate::ir::ResolvedSpec;
use crate::syntax::Section;

/// The rules of one kind of section.
pub(super) struct Kind {
    /// The spec's table name, e.g. `reward`.
    pub name: &'static str,
    pub added: RuleId,
    pub removed: RuleId,
    pub renamed: RuleId,
    pub key_changed: RuleId,
    pub resolved_changed: RuleId,
    /// The resolved item of a section, in words (None: switched off).
    pub describe: fn(&ResolvedSpec, &str) -> Option<String>,
}

fn describe_segment(r: &ResolvedSpec, name: &str) -> Option<String> {
    let s = r.observation.iter().find(|s| s.name == name)?;
    let names = s.element_names();
    let mut d = match names.as_slice() {
        [] => "nothing".to_string(),
        [one] => one.clone(),
        [first, .., last] => format!("{first} … {last} ({} elements)", names.len()),
    };
    if let Some((lo, hi)) = s.clip {
        d.push_str(&format!(", clipped to [{lo}, {hi}]"));
    }
    Some(d)
}

fn describe_term(r: &ResolvedSpec, name: &str) -> Option<String> {
    r.reward.iter().find(|t| t.name == name).map(describe::term)
}

fn describe_check(r: &ResolvedSpec, name: &str) -> Option<String> {
    r.health
        .iter()
        .find(|c| c.name == name)
        .map(describe::check)
}

fn describe_termination(r: &ResolvedSpec, name: &str) -> Option<String> {
    r.termination
        .iter()
        .find(|c| c.name == name)
        .map(describe::termination)
}

fn describe_reset(r: &ResolvedSpec, name: &str) -> Option<String> {
    r.reset
        .iter()
        .find(|c| c.name == name)
        .map(describe::reset_step)
}

pub(super) const OBSERVATION: Kind = Kind {
    name: "observation",
    added: RuleId::ObservationSegmentAdded,
    removed: RuleId::ObservationSegmentRemoved,
    renamed: RuleId::ObservationSegmentRenamed,
    key_changed: RuleId::ObservationSegmentKeyChanged,
    resolved_changed: RuleId::ObservationSegmentResolvedChanged,
    describe: describe_segment,
};
pub(super) const REWARD: Kind = Kind {
    name: "reward",
    added: RuleId::RewardTermAdded,
    removed: RuleId::RewardTermRemoved,
    renamed: RuleId::RewardTermRenamed,
    key_changed: RuleId::RewardTermKeyChanged,
    resolved_changed: RuleId::RewardTermResolvedChanged,
    describe: describe_term,
};
pub(super) const HEALTH: Kind = Kind {
    name: "health",
    added: RuleId::HealthCheckAdded,
    removed: RuleId::HealthCheckRemoved,
    renamed: RuleId::HealthCheckRenamed,
    key_changed: RuleId::HealthCheckKeyChanged,
    resolved_changed: RuleId::HealthCheckResolvedChanged,
    describe: describe_check,
};
pub(super) const TERMINATION: Kind = Kind {
    name: "termination",
    added: RuleId::TerminationAdded,
    removed: RuleId::TerminationRemoved,
    renamed: RuleId::TerminationRenamed,
    key_changed: RuleId::TerminationKeyChanged,
    resolved_changed: RuleId::TerminationResolvedChanged,
    describe: describe_termination,
};
pub(super) const RESET: Kind = Kind {
    name: "reset",
    added: RuleId::ResetStepAdded,
    removed: RuleId::ResetStepRemoved,
    renamed: RuleId::ResetStepRenamed,
    key_changed: RuleId::ResetStepKeyChanged,
    resolved_changed: RuleId::ResetStepResolvedChanged,
    describe: describe_reset,
};

fn describe_actuators(r: &ResolvedSpec, name: &str) -> Option<String> {
    let a: Vec<String> = r
        .model_edits
        .actuators
        .iter()
        .filter(|a| a.section == name)
        .map(crate::describe::actuator)
        .collect();
    (!a.is_empty()).then(|| a.join("; "))
}

/// The actuators of table `name` that differ between the two specs, described on each side.
fn actuator_delta(
    old: &ResolvedSpec,
    new: &ResolvedSpec,
    name: &str,
) -> (Option<String>, Option<String>) {
    let of = |r: &ResolvedSpec| -> Vec<crate::ir::AddedActuator> {
        r.model_edits
            .actuators
            .iter()
            .filter(|a| a.section == name)
            .cloned()
            .collect()
    };
    let (a, b) = (of(old), of(new));
    let differs = |x: &crate::ir::AddedActuator, other: &[crate::ir::AddedActuator]| {
        !other.iter().any(|y| y == x)
    };
    let show = |v: Vec<String>| (!v.is_empty()).then(|| v.join("; "));
    (
        show(
            a.iter()
                .filter(|x| differs(x, &b))
                .map(crate::describe::actuator)
                .collect(),
        ),
        show(
            b.iter()
                .filter(|x| differs(x, &a))
                .map(crate::describe::actuator)
                .collect(),
        ),
    )
}

fn describe_joint_properties(r: &ResolvedSpec, name: &str) -> Option<String> {
    let j: Vec<String> = r
        .model_edits
        .joints
        .iter()
        .filter(|j| j.rows.iter().any(|p| p == name))
        .map(crate::describe::joint_edit)
        .collect();
    Some(if j.is_empty() {
        "no joint property".into()
    } else {
        j.join("; ")
    })
}

fn describe_geom_properties(r: &ResolvedSpec, name: &str) -> Option<String> {
    let row = r.model_edits.geom_rows.iter().find(|row| row.0 == name)?;
    let set: Vec<String> = row.2.iter().map(|(k, v)| format!("{k} {v:?}")).collect();
    Some(format!("{} on {} geoms", set.join(", "), row.1.len()))
}

fn describe_keyframe(r: &ResolvedSpec, name: &str) -> Option<String> {
    r.model_edits
        .keyframes
        .iter()
        .find(|k| k.name == name)
        .map(|k| crate::describe::keyframe(r, k))
}

pub(super) const ACTUATORS: Kind = Kind {
    name: "actuators",
    added: RuleId::ActuatorsAdded,
    removed: RuleId::ActuatorsRemoved,
    renamed: RuleId::ActuatorsRenamed,
    key_changed: RuleId::ActuatorsKeyChanged,
    resolved_changed: RuleId::ActuatorsResolvedChanged,
    describe: describe_actuators,
};
pub(super) const JOINT_PROPERTIES: Kind = Kind {
    name: "joint_properties",
    added: RuleId::JointPropertiesAdded,
    removed: RuleId::JointPropertiesRemoved,
    renamed: RuleId::JointPropertiesRenamed,
    key_changed: RuleId::JointPropertiesKeyChanged,
    resolved_changed: RuleId::JointPropertiesResolvedChanged,
    describe: describe_joint_properties,
};
pub(super) const GEOM_PROPERTIES: Kind = Kind {
    name: "geom_properties",
    added: RuleId::GeomPropertiesAdded,
    removed: RuleId::GeomPropertiesRemoved,
    renamed: RuleId::GeomPropertiesRenamed,
    key_changed: RuleId::GeomPropertiesKeyChanged,
    resolved_changed: RuleId::GeomPropertiesResolvedChanged,
    describe: describe_geom_properties,
};
pub(super) const KEYFRAMES: Kind = Kind {
    name: "keyframes",
    added: RuleId::KeyframesAdded,
    removed: RuleId::KeyframesRemoved,
    renamed: RuleId::KeyframesRenamed,
    key_changed: RuleId::KeyframesKeyChanged,
    resolved_changed: RuleId::KeyframesResolvedChanged,
    describe: describe_keyframe,
};

/// Entries of a section as (key, TOML text, position), docs included.
fn entries(s: &Section) -> Vec<(String, String, Pos)> {
    s.entries
        .iter()
        .map(|e| (e.key.clone(), e.value.to_toml(), pos(&e.key_loc)))
        .collect()
}

fn content(s: &Section) -> Vec<(String, String)> {
    entries(s)
        .into_iter()
        .filter(|(k, _, _)| k != "doc")
        .map(|(k, v, _)| (k, v))
        .collect()
}

/// A section's keys as an inline table, docs left out.
pub(super) fn summary(s: &Section) -> String {
    let c = content(s);
    format!(
        "{{ {} }}",
        c.iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// The rule of a changed key: docs are documentation, any other key the section kind's.
fn key_rule(kind: &Kind, key: &str, same_effect: bool) -> RuleId {
    // A selector spelled another way whose section resolves the same.
    let selector = matches!(key, "source" | "minus" | "target" | "achieved" | "desired");
    if same_effect && selector {
        RuleId::SelectorRespelled
    } else if key == "doc" {
        RuleId::DocChanged
    } else {
        kind.key_changed
    }
}

/// A reward term's `info` key is compared by key with the other info entries (`info_items`).
fn skipped(kind: &Kind, key: &str) -> bool {
    (kind.name == "reward" && key == "info")
        // Observation noise and delay have their own rules (`diff/noise.rs`).
        || (kind.name == "observation" && matches!(key, "noise" | "delay"))
}

/// Match sections by name (renames: same content, different name) and report key changes.
/// `resolved` gives the behaviour key of a section's resolved item (None: switched off), so
/// textual changes with the same effect are reported as compatible.
pub(super) fn sections<K: PartialEq>(
    cx: &mut Ctx,
    kind: &Kind,
    old: &[Section],
    new: &[Section],
    resolved: &dyn Fn(&ResolvedSpec, &str) -> Option<K>,
) {
    let mut matched_new = vec![false; new.len()];
    let mut unmatched_old = vec![];
    for s in old {
        let Some(j) = new.iter().position(|t| t.name == s.name) else {
            unmatched_old.push(s);
            continue;
        };
        matched_new[j] = true;
        let t = &new[j];
        let (was_r, now_r) = (resolved(cx.old_r, &s.name), resolved(cx.new_r, &t.name));
        matched(cx, kind, s, t, was_r, now_r);
    }
    let added: Vec<&Section> = new
        .iter()
        .zip(&matched_new)
        .filter(|(_, m)| !**m)
        .map(|(s, _)| s)
        .collect();
    let mut renamed_to = vec![false; added.len()];
    for s in unmatched_old {
        let subject = format!("{}.{}", kind.name, s.name);
        let rename = added
            .iter()
            .enumerate()
            .find(|(j, t)| !renamed_to[*j] && content(s) == content(t));
        match rename {
            Some((j, t)) => {
                renamed_to[j] = true;
                let same = resolved(cx.old_r, &s.name) == resolved(cx.new_r, &t.name);
                cx.add(
                    Change::new(kind.renamed, subject, "renamed")
                        .values(Some(s.name.clone()), Some(t.name.clone()))
                        .at(Some(pos(&s.name_loc)), Some(pos(&t.name_loc)))
                        .breaking(!same),
                );
            }
            None => {
                let active = resolved(cx.old_r, &s.name).is_some();
                cx.add(
                    Change::new(kind.removed, subject, "removed")
                        .values(Some(summary(s)), None)
                        .at(Some(pos(&s.name_loc)), None)
                        .breaking(active),
                );
            }
        }
    }
    for (j, t) in added.iter().enumerate() {
        if !renamed_to[j] {
            let active = resolved(cx.new_r, &t.name).is_some();
            cx.add(
                Change::new(kind.added, format!("{}.{}", kind.name, t.name), "added")
                    .values(None, Some(summary(t)))
                    .at(None, Some(pos(&t.name_loc)))
                    .breaking(active),
            );
        }
    }
}

/// The changes of a section present on both sides: each key "was X, now Y" (compatible when the
/// resolved items are equal), then the same text resolving differently.
fn matched<K: PartialEq>(
    cx: &mut Ctx,
    kind: &Kind,
    s: &Section,
    t: &Section,
    was_r: Option<K>,
    now_r: Option<K>,
) {
    let subject = format!("{}.{}", kind.name, s.name);
    let same_effect = was_r == now_r;
    let (a, b) = (entries(s), entries(t));
    for (k, v, p) in &a {
        if skipped(kind, k) {
            continue;
        }
        let (now, np) = match b.iter().find(|(k2, _, _)| k2 == k) {
            Some((_, v2, _)) if v2 == v => continue,
            Some((_, v2, p2)) => (Some(v2.clone()), Some(p2.clone())),
            None => (None, Some(pos(&t.name_loc))),
        };
        let rule = key_rule(kind, k, same_effect && now.is_some());
        cx.add(
            Change::new(rule, &subject, k.clone())
                .values(Some(v.clone()), now)
                .at(Some(p.clone()), np)
                .breaking(rule.rule().breaking && !same_effect),
        );
    }
    for (k, v, p) in &b {
        if !(a.iter().any(|(k2, _, _)| k2 == k) || skipped(kind, k)) {
            let rule = key_rule(kind, k, false);
            cx.add(
                Change::new(rule, &subject, k.clone())
                    .values(None, Some(v.clone()))
                    .at(Some(pos(&s.name_loc)), Some(p.clone()))
                    .breaking(rule.rule().breaking && !same_effect),
            );
        }
    }
    if !same_effect && a.len() == b.len() && a.iter().zip(&b).all(|(x, y)| x.0 == y.0 && x.1 == y.1)
    {
        // Same text, different effect: a parameter default or the model changed under it.
        let witness = match (was_r, now_r) {
            (None, Some(_)) => "switched on under the default parameters",
            (Some(_), None) => "switched off under the default parameters",
            _ => "same text, different value under the default parameters",
        };
        // (an actuator table can add dozens of actuators: name only those that changed)
        let (was, now) = if kind.name == "actuators" {
            actuator_delta(cx.old_r, cx.new_r, &s.name)
        } else {
            (
                (kind.describe)(cx.old_r, &s.name),
                (kind.describe)(cx.new_r, &t.name),
            )
        };
        cx.add(
            Change::new(kind.resolved_changed, &subject, "resolved value")
                .values(was, now)
                .at(Some(pos(&s.name_loc)), Some(pos(&t.name_loc)))
                .witness(witness),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind(name: &'static str) -> Kind {
        Kind {
            name,
            added: RuleId::RewardTermAdded,
            removed: RuleId::RewardTermRemoved,
            renamed: RuleId::RewardTermRenamed,
            key_changed: RuleId::RewardTermKeyChanged,
            resolved_changed: RuleId::RewardTermResolvedChanged,
            describe: |_, _| None,
        }
    }

    #[test]
    fn key_rules() {
        let k = kind("reward");
        // A selector key respelled with the same effect is documentation (selector-respelled).
        for key in ["source", "minus", "target", "achieved", "desired"] {
            assert_eq!(key_rule(&k, key, true), RuleId::SelectorRespelled, "{key}");
            assert_eq!(
                key_rule(&k, key, false),
                RuleId::RewardTermKeyChanged,
                "{key}"
            );
        }
        assert_eq!(key_rule(&k, "doc", false), RuleId::DocChanged);
        assert_eq!(key_rule(&k, "doc", true), RuleId::DocChanged);
        // Any other key is the section's own key-changed rule, same effect or not (the
        // same-effect case is lowered to compatible where the change is made, not here).
        assert_eq!(key_rule(&k, "weight", true), RuleId::RewardTermKeyChanged);
        assert_eq!(key_rule(&k, "weight", false), RuleId::RewardTermKeyChanged);
    }

    #[test]
    fn keys_with_rules_of_their_own_are_skipped() {
        assert!(skipped(&kind("reward"), "info"));
        assert!(!skipped(&kind("reward"), "weight"));
        assert!(!skipped(&kind("reward"), "noise"));
        assert!(skipped(&kind("observation"), "noise"));
        assert!(skipped(&kind("observation"), "delay"));
        assert!(!skipped(&kind("observation"), "info"));
        assert!(!skipped(&kind("observation"), "source"));
    }
}
