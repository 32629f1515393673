//! E0706: a robot wider than a maze cell. Checked on the compiled maze world, where MuJoCo has
//! placed every geom at the robot's initial pose.

use std::path::Path;
use std::sync::Arc;

use envspec::maze::MazeSpec;
use envspec::{Code, Diagnostic, ResolvedSpec};
use mujoco_rs::prelude::*;

use crate::error::EnvError;

/// The robot's horizontal footprint at its initial pose (`qpos0`): the width in x and in y of
/// the geoms that can touch a wall (contype or conaffinity bit 1, as the wall blocks have), each
/// geom's bounding box (`geom_aabb`) rotated into the world frame. World-body geoms (the floor,
/// the walls) are not the robot's. None when no robot geom can touch a wall.
pub fn footprint(model: &Arc<MjModel>, path: &Path) -> Result<Option<[f64; 2]>, EnvError> {
    let mut data = MjData::try_new(Arc::clone(model)).map_err(|e| EnvError::Compile {
        path: path.to_path_buf(),
        message: format!("cannot allocate mjData: {e}"),
    })?;
    crate::mj::call(&mut data, crate::mj::Call::Forward).map_err(|message| EnvError::Mujoco {
        env: path.display().to_string(),
        during: "in mj_forward at the initial pose (measuring the robot's footprint)",
        message,
    })?;
    let (body, contype, conaffinity) = (
        model.geom_bodyid(),
        model.geom_contype(),
        model.geom_conaffinity(),
    );
    let (aabb, xpos, xmat) = (model.geom_aabb(), data.geom_xpos(), data.geom_xmat());
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for g in 0..body.len() {
        if body[g] == 0 || (contype[g] | conaffinity[g]) & 1 == 0 {
            continue;
        }
        let (c, h, r) = (&aabb[g][..3], &aabb[g][3..], &xmat[g]);
        for k in 0..2 {
            let row = &r[3 * k..3 * k + 3];
            let centre = xpos[g][k] + (0..3).map(|m| row[m] * c[m]).sum::<f64>();
            let half: f64 = (0..3).map(|m| row[m].abs() * h[m]).sum();
            lo[k] = lo[k].min(centre - half);
            hi[k] = hi[k].max(centre + half);
        }
    }
    Ok(lo[0].is_finite().then(|| [hi[0] - lo[0], hi[1] - lo[1]]))
}

/// E0706 when the footprint is wider than a cell in both x and y: such a robot cannot stand in
/// a cell, nor pass a corridor one cell wide, in its initial orientation. Narrower in one axis
/// passes (conservative: a long robot may still travel a corridor lengthwise).
pub fn check_robot_fits(
    spec: &MazeSpec,
    robot: &ResolvedSpec,
    model: &Arc<MjModel>,
) -> Result<(), EnvError> {
    let robot_id = &robot.id;
    let Some([w, h]) = footprint(model, &robot.model_path)? else {
        return Ok(());
    };
    let s = spec.maze_size_scaling;
    if w.min(h) <= s {
        return Ok(());
    }
    Err(EnvError::Spec(
        Diagnostic::new(
            Code::E0706,
            format!(
                "the robot `{robot_id}` is {w:.3} × {h:.3} (x × y) at its initial pose, wider than a maze cell of {s}"
            ),
        )
        .at_opt(spec.locations.maze_size_scaling.clone())
        .label(format!("expected at least {:.3}, the robot's narrower width", w.min(h)))
        .help("raise `maze_size_scaling` (the cell size) or use a smaller robot")
        .into(),
    ))
}
