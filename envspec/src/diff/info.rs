//! Info entries, compared by key on the resolved specs (a key may move between an `[info]` table
//! and a reward term without changing), plus `[info.*]` tables only active under non-default
//! parameters and their docs.

use super::rules::RuleId;
use super::{Change, Ctx, Pos, behaviour, pos, sections};
use crate::describe;
use crate::ir::{InfoItem, InfoKind, ResolvedSpec};
use crate::syntax::Spec;

/// Where an info key is defined: an `[info.*]` table (by name or `key`), or a reward term's `info`.
fn info_pos(spec: &Spec, key: &str) -> Option<Pos> {
    for s in &spec.info {
        if s.name == key || s.str("key") == Some(key) {
            return Some(pos(&s.name_loc));
        }
    }
    spec.reward
        .iter()
        .find(|t| t.str("info") == Some(key))
        .and_then(|t| t.get("info"))
        .map(|v| pos(&v.loc))
}

/// The reward term an info entry reports, if any.
fn info_term<'a>(r: &'a ResolvedSpec, i: &InfoItem) -> Option<&'a str> {
    match i.kind {
        InfoKind::Term(t) => r.reward.get(t).map(|t| t.name.as_str()),
        _ => None,
    }
}

/// An info entry's definition, with the weight of a reward-term entry spelled out.
fn info_text(r: &ResolvedSpec, i: &InfoItem) -> String {
    match &i.kind {
        InfoKind::Term(t) => match r.reward.get(*t) {
            Some(term) => {
                let w = if i.unweighted {
                    " without its weight"
                } else {
                    ""
                };
                format!("reward term `{}`{w}: {}", term.name, describe::term(term))
            }
            None => format!("reward term #{t}"),
        },
        _ => describe::info(r, i),
    }
}

pub(super) fn info_items(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let removed: Vec<&InfoItem> = o
        .info
        .iter()
        .filter(|i| !n.info.iter().any(|j| j.key == i.key))
        .collect();
    let added: Vec<&InfoItem> = n
        .info
        .iter()
        .filter(|j| !o.info.iter().any(|i| i.key == j.key))
        .collect();
    let (renamed_to, taken) = renames(cx, &removed, &added);
    for (r, i) in removed.iter().enumerate() {
        let subject = format!("info.{}", i.key);
        cx.add(match renamed_to[r] {
            Some(a) => Change::new(RuleId::InfoKeyRenamed, subject, "renamed")
                .values(Some(i.key.clone()), Some(added[a].key.clone()))
                .at(info_pos(cx.old, &i.key), info_pos(cx.new, &added[a].key)),
            None => Change::new(RuleId::InfoKeyRemoved, subject, "removed")
                .values(Some(info_text(o, i)), None)
                .at(info_pos(cx.old, &i.key), None),
        });
    }
    kept(cx);
    for (a, j) in added.iter().enumerate() {
        if !taken[a] {
            let when = if j.at_reset { "reset and step" } else { "step" };
            cx.add(
                Change::new(RuleId::InfoKeyAdded, format!("info.{}", j.key), "added")
                    .values(None, Some(format!("{} ({when})", info_text(n, j))))
                    .at(None, info_pos(cx.new, &j.key)),
            );
        }
    }
    inactive_tables_removed(cx);
    docs(cx);
}

