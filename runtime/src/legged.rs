//! The legged machinery at run time: commands, PD position actions, feet contacts and the
//! legged reward kernels (IR in `envspec::commands`; docs/spec-reference.md, "Commands, PD
//! actions and legged terms").
//!
//! Draws: at reset, after the `[reset.*]` steps, every command in declared order; at a step, after
//! the reward, the commands whose interval is due. One command draws one numpy `uniform(low,
//! high)` per component in order, then (only when `standing_probability > 0`) one `random()`:
//! below the probability, every component is 0. A spec without `[commands]` draws nothing.

use envspec::ir::*;
use envspec::{Field, ResolvedSpec, Selection};
use mujoco_rs::mujoco_c::{mjModel, mjtBias, mjtGain, mjtObj};
use mujoco_rs::prelude::{MjData, MjModel, MjtObjBase};
use mujoco_rs::wrappers::mj_model::traits::ModelType;

use crate::error::unfit;
use crate::mj::model_edit::{ModelArray, ModelValues, NPRM};

use crate::numerics::{Profile, norm, pairwise_sum};
use crate::rng::NumpyRng;

fn id(m: &mjModel, obj: mjtObj, name: &str) -> Option<usize> {
    crate::mj::names::id(m, obj, name)
}

/// Set the `[actions]` gains on the compiled model (before any env shares it).
pub(crate) fn apply_gains(spec: &ResolvedSpec, model: &mut MjModel) -> Result<(), crate::EnvError> {
    let Some(a) = &spec.actions else {
        return Ok(());
    };
    // We own the model; no data uses it yet.
    let nu = model.ffi().nu as usize;
    for i in 0..nu {
        // The gains are the joints' servos: an actuator on a tendon or a site (a tendon-driven
        // gripper) keeps the model's own gains.
        if model.actuator_trntype()[i] as i32 != 0 || model.actuator_trnid()[i][0] < 0 {
            continue;
        }
        if a.kp.is_some() || a.kd.is_some() {
            let servo = model.actuator_gaintype()[i] as i32 == mjtGain::mjGAIN_FIXED as i32
                && model.actuator_biastype()[i] as i32 == mjtBias::mjBIAS_AFFINE as i32;
            if !servo {
                return Err(unfit(
                    spec,
                    format!(
                        "actuator {i} is not a position servo (fixed gain, affine bias), so [actions] kp/kd cannot be set on it"
                    ),
                ));
            }
        }
        let mut values = ModelValues::owned(model);
        if let Some(kp) = a.kp {
            values.set(ModelArray::GainPrm, i * NPRM, kp);
            values.set(ModelArray::BiasPrm, i * NPRM + 1, -kp);
        }
        if let Some(kd) = a.kd {
            values.set(ModelArray::BiasPrm, i * NPRM + 2, -kd);
        }
        if let Some(damping) = a.damping {
            let j = model.actuator_trnid()[i][0];
            let dof = model.jnt_dofadr()[j as usize] as usize;
            ModelValues::owned(model).set(ModelArray::DofDamping, dof, damping);
        }
    }
    Ok(())
}

/// Contact state of one feet term.
#[derive(Clone, Debug, Default)]
struct Feet {
    /// Geom ids, or body ids where `bodies` says so.
    geoms: Vec<i32>,
    bodies: Vec<bool>,
    floor: i32,
    floor_is_body: bool,
    contact: Vec<bool>,
    last_contact: Vec<bool>,
    first_contact: Vec<bool>,
    /// Air time including this step (what the reward reads).
    air_now: Vec<f64>,
    air_time: Vec<f64>,
}

/// The contact state of a feet term, its feet and floor named by the model's ids.
fn feet_state(spec: &ResolvedSpec, m: &mjModel, f: &FeetContact) -> Result<Feet, crate::EnvError> {
    let geom = |n: &str, body: bool| {
        let (obj, what) = if body {
            (mjtObj::mjOBJ_BODY, "body")
        } else {
            (mjtObj::mjOBJ_GEOM, "geom")
        };
        id(m, obj, n)
            .map(|i| i as i32)
            .ok_or_else(|| unfit(spec, format!("the compiled model has no {what} `{n}`")))
    };
    let n = f.geoms.len();
    Ok(Feet {
        geoms: (0..n)
            .map(|i| geom(&f.geoms[i], f.bodies[i]))
            .collect::<Result<_, _>>()?,
        bodies: f.bodies.clone(),
        floor: geom(&f.floor, f.floor_is_body)?,
        floor_is_body: f.floor_is_body,
        contact: vec![false; n],
        last_contact: vec![false; n],
        first_contact: vec![false; n],
        air_now: vec![0.0; n],
        air_time: vec![0.0; n],
    })
}

