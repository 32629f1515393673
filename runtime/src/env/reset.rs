//! Reset: the events' draws, the `[reset.*]` steps in spec order, then what the first
//! observation and the reset info read.

use std::sync::Arc;

use envspec::ir::*;
use envspec::{Field, ResolvedSpec};
use mujoco_rs::prelude::MjModel;

use super::Env;
use super::info::{Info, write_info};
use super::sim::Sim;
use crate::error::EnvError;
use crate::mj::log as mujoco_log;
use crate::mj::{self, Call};
use crate::numerics::{Profile, norm};
use crate::rng::NumpyRng;

/// Why a reset gave no valid start.
pub(super) enum ResetFailure {
    /// The reset step (index) whose `resample_until` went unmet.
    Unmet(usize),
    /// A MuJoCo error (`mju_error`) in `mj_resetData` or `mj_forward`.
    Mujoco(String),
}

impl Env {
    /// Start an episode. With a seed the RNG restarts from it (numpy `SeedSequence(seed)` →
    /// PCG64); without one the stream continues (the first reset without any seed draws OS entropy).
    pub fn reset(&mut self, seed: Option<u64>) -> (&[f64], Info<'_>) {
        match seed {
            Some(s) => self.rng = Some(NumpyRng::from_seed(s)),
            None if self.rng.is_none() => self.rng = Some(NumpyRng::from_entropy()),
            None => {}
        }
        // No action yet: a reset's observation never carries the last episode's (mjlab's
        // `last_action` after a reset; the same seed, the same reset observation).
        self.sim.action.fill(0.0);
        // Draw order steps 1–2 (docs/spec-reference.md): the events, before `[reset]`.
        let event_error = self.reset_events(seed.is_some());
        let init = self.spec.manipulation.init.as_ref();
        let mut mujoco_error = if init.is_some_and(|i| !i.reset_data) {
            event_error
        } else {
            self.sim.call(Call::ResetData).err().or(event_error)
        };
        self.sim
            .restart(init.is_some(), &self.qpos_init, &self.qvel_init);
        self.start_parts();
        self.reset_failure = None;
        if let Some(message) = self.reset_steps() {
            mujoco_error = Some(message);
        }
        self.sim
            .manip
            .place_marker(&self.sim.goal, &mut self.sim.data);
        // Gymnasium's set_state: qpos, qvel, then mj_forward.
        if mujoco_error.is_none() {
            mujoco_error = self.sim.call(Call::Forward).err();
        }
        if let Some(message) = mujoco_error {
            self.reset_failure = Some(ResetFailure::Mujoco(message));
        }
        self.finish_reset();
        (
            &self.obs,
            Info {
                slots: &self.reset_info,
                values: &self.reset_info_values,
            },
        )
    }

    /// A `[goal]` of parts: every part to complete, the goal vector their desired values
    /// (before the `[reset.*]` steps, which may draw it anew).
    fn start_parts(&mut self) {
        let Some(c) = self.sim.parts.as_mut() else {
            return;
        };
        c.reset();
        let goal = self.spec.manipulation.goal.as_ref();
        for p in goal
            .and_then(|g| g.parts.as_ref())
            .map_or(&[][..], |p| &p.parts)
        {
            self.sim.goal[p.offset..p.offset + p.len()].copy_from_slice(&p.desired);
        }
    }

    /// The `[reset.*]` steps in spec order; a `settle` step whose check fails starts them over.
    /// A MuJoCo error in a `settle` step ends them and comes back as its message.
    fn reset_steps(&mut self) -> Option<String> {
        let spec = Arc::clone(&self.spec);
        let init = spec.manipulation.init.as_ref();
        let rng = self.rng.as_mut().expect("set by reset");
        let (mut next, mut restarts) = (0, 0);
        while next < spec.reset.len() {
            let (k, step) = (next, &spec.reset[next]);
            next += 1;
            let Distribution::Settle(s) = &step.dist else {
                let terrain = self.terrain_origins;
                if !draw_step(&mut self.sim, &mut self.draw, rng, step, terrain, &spec) {
                    self.reset_failure = Some(ResetFailure::Unmet(k));
                }
                continue;
            };
            match self.sim.settle(s, init, spec.frame_skip) {
                Ok(true) => {}
                Ok(false) if restarts < envspec::limits::MAX_SETTLE_RESTARTS => {
                    // Gymnasium-Robotics' `_reset_sim` until it succeeds: anew from the
                    // start state, the stream continuing.
                    restarts += 1;
                    next = 0;
                    self.sim
                        .restart(init.is_some(), &self.qpos_init, &self.qvel_init);
                }
                Ok(false) => {
                    self.reset_failure = Some(ResetFailure::Unmet(k));
                    break;
                }
                Err(message) => return Some(message),
            }
        }
        None
    }

