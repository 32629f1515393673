//! Building the model a spec runs on: the model file as is, or, when the spec has `[actuators]` or
//! `[physics]`, the file loaded into an mjSpec, edited and compiled. Works the same for MJCF and
//! URDF files (MuJoCo reads both).

use envspec::ir::{ActuatorKind, AddedActuator, Integrator, ModelEdits};
use mujoco_rs::mujoco_c::mjtIntegrator;
use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_editing::{MjtLimited, PositionConfig};

/// Load the model file into an mjSpec, apply the edits and compile it.
pub(crate) fn compile_edited(
    path: &std::path::Path,
    edits: &ModelEdits,
) -> Result<MjModel, String> {
    load_edited(path, edits)?
        .compile()
        .map_err(|e| e.to_string())
}

/// Load the model file into an mjSpec and apply the edits (a maze then adds its world).
pub(crate) fn load_edited(path: &std::path::Path, edits: &ModelEdits) -> Result<MjSpec, String> {
    let mut spec = MjSpec::from_xml(path).map_err(|e| e.to_string())?;
    if let Some(ts) = edits.timestep {
        spec.option_mut().timestep = ts;
    }
    if let Some(i) = edits.integrator {
        spec.option_mut().integrator = match i {
            Integrator::Euler => mjtIntegrator::mjINT_EULER,
            Integrator::Rk4 => mjtIntegrator::mjINT_RK4,
            Integrator::Implicit => mjtIntegrator::mjINT_IMPLICIT,
            Integrator::ImplicitFast => mjtIntegrator::mjINT_IMPLICITFAST,
        } as i32;
    }
    for a in &edits.actuators {
        add_actuator(&mut spec, a)?;
    }
    Ok(spec)
}

fn add_actuator(spec: &mut MjSpec, a: &AddedActuator) -> Result<(), String> {
    let act = spec.add_actuator();
    act.set_name(&a.name)
        .map_err(|e| format!("cannot add actuator `{}`: {e}", a.name))?;
    act.set_trntype(MjtTrn::mjTRN_JOINT);
    act.set_target(&a.joint);
    match a.kind {
        ActuatorKind::Motor => act.set_to_motor(),
        ActuatorKind::Position { kp, kv } => act
            .set_to_position(PositionConfig {
                kp,
                kv,
                ..Default::default()
            })
            .map_err(|e| format!("actuator `{}`: {e}", a.name))?,
        ActuatorKind::Velocity { kv } => act.set_to_velocity(kv),
    }
    act.gear_mut()[0] = a.gear;
    act.set_ctrllimited(MjtLimited::mjLIMITED_TRUE);
    *act.ctrlrange_mut() = [a.ctrlrange.0, a.ctrlrange.1];
    if let Some((lo, hi)) = a.forcerange {
        act.set_forcelimited(MjtLimited::mjLIMITED_TRUE);
        *act.forcerange_mut() = [lo, hi];
    }
    Ok(())
}
