//! Differences between two compiled MuJoCo models, for `envc diff`: a spec that names a new model
//! file may or may not change the physics, and a spec that keeps the file name may point at a
//! different file. We compare what MuJoCo compiled, not the file names.
//!
//! The arrays that matter to dynamics and the action space are compared element by element with
//! readable names (`geom_friction[foot_geom]`); everything else is covered by comparing the
//! complete binary model (`mj_saveModel`), reported as one residual change.

use envspec::diff::{Change, RuleId};
use mujoco_rs::mujoco_c::{mjModel, mjtObj};
use mujoco_rs::prelude::{MjModel, MjtBias, MjtDyn, MjtEq, MjtGain, MjtGeomBase, MjtJoint};

fn name(m: &mjModel, obj: mjtObj, id: usize) -> String {
    crate::mj::names::name(m, obj, id).unwrap_or_else(|| format!("#{id}"))
}

/// A model array's values as doubles, row-major.
trait Flat {
    fn flat(&self) -> Vec<f64>;
}

impl Flat for [f64] {
    fn flat(&self) -> Vec<f64> {
        self.to_vec()
    }
}

impl<const N: usize> Flat for [[f64; N]] {
    fn flat(&self) -> Vec<f64> {
        self.as_flattened().to_vec()
    }
}

impl Flat for [i32] {
    fn flat(&self) -> Vec<f64> {
        self.iter().map(|&x| f64::from(x)).collect()
    }
}

impl<const N: usize> Flat for [[i32; N]] {
    fn flat(&self) -> Vec<f64> {
        self.as_flattened().flat()
    }
}

/// MuJoCo's enumerations, by their numbers.
macro_rules! flat_enum {
    ($($t:ty),*) => {$(
        impl Flat for [$t] {
            fn flat(&self) -> Vec<f64> {
                self.iter().map(|&x| f64::from(x as i32)).collect()
            }
        }
    )*};
}
flat_enum!(MjtGeomBase, MjtJoint, MjtDyn, MjtGain, MjtBias, MjtEq);

/// The first `n` values of `x` (the count the comparison is made for).
fn nums<T: Flat + ?Sized>(x: &T, n: usize) -> Vec<f64> {
    let mut v = x.flat();
    v.truncate(n);
    v
}

/// Per actuator: its dynamics, gain and bias types.
fn types(m: &MjModel) -> Vec<f64> {
    let nu = m.ffi().nu as usize;
    let (d, g, b) = (
        nums(m.actuator_dyntype(), nu),
        nums(m.actuator_gaintype(), nu),
        nums(m.actuator_biastype(), nu),
    );
    (0..nu).flat_map(|i| [d[i], g[i], b[i]]).collect()
}

/// Per row: whether the range is limited (1 or 0), then the range.
fn limited(flag: &[bool], range: &[[f64; 2]], n: usize) -> Vec<f64> {
    (0..n.min(flag.len()).min(range.len()))
        .flat_map(|i| [f64::from(u8::from(flag[i])), range[i][0], range[i][1]])
        .collect()
}

/// The complete binary model (`mj_saveModel`).
fn saved(m: &MjModel) -> Vec<u8> {
    let mut buf = vec![0u8; m.size()];
    // The buffer has the size MuJoCo asks for, so the save cannot fail.
    match m.save_to_buffer(&mut buf) {
        Ok(()) => buf,
        Err(_) => vec![],
    }
}

/// One compared array: its name, rule, per-row width, object type for row names, and values.
struct Arr {
    field: &'static str,
    rule: RuleId,
    width: usize,
    obj: mjtObj,
    old: Vec<f64>,
    new: Vec<f64>,
}

