//! Info dicts: where each key's values sit in the env's info buffers, the read-only view of them,
//! and how one info entry's values are computed.

use envspec::ir::*;

use super::Env;
use super::sim::Sim;
use crate::numerics::norm;

/// Where one info key's values sit in the info buffer.
#[derive(Clone, Debug)]
pub(super) struct InfoSlot {
    key: String,
    offset: usize,
    len: usize,
}

/// Read-only view of an info dict: keys in spec order, each with one or more f64 values.
#[derive(Clone, Copy, Debug)]
pub struct Info<'a> {
    pub(super) slots: &'a [InfoSlot],
    pub(super) values: &'a [f64],
}

impl<'a> Info<'a> {
    /// The values of `key`, or None when the spec declares no such key.
    pub fn get(&self, key: &str) -> Option<&'a [f64]> {
        self.slots
            .iter()
            .find(|s| s.key == key)
            .map(|s| &self.values[s.offset..s.offset + s.len])
    }
    /// The value of a scalar key.
    pub fn scalar(&self, key: &str) -> Option<f64> {
        self.get(key).and_then(|v| (v.len() == 1).then(|| v[0]))
    }
    /// Every key with its values, in spec order.
    pub fn iter(&self) -> impl Iterator<Item = (&'a str, &'a [f64])> + 'a {
        let values = self.values;
        self.slots
            .iter()
            .map(move |s| (s.key.as_str(), &values[s.offset..s.offset + s.len]))
    }
    /// The number of keys.
    pub fn len(&self) -> usize {
        self.slots.len()
    }
    /// Whether the dict has no keys.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }
    /// The keys, in spec order.
    pub fn keys(&self) -> impl Iterator<Item = &'a str> + 'a {
        self.slots.iter().map(|s| s.key.as_str())
    }
}

impl Env {
    /// The info of the last `step` (kept when a later `reset` fills the reset info).
    pub fn step_info(&self) -> Info<'_> {
        Info {
            slots: &self.step_info,
            values: &self.step_info_values,
        }
    }
    /// The info of the last `reset`.
    pub fn reset_info(&self) -> Info<'_> {
        Info {
            slots: &self.reset_info,
            values: &self.reset_info_values,
        }
    }
}

/// Where each item's values go in one info buffer: consecutive, in the items' order.
pub(super) fn layout(items: &mut dyn Iterator<Item = &InfoItem>) -> Vec<InfoSlot> {
    let mut off = 0;
    items
        .map(|i| {
            let s = InfoSlot {
                key: i.key.clone(),
                offset: off,
                len: i.len,
            };
            off += i.len;
            s
        })
        .collect::<Vec<_>>()
}

/// How many values an info buffer laid out as `slots` holds.
pub(super) fn total(slots: &[InfoSlot]) -> usize {
    slots.iter().map(|s| s.len).sum::<usize>()
}

/// One info item's values, written into `out` (a free function so the spec can stay borrowed
/// while the env's buffers are written: no per-step `Arc` clone).
pub(super) fn write_info(
    sim: &Sim,
    before: &[f64],
    term_values: &[f64],
    dt: f64,
    item: &InfoItem,
    slot: Option<usize>,
    out: &mut [f64],
) {
    match &item.kind {
        InfoKind::Value { source, minus } => {
            let f = sim.field(source.field);
            for (k, o) in out.iter_mut().enumerate() {
                *o = f[source.indices[k]];
                if let Some(m) = minus {
                    *o -= sim.field(m.field)[m.indices[k]];
                }
            }
        }
        InfoKind::Norm { source } => {
            let f = sim.field(source.field);
            out[0] = norm(sim.numerics, source.len(), &|k| f[source.indices[k]]);
        }
        InfoKind::Velocity { source } => {
            let k = slot.expect("velocity infos have a slot");
            out[0] = (sim.get(source, 0) - before[k]) / dt;
        }
        InfoKind::Term(i) if item.unweighted => out[0] = term_values[term_values.len() / 2 + *i],
        InfoKind::Term(i) => out[0] = term_values[*i],
        InfoKind::GoalReached(c) => out[0] = sim.goal_reached(c) as u8 as f64,
        InfoKind::GoalsReached(cs) => out[0] = sim.goals_reached(cs) as u8 as f64,
        InfoKind::Condition(cs) => out[0] = cs.iter().all(|c| sim.condition_holds(c)) as u8 as f64,
        InfoKind::GoalParts(which) => {
            if let Some(c) = &sim.parts {
                c.write(*which, out);
            }
        }
    }
}
