//! Changes of the spec as a whole rather than of one section: the reward sum, whether an
//! unhealthy state ends the episode, `dt`, and the reset draw order.

use super::rules::RuleId;
use super::{Change, Ctx, pos};
use crate::describe;
use crate::ir::ResolvedSpec;
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