/// The arrays `diff_models` compares, with the values of both models (each array's element count
/// from the old model; only compared where both models have that count).
fn compared_arrays(old: &MjModel, new: &MjModel) -> Vec<Arr> {
    let (a, b) = (old.ffi(), new.ffi());
    let (nb, ng, nj, nv, nu) = (
        a.nbody as usize,
        a.ngeom as usize,
        a.njnt as usize,
        a.nv as usize,
        a.nu as usize,
    );
    /// Array `field` of both models, `n` values each.
    macro_rules! arr {
        ($field:ident, $rule:ident, $width:expr, $obj:ident, $n:expr) => {
            Arr {
                field: stringify!($field),
                rule: RuleId::$rule,
                width: $width,
                obj: $obj,
                old: nums(old.$field(), $n),
                new: nums(new.$field(), $n),
            }
        };
    }
    use mjtObj::*;
    let mut arrays = vec![
        arr!(body_mass, ModelArrayChanged, 1, mjOBJ_BODY, nb),
        arr!(body_inertia, ModelArrayChanged, 3, mjOBJ_BODY, nb * 3),
        arr!(body_ipos, ModelArrayChanged, 3, mjOBJ_BODY, nb * 3),
        arr!(body_pos, ModelArrayChanged, 3, mjOBJ_BODY, nb * 3),
        arr!(body_quat, ModelArrayChanged, 4, mjOBJ_BODY, nb * 4),
        arr!(geom_friction, ModelArrayChanged, 3, mjOBJ_GEOM, ng * 3),
        arr!(geom_size, ModelArrayChanged, 3, mjOBJ_GEOM, ng * 3),
        arr!(geom_pos, ModelArrayChanged, 3, mjOBJ_GEOM, ng * 3),
        arr!(geom_type, ModelArrayChanged, 1, mjOBJ_GEOM, ng),
        arr!(geom_condim, ModelArrayChanged, 1, mjOBJ_GEOM, ng),
        arr!(geom_contype, ModelArrayChanged, 1, mjOBJ_GEOM, ng),
        arr!(geom_conaffinity, ModelArrayChanged, 1, mjOBJ_GEOM, ng),
        arr!(geom_solref, ModelArrayChanged, 2, mjOBJ_GEOM, ng * 2),
        arr!(jnt_type, ModelArrayChanged, 1, mjOBJ_JOINT, nj),
        arr!(jnt_axis, ModelArrayChanged, 3, mjOBJ_JOINT, nj * 3),
        arr!(jnt_range, ModelArrayChanged, 2, mjOBJ_JOINT, nj * 2),
        arr!(jnt_stiffness, ModelArrayChanged, 1, mjOBJ_JOINT, nj),
        arr!(dof_damping, ModelArrayChanged, 1, mjOBJ_DOF, nv),
        arr!(dof_armature, ModelArrayChanged, 1, mjOBJ_DOF, nv),
        arr!(dof_frictionloss, ModelArrayChanged, 1, mjOBJ_DOF, nv),
        arr!(
            actuator_ctrlrange,
            ModelActuatorArrayChanged,
            2,
            mjOBJ_ACTUATOR,
            nu * 2
        ),
        arr!(actuator_gear, ModelArrayChanged, 6, mjOBJ_ACTUATOR, nu * 6),
        arr!(
            actuator_gainprm,
            ModelArrayChanged,
            10,
            mjOBJ_ACTUATOR,
            nu * 10
        ),
        arr!(
            actuator_biasprm,
            ModelArrayChanged,
            10,
            mjOBJ_ACTUATOR,
            nu * 10
        ),
        arr!(
            actuator_dynprm,
            ModelArrayChanged,
            10,
            mjOBJ_ACTUATOR,
            nu * 10
        ),
        Arr {
            field: "actuator_type",
            rule: RuleId::ModelArrayChanged,
            width: 3,
            obj: mjOBJ_ACTUATOR,
            old: types(old),
            new: types(new),
        },
        Arr {
            field: "actuator_forcerange",
            rule: RuleId::ModelArrayChanged,
            width: 3,
            obj: mjOBJ_ACTUATOR,
            old: limited(old.actuator_forcelimited(), old.actuator_forcerange(), nu),
            new: limited(new.actuator_forcelimited(), new.actuator_forcerange(), nu),
        },
        Arr {
            field: "key_qpos",
            rule: RuleId::ModelQpos0Changed,
            width: a.nq as usize,
            obj: mjOBJ_KEY,
            old: nums(old.key_qpos(), a.nkey as usize * a.nq as usize),
            new: nums(new.key_qpos(), a.nkey as usize * a.nq as usize),
        },
        arr!(
            actuator_trnid,
            ModelActuatorArrayChanged,
            2,
            mjOBJ_ACTUATOR,
            nu * 2
        ),
        Arr {
            field: "qpos0",
            rule: RuleId::ModelQpos0Changed,
            width: 1,
            obj: mjOBJ_UNKNOWN,
            old: nums(old.qpos0(), a.nq as usize),
            new: nums(new.qpos0(), b.nq as usize),
        },
    ];
    arrays.extend(equality_arrays(old, new));
    arrays
}