/// Per joint, the soft-limit range `joint_limits` reads (None where the joint is unlimited).
fn soft_limits(model: &MjModel, factor: f64, centered: bool) -> Vec<Option<(f64, f64)>> {
    let njnt = model.ffi().njnt as usize;
    let (limited, range) = (model.jnt_limited(), model.jnt_range());
    let soft = |[lo, hi]: [f64; 2]| {
        if centered {
            // mjlab's order of operations: mean ∓ 0.5 · range · factor.
            let (mean, width) = ((lo + hi) / 2.0, hi - lo);
            (mean - 0.5 * width * factor, mean + 0.5 * width * factor)
        } else {
            (factor * lo, factor * hi)
        }
    };
    (0..njnt)
        .map(|j| limited[j].then(|| soft(range[j])))
        .collect()
}

/// What the env holds for commands, PD actions and legged terms.
#[derive(Clone, Debug, Default)]
pub(crate) struct Legged {
    pub command: Vec<f64>,
    steps: u64,
    pub last_action: Vec<f64>,
    pub default_pose: Vec<f64>,
    /// Action scale of each actuator (`[actions] scale`).
    scale: Vec<f64>,
    pd: bool,
    /// `[actions] kind = "ctrlrange"`: each actuator's control range; the action is clipped to
    /// [−1, 1] and `ctrl` to this range.
    ctrl_clip: Vec<(f64, f64)>,
    /// nsite × 3 each: linvel, angvel, local linvel, local angvel, z axis, gravity.
    pub site: [Vec<f64>; 6],
    site_frames: bool,
    /// Per reward term: its feet state (feet terms only).
    feet: Vec<Option<Feet>>,
    /// Per joint: the soft-limit range (`joint_limits` reads it), or None when unlimited.
    jnt_range: Vec<Option<(f64, f64)>>,
    /// Contacts tracked at every physics substep (mjlab's landings and self contacts).
    pub landings: crate::landings::Landings,
}

impl Legged {
    pub fn new(spec: &ResolvedSpec, model: &MjModel) -> Result<Legged, crate::EnvError> {
        let m = model.ffi();
        let (nu, nsite) = (m.nu as usize, m.nsite as usize);
        let mut l = Legged {
            command: vec![0.0; spec.command_dim],
            last_action: vec![0.0; spec.act_dim()],
            default_pose: vec![0.0; nu],
            scale: vec![1.0; nu],
            ..Default::default()
        };
        if let Some(a) = &spec.actions {
            l.set_actions(spec, model, a)?;
        }
        l.landings = crate::landings::Landings::new(spec, model)?;
        l.site_frames = spec.sources().any(|s| s.field.is_site_frame());
        if l.site_frames {
            l.site = std::array::from_fn(|_| vec![0.0; nsite * 3]);
        }
        for t in &spec.reward {
            let feet = match &t.kind {
                TermKind::Legged(lt) => lt.feet(),
                _ => None,
            };
            l.feet.push(match feet {
                None => None,
                Some(f) => Some(feet_state(spec, m, f)?),
            });
            if let TermKind::Legged(LeggedTerm::JointLimits {
                factor, centered, ..
            }) = &t.kind
                && l.jnt_range.is_empty()
            {
                l.jnt_range = soft_limits(model, *factor, *centered);
            }
        }
        Ok(l)
    }

