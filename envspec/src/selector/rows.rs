//! A field's rows: their readable names, and the rows an index selects by name, by name range
//! or by integer.

use super::parse::Index;
use super::{Field, ParamIndex, Rows};
use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::mjcf::ModelInfo;

/// Readable names of a field's rows.
pub(super) fn row_names(field: Field, model: &ModelInfo) -> Vec<String> {
    let or_id = |name: &str, prefix: &str, i: usize| {
        if name.is_empty() {
            format!("{prefix}{i}")
        } else {
            name.to_string()
        }
    };
    match field.rows() {
        Rows::Qpos | Rows::Dof => {
            let mut out = vec![];
            for (j, joint) in model.joints.iter().enumerate() {
                let parts = if field.rows() == Rows::Qpos {
                    joint.kind.qpos_parts()
                } else {
                    joint.kind.dof_parts()
                };
                let base = or_id(&joint.name, "joint", j);
                for p in parts {
                    out.push(if p.is_empty() {
                        base.clone()
                    } else {
                        format!("{base}:{p}")
                    });
                }
            }
            out
        }
        Rows::Body => model
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| or_id(b, "body", i))
            .collect(),
        Rows::Site => model
            .sites
            .iter()
            .enumerate()
            .map(|(i, s)| or_id(s, "site", i))
            .collect(),
        Rows::Mocap => model
            .mocap
            .iter()
            .enumerate()
            .map(|(i, &b)| or_id(&model.bodies[b], "mocap", i))
            .collect(),
        Rows::Tendon => model
            .tendons
            .iter()
            .enumerate()
            .map(|(i, s)| or_id(s, "tendon", i))
            .collect(),
        Rows::Actuator => model
            .actuators
            .iter()
            .enumerate()
            .map(|(i, a)| or_id(&a.name, "actuator", i))
            .collect(),
        Rows::Xyz => vec!["x".into(), "y".into(), "z".into()],
        Rows::Command => vec![],
        // One row per value: `touch` (one value), `accel:0` … `accel:2`.
        Rows::Sensor => {
            let mut out = vec![];
            for (i, (name, dim)) in model.sensors.iter().enumerate() {
                let base = or_id(name, "sensor", i);
                match dim {
                    Some(1) => out.push(base),
                    Some(n) => out.extend((0..*n).map(|k| format!("{base}:{k}"))),
                    // (a sensor of unknown size ends what can be numbered)
                    None => break,
                }
            }
            out
        }
        Rows::TendonDof => {
            let dofs = row_names(Field::Qvel, model);
            let mut out = vec![];
            for (i, t) in model.tendons.iter().enumerate() {
                for d in &dofs {
                    out.push(format!("{}:{d}", or_id(t, "tendon", i)));
                }
            }
            out
        }
    }
}

/// The rows an index selects: by name, name range, `$param` or integers.
pub(super) fn select_rows(
    idx: &Index,
    field: Field,
    model: &ModelInfo,
    nrows: usize,
    loc: &Location,
    param: &dyn Fn(&str) -> Result<ParamIndex, Diagnostic>,
) -> Result<Vec<usize>, Diagnostic> {
    let by_name = |name: &str| -> Result<Vec<usize>, Diagnostic> {
        // A row by the name envc prints: one element of a multi-element joint (`root:z`), or
        // an unnamed element by its generated name (`actuator0`). A joint's own name still
        // selects all its elements (`qpos[root]`: 7).
        if let Some(i) = row_names(field, model).iter().position(|r| r == name) {
            return Ok(vec![i]);
        }
        match rows_by_name(name, field, model, loc) {
            Ok(rows) => Ok(rows),
            Err(e) => name_range(name, field, model, loc).unwrap_or(Err(e)),
        }
    };
    match idx {
        Index::Name(n) => by_name(n),
        Index::Names(l) => {
            let mut out = vec![];
            for n in l {
                match n.parse::<i64>() {
                    Ok(i) => out.extend(select_ints(&Index::Int(i), nrows, loc)?),
                    Err(_) => out.extend(by_name(n)?),
                }
            }
            Ok(out)
        }
        Index::Param(p) => match param(p)? {
            ParamIndex::Name(n) => by_name(&n),
            ParamIndex::Int(i) => select_ints(&Index::Int(i), nrows, loc),
        },
        other => select_ints(other, nrows, loc),
    }
}

/// `first:last`, two names (names may hold `:` themselves, as `root:z`): every row from the
/// first's first to the last's last, both included (`qpos[shoulder:wrist]`). `None` when no split
/// of the text names two elements; an error when the two are out of order or several splits do.
fn name_range(
    text: &str,
    field: Field,
    model: &ModelInfo,
    loc: &Location,
) -> Option<Result<Vec<usize>, Diagnostic>> {
    let names = row_names(field, model);
    let rows = |n: &str| -> Option<Vec<usize>> {
        match names.iter().position(|r| r == n) {
            Some(i) => Some(vec![i]),
            None => rows_by_name(n, field, model, loc)
                .ok()
                .filter(|r| !r.is_empty()),
        }
    };
    let ranges: Vec<(usize, usize)> = text
        .match_indices(':')
        .filter_map(|(k, _)| {
            let (a, b) = (rows(text[..k].trim())?, rows(text[k + 1..].trim())?);
            Some((*a.first()?, *b.last()?))
        })
        .collect();
    let err = |label: String| {
        Some(Err(Diagnostic::new(
            Code::E0401,
            format!("cannot read the name range `{text}`"),
        )
        .at(loc.clone())
        .label(label)))
    };
    match ranges.as_slice() {
        [] => None,
        [(a, b)] if a <= b => Some(Ok((*a..=*b).collect())),
        [(a, b)] => err(format!(
            "expected the first name before the last: `{}` comes after `{}`",
            names[*a], names[*b]
        )),
        _ => err("expected one way to split it into two names; list the names with `,`".into()),
    }
}