    /// What follows the reset steps: the commands, the derived values, the first observation and
    /// the reset info.
    fn finish_reset(&mut self) {
        // Commands are drawn after the `[reset.*]` steps (the design's draw order).
        let rng = self.rng.as_mut().expect("set by reset");
        self.sim.legged.update_sites(&self.sim.data);
        self.sim.legged.reset(&self.spec, rng);
        self.derive_after_physics();
        self.update_derived(true);
        self.elapsed = 0;
        self.has_reset = self.reset_failure.is_none();
        if let Some(l) = &mut self.latency {
            l.clear();
        }
        self.write_obs_at(true);
        let mut off = 0;
        for item in self.spec.reset_info() {
            let out = &mut self.reset_info_values[off..off + item.len];
            write_info(
                &self.sim,
                &self.before,
                &self.term_values,
                self.dt,
                item,
                None,
                out,
            );
            off += item.len;
        }
        mujoco_log::drain_into(&mut self.warnings);
    }

    /// The events' part of a reset (draw order steps 1–2), then what MuJoCo and the env derive
    /// from the changed fields. A MuJoCo error in `mj_setConst` comes back as its message.
    fn reset_events(&mut self, reseed: bool) -> Option<String> {
        let (Some(ev), Some(rng)) = (self.events.as_mut(), self.rng.as_mut()) else {
            return None;
        };
        let mut t = crate::events::Target {
            // The env's own copy of the model when any event writes it (`with_world_model`),
            // shared with nothing but its own data, which MuJoCo does not use meanwhile.
            m: mj::model_edit::ModelValues::env_copy(&self.sim.model),
            qvel: self.sim.data.qvel_mut(),
            rng,
            profile: self.sim.numerics,
        };
        ev.reset(&mut t, reseed);
        let (set_const, mass, timestep) = (ev.set_const, ev.changes_mass, ev.changes_timestep);
        let mut error = None;
        if set_const {
            // Subtree masses, `dof_invweight0`, `body_invweight0`, `actuator_acc0`, ... from the
            // new masses, inertia positions and armature (at qpos0; `mj_resetData` follows).
            error = self.sim.call(Call::SetConst).err();
        }
        self.model_changed(mass, timestep);
        error
    }

    /// Why the last reset did not give a valid start (E1104), if it did not.
    pub fn reset_error(&self) -> Option<EnvError> {
        Some(match self.reset_failure.as_ref()? {
            ResetFailure::Unmet(k) => EnvError::ResampleUnmet {
                env: self.spec.id.clone(),
                step: self.spec.reset[*k].name.clone(),
                draws: match self.spec.reset[*k].dist {
                    Distribution::Settle(_) => envspec::limits::MAX_SETTLE_RESTARTS,
                    _ => envspec::limits::MAX_RESAMPLE_DRAWS,
                },
            },
            ResetFailure::Mujoco(message) => EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in reset (reset again, or fix the model)",
                message: message.clone(),
            },
        })
    }
}

/// One reset step other than `settle`: its draws, then what it writes. False when its
/// `resample_until` went unmet (the last draw is written all the same).
fn draw_step(
    sim: &mut Sim,
    draw: &mut [f64],
    rng: &mut NumpyRng,
    step: &ResetStep,
    terrain: Option<(usize, usize)>,
    spec: &ResolvedSpec,
) -> bool {
    let numerics = sim.numerics;
    let [qpos, qvel, mocap_pos, mocap_quat] = mj::state::state_mut(&mut sim.data);
    let n = step.target.len();
    let draw = &mut draw[..n];
    if place_root(&sim.model, sim.nq, qpos, rng, step, terrain, spec) {
        return true;
    }
    // `probability`: one uniform decides whether the step runs at all.
    if let Some(p) = step.probability
        && rng.uniform(0.0, 1.0) >= p
    {
        return true;
    }
    let records = &sim.manip.records;
    if let Distribution::Rotation(_) | Distribution::UnitQuaternion = &step.dist {
        let state = [qpos, qvel, mocap_pos, mocap_quat];
        let target = reset_target(step.target.field, state, &mut sim.goal);
        crate::manipulation::quaternion_step(step, target, rng, numerics);
        return true;
    }
    if let Distribution::Meet(m) = &step.dist {
        let around = step.around.as_deref().unwrap_or(&[]);
        crate::manipulation::meet(m, around, records, rng, numerics, draw);
        let state = [qpos, qvel, mocap_pos, mocap_quat];
        let target = reset_target(step.target.field, state, &mut sim.goal);
        for (k, &i) in step.target.indices.iter().enumerate() {
            target[i] = draw[k];
        }
        return true;
    }
    let met = draw_until(step, draw, rng, numerics, records);
    let state = [qpos, qvel, mocap_pos, mocap_quat];
    let target = reset_target(step.target.field, state, &mut sim.goal);
    for (k, &i) in step.target.indices.iter().enumerate() {
        target[i] = match &step.around {
            Some(a) => records[a[k]] + draw[k],
            None if step.set => draw[k],
            None => target[i] + draw[k],
        };
    }
    met
}

