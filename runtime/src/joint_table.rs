//! The resolved per-joint table `envc show` prints: every hinge and slide joint with the
//! actuators on it and their properties, read from the compiled model (what runs), and the
//! `[joint_properties]` rows that set them.

use mujoco_rs::mujoco_c::{mjtBias, mjtGain, mjtJoint, mjtObj, mjtTrn};

use crate::Env;

/// One joint (and the first actuator on it, if any).
#[derive(Clone, Debug, PartialEq)]
pub struct JointRow {
    pub joint: String,
    /// The actuator's name and index in the action.
    pub actuator: Option<(String, usize)>,
    /// `position`, `velocity`, `motor` or `other` (from the gain and bias types).
    pub kind: &'static str,
    pub kp: Option<f64>,
    pub kv: Option<f64>,
    pub gear: Option<f64>,
    pub forcerange: Option<(f64, f64)>,
    pub ctrlrange: Option<(f64, f64)>,
    pub armature: f64,
    pub damping: f64,
    pub frictionloss: f64,
    /// The `[joint_properties]` rows that set one of this joint's values (patterns, in order).
    pub rows: Vec<String>,
}

fn name(m: &mujoco_rs::mujoco_c::mjModel, obj: mjtObj, i: usize) -> String {
    // SAFETY: i is below the object count; MuJoCo returns NULL for unnamed objects.
    let p = unsafe { mujoco_rs::mujoco_c::mj_id2name(m, obj as i32, i as i32) };
    if p.is_null() {
        format!("#{i}")
    } else {
        // SAFETY: a NUL-terminated string owned by the model.
        unsafe { std::ffi::CStr::from_ptr(p) }
            .to_string_lossy()
            .into_owned()
    }
}

/// The table, in joint order (hinge and slide joints only).
pub fn joint_table(env: &Env) -> Vec<JointRow> {
    let m = env.model().ffi();
    let spec = env.spec();
    let (njnt, nu) = (m.njnt as usize, m.nu as usize);
    const N: usize = mujoco_rs::mujoco_c::mjNGAIN as usize;
    let mut out = vec![];
    // SAFETY: every array is read within its documented length (njnt, nv, nu × width).
    unsafe {
        for j in 0..njnt {
            let t = *m.jnt_type.add(j);
            if t != mjtJoint::mjJNT_HINGE as i32 && t != mjtJoint::mjJNT_SLIDE as i32 {
                continue;
            }
            let dof = *m.jnt_dofadr.add(j) as usize;
            let joint = name(m, mjtObj::mjOBJ_JOINT, j);
            let a = (0..nu).find(|&a| {
                *m.actuator_trntype.add(a) == mjtTrn::mjTRN_JOINT as i32
                    && *m.actuator_trnid.add(2 * a) as usize == j
            });
            let mut row = JointRow {
                rows: spec
                    .model_edits
                    .joints
                    .iter()
                    .find(|e| e.joint == joint)
                    .map(|e| e.rows.clone())
                    .unwrap_or_default(),
                joint,
                actuator: None,
                kind: "-",
                kp: None,
                kv: None,
                gear: None,
                forcerange: None,
                ctrlrange: None,
                armature: *m.dof_armature.add(dof),
                damping: *m.dof_damping.add(dof),
                frictionloss: *m.dof_frictionloss.add(dof),
            };
            if let Some(a) = a {
                let (g, b) = (*m.actuator_gaintype.add(a), *m.actuator_biastype.add(a));
                let (gain, bias) = (
                    *m.actuator_gainprm.add(a * N),
                    m.actuator_biasprm.add(a * N),
                );
                let fixed = g == mjtGain::mjGAIN_FIXED as i32;
                let affine = b == mjtBias::mjBIAS_AFFINE as i32;
                row.kind = if fixed && affine && *bias.add(1) != 0.0 {
                    row.kp = Some(gain);
                    row.kv = Some(-*bias.add(2));
                    "position"
                } else if fixed && affine {
                    row.kv = Some(gain);
                    "velocity"
                } else if fixed && b == mjtBias::mjBIAS_NONE as i32 {
                    "motor"
                } else {
                    "other"
                };
                row.actuator = Some((name(m, mjtObj::mjOBJ_ACTUATOR, a), a));
                row.gear = Some(*m.actuator_gear.add(6 * a));
                row.ctrlrange = (*m.actuator_ctrllimited.add(a)).then(|| {
                    (
                        *m.actuator_ctrlrange.add(2 * a),
                        *m.actuator_ctrlrange.add(2 * a + 1),
                    )
                });
                row.forcerange = (*m.actuator_forcelimited.add(a)).then(|| {
                    (
                        *m.actuator_forcerange.add(2 * a),
                        *m.actuator_forcerange.add(2 * a + 1),
                    )
                });
            }
            out.push(row);
        }
    }
    out
}
