//! `[derived.*]`, each table judged by what it resolves to.

use super::rules::RuleId;
use super::{Ctx, change::Change, pos};
use crate::derived::Derived;

/// One change per table added, removed, or resolving to other values.
pub(super) fn derived(cx: &mut Ctx) {
    // The resolved value decides; the description is what the report shows.
    let key = |d: &Derived| {
        (
            format!("{:?} {:?}", d.kind, d.at_reset),
            crate::describe::derived(d),
        )
    };
    let (o, n) = (&cx.old_r.derived, &cx.new_r.derived);
    let mut names: Vec<&str> = o.iter().map(|d| d.name.as_str()).collect();
    names.extend(
        n.iter()
            .map(|d| d.name.as_str())
            .filter(|x| !o.iter().any(|d| d.name == *x)),
    );
    let mut out = vec![];
    for name in names {
        let was = o.iter().find(|d| d.name == name).map(key);
        let now = n.iter().find(|d| d.name == name).map(key);
        if was.as_ref().map(|w| &w.0) == now.as_ref().map(|n| &n.0) {
            continue;
        }
        let (was, now) = (was.map(|w| w.1), now.map(|n| n.1));
        let aspect = match (&was, &now) {
            (None, _) => "added",
            (_, None) => "removed",
            _ => "changed",
        };
        let at = |s: &crate::syntax::Spec| {
            s.derived
                .iter()
                .find(|x| x.name == name)
                .map(|x| pos(&x.name_loc))
        };
        out.push(
            Change::new(RuleId::DerivedChanged, format!("derived.{name}"), aspect)
                .values(was, now)
                .at(at(cx.old), at(cx.new)),
        );
    }
    for c in out {
        cx.add(c);
    }
}
