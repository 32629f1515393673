//! The observation-segment kernel: one evaluator of the IR's [`Segment`]s, shared by the
//! single-agent env (its observation) and the multi-agent env (each agent's observation), so
//! both compute every element with the same operations in the same order.

use envspec::Field;
use envspec::ir::{Apply, Segment};

use crate::numerics::clip;

/// Write each segment into `out[seg.offset..]`: `source − minus`, then `apply`, then `clip`.
/// `field` gives a field's current values. Allocation-free.
pub(crate) fn write_segments<'a>(
    segments: &[Segment],
    field: impl Fn(Field) -> &'a [f64],
    out: &mut [f64],
) {
    for seg in segments {
        let f = field(seg.source.field);
        let minus = seg.minus.as_ref().map(|m| (m, field(m.field)));
        let dst = &mut out[seg.offset..seg.offset + seg.len()];
        for (k, o) in dst.iter_mut().enumerate() {
            let mut x = f[seg.source.indices[k]];
            if let Some((m, g)) = minus {
                x -= g[m.indices[k]];
            }
            x = match seg.apply {
                Some(Apply::Sin) => x.sin(),
                Some(Apply::Cos) => x.cos(),
                None => x,
            };
            if let Some((lo, hi)) = seg.clip {
                x = clip(x, lo, hi);
            }
            *o = x;
        }
    }
}