/// The rows a name selects: a joint's, a body's, a sensor's values, ... E0303 when the model has
/// no element of that name.
fn rows_by_name(
    name: &str,
    field: Field,
    model: &ModelInfo,
    loc: &Location,
) -> Result<Vec<usize>, Diagnostic> {
    let (what, candidates, found) = named_rows(name, field, model);
    found.ok_or_else(|| {
        let named: Vec<&str> = candidates
            .iter()
            .copied()
            .filter(|c| !c.is_empty())
            .collect();
        Diagnostic::new(
            Code::E0303,
            format!(
                "the model {} has no {what} named `{name}`",
                model.path.display()
            ),
        )
        .at(loc.clone())
        .label(format!(
            "expected the name of a {what} of the model ({} named)",
            named.len()
        ))
        .help_opt(
            // No such site but a body of that name (URDF models have no sites): its position is
            // `xpos[name]`.
            (field == Field::SiteXpos && model.body_id(name).is_some())
                .then(|| {
                    format!(
                        "`{name}` is a body of this model, not a site: its position is `xpos[{name}]`"
                    )
                })
                .or_else(|| suggest(name, named.iter().copied())),
        )
    })
}

/// What a field's rows are, the names the model gives them, and the rows `name` selects.
fn named_rows<'m>(
    name: &str,
    field: Field,
    model: &'m ModelInfo,
) -> (&'static str, Vec<&'m str>, Option<Vec<usize>>) {
    match field.rows() {
        Rows::Qpos | Rows::Dof => {
            let found = model.joint(name).map(|j| {
                if field.rows() == Rows::Qpos {
                    (j.qposadr..j.qposadr + j.kind.nq()).collect()
                } else {
                    (j.dofadr..j.dofadr + j.kind.nv()).collect()
                }
            });
            (
                "joint",
                model.joints.iter().map(|j| j.name.as_str()).collect(),
                found,
            )
        }
        Rows::Body => (
            "body",
            model.bodies.iter().map(String::as_str).collect(),
            model.body_id(name).map(|i| vec![i]),
        ),
        Rows::Site => (
            "site",
            model.sites.iter().map(String::as_str).collect(),
            model.sites.iter().position(|s| s == name).map(|i| vec![i]),
        ),
        Rows::Mocap => (
            "mocap body",
            model
                .mocap
                .iter()
                .map(|&b| model.bodies[b].as_str())
                .collect(),
            model
                .mocap
                .iter()
                .position(|&b| model.bodies[b] == name)
                .map(|i| vec![i]),
        ),
        Rows::Tendon => (
            "tendon",
            model.tendons.iter().map(String::as_str).collect(),
            model
                .tendons
                .iter()
                .position(|s| s == name)
                .map(|i| vec![i]),
        ),
        Rows::Actuator => (
            "actuator",
            model.actuators.iter().map(|a| a.name.as_str()).collect(),
            model
                .actuators
                .iter()
                .position(|a| a.name == name)
                .map(|i| vec![i]),
        ),
        Rows::TendonDof => ("tendon:dof pair", vec![], None),
        Rows::Sensor => {
            let mut adr = 0;
            let mut found = None;
            for (n, dim) in &model.sensors {
                let Some(dim) = dim else { break };
                if n == name {
                    found = Some((adr..adr + dim).collect());
                    break;
                }
                adr += dim;
            }
            (
                "sensor",
                model.sensors.iter().map(|s| s.0.as_str()).collect(),
                found,
            )
        }
        Rows::Command => ("command", vec![], None),
        Rows::Xyz => (
            "component",
            vec!["x", "y", "z"],
            ["x", "y", "z"]
                .iter()
                .position(|c| *c == name)
                .map(|i| vec![i]),
        ),
    }
}

/// The entries of `n` that integers, lists or slices select (Python semantics).
pub(super) fn select_ints(idx: &Index, n: usize, loc: &Location) -> Result<Vec<usize>, Diagnostic> {
    let n_i = n as i64;
    let one = |i: i64| -> Result<usize, Diagnostic> {
        let j = if i < 0 { i + n_i } else { i };
        if j < 0 || j >= n_i {
            Err(Diagnostic::new(
                Code::E0304,
                format!("index {i} is out of range for {n} entries"),
            )
            .at(loc.clone())
            .label(format!("expected an index in -{n}..{n}")))
        } else {
            Ok(j as usize)
        }
    };
    match idx {
        Index::Int(i) => Ok(vec![one(*i)?]),
        Index::List(l) => l.iter().map(|&i| one(i)).collect(),
        Index::Slice(a, b) => {
            // Python slice semantics: clamp, negative counts from the end.
            let clamp = |v: i64| -> i64 { if v < 0 { (v + n_i).max(0) } else { v.min(n_i) } };
            let a = a.map(clamp).unwrap_or(0);
            let b = b.map(clamp).unwrap_or(n_i);
            Ok((a..b.max(a)).map(|i| i as usize).collect())
        }
        Index::Name(_) | Index::Names(_) | Index::Param(_) => {
            unreachable!("names are resolved by the caller")
        }
    }
}