/// Equality constraints (a weld ties a mocap target to a hand): what and which they tie, their
/// data (anchor, relative pose, torque scale) and their softness.
fn equality_arrays(old: &MjModel, new: &MjModel) -> Vec<Arr> {
    let neq = old.ffi().neq as usize;
    let data = mujoco_rs::mujoco_c::mjNEQDATA as usize;
    let arr = |field, width, old: Vec<f64>, new: Vec<f64>| Arr {
        field,
        rule: RuleId::ModelArrayChanged,
        width,
        obj: mjtObj::mjOBJ_EQUALITY,
        old,
        new,
    };
    vec![
        arr(
            "eq_type",
            1,
            nums(old.eq_type(), neq),
            nums(new.eq_type(), neq),
        ),
        arr(
            "eq_obj1id",
            1,
            nums(old.eq_obj1id(), neq),
            nums(new.eq_obj1id(), neq),
        ),
        arr(
            "eq_obj2id",
            1,
            nums(old.eq_obj2id(), neq),
            nums(new.eq_obj2id(), neq),
        ),
        arr(
            "eq_data",
            data,
            nums(old.eq_data(), neq * data),
            nums(new.eq_data(), neq * data),
        ),
        arr(
            "eq_solref",
            2,
            nums(old.eq_solref(), neq * 2),
            nums(new.eq_solref(), neq * 2),
        ),
        arr(
            "eq_solimp",
            5,
            nums(old.eq_solimp(), neq * 5),
            nums(new.eq_solimp(), neq * 5),
        ),
    ]
}

/// Compiled-model changes between `old` and `new` (empty when the compiled models are identical).
pub fn diff_models(old: &MjModel, new: &MjModel) -> Vec<Change> {
    let (a, b) = (old.ffi(), new.ffi());
    let mut out = vec![];
    size_changes(a, b, &mut out);
    option_changes(a, b, &mut out);
    array_changes(old, new, &mut out);
    if out.is_empty() && saved(old) != saved(new) {
        // Not classified here: `envc diff` judges it by a rollout, as every model change.
        out.push(
            Change::new(RuleId::ModelBinaryChanged, "model", "compiled model")
                .values(
                    Some("one binary model".into()),
                    Some("another (outside the compared arrays)".into()),
                )
                .witness("the binary models differ outside the compared physics arrays (visual settings, names or other options)")
                .breaking(false),
        );
    }
    out
}

/// One change of the model: `aspect` was `was` and is `now`.
fn change(
    rule: RuleId,
    aspect: String,
    was: String,
    now: String,
    witness: Option<String>,
) -> Change {
    let c = Change::new(rule, "model", aspect).values(Some(was), Some(now));
    match witness {
        Some(w) => c.witness(w),
        None => c,
    }
}

/// The sizes (`nq`, `nu`, ...) that differ.
fn size_changes(a: &mjModel, b: &mjModel, out: &mut Vec<Change>) {
    let sizes = [
        ("nq", a.nq, b.nq),
        ("nv", a.nv, b.nv),
        ("nu", a.nu, b.nu),
        ("nbody", a.nbody, b.nbody),
        ("njnt", a.njnt, b.njnt),
        ("ngeom", a.ngeom, b.ngeom),
        ("nsite", a.nsite, b.nsite),
        ("ntendon", a.ntendon, b.ntendon),
    ];
    for (n, x, y) in sizes {
        if x != y {
            let rule = if n == "nu" {
                RuleId::ModelActuatorCountChanged
            } else {
                RuleId::ModelSizeChanged
            };
            out.push(change(rule, n.into(), x.to_string(), y.to_string(), None));
        }
    }
}