/// The `keyframe`, `terrain_origin` and `root_pose` steps, which write `qpos` alone (false for any
/// other step).
fn place_root(
    model: &MjModel,
    nq: usize,
    qpos: &mut [f64],
    rng: &mut NumpyRng,
    step: &ResetStep,
    terrain: Option<(usize, usize)>,
    spec: &ResolvedSpec,
) -> bool {
    match &step.dist {
        Distribution::Keyframe { index, .. } => {
            // The resolver checked the index against the model's keyframes and the
            // env's model check their count.
            let key = &model.key_qpos()[index * nq..(index + 1) * nq];
            qpos.copy_from_slice(key);
        }
        Distribution::TerrainOrigin { rows } => {
            // Row first, then column (`integers` draws); the resolver checked the rows
            // against `[terrain]`, which the model was built with.
            let Some((adr, tiles)) = terrain else {
                return true;
            };
            let cols = tiles / spec.model_edits.terrain.as_ref().map_or(1, |t| t.rows);
            let row = rng.integers(rows.0 as i64, rows.1 as i64 + 1) as usize;
            let col = rng.integers(0, cols.max(1) as i64) as usize;
            let o = &model.numeric_data()[adr + 3 * (row * cols + col)..][..3];
            let a = step.target.indices[0];
            for i in 0..3 {
                qpos[a + i] += o[i];
            }
        }
        Distribution::RootPose { ranges } => {
            let mut x = [0.0; 6];
            for (v, r) in x.iter_mut().zip(ranges) {
                *v = rng.uniform(r.0, r.1);
            }
            let a = step.target.indices[0];
            for i in 0..3 {
                qpos[a + i] += x[i];
            }
            let q = [qpos[a + 3], qpos[a + 4], qpos[a + 5], qpos[a + 6]];
            let d = quat_from_euler_xyz(x[3], x[4], x[5]);
            qpos[a + 3..a + 7].copy_from_slice(&quat_mul(q, d));
        }
        _ => return false,
    }
    true
}

/// Draw a step's values until its `resample_until` holds: false when the draws ran out (the
/// reference redraws for ever; envc gives up after a bound no real spec reaches).
fn draw_until(
    step: &ResetStep,
    draw: &mut [f64],
    rng: &mut NumpyRng,
    numerics: Profile,
    records: &[f64],
) -> bool {
    let n = draw.len();
    for _ in 0..envspec::limits::MAX_RESAMPLE_DRAWS {
        match &step.dist {
            Distribution::Uniform { low, high } => {
                for i in 0..n {
                    draw[i] = rng.uniform(low[i], high[i]);
                }
            }
            Distribution::Normal { scale } => {
                for d in draw.iter_mut() {
                    *d = scale * rng.standard_normal();
                }
            }
            Distribution::Constant { value } => draw.fill(*value),
            Distribution::Values { values } => draw.copy_from_slice(values),
            Distribution::Keyframe { .. }
            | Distribution::RootPose { .. }
            | Distribution::Meet(_)
            | Distribution::Rotation(_)
            | Distribution::UnitQuaternion
            | Distribution::Settle(_)
            | Distribution::TerrainOrigin { .. } => {}
        }
        let done = match step.resample_until {
            None => true,
            Some(Until::NormBelow(x)) => norm(numerics, n, &|i| draw[i]) < x,
            Some(Until::NormAbove(x)) => norm(numerics, n, &|i| draw[i]) > x,
            Some(Until::MinDistance(x)) => {
                let a = step.around.as_deref().unwrap_or(&[]);
                let at = |i: usize| a.get(i).map_or(0.0, |&j| records[j]);
                norm(numerics, n, &|i| (at(i) + draw[i]) - at(i)) >= x
            }
        };
        if done {
            return true;
        }
    }
    false
}

/// What a reset step writes: the state array of its target's field, or the goal vector.
fn reset_target<'a>(field: Field, state: [&'a mut [f64]; 4], goal: &'a mut [f64]) -> &'a mut [f64] {
    let [qpos, qvel, mocap_pos, mocap_quat] = state;
    match field {
        Field::Qpos => qpos,
        Field::Goal => goal,
        Field::MocapPos => mocap_pos,
        Field::MocapQuat => mocap_quat,
        _ => qvel,
    }
}

/// mjlab's `quat_from_euler_xyz` (w, x, y, z), term for term in its order of operations.
fn quat_from_euler_xyz(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (cy, sy) = ((yaw * 0.5).cos(), (yaw * 0.5).sin());
    let (cr, sr) = ((roll * 0.5).cos(), (roll * 0.5).sin());
    let (cp, sp) = ((pitch * 0.5).cos(), (pitch * 0.5).sin());
    [
        cy * cr * cp + sy * sr * sp,
        cy * sr * cp - sy * cr * sp,
        cy * cr * sp + sy * sr * cp,
        sy * cr * cp - cy * sr * sp,
    ]
}

/// The Hamilton product `a ⊗ b` (w, x, y, z).
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [w1, x1, y1, z1] = a;
    let [w2, x2, y2, z2] = b;
    [
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ]
}
