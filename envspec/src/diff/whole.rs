//! Changes of the spec as a whole rather than of one section: the reward sum, whether an
//! unhealthy state ends the episode, `dt`, and the reset draw order.

use super::rules::RuleId;
use super::{Change, Ctx, pos};
use crate::describe;
use crate::ir::{ResolvedSpec, SOLVER_OPTIONS, SolverOption};
use crate::syntax::Spec;

pub(super) fn reward_sum(cx: &mut Ctx) {
    let (a, b) = (
        describe::reward_sum(cx.old_r),
        describe::reward_sum(cx.new_r),
    );
    if a != b {
        let at = |s: &Spec| s.reward_sum.as_ref().map(|v| pos(&v.loc));
        cx.add(
            Change::new(RuleId::RewardSumChanged, "reward", "sum")
                .values(Some(a), Some(b))
                .at(at(cx.old), at(cx.new)),
        );
    }
}

pub(super) fn episode(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    if o.terminate_when_unhealthy != n.terminate_when_unhealthy {
        cx.add(
            Change::new(
                RuleId::HealthTerminateChanged,
                "health",
                "an unhealthy state ends the episode",
            )
            .values(
                Some(o.terminate_when_unhealthy.to_string()),
                Some(n.terminate_when_unhealthy.to_string()),
            ),
        );
    }
    if o.frame_skip != n.frame_skip || o.model.timestep.to_bits() != n.model.timestep.to_bits() {
        let dt = |r: &ResolvedSpec| format!("{} × {} = {}", r.model.timestep, r.frame_skip, r.dt());
        cx.add(
            Change::new(RuleId::EnvDtChanged, "env", "dt = timestep × frame_skip")
                .values(Some(dt(o)), Some(dt(n))),
        );
    }
}

pub(super) fn reset_order(cx: &mut Ctx) {
    let names = |r: &ResolvedSpec| r.reset.iter().map(|s| s.name.clone()).collect::<Vec<_>>();
    let (a, b) = (names(cx.old_r), names(cx.new_r));
    let common_a: Vec<&String> = a.iter().filter(|x| b.contains(x)).collect();
    let common_b: Vec<&String> = b.iter().filter(|x| a.contains(x)).collect();
    if common_a != common_b {
        cx.add(
            Change::new(RuleId::ResetDrawOrderChanged, "reset", "draw order")
                .values(Some(a.join(", ")), Some(b.join(", "))),
        );
    }
}

/// `[physics]` solver options, one change per key that differs, at its lines (the compiled
/// model's `opt.*` witness the same change when models are compared).
pub(super) fn physics_options(cx: &mut Ctx) {
    let value = |r: &ResolvedSpec, o: SolverOption| {
        r.model_edits
            .solver
            .iter()
            .find(|(x, _)| *x == o)
            .map(|(_, v)| v.to_string())
    };
    for &(key, option, _, _) in SOLVER_OPTIONS {
        let (was, now) = (value(cx.old_r, option), value(cx.new_r, option));
        if was != now {
            let at = |s: &Spec| {
                s.physics
                    .as_ref()
                    .and_then(|p| p.get(key))
                    .map(|v| pos(&v.loc))
            };
            let unset = || Some("the model's".to_string());
            cx.add(
                Change::new(RuleId::PhysicsOptionChanged, "physics", key)
                    .values(was.or_else(unset), now.or_else(unset))
                    .at(at(cx.old), at(cx.new)),
            );
        }
    }
}

/// `[physics] forward_before_observation`, which changes no model array.
pub(super) fn observation_refresh(cx: &mut Ctx) {
    let (o, n) = (
        cx.old_r.model_edits.forward_before_observation,
        cx.new_r.model_edits.forward_before_observation,
    );
    if o != n {
        let at = |s: &Spec| {
            s.physics
                .as_ref()
                .and_then(|p| p.get("forward_before_observation"))
                .map(|v| pos(&v.loc))
        };
        cx.add(
            Change::new(
                RuleId::ObservationRefreshChanged,
                "physics",
                "forward_before_observation",
            )
            .values(Some(o.to_string()), Some(n.to_string()))
            .at(at(cx.old), at(cx.new)),
        );
    }
}

/// `[terrain]` judged by what it resolves to; each written key or generator key that differs is
/// one change at its lines. A terrain change is breaking by rule: a seeded rollout walks on a few
/// tiles and cannot witness the others.
pub(super) fn terrain(cx: &mut Ctx) {
    let (o, n) = (&cx.old_r.model_edits.terrain, &cx.new_r.model_edits.terrain);
    if o == n {
        return;
    }
    let (a, b) = (cx.old.terrain.as_ref(), cx.new.terrain.as_ref());
    match (a, b) {
        (None, Some(s)) => cx.add(
            Change::new(RuleId::TerrainAdded, "terrain", "added")
                .values(None, Some(super::sections::summary(s)))
                .at(None, Some(pos(&s.name_loc))),
        ),
        (Some(s), None) => cx.add(
            Change::new(RuleId::TerrainRemoved, "terrain", "removed")
                .values(Some(super::sections::summary(s)), None)
                .at(Some(pos(&s.name_loc)), None),
        ),
        (Some(a), Some(b)) => {
            let (ka, kb) = (keys(a), keys(b));
            let mut any = false;
            let mut names: Vec<&String> = ka.iter().chain(&kb).map(|(k, _, _)| k).collect();
            names.dedup();
            let mut seen = std::collections::BTreeSet::new();
            for name in names {
                if !seen.insert(name.clone()) {
                    continue;
                }
                let find = |v: &[(String, String, super::Pos)]| {
                    v.iter().find(|(k, _, _)| k == name).cloned()
                };
                let (x, y) = (find(&ka), find(&kb));
                if x.as_ref().map(|e| &e.1) != y.as_ref().map(|e| &e.1) {
                    any = true;
                    cx.add(
                        Change::new(RuleId::TerrainChanged, "terrain", name.clone())
                            .values(
                                x.as_ref().map(|e| e.1.clone()),
                                y.as_ref().map(|e| e.1.clone()),
                            )
                            .at(x.map(|e| e.2), y.map(|e| e.2)),
                    );
                }
            }
            if !any {
                // Same text, another result: a parameter it reads changed.
                cx.add(
                    Change::new(RuleId::TerrainChanged, "terrain", "resolved")
                        .values(Some(format!("{o:?}")), Some(format!("{n:?}")))
                        .at(Some(pos(&a.name_loc)), Some(pos(&b.name_loc))),
                );
            }
        }
        (None, None) => {}
    }
}

/// `[terrain]`'s keys and its generators' keys (`<generator>.<key>`), with values and lines.
fn keys(s: &crate::syntax::Section) -> Vec<(String, String, super::Pos)> {
    let mut out = vec![];
    for e in &s.entries {
        if e.key == "doc" {
            continue;
        }
        match e.value.as_table() {
            Some(t) => {
                for inner in t.iter().filter(|x| x.key != "doc") {
                    out.push((
                        format!("{}.{}", e.key, inner.key),
                        inner.value.to_toml(),
                        pos(&inner.key_loc),
                    ));
                }
            }
            None => out.push((e.key.clone(), e.value.to_toml(), pos(&e.key_loc))),
        }
    }
    out
}