/// The physics options (`opt.*`) that differ, bit for bit.
fn option_changes(a: &mjModel, b: &mjModel, out: &mut Vec<Change>) {
    let (oa, ob) = (&a.opt, &b.opt);
    let scalars = [
        ("opt.timestep", oa.timestep, ob.timestep),
        ("opt.density", oa.density, ob.density),
        ("opt.viscosity", oa.viscosity, ob.viscosity),
        ("opt.integrator", oa.integrator as f64, ob.integrator as f64),
        ("opt.solver", oa.solver as f64, ob.solver as f64),
        ("opt.iterations", oa.iterations as f64, ob.iterations as f64),
        (
            "opt.ls_iterations",
            oa.ls_iterations as f64,
            ob.ls_iterations as f64,
        ),
        (
            "opt.noslip_iterations",
            oa.noslip_iterations as f64,
            ob.noslip_iterations as f64,
        ),
        (
            "opt.ccd_iterations",
            oa.ccd_iterations as f64,
            ob.ccd_iterations as f64,
        ),
        ("opt.tolerance", oa.tolerance, ob.tolerance),
        ("opt.ls_tolerance", oa.ls_tolerance, ob.ls_tolerance),
        ("opt.impratio", oa.impratio, ob.impratio),
        ("opt.cone", oa.cone as f64, ob.cone as f64),
    ];
    for (n, x, y) in scalars {
        if x.to_bits() != y.to_bits() {
            out.push(change(
                RuleId::ModelOptionChanged,
                n.into(),
                x.to_string(),
                y.to_string(),
                None,
            ));
        }
    }
    if oa.gravity != ob.gravity {
        out.push(change(
            RuleId::ModelOptionChanged,
            "opt.gravity".into(),
            format!("{:?}", oa.gravity),
            format!("{:?}", ob.gravity),
            None,
        ));
    }
}

/// The compared arrays' rows that differ, one change per array (its first row, the others
/// named in the witness).
fn array_changes(old: &MjModel, new: &MjModel, out: &mut Vec<Change>) {
    let (a, b) = (old.ffi(), new.ffi());
    // Each group of arrays is compared when its element count is the same in both models
    // (a removed geom must not hide a changed body mass).
    let same = |x: i64, y: i64| x == y;
    let counts_match = |field: &str| match field.split('_').next().unwrap_or("") {
        "body" => same(a.nbody, b.nbody),
        "geom" => same(a.ngeom, b.ngeom),
        "jnt" => same(a.njnt, b.njnt),
        "dof" => same(a.nv, b.nv),
        "actuator" => same(a.nu, b.nu),
        "eq" => same(a.neq, b.neq),
        "key" => same(a.nkey, b.nkey) && same(a.nq, b.nq),
        _ => same(a.nq, b.nq),
    };
    let arrs = compared_arrays(old, new);
    for arr in arrs {
        if !counts_match(arr.field) {
            continue;
        }
        let mut diffs = row_diffs(&arr, b);
        match diffs.len() {
            0 => {}
            1 => {
                let (l, x, y) = diffs.remove(0);
                out.push(change(arr.rule, format!("{}[{l}]", arr.field), x, y, None));
            }
            n => {
                let (l, x, y) = diffs[0].clone();
                let others: Vec<&str> = diffs[1..].iter().map(|d| d.0.as_str()).take(8).collect();
                out.push(change(
                    arr.rule,
                    format!("{}[{l}]", arr.field),
                    x,
                    y,
                    Some(format!(
                        "{n} rows differ; also {}{}",
                        others.join(", "),
                        if n > 9 { ", …" } else { "" }
                    )),
                ));
            }
        }
    }
}

/// The rows of `arr` that differ bit for bit: each row's name (in model `b`), old and new values.
fn row_diffs(arr: &Arr, b: &mjModel) -> Vec<(String, String, String)> {
    let rows = arr.old.len() / arr.width.max(1);
    let mut diffs = vec![];
    for r in 0..rows {
        let (x, y) = (
            &arr.old[r * arr.width..(r + 1) * arr.width],
            &arr.new[r * arr.width..(r + 1) * arr.width],
        );
        if x.iter().zip(y).any(|(p, q)| p.to_bits() != q.to_bits()) {
            let label = if arr.obj == mjtObj::mjOBJ_UNKNOWN {
                format!("{r}")
            } else {
                name(b, arr.obj, r)
            };
            let fmt = |v: &[f64]| {
                if v.len() == 1 {
                    format!("{}", v[0])
                } else {
                    format!("{v:?}")
                }
            };
            diffs.push((label, fmt(x), fmt(y)));
        }
    }
    diffs
}
