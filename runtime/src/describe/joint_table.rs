//! The resolved per-joint table `envc show` prints: every hinge and slide joint with the
//! actuators on it and their properties, read from the compiled model (what runs), and the
//! `[joint_properties]` rows that set them.

use mujoco_rs::mujoco_c::{mjtBias, mjtGain, mjtJoint, mjtObj, mjtTrn};

use crate::Env;

/// One joint (and the first actuator on it, if any).
#[derive(Clone, Debug, PartialEq)]
pub struct JointRow {
    /// The joint's name (`#<index>` when unnamed).
    pub joint: String,
    /// The actuator's name and index in the action.
    pub actuator: Option<(String, usize)>,
    /// The actuator's `[actions]` scale (target radians or metres per unit of action).
    pub action_scale: Option<f64>,
    /// `position`, `velocity`, `motor` or `other` (from the gain and bias types).
    pub kind: &'static str,
    /// Position gain (position actuators).
    pub kp: Option<f64>,
    /// Velocity gain (position and velocity actuators).
    pub kv: Option<f64>,
    /// The actuator's first gear entry.
    pub gear: Option<f64>,
    /// The actuator's force range, when limited.
    pub forcerange: Option<(f64, f64)>,
    /// The actuator's control range, when limited.
    pub ctrlrange: Option<(f64, f64)>,
    /// The joint's armature.
    pub armature: f64,
    /// The joint's damping.
    pub damping: f64,
    /// The joint's friction loss.
    pub frictionloss: f64,
    /// The `[joint_properties]` rows that set one of this joint's values (patterns, in order).
    pub rows: Vec<String>,
}

fn name(m: &mujoco_rs::mujoco_c::mjModel, obj: mjtObj, i: usize) -> String {
    crate::mj::names::name(m, obj, i).unwrap_or_else(|| format!("#{i}"))
}

/// The table, in joint order (hinge and slide joints only).
pub fn joint_table(env: &Env) -> Vec<JointRow> {
    let model = env.model();
    let m = model.ffi();
    let spec = env.spec();
    let nu = m.nu as usize;
    let (trn_type, trn_id) = (model.actuator_trntype(), model.actuator_trnid());
    let mut out = vec![];
    for (j, &t) in model.jnt_type().iter().enumerate() {
        if t != mjtJoint::mjJNT_HINGE && t != mjtJoint::mjJNT_SLIDE {
            continue;
        }
        let dof = model.jnt_dofadr()[j] as usize;
        let joint = name(m, mjtObj::mjOBJ_JOINT, j);
        let a = (0..nu).find(|&a| trn_type[a] == mjtTrn::mjTRN_JOINT && trn_id[a][0] as usize == j);
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
            action_scale: None,
            kind: "-",
            kp: None,
            kv: None,
            gear: None,
            forcerange: None,
            ctrlrange: None,
            armature: model.dof_armature()[dof],
            damping: model.dof_damping()[dof],
            frictionloss: model.dof_frictionloss()[dof],
        };
        if let Some(a) = a {
            let (g, b) = (model.actuator_gaintype()[a], model.actuator_biastype()[a]);
            let (gain, bias) = (model.actuator_gainprm()[a][0], model.actuator_biasprm()[a]);
            let fixed = g == mjtGain::mjGAIN_FIXED;
            let affine = b == mjtBias::mjBIAS_AFFINE;
            row.kind = if fixed && affine && bias[1] != 0.0 {
                row.kp = Some(gain);
                row.kv = Some(-bias[2]);
                "position"
            } else if fixed && affine {
                row.kv = Some(gain);
                "velocity"
            } else if fixed && b == mjtBias::mjBIAS_NONE {
                "motor"
            } else {
                "other"
            };
            row.actuator = Some((name(m, mjtObj::mjOBJ_ACTUATOR, a), a));
            row.action_scale = spec.actions.as_ref().and_then(|p| p.scale.get(a).copied());
            row.gear = Some(model.actuator_gear()[a][0]);
            let range = |r: [f64; 2]| (r[0], r[1]);
            row.ctrlrange =
                model.actuator_ctrllimited()[a].then(|| range(model.actuator_ctrlrange()[a]));
            row.forcerange =
                model.actuator_forcelimited()[a].then(|| range(model.actuator_forcerange()[a]));
        }
        out.push(row);
    }
    out
}