    /// `[actions]`: PD actions, their scale and default pose, checked against the actuators'
    /// control ranges.
    fn set_actions(
        &mut self,
        spec: &ResolvedSpec,
        model: &MjModel,
        a: &PdActions,
    ) -> Result<(), crate::EnvError> {
        let m = model.ffi();
        let (nu, nq) = (m.nu as usize, m.nq as usize);
        self.pd = true;
        if matches!(a.kind, ActionKind::PdPosition | ActionKind::PositionDelta) {
            self.scale.clone_from(&a.scale);
        }
        match &a.default_pose {
            DefaultPose::Values(v) => self.default_pose.copy_from_slice(v),
            DefaultPose::CtrlRangeCentre => {
                // Gymnasium-Robotics' hands: (hi + lo) / 2 and (hi − lo) / 2, as numpy
                // computes them (Adroit's mean and 0.5 × span are the same numbers).
                let limited = model.actuator_ctrllimited();
                for (i, r) in model.actuator_ctrlrange().iter().enumerate() {
                    if !limited.get(i).is_some_and(|&on| on)
                        || r[0].partial_cmp(&r[1]).is_none_or(|o| o.is_gt())
                    {
                        let name = crate::describe::inventory::name(m, mjtObj::mjOBJ_ACTUATOR, i);
                        return Err(unfit(
                            spec,
                            format!(
                                "[actions] kind = \"ctrlrange\" needs every actuator's control range, and actuator `{name}` has none (ctrllimited is false)"
                            ),
                        ));
                    }
                    self.default_pose[i] = (r[1] + r[0]) / 2.0;
                    self.scale[i] = (r[1] - r[0]) / 2.0;
                    self.ctrl_clip.push((r[0], r[1]));
                }
            }
            DefaultPose::Keyframe { name, qposadr } => {
                let k = id(m, mjtObj::mjOBJ_KEY, name).ok_or_else(|| {
                    unfit(spec, format!("the compiled model has no keyframe `{name}`"))
                })?;
                for (i, &adr) in qposadr.iter().enumerate() {
                    // k < nkey, adr < nq, i < nu.
                    self.default_pose[i] = match adr {
                        Some(adr) => model.key_qpos()[k * nq + adr],
                        None => model.key_ctrl()[k * nu + i],
                    };
                }
            }
        }
        // A target outside a limited actuator's control range is clamped by MuJoCo: the
        // default pose would not be what the spec says (degrees for radians, say).
        let (limited, range) = (model.actuator_ctrllimited(), model.actuator_ctrlrange());
        for (i, &p) in self.default_pose.iter().enumerate() {
            let (lo, hi) = (range[i][0], range[i][1]);
            if limited.get(i).is_some_and(|&on| on) && !(lo <= p && p <= hi) {
                let name = crate::describe::inventory::name(m, mjtObj::mjOBJ_ACTUATOR, i);
                return Err(unfit(
                    spec,
                    format!(
                        "[actions] default_pose[{i}] = {p} is outside actuator `{name}`'s control range [{lo}, {hi}] (MuJoCo would clamp every target to it; are the values in the model's units?)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Compute the site velocities and axes from now on (a reader the spec does not know of,
    /// e.g. an agent's observation).
    pub fn enable_site_frames(&mut self, nsite: usize) {
        if !self.site_frames {
            self.site_frames = true;
            self.site = std::array::from_fn(|_| vec![0.0; nsite * 3]);
        }
    }

    /// The field's values, for the fields this module holds.
    pub fn field(&self, f: Field) -> Option<&[f64]> {
        Some(match f {
            Field::SiteLinvel => &self.site[0],
            Field::SiteAngvel => &self.site[1],
            Field::SiteLocalLinvel => &self.site[2],
            Field::SiteLocalAngvel => &self.site[3],
            Field::SiteZaxis => &self.site[4],
            Field::SiteGravity => &self.site[5],
            Field::LastAction => &self.last_action,
            Field::DefaultPose => &self.default_pose,
            Field::Command => &self.command,
            _ => return None,
        })
    }

    /// `ctrl` for an action: `default_pose + scale × action` under `[actions]`, else the action.
    pub fn write_ctrl(&self, action: &[f64], ctrl: &mut [f64]) {
        if self.ctrl_clip.is_empty() && !self.pd {
            ctrl.copy_from_slice(action);
        } else {
            self.write_ctrl_by(|i| action[i], ctrl);
        }
    }

    /// [`write_ctrl`](Self::write_ctrl) with the action's elements given by `action(i)`.
    pub fn write_ctrl_by(&self, action: impl Fn(usize) -> f64, ctrl: &mut [f64]) {
        if !self.ctrl_clip.is_empty() {
            // np.clip twice: the action to the action space, then ctrl to the control range.
            for (i, c) in ctrl.iter_mut().enumerate() {
                let a = action(i).clamp(-1.0, 1.0);
                let (lo, hi) = self.ctrl_clip[i];
                *c = (self.default_pose[i] + a * self.scale[i]).clamp(lo, hi);
            }
        } else if self.pd {
            for (i, c) in ctrl.iter_mut().enumerate() {
                *c = self.default_pose[i] + self.scale[i] * action(i);
            }
        } else {
            for (i, c) in ctrl.iter_mut().enumerate() {
                *c = action(i);
            }
        }
    }

    /// `[actions] kind = "position_delta"`: `ctrl = clip(observed + clip(0 + scale × action,
    /// velocity) × dt, position)`, the action first clipped to [−1, 1], in the reference's order
    /// (`act_mid + action × act_rng` with `act_mid = 0`).
    pub fn write_ctrl_delta(
        &self,
        d: &envspec::ir::PositionDelta,
        action: &[f64],
        observed: &[f64],
        dt: f64,
        ctrl: &mut [f64],
    ) {
        for (i, c) in ctrl.iter_mut().enumerate() {
            let a = crate::numerics::clip(action[i], -1.0, 1.0);
            // `0.0 +` as the reference adds its zero midpoint: −0.0 becomes +0.0.
            #[allow(clippy::identity_op)]
            let v = 0.0 + a * self.scale[i];
            let (vlo, vhi) = d.velocity[i];
            let (plo, phi) = d.position[i];
            let v = crate::numerics::clip(v, vlo, vhi);
            *c = crate::numerics::clip(observed[i] + v * dt, plo, phi);
        }
    }

    /// Site velocities and axes from the current (lagged) derived quantities.
    pub fn update_sites<M: ModelType>(&mut self, d: &MjData<M>) {
        if !self.site_frames {
            return;
        }
        let site_xmat = d.site_xmat();
        for (s, r) in site_xmat.iter().enumerate() {
            for (local, off) in [(false, 0), (true, 2)] {
                // [angular, linear]; s is below nsite, so this cannot fail.
                let res = d
                    .try_object_velocity(MjtObjBase::mjOBJ_SITE, s, local)
                    .unwrap_or_default();
                self.site[off][3 * s..3 * s + 3].copy_from_slice(&res[3..6]);
                self.site[off + 1][3 * s..3 * s + 3].copy_from_slice(&res[0..3]);
            }
            // Row-major rotation, site to world.
            self.site[4][3 * s..3 * s + 3].copy_from_slice(&[r[2], r[5], r[8]]);
            self.site[5][3 * s..3 * s + 3].copy_from_slice(&[-r[6], -r[7], -r[8]]);
        }
    }

    /// Reset: zero the previous action and the feet state, draw every command.
    pub fn reset(&mut self, spec: &ResolvedSpec, rng: &mut NumpyRng) {
        self.last_action.fill(0.0);
        self.landings.reset();
        self.steps = 0;
        for f in self.feet.iter_mut().flatten() {
            f.last_contact.fill(false);
            f.air_time.fill(0.0);
            f.air_now.fill(0.0);
            f.contact.fill(false);
            f.first_contact.fill(false);
        }
        for c in &spec.commands {
            self.draw(c, rng);
        }
    }

    fn draw(&mut self, c: &Command, rng: &mut NumpyRng) {
        let out = &mut self.command[c.offset..c.offset + c.len()];
        for (k, o) in out.iter_mut().enumerate() {
            *o = rng.uniform(c.low[k], c.high[k]);
        }
        if c.standing_probability > 0.0 && rng.next_f64() < c.standing_probability {
            out.fill(0.0);
        }
    }

    /// After the reward: count the step, redraw the commands whose interval is due.
    pub fn resample(&mut self, spec: &ResolvedSpec, rng: &mut NumpyRng) {
        self.steps += 1;
        for c in &spec.commands {
            if c.resample_steps > 0 && self.steps.is_multiple_of(c.resample_steps) {
                self.draw(c, rng);
            }
        }
    }

    /// Before the reward: contacts of the feet with the floor in the last forward pass; the
    /// first contacts (air time so far > 0 and in contact now or at the previous step) and the
    /// air time including this step.
    pub fn update_contacts<M: ModelType>(&mut self, d: &MjData<M>, dt: f64) {
        let (geom_bodyid, contacts) = (d.model().geom_bodyid(), d.contact());
        // A contact geom as the element a foot or floor names: itself, or its body.
        let of = |g: i32, body: bool| {
            if body && g >= 0 {
                // g is a geom id from the contact list.
                geom_bodyid[g as usize]
            } else {
                g
            }
        };
        for f in self.feet.iter_mut().flatten() {
            f.contact.fill(false);
            for c in contacts {
                let g = c.geom;
                let floor = [of(g[0], f.floor_is_body), of(g[1], f.floor_is_body)];
                for (i, &foot) in f.geoms.iter().enumerate() {
                    let b = f.bodies[i];
                    if (of(g[0], b) == foot && floor[1] == f.floor)
                        || (of(g[1], b) == foot && floor[0] == f.floor)
                    {
                        f.contact[i] = true;
                    }
                }
            }
            for i in 0..f.geoms.len() {
                let filt = f.contact[i] || f.last_contact[i];
                f.first_contact[i] = f.air_time[i] > 0.0 && filt;
                f.air_now[i] = f.air_time[i] + dt;
            }
        }
    }

    /// After the reward: the air time restarts on contact; the contact is remembered. The
    /// action becomes the previous action once the observation is written (`end_step`).
    pub fn commit_contacts(&mut self) {
        for f in self.feet.iter_mut().flatten() {
            for i in 0..f.geoms.len() {
                f.air_time[i] = if f.contact[i] { 0.0 } else { f.air_now[i] };
                f.last_contact[i] = f.contact[i];
            }
        }
    }

    pub fn end_step(&mut self, action: &[f64]) {
        self.last_action.copy_from_slice(action);
    }

    /// The kernel of a legged term (reward term `i`). `field` reads any field.
    pub fn kernel<'a>(
        &self,
        i: usize,
        t: &LeggedTerm,
        numerics: Profile,
        field: &dyn Fn(Field) -> &'a [f64],
        action: &[f64],
    ) -> f64 {
        let gate = |g: &Option<Gate>| gate_factor(g, numerics, field);
        match t {
            LeggedTerm::Tracking {
                source,
                target,
                coefs,
                sigma,
                zero,
            } => tracking(source, target, coefs, *sigma, zero.as_ref(), field),
            LeggedTerm::SumAbs {
                source,
                minus,
                gate: g,
            } => {
                let x = field(source.field);
                let s = match minus {
                    Some(m) => {
                        let y = field(m.field);
                        pairwise_sum(source.len(), &|k| {
                            (x[source.indices[k]] - y[m.indices[k]]).abs()
                        })
                    }
                    None => pairwise_sum(source.len(), &|k| x[source.indices[k]].abs()),
                };
                s * gate(g)
            }
            LeggedTerm::ActionRate => pairwise_sum(action.len(), &|k| {
                let d = action[k] - self.last_action[k];
                d * d
            }),
            LeggedTerm::FeetAirTime {
                threshold, gate: g, ..
            } => {
                let f = self.feet[i].as_ref().expect("feet terms have a state");
                pairwise_sum(f.geoms.len(), &|k| {
                    (f.air_now[k] - threshold) * f.first_contact[k] as u8 as f64
                }) * gate(g)
            }
            LeggedTerm::FeetSlip {
                velocity, gate: g, ..
            } => {
                let f = self.feet[i].as_ref().expect("feet terms have a state");
                let v = field(velocity.field);
                pairwise_sum(f.geoms.len(), &|k| {
                    let (vx, vy) = (v[velocity.indices[2 * k]], v[velocity.indices[2 * k + 1]]);
                    (vx * vx + vy * vy) * f.contact[k] as u8 as f64
                }) * gate(g)
            }
            LeggedTerm::Posture {
                source,
                minus,
                speed: parts,
                thresholds,
                sigma,
            } => {
                let v = if parts.is_empty() {
                    0.0
                } else {
                    speed(parts, numerics, field)
                };
                posture(source, minus, thresholds, sigma, v, field)
            }
            LeggedTerm::FeetClearance {
                height,
                velocity,
                target,
                max_height,
                power,
                gate: g,
            } => clearance(height, velocity, *target, *max_height, *power, field) * gate(g),
            LeggedTerm::FeetSwingHeight { gate: g, .. }
            | LeggedTerm::SoftLanding { gate: g, .. } => self.landings.kernel(i) * gate(g),
            LeggedTerm::SelfCollisions { .. } => self.landings.kernel(i),
            LeggedTerm::JointLimits { source, joints, .. } => {
                let x = field(source.field);
                pairwise_sum(source.len(), &|k| match self.jnt_range[joints[k]] {
                    None => 0.0,
                    Some((lo, hi)) => {
                        let q = x[source.indices[k]];
                        -(q - lo).min(0.0) + (q - hi).max(0.0)
                    }
                })
            }
        }
    }
}

/// The sum of the selections' norms, left to right (mjlab's `‖cmd_xy‖ + |cmd_wz|`).
fn speed<'a>(parts: &[Selection], numerics: Profile, field: &dyn Fn(Field) -> &'a [f64]) -> f64 {
    parts.iter().fold(0.0, |acc, p| {
        let f = field(p.field);
        acc + norm(numerics, p.len(), &|k| f[p.indices[k]])
    })
}

/// A term's command gate: 1 where it is open (or the term has none), else 0.
fn gate_factor<'a>(g: &Option<Gate>, numerics: Profile, field: &dyn Fn(Field) -> &'a [f64]) -> f64 {
    match g {
        None => 1.0,
        Some(g) => {
            let n = speed(&g.command, numerics, field);
            let open = if g.below {
                n < g.threshold
            } else {
                n > g.threshold
            };
            open as u8 as f64
        }
    }
}

/// `exp(−Σ coefₖ (targetₖ − xₖ)² / σ)`, the `zero` selection's squares added to the sum.
fn tracking<'a>(
    source: &Selection,
    target: &Selection,
    coefs: &[f64],
    sigma: f64,
    zero: Option<&Selection>,
    field: &dyn Fn(Field) -> &'a [f64],
) -> f64 {
    let (x, y) = (field(source.field), field(target.field));
    let mut s = pairwise_sum(source.len(), &|k| {
        let d = y[target.indices[k]] - x[source.indices[k]];
        d * d * coefs[k]
    });
    if let Some(z) = zero {
        let v = field(z.field);
        s += pairwise_sum(z.len(), &|k| v[z.indices[k]] * v[z.indices[k]]);
    }
    (-s / sigma).exp()
}

/// `exp(−mean((x − minus)² / std²))`, `std` the row of `sigma` for the regime the command speed
/// `v` is in (the thresholds it reaches).
fn posture<'a>(
    source: &Selection,
    minus: &Selection,
    thresholds: &[f64],
    sigma: &[Vec<f64>],
    v: f64,
    field: &dyn Fn(Field) -> &'a [f64],
) -> f64 {
    let regime = thresholds.iter().take_while(|&&t| v >= t).count();
    let (x, m, std) = (field(source.field), field(minus.field), &sigma[regime]);
    let n = source.len();
    let s = pairwise_sum(n, &|k| {
        let d = x[source.indices[k]] - m[minus.indices[k]];
        d * d / (std[k] * std[k])
    });
    (-(s / n as f64)).exp()
}

/// `Σ |clip(z, 0, max_height) − target| · ‖v_xy‖^power` over the feet.
fn clearance<'a>(
    height: &Selection,
    velocity: &Selection,
    target: f64,
    max_height: f64,
    power: f64,
    field: &dyn Fn(Field) -> &'a [f64],
) -> f64 {
    let (z, v) = (field(height.field), field(velocity.field));
    pairwise_sum(height.len(), &|k| {
        let h = z[height.indices[k]].clamp(0.0, max_height);
        let (vx, vy) = (v[velocity.indices[2 * k]], v[velocity.indices[2 * k + 1]]);
        let speed = (vx * vx + vy * vy).sqrt();
        let speed = if power == 1.0 {
            speed
        } else {
            speed.powf(power)
        };
        (h - target).abs() * speed
    })
}
