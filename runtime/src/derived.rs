//! `[derived.*]` computed (IR: `envspec::derived`): each table in document order, after every
//! reset (all of them) and after every step's physics (those without `at = "reset"`), into a
//! preallocated buffer that `derived[...]` selections read.

use envspec::Field;
use envspec::derived::{Derived, DerivedKind};
use envspec::selector::Selection;

use crate::numerics::{self, Profile};

/// Element `k` of `s`: from `derived` for a `derived[...]` selection, else from `field`.
fn read<'a>(field: &impl Fn(Field) -> &'a [f64], derived: &[f64], s: &Selection, k: usize) -> f64 {
    let i = s.indices[k];
    match s.field {
        Field::Derived => derived[i],
        f => field(f)[i],
    }
}

/// Recompute the derived values into `out` (`reset`: the `at = "reset"` ones too). A table reads
/// only the ones above it, so each is computed from values already final.
pub(crate) fn update<'a>(
    tables: &[Derived],
    field: impl Fn(Field) -> &'a [f64],
    profile: Profile,
    reset: bool,
    out: &mut [f64],
) {
    for d in tables.iter().filter(|d| reset || !d.at_reset) {
        match &d.kind {
            DerivedKind::Difference {
                source,
                minus,
                divide_by,
            } => {
                let div = divide_by.as_ref().map(|s| read(&field, out, s, 0));
                for k in 0..d.len {
                    let mut x = read(&field, out, source, k);
                    if let Some(m) = minus {
                        x -= read(&field, out, m, k);
                    }
                    if let Some(v) = div {
                        x /= v;
                    }
                    out[d.offset + k] = x;
                }
            }
            DerivedKind::Norm { source, minus } => {
                let x = {
                    let o: &[f64] = out;
                    numerics::norm(profile, source.len(), &|k| {
                        let x = read(&field, o, source, k);
                        minus.as_ref().map_or(x, |m| x - read(&field, o, m, k))
                    })
                };
                out[d.offset] = x;
            }
            DerivedKind::Dot { source, with } => {
                let x = {
                    let o: &[f64] = out;
                    numerics::dot(
                        profile,
                        source.len(),
                        &|k| read(&field, o, source, k),
                        &|k| read(&field, o, with, k),
                    )
                };
                out[d.offset] = x;
            }
        }
    }
}
