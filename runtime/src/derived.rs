//! `[derived.*]` computed (IR: `envspec::derived`): each table in document order, after every
//! reset (all of them) and after every step's physics (those without `at = "reset"`), into a
//! preallocated buffer that `derived[...]` selections read.

use envspec::derived::{ContactSide, ContactValue, Derived, DerivedKind};
use envspec::selector::Selection;
use envspec::{Field, ResolvedSpec};
use mujoco_rs::mujoco_c::{mjModel, mjtObj};
use mujoco_rs::prelude::MjData;
use mujoco_rs::wrappers::mj_model::traits::ModelType;

use crate::numerics::{self, Profile};

/// Element `k` of `s`: from `derived` for a `derived[...]` selection, else from `field`.
fn read<'a>(field: &impl Fn(Field) -> &'a [f64], derived: &[f64], s: &Selection, k: usize) -> f64 {
    let i = s.indices[k];
    match s.field {
        Field::Derived => derived[i],
        f => field(f)[i],
    }
}

/// A `contact` table's two sides as ids: `(geom or body id, is a body)`; the second side
/// `None` matches any geom.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ContactIds {
    a: (i32, bool),
    b: Option<(i32, bool)>,
    value: ContactValue,
}

/// One entry per `[derived.*]` table: the ids of a `contact` table, `None` for the others.
pub(crate) fn contact_ids(
    spec: &ResolvedSpec,
    m: &mjModel,
) -> Result<Vec<Option<ContactIds>>, crate::EnvError> {
    let side = |s: &ContactSide| {
        let (obj, what) = if s.body {
            (mjtObj::mjOBJ_BODY, "body")
        } else {
            (mjtObj::mjOBJ_GEOM, "geom")
        };
        crate::mj::names::id(m, obj, &s.name)
            .map(|i| (i as i32, s.body))
            .ok_or_else(|| crate::EnvError::Legged {
                env: spec.id.clone(),
                what: format!("the compiled model has no {what} `{}`", s.name),
            })
    };
    spec.derived
        .iter()
        .map(|d| match &d.kind {
            DerivedKind::Contact { a, b, value } => Ok(Some(ContactIds {
                a: side(a)?,
                b: b.as_ref().map(side).transpose()?,
                value: *value,
            })),
            _ => Ok(None),
        })
        .collect()
}

/// A `contact` value from the contacts of the last forward pass, into `out` (1 or 3 values).
/// The force on the first side: MuJoCo's contact frame has its normal from `geom[0]` to
/// `geom[1]`, and `mj_contactForce` gives the force on `geom[1]` in that frame, so it is
/// `± frameᵀ · f[0:3]`, summed in contact order.
fn contact<M: ModelType>(ids: &ContactIds, d: &MjData<M>, out: &mut [f64]) {
    let geom_bodyid = d.model().geom_bodyid();
    let is = |g: i32, (id, body): (i32, bool)| {
        if body && g >= 0 {
            geom_bodyid[g as usize] == id
        } else {
            g == id
        }
    };
    let other = |g: i32| ids.b.is_none_or(|b| is(g, b));
    let (mut count, mut normal, mut force) = (0usize, 0.0, [0.0; 3]);
    for (i, c) in d.contact().iter().enumerate() {
        let [g0, g1] = c.geom;
        let sign = if is(g1, ids.a) && other(g0) {
            1.0
        } else if is(g0, ids.a) && other(g1) {
            -1.0
        } else {
            continue;
        };
        count += 1;
        if matches!(ids.value, ContactValue::Touching | ContactValue::Count) {
            continue;
        }
        // i < ncon, so this cannot fail; a failure reads as no force.
        let f = d.try_contact_force(i).unwrap_or([0.0; 6]);
        normal += f[0];
        for (k, fk) in force.iter_mut().enumerate() {
            let world = c.frame[k] * f[0] + c.frame[3 + k] * f[1] + c.frame[6 + k] * f[2];
            *fk += sign * world;
        }
    }
    match ids.value {
        ContactValue::Touching => out[0] = f64::from(u8::from(count > 0)),
        ContactValue::Count => out[0] = count as f64,
        ContactValue::NormalForce => out[0] = normal,
        ContactValue::Force => out[..3].copy_from_slice(&force),
    }
}

/// Recompute the derived values into `out` (`reset`: the `at = "reset"` ones too). A table reads
/// only the ones above it, so each is computed from values already final.
pub(crate) fn update<'a, M: ModelType>(
    tables: &[Derived],
    contacts: &[Option<ContactIds>],
    data: &MjData<M>,
    field: impl Fn(Field) -> &'a [f64],
    profile: Profile,
    reset: bool,
    out: &mut [f64],
) {
    for (d, ids) in tables
        .iter()
        .zip(contacts)
        .filter(|(d, _)| reset || !d.at_reset)
    {
        match &d.kind {
            DerivedKind::Contact { .. } => {
                if let Some(ids) = ids {
                    contact(ids, data, &mut out[d.offset..d.offset + d.len]);
                }
            }
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
