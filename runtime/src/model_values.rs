//! Values a compiled model may hold that envc cannot run (E1003), checked once when an env is
//! built: a control range that is not finite (a random policy's action is then meaningless, and
//! numpy's `uniform` raises), and positions or sizes that are not finite or beyond
//! `envspec::limits::MAX_COORDINATE` (MuJoCo then takes seconds per step, or resets the state
//! with a warning every step).

use envspec::limits::MAX_COORDINATE;
use mujoco_rs::mujoco_c::{mjModel, mjtObj};
use mujoco_rs::prelude::MjModel;

use crate::describe::inventory::name;
use crate::error::EnvError;

/// `1e308`, `-0.4`: plain for ordinary magnitudes, exponent form for huge ones.
fn num(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// An actuator by name, or by number and the joint it drives (Gymnasium's are unnamed).
fn actuator(model: &MjModel, i: usize) -> String {
    let m: &mjModel = model.ffi();
    let own = name(m, mjtObj::mjOBJ_ACTUATOR, i);
    if !own.ends_with("(unnamed)") {
        return format!("`{own}`");
    }
    let (kind, id) = (model.actuator_trntype()[i], model.actuator_trnid()[i][0]);
    if kind == mujoco_rs::mujoco_c::mjtTrn::mjTRN_JOINT {
        format!(
            "#{i} (on joint `{}`)",
            name(m, mjtObj::mjOBJ_JOINT, id as usize)
        )
    } else {
        format!("#{i}")
    }
}

pub(crate) fn check(path: &std::path::Path, model: &MjModel) -> Result<(), EnvError> {
    let m: &mjModel = model.ffi();
    let bad = |what: String| EnvError::BadModelValues {
        path: path.to_path_buf(),
        what,
    };
    let show = |r: &[f64]| r.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ");
    for (i, r) in model.actuator_ctrlrange().iter().enumerate() {
        let [lo, hi] = *r;
        if !(lo as f32).is_finite() || !(hi as f32).is_finite() || !(hi - lo).is_finite() {
            return Err(bad(format!(
                "actuator {} has ctrlrange [{}], which is not finite in float32 (the action space)",
                actuator(model, i),
                show(r)
            )));
        }
    }
    let coords: [(&str, &[f64], usize, mjtObj); 7] = [
        ("qpos0 of joint", model.qpos0(), 1, mjtObj::mjOBJ_UNKNOWN),
        (
            "pos of joint",
            model.jnt_pos().as_flattened(),
            3,
            mjtObj::mjOBJ_JOINT,
        ),
        (
            "pos of body",
            model.body_pos().as_flattened(),
            3,
            mjtObj::mjOBJ_BODY,
        ),
        (
            "ipos of body",
            model.body_ipos().as_flattened(),
            3,
            mjtObj::mjOBJ_BODY,
        ),
        (
            "pos of geom",
            model.geom_pos().as_flattened(),
            3,
            mjtObj::mjOBJ_GEOM,
        ),
        (
            "size of geom",
            model.geom_size().as_flattened(),
            3,
            mjtObj::mjOBJ_GEOM,
        ),
        (
            "pos of site",
            model.site_pos().as_flattened(),
            3,
            mjtObj::mjOBJ_SITE,
        ),
    ];
    for (what, values, cols, obj) in coords {
        for (i, r) in values.chunks(cols).enumerate() {
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
