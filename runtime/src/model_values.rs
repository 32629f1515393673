//! Values a compiled model may hold that envc cannot run (E1003), checked once when an env is
//! built: a control range that is not finite (a random policy's action is then meaningless, and
//! numpy's `uniform` raises), and positions or sizes that are not finite or beyond
//! `envspec::limits::MAX_COORDINATE` (MuJoCo then takes seconds per step, or resets the state
//! with a warning every step).

use envspec::limits::MAX_COORDINATE;
use mujoco_rs::mujoco_c::{mjModel, mjtObj};

use crate::error::EnvError;
use crate::inventory::name;

/// `rows × cols` doubles of a model array.
fn rows<'a>(ptr: *const f64, n: i64, cols: usize) -> impl Iterator<Item = &'a [f64]> {
    let len = n.max(0) as usize * cols;
    // SAFETY: callers pass a model array of `n` rows of `cols` doubles.
    let all = if len == 0 {
        &[][..]
    } else {
        unsafe { std::slice::from_raw_parts(ptr, len) }
    };
    all.chunks(cols)
}

/// `1e308`, `-0.4`: plain for ordinary magnitudes, exponent form for huge ones.
fn num(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// An actuator by name, or by number and the joint it drives (Gymnasium's are unnamed).
fn actuator(m: &mjModel, i: usize) -> String {
    let own = name(m, mjtObj::mjOBJ_ACTUATOR, i);
    if !own.ends_with("(unnamed)") {
        return format!("`{own}`");
    }
    // SAFETY: actuator_trntype has nu entries, actuator_trnid nu×2.
    let (kind, id) = unsafe { (*m.actuator_trntype.add(i), *m.actuator_trnid.add(2 * i)) };
    if kind == mujoco_rs::mujoco_c::mjtTrn::mjTRN_JOINT as i32 {
        format!(
            "#{i} (on joint `{}`)",
            name(m, mjtObj::mjOBJ_JOINT, id as usize)
        )
    } else {
        format!("#{i}")
    }
}

pub(crate) fn check(path: &std::path::Path, m: &mjModel) -> Result<(), EnvError> {
    let bad = |what: String| EnvError::BadModelValues {
        path: path.to_path_buf(),
        what,
    };
    let show = |r: &[f64]| r.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ");
    for (i, r) in rows(m.actuator_ctrlrange, m.nu, 2).enumerate() {
        let (lo, hi) = (r[0], r[1]);
        if !(lo as f32).is_finite() || !(hi as f32).is_finite() || !(hi - lo).is_finite() {
            return Err(bad(format!(
                "actuator {} has ctrlrange [{}], which is not finite in float32 (the action space)",
                actuator(m, i),
                show(r)
            )));
        }
    }
    let coords: [(&str, *const f64, i64, usize, mjtObj); 7] = [
        ("qpos0 of joint", m.qpos0, m.nq, 1, mjtObj::mjOBJ_UNKNOWN),
        ("pos of joint", m.jnt_pos, m.njnt, 3, mjtObj::mjOBJ_JOINT),
        ("pos of body", m.body_pos, m.nbody, 3, mjtObj::mjOBJ_BODY),
        ("ipos of body", m.body_ipos, m.nbody, 3, mjtObj::mjOBJ_BODY),
        ("pos of geom", m.geom_pos, m.ngeom, 3, mjtObj::mjOBJ_GEOM),
        ("size of geom", m.geom_size, m.ngeom, 3, mjtObj::mjOBJ_GEOM),
        ("pos of site", m.site_pos, m.nsite, 3, mjtObj::mjOBJ_SITE),
    ];
    for (what, ptr, n, cols, obj) in coords {
        for (i, r) in rows(ptr, n, cols).enumerate() {
            if r.iter().all(|x| x.abs() <= MAX_COORDINATE) {
                continue;
            }
            let element = match obj {
                mjtObj::mjOBJ_UNKNOWN => format!("(qpos[{i}])"),
                _ => format!("`{}`", name(m, obj, i)),
            };
            return Err(bad(format!(
                "the {what} {element} is [{}]: not finite, or beyond envc's limit of {MAX_COORDINATE:e}",
                show(r)
            )));
        }
    }
    Ok(())
}