/// Pair removed keys with added ones: for each removed key, the added key it was renamed to;
/// for each added key, whether a removed one took it. A rename that also changed the reported
/// reward term's definition is reported here.
fn renames(
    cx: &mut Ctx,
    removed: &[&InfoItem],
    added: &[&InfoItem],
) -> (Vec<Option<usize>>, Vec<bool>) {
    let (o, n) = (cx.old_r, cx.new_r);
    let same = |i: &InfoItem, j: &InfoItem| behaviour::info(o, i) == behaviour::info(n, j);
    // A key that disappears while another with the same definition appears was renamed.
    let mut renamed_to: Vec<Option<usize>> = vec![None; removed.len()];
    let mut taken = vec![false; added.len()];
    for (r, i) in removed.iter().enumerate() {
        if let Some(a) = (0..added.len()).find(|&a| !taken[a] && same(i, added[a])) {
            taken[a] = true;
            renamed_to[r] = Some(a);
        }
    }
    // Failing that, a key moving to another key of the same reward term is a rename too (the
    // term itself may have changed; that is reported as its definition).
    for (r, i) in removed.iter().enumerate() {
        if renamed_to[r].is_some() {
            continue;
        }
        let Some(term) = info_term(o, i) else {
            continue;
        };
        if let Some(a) =
            (0..added.len()).find(|&a| !taken[a] && info_term(n, added[a]) == Some(term))
        {
            taken[a] = true;
            renamed_to[r] = Some(a);
            if !same(i, added[a]) {
                cx.add(
                    Change::new(
                        RuleId::InfoKeyDefinitionChanged,
                        format!("info.{}", added[a].key),
                        "definition",
                    )
                    .values(Some(info_text(o, i)), Some(info_text(n, added[a])))
                    .at(info_pos(cx.old, &i.key), info_pos(cx.new, &added[a].key)),
                );
            }
        }
    }
    (renamed_to, taken)
}

/// Keys on both sides: their definition and when they are reported.
fn kept(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let same = |i: &InfoItem, j: &InfoItem| behaviour::info(o, i) == behaviour::info(n, j);
    for i in &o.info {
        let Some(j) = n.info.iter().find(|j| j.key == i.key) else {
            continue;
        };
        let subject = format!("info.{}", i.key);
        let at = (info_pos(cx.old, &i.key), info_pos(cx.new, &j.key));
        if !same(i, j) {
            cx.add(
                Change::new(RuleId::InfoKeyDefinitionChanged, &subject, "definition")
                    .values(Some(info_text(o, i)), Some(info_text(n, j)))
                    .at(at.0.clone(), at.1.clone()),
            );
        }
        if i.at_reset != j.at_reset {
            let f = |b: bool| if b { "reset and step" } else { "step only" }.to_string();
            cx.add(
                Change::new(RuleId::InfoKeyReportedAtChanged, &subject, "reported at")
                    .values(Some(f(i.at_reset)), Some(f(j.at_reset)))
                    .at(at.0, at.1),
            );
        }
    }
}

/// `[info.*]` tables that only apply under non-default parameters and are gone in the new spec
/// (e.g. an alternative definition of a key switched on by a flag).
fn inactive_tables_removed(cx: &mut Ctx) {
    let o = cx.old_r;
    for s in &cx.old.info {
        let key = s.str("key").unwrap_or(&s.name);
        let active = o
            .info
            .iter()
            .any(|i| i.key == key && info_pos(cx.old, key) == Some(pos(&s.name_loc)));
        if !active && !cx.new.info.iter().any(|t| t.name == s.name) {
            let witness = match s.get("when") {
                Some(w) => format!("it applied only when {}", w.to_toml()),
                None => "it applied only under non-default parameters".into(),
            };
            cx.changes.push(
                Change::new(
                    RuleId::InfoTableInactiveRemoved,
                    format!("info.{}", s.name),
                    "removed",
                )
                .values(Some(sections::summary(s)), None)
                .at(Some(pos(&s.name_loc)), None)
                .witness(witness),
            );
        }
    }
}

/// The docs of `[info.*]` tables on both sides.
fn docs(cx: &mut Ctx) {
    for s in &cx.old.info {
        let Some(t) = cx.new.info.iter().find(|t| t.name == s.name) else {
            continue;
        };
        if s.doc() != t.doc() {
            cx.changes.push(
                Change::new(RuleId::DocChanged, format!("info.{}", s.name), "doc")
                    .values(Some(s.doc()), Some(t.doc()))
                    .at(Some(pos(&s.name_loc)), Some(pos(&t.name_loc))),
            );
        }
    }
}
