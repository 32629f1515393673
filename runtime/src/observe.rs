//! The observation-segment kernel: one evaluator of the IR's [`Segment`]s, shared by the
//! single-agent env (its observation) and the multi-agent env (each agent's observation), so
//! both compute every element with the same operations in the same order.

use envspec::Field;
use envspec::ir::{Apply, Segment};

use crate::numerics::clip;

/// Write each segment into `out[seg.offset..]`: `source − minus`, then `apply`, then
/// `indicator`, then `clip`.
/// `field` gives a field's current values. Allocation-free.
pub(crate) fn write_segments<'a>(
    segments: &[Segment],
    field: impl Fn(Field) -> &'a [f64],
    out: &mut [f64],
) {
    write_segments_with(segments, field, out, |_, x| x);
}

/// [`write_segments`] with `pre_clip(segment index, x)` applied to each element before its
/// segment's `clip` (observation noise: Isaac Lab's order, noise then clip), in element order.
#[inline]
pub(crate) fn write_segments_with<'a>(
    segments: &[Segment],
    field: impl Fn(Field) -> &'a [f64],
    out: &mut [f64],
    mut pre_clip: impl FnMut(usize, f64) -> f64,
) {
    for (i, seg) in segments.iter().enumerate() {
        let f = field(seg.source.field);
        let minus = seg.minus.as_ref().map(|m| (m, field(m.field)));
        let dst = &mut out[seg.offset..seg.offset + seg.len()];
        for (k, o) in dst.iter_mut().enumerate() {
            let mut x = f[seg.source.indices[k]];
            if let Some(s) = seg.scale {
                x *= s;
            }
            if let Some((m, g)) = minus {
                let y = g[m.indices[k]];
                x -= seg.scale.map_or(y, |s| y * s);
            }
            x = match seg.apply {
                Some(Apply::Sin) => x.sin(),
                Some(Apply::Cos) => x.cos(),
                Some(Apply::Positive) => f64::from(u8::from(x > 0.0)),
                None => x,
            };
            if let Some(ind) = &seg.indicator {
                x = ind.apply(x);
            }
            x = pre_clip(i, x);
            if let Some((lo, hi)) = seg.clip {
                x = clip(x, lo, hi);
            }
            *o = x;
        }
    }
}
