//! `[init]`, `[end_effector]`, `[hold.*]` and `[goal]`, each judged by what it resolves to.

use super::rules::RuleId;
use super::{Ctx, change::Change, pos};
use crate::syntax::Section;

/// One change per table whose resolved value differs (added, removed or changed).
pub(super) fn manipulation(cx: &mut Ctx) {
    let (o, n) = (&cx.old_r.manipulation, &cx.new_r.manipulation);
    let holds = |m: &crate::manipulation::Manipulation| {
        (!m.hold.is_empty()).then(|| format!("{:?}", m.hold))
    };
    let tables: [(RuleId, &str, Option<String>, Option<String>); 4] = [
        (
            RuleId::ManipulationInitChanged,
            "init",
            o.init.as_ref().map(|x| format!("{x:?}")),
            n.init.as_ref().map(|x| format!("{x:?}")),
        ),
        (
            RuleId::EndEffectorChanged,
            "end_effector",
            o.end_effector.as_ref().map(|x| format!("{x:?}")),
            n.end_effector.as_ref().map(|x| format!("{x:?}")),
        ),
        (RuleId::HoldChanged, "hold", holds(o), holds(n)),
        (
            RuleId::GoalChanged,
            "goal",
            o.goal.as_ref().map(goal),
            n.goal.as_ref().map(goal),
        ),
    ];
    for (rule, table, was, now) in tables {
        if was == now {
            continue;
        }
        let aspect = match (&was, &now) {
            (None, _) => "added",
            (_, None) => "removed",
            _ => "changed",
        };
        let at = |s: &crate::syntax::Spec| -> Option<super::Pos> {
            let sec: Option<&Section> = match table {
                "init" => s.init.as_ref(),
                "end_effector" => s.end_effector.as_ref(),
                "goal" => s.goal.as_ref(),
                _ => s.hold.first(),
            };
            sec.map(|x| pos(&x.name_loc))
        };
        let c = Change::new(rule, table, aspect)
            .values(was, now)
            .at(at(cx.old), at(cx.new));
        cx.add(c);
    }
}

/// What a `[goal]` resolves to: the achieved elements, and the parts with their values.
fn goal(g: &crate::manipulation::GoalTable) -> String {
    let names = g.achieved.names.join(", ");
    match &g.parts {
        None => names,
        Some(p) => format!("{names}; {p:?}"),
    }
}
