//! The manipulation tables at run time (`envspec::manipulation`): `[init]` when the env is made,
//! `[end_effector]` actions, `[hold.*]` after the physics, and the fields manipulation tasks read
//! (`site_euler`, `site_xvelp`, `site_xvelr`), as Gymnasium-Robotics computes them.

use envspec::ir::ResolvedSpec;
use envspec::manipulation::{EndEffector, Init};
use envspec::{Field, Selection};
use mujoco_rs::prelude::{MjData, MjModel};

use crate::error::EnvError;
use crate::mj::{self, Call};
use crate::numerics::{self, Profile};

/// `_EPS4` of Gymnasium-Robotics' `rotations.py`: `np.finfo(float).eps * 4.0`.
const EPS4: f64 = f64::EPSILON * 4.0;

/// What the end effector drives, resolved in the compiled model.
#[derive(Clone, Debug)]
struct Driven {
    /// The mocap body's index in `mocap_pos`.
    mocap: usize,
    /// The body welded to it, whose pose the action starts from.
    body: usize,
    /// Per gripper actuator: its index, and the qpos address of its joint when it has a bias
    /// (a position servo: `ctrl = qpos + action`).
    gripper: Vec<(usize, Option<usize>)>,
}

/// The manipulation state of one env.
pub(crate) struct Manip {
    /// Where `[init]` left the state: every reset starts from it.
    pub(crate) init_time: f64,
    /// `[init] record` values, flat.
    pub(crate) records: Vec<f64>,
    driven: Option<Driven>,
    /// `[goal] marker`'s mocap index.
    marker: Option<usize>,
    /// `[goal] marker_site`: the site, its body, and the site position the reference keeps in
    /// its model (each render writes it there, and it persists).
    marker_site: Option<(usize, usize, [f64; 3])>,
    /// The sites whose `site_euler` / `site_xvelp` and `site_xvelr` something reads: only
    /// those are computed after the physics.
    euler_sites: Vec<usize>,
    xvel_sites: Vec<usize>,
    /// The bodies whose `body_euler` something reads.
    euler_bodies: Vec<usize>,
    site_euler: Vec<f64>,
    body_euler: Vec<f64>,
    site_xvelp: Vec<f64>,
    site_xvelr: Vec<f64>,
    jacp: Vec<f64>,
    jacr: Vec<f64>,
    velocity: [f64; 3],
}

/// The mocap index of body `name`, or E1111.
fn mocap_of(
    spec: &ResolvedSpec,
    model: &MjModel,
    name: &str,
    what: &str,
) -> Result<usize, EnvError> {
    let err = |why: String| EnvError::Mocap {
        env: spec.id.clone(),
        what: format!("{what} `{name}` {why}"),
    };
    let body = mj::names::id(model.ffi(), mujoco_rs::mujoco_c::mjtObj::mjOBJ_BODY, name)
        .ok_or_else(|| err("is not a body of the compiled model".into()))?;
    usize::try_from(model.body_mocapid()[body])
        .map_err(|_| err("is not a mocap body (declare it with mocap=\"true\" in the MJCF)".into()))
}

impl Manip {
    /// The manipulation state for `spec` over `model` (the mocap bodies and welds checked).
    pub(crate) fn new(spec: &ResolvedSpec, model: &MjModel) -> Result<Manip, EnvError> {
        let m = &spec.manipulation;
        let driven = match &m.end_effector {
            Some(e) => Some(Self::driven(spec, model, e)?),
            None => None,
        };
        if let Some(init) = &m.init {
            for p in &init.mocap {
                mocap_of(spec, model, &p.body, "[init] mocap body")?;
            }
        }
        let marker = match m.goal.as_ref().and_then(|g| g.marker.as_ref()) {
            Some(b) => Some(mocap_of(spec, model, b, "[goal] marker")?),
            None => None,
        };
        let marker_site = m.goal.as_ref().and_then(|g| g.marker_site).map(|s| {
            // A site id the resolver found in this model.
            let body = model.site_bodyid()[s] as usize;
            (s, body, model.site_pos()[s])
        });
        let nsite = usize::try_from(model.ffi().nsite).unwrap_or(0);
        let nv = usize::try_from(model.ffi().nv).unwrap_or(0);
        let nbody = usize::try_from(model.ffi().nbody).unwrap_or(0);
        let mut manip = Manip {
            init_time: 0.0,
            records: vec![0.0; m.record_len()],
            driven,
            marker,
            marker_site,
            euler_sites: vec![],
            xvel_sites: vec![],
            euler_bodies: vec![],
            site_euler: vec![0.0; 3 * nsite],
            body_euler: vec![0.0; 3 * nbody],
            site_xvelp: vec![0.0; 3 * nsite],
            site_xvelr: vec![0.0; 3 * nsite],
            jacp: vec![0.0; 3 * nv],
            jacr: vec![0.0; 3 * nv],
            velocity: [0.0; 3],
        };
        let records = m
            .init
            .iter()
            .flat_map(|i| i.records.iter().map(|r| &r.source));
        for s in spec.sources().chain(records) {
            manip.read_also(s);
        }
        Ok(manip)
    }

    /// Compute the fields of `s`'s sites from now on (a reader the spec does not know of, e.g.
    /// an agent's observation, or an `[init] record`).
    pub(crate) fn read_also(&mut self, s: &Selection) {
        let list = match s.field {
            Field::SiteEuler => &mut self.euler_sites,
            Field::SiteXvelp | Field::SiteXvelr => &mut self.xvel_sites,
            Field::BodyEuler => &mut self.euler_bodies,
            _ => return,
        };
        for &i in &s.indices {
            if !list.contains(&(i / 3)) {
                list.push(i / 3);
            }
        }
        list.sort_unstable();
    }

    fn driven(spec: &ResolvedSpec, model: &MjModel, e: &EndEffector) -> Result<Driven, EnvError> {
        let mocap = mocap_of(spec, model, &e.mocap, "[end_effector] mocap")?;
        let ids = model.body_mocapid();
        let weld = mujoco_rs::mujoco_c::mjtEq::mjEQ_WELD as i32;
        let (types, a, b) = (model.eq_type(), model.eq_obj1id(), model.eq_obj2id());
        // The weld's other side, as `reset_mocap2body_xpos` finds it.
        let body = (0..types.len()).find_map(|i| {
            if types[i] as i32 != weld {
                return None;
            }
            let (a, b) = (usize::try_from(a[i]).ok()?, usize::try_from(b[i]).ok()?);
            let is = |x: usize| usize::try_from(ids[x]).ok() == Some(mocap);
            if is(a) {
                Some(b)
            } else if is(b) {
                Some(a)
            } else {
                None
            }
        });
        let body = body.ok_or_else(|| EnvError::Mocap {
            env: spec.id.clone(),
            what: format!(
                "[end_effector] mocap `{}` is tied to no body by a weld constraint (add <weld body1=\"{}\" body2=\"...\"/> to the MJCF's <equality>)",
                e.mocap, e.mocap
            ),
        })?;
        let (bias, trn, adr) = (
            model.actuator_biastype(),
            model.actuator_trnid(),
            model.jnt_qposadr(),
        );
        let gripper = e
            .gripper
            .iter()
            .map(|&i| {
                let biased = bias.get(i).is_some_and(|b| *b as i32 != 0);
                let joint = trn.get(i).and_then(|t| usize::try_from(t[0]).ok());
                let qpos = joint
                    .and_then(|j| adr.get(j))
                    .and_then(|&a| usize::try_from(a).ok());
                (i, if biased { qpos } else { None })
            })
            .collect();
        Ok(Driven {
            mocap,
            body,
            gripper,
        })
    }

    /// `[init]` on a data fresh from `mj_resetData`: the joint values, `mj_forward`, the mocap
    /// placements, the settling steps, then the records. Returns MuJoCo's error message, if any.
    pub(crate) fn run_init(
        &mut self,
        init: &Init,
        data: &mut MjData<std::sync::Arc<MjModel>>,
        frame_skip: u32,
        profile: Profile,
    ) -> Result<(), String> {
        mj::call(data, Call::ResetData)?;
        {
            let (qpos, _) = mj::state::qpos_qvel_mut(data);
            for (_, adr, values) in &init.qpos {
                if let Some(dst) = qpos.get_mut(*adr..*adr + values.len()) {
                    dst.copy_from_slice(values);
                }
            }
        }
        mj::call(data, Call::Forward)?;
        for p in &init.mocap {
            let model = data.model();
            let Some(id) = mj::names::id(
                model.ffi(),
                mujoco_rs::mujoco_c::mjtObj::mjOBJ_BODY,
                &p.body,
            )
            .and_then(|b| usize::try_from(model.body_mocapid()[b]).ok()) else {
                continue; // checked in `new`
            };
            let site = p.site.map(|s| data.site_xpos()[s]);
            let (pos, quat, _, _) = mj::manip::mocap_mut(data);
            for k in 0..3 {
                pos[3 * id + k] = match site {
                    Some(x) => p.offset[k] + x[k],
                    None => p.offset[k],
                };
            }
            quat[4 * id..4 * id + 4].copy_from_slice(&p.quat);
        }
        for _ in 0..init.settle_steps {
            mj::call(
                data,
                Call::Step {
                    n: frame_skip,
                    rne: false,
                },
            )?;
        }
        self.update(data, profile);
        for r in &init.records {
            for (k, &i) in r.source.indices.iter().enumerate() {
                self.records[r.offset + k] = self.read(data, &r.source, i);
            }
        }
        self.init_time = data.ffi().time;
        Ok(())
    }

    /// Read the `[init] record`s `which` (indices) again from the current state.
    pub(crate) fn refresh_records(
        &mut self,
        init: &Init,
        data: &MjData<std::sync::Arc<MjModel>>,
        which: &[usize],
    ) {
        for r in which.iter().filter_map(|&i| init.records.get(i)) {
            for (k, &i) in r.source.indices.iter().enumerate() {
                self.records[r.offset + k] = self.read(data, &r.source, i);
            }
        }
    }

    fn read(&self, data: &MjData<std::sync::Arc<MjModel>>, s: &Selection, i: usize) -> f64 {
        match s.field {
            Field::Qpos => data.qpos()[i],
            Field::Qvel => data.qvel()[i],
            Field::Xpos => data.xpos().as_flattened()[i],
            Field::Xquat => data.xquat().as_flattened()[i],
            Field::SiteXpos => data.site_xpos().as_flattened()[i],
            Field::SiteXmat => data.site_xmat().as_flattened()[i],
            f => self.field(f).and_then(|v| v.get(i).copied()).unwrap_or(0.0),
        }
    }

    /// The end-effector action: the gripper controls, then the mocap pose from the welded
    /// body's current (lagged) pose plus the scaled action. `f32`: the action came as float32,
    /// and numpy scales it in float32.
    pub(crate) fn apply_action(
        &self,
        e: &EndEffector,
        action: &[f64],
        f32: bool,
        data: &mut MjData<std::sync::Arc<MjModel>>,
    ) {
        let Some(d) = &self.driven else { return };
        let clip = |x: f64| x.clamp(-1.0, 1.0);
        let g = if e.block_gripper || !e.gripper_action {
            0.0
        } else {
            clip(action[3])
        };
        for &(i, qpos) in &d.gripper {
            let v = match qpos {
                Some(a) => data.qpos()[a] + g,
                None => g,
            };
            if let Some(c) = data.ctrl_mut().get_mut(i) {
                *c = v;
            }
        }
        let mut delta = [0.0; 3];
        for (k, dk) in delta.iter_mut().enumerate() {
            *dk = if f32 {
                f64::from(clip(action[k]) as f32 * e.scale as f32)
            } else {
                clip(action[k]) * e.scale
            };
        }
        let (pos, quat, xpos, xquat) = mj::manip::mocap_mut(data);
        let (m, b) = (d.mocap, d.body);
        for k in 0..3 {
            pos[3 * m + k] = xpos[3 * b + k] + delta[k];
        }
        for k in 0..4 {
            quat[4 * m + k] = xquat[4 * b + k] + e.rotation[k];
        }
    }

    /// The derived fields the spec reads, from the current (lagged) kinematics.
    pub(crate) fn update(&mut self, data: &MjData<std::sync::Arc<MjModel>>, profile: Profile) {
        let xmat = data.site_xmat();
        for &s in &self.euler_sites {
            self.site_euler[3 * s..3 * s + 3].copy_from_slice(&mat2euler(&xmat[s], profile));
        }
        let xquat = data.xquat();
        for &b in &self.euler_bodies {
            let m = quat2mat(&xquat[b]);
            self.body_euler[3 * b..3 * b + 3].copy_from_slice(&mat2euler(&m, profile));
        }
        if !self.xvel_sites.is_empty() {
            let qvel = data.qvel();
            let nv = qvel.len();
            for &s in &self.xvel_sites {
                mj::manip::jac_site(data, s, &mut self.jacp, &mut self.jacr);
                numerics::matvec(profile, 3, nv, &self.jacp, qvel, &mut self.velocity);
                self.site_xvelp[3 * s..3 * s + 3].copy_from_slice(&self.velocity);
                numerics::matvec(profile, 3, nv, &self.jacr, qvel, &mut self.velocity);
                self.site_xvelr[3 * s..3 * s + 3].copy_from_slice(&self.velocity);
            }
        }
    }

    /// Whether a render must first run the reference's render callback.
    pub(crate) fn renders_marker_site(&self) -> bool {
        self.marker_site.is_some()
    }

    /// `[goal] marker_site` before a frame, as Gymnasium-Robotics' Fetch `_render_callback`:
    /// the site's offset from its model position as the data holds it, the model position moved
    /// so the site lands on the goal, `mj_forward`. The model is shared, so the moved position is
    /// kept here and the site's frame written into the data after the forward, computed as
    /// MuJoCo's kinematics do (`xmat · pos`, then `+ xpos`).
    pub(crate) fn render_marker_site(
        &mut self,
        goal: &[f64],
        data: &mut MjData<std::sync::Arc<MjModel>>,
    ) -> Result<(), String> {
        let (Some((s, b, pos)), [gx, gy, gz]) = (&mut self.marker_site, goal) else {
            return Ok(());
        };
        let frame = |d: &MjData<std::sync::Arc<MjModel>>, p: &[f64; 3]| {
            let (xpos, xmat) = (d.xpos()[*b], d.xmat()[*b]);
            std::array::from_fn::<f64, 3, _>(|i| {
                (xmat[3 * i] * p[0] + xmat[3 * i + 1] * p[1] + xmat[3 * i + 2] * p[2]) + xpos[i]
            })
        };
        let was = frame(data, pos);
        let offset: [f64; 3] = std::array::from_fn(|i| was[i] - pos[i]);
        *pos = [gx - offset[0], gy - offset[1], gz - offset[2]];
        crate::mj::call(data, crate::mj::Call::Forward)?;
        let now = frame(data, pos);
        data.site_xpos_mut()[*s] = now;
        Ok(())
    }

    /// `[goal] marker`: its mocap body to the goal (at reset, before `mj_forward`).
    pub(crate) fn place_marker(&self, goal: &[f64], data: &mut MjData<std::sync::Arc<MjModel>>) {
        if let (Some(m), [x, y, z]) = (self.marker, goal) {
            let (pos, _, _, _) = mj::manip::mocap_mut(data);
            pos[3 * m..3 * m + 3].copy_from_slice(&[*x, *y, *z]);
        }
    }

    /// The values of the fields this module computes.
    pub(crate) fn field(&self, f: Field) -> Option<&[f64]> {
        Some(match f {
            Field::SiteEuler => &self.site_euler,
            Field::BodyEuler => &self.body_euler,
            Field::SiteXvelp => &self.site_xvelp,
            Field::SiteXvelr => &self.site_xvelr,
            _ => return None,
        })
    }
}

/// Gymnasium-Robotics' `rotations.quat2mat` of one quaternion (w, x, y, z): numpy's pairwise
/// sum of the squares, its products in its order, the identity for a (near) zero quaternion.
pub(crate) fn quat2mat(q: &[f64; 4]) -> [f64; 9] {
    let [w, x, y, z] = *q;
    let nq = numerics::pairwise_sum(4, &|k| q[k] * q[k]);
    // numpy's `np.where(Nq > eps, mat, eye)`: a NaN norm gives the identity too.
    if nq.partial_cmp(&f64::EPSILON) != Some(std::cmp::Ordering::Greater) {
        return [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    }
    let s = 2.0 / nq;
    let (xs, ys, zs) = (x * s, y * s, z * s);
    let (wx, wy, wz) = (w * xs, w * ys, w * zs);
    let (xx, xy, xz) = (x * xs, x * ys, x * zs);
    let (yy, yz, zz) = (y * ys, y * zs, z * zs);
    [
        1.0 - (yy + zz),
        xy - wz,
        xz + wy,
        xy + wz,
        1.0 - (xx + zz),
        yz - wx,
        xz - wy,
        yz + wx,
        1.0 - (xx + yy),
    ]
}

/// Gymnasium-Robotics' `rotations.mat2euler` of one row-major 3 × 3 matrix: numpy's `sqrt`,
/// `arctan2` (SVML's under an AVX-512 profile, glibc's otherwise) and negations, in its order.
pub(crate) fn mat2euler(m: &[f64; 9], profile: Profile) -> [f64; 3] {
    let at = |r: usize, c: usize| m[3 * r + c];
    let atan2 = |y: f64, x: f64| numerics::atan2(profile, y, x);
    let cy = (at(2, 2) * at(2, 2) + at(1, 2) * at(1, 2)).sqrt();
    let condition = cy > EPS4;
    let z = if condition {
        -atan2(at(0, 1), at(0, 0))
    } else {
        -atan2(-at(1, 0), at(1, 1))
    };
    let y = -atan2(-at(0, 2), cy);
    let x = if condition {
        -atan2(at(1, 2), at(2, 2))
    } else {
        0.0
    };
    [x, y, z]
}

/// Gymnasium-Robotics' `rotations.quat2euler`: `mat2euler(quat2mat(q))`.
pub(crate) fn quat2euler(q: [f64; 4], profile: Profile) -> [f64; 3] {
    mat2euler(&quat2mat(&q), profile)
}

/// Gymnasium-Robotics' `rotations.euler2quat` (glibc's `sin` and `cos`, as numpy's float64).
pub(crate) fn euler2quat(e: [f64; 3]) -> [f64; 4] {
    let (ai, aj, ak) = (e[2] / 2.0, -e[1] / 2.0, e[0] / 2.0);
    let (si, sj, sk) = (ai.sin(), aj.sin(), ak.sin());
    let (ci, cj, ck) = (ai.cos(), aj.cos(), ak.cos());
    let (cc, cs) = (ci * ck, ci * sk);
    let (sc, ss) = (si * ck, si * sk);
    [
        cj * cc + sj * ss,
        cj * cs - sj * sc,
        -(cj * ss + sj * cc),
        cj * sc - sj * cs,
    ]
}

/// A `meet` reset draw into `out` (the target's numbers, 3 per point), starting from the
/// `around` records; numpy's order: the `one_of` choice, the three normals, the last uniform.
pub(crate) fn meet(
    m: &envspec::ir::Meet,
    around: &[usize],
    records: &[f64],
    rng: &mut crate::rng::NumpyRng,
    numerics: Profile,
    out: &mut [f64],
) {
    for (o, &i) in out.iter_mut().zip(around) {
        *o = records[i];
    }
    let chosen = match m.one_of.len() {
        0 => None,
        n => Some(m.one_of[rng.integers(0, n as i64) as usize]),
    };
    let mut at = [0.0; 3];
    for (k, a) in at.iter_mut().enumerate() {
        *a = records[m.center[k]] + m.offset[k];
    }
    for a in &mut at {
        // numpy's normal(loc=0, scale): loc + scale × z.
        *a += 0.0 + m.scale * rng.standard_normal();
    }
    for &p in m.always.iter().chain(chosen.as_ref()) {
        let point = &mut out[3 * p..3 * p + 3];
        let mut dir = [at[0] - point[0], at[1] - point[1], at[2] - point[2]];
        let len = numerics::norm(numerics, 3, &|i| dir[i]);
        for d in &mut dir {
            *d /= len;
        }
        for k in 0..3 {
            point[k] = at[k] - m.gap * dir[k];
        }
    }
    if rng.uniform(0.0, 1.0) < m.unchanged {
        for (o, &i) in out.iter_mut().zip(around) {
            *o = records[i];
        }
    }
}

/// Gymnasium-Robotics' `quat_from_angle_and_axis`: the axis divided by its norm, then
/// `[cos(a/2), sin(a/2) · axis]` divided by its norm (numpy's 1-D norms: OpenBLAS `ddot`).
pub(crate) fn quat_from_angle_and_axis(angle: f64, axis: [f64; 3], profile: Profile) -> [f64; 4] {
    let n = numerics::norm(profile, 3, &|i| axis[i]);
    let axis = axis.map(|x| x / n);
    let (c, s) = ((angle / 2.0).cos(), (angle / 2.0).sin());
    let q = [c, s * axis[0], s * axis[1], s * axis[2]];
    unit_quaternion(q, profile)
}

/// `q / ‖q‖` (numpy's 1-D norm).
pub(crate) fn unit_quaternion(q: [f64; 4], profile: Profile) -> [f64; 4] {
    let n = numerics::norm(profile, 4, &|i| q[i]);
    q.map(|x| x / n)
}

/// Gymnasium-Robotics' `rotations.quat_mul` (w first), term by term as it writes it.
pub(crate) fn quat_mul(q0: [f64; 4], q1: [f64; 4]) -> [f64; 4] {
    let [w0, x0, y0, z0] = q0;
    let [w1, x1, y1, z1] = q1;
    [
        w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1,
        w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1,
        w0 * y1 + y0 * w1 + z0 * x1 - x0 * z1,
        w0 * z1 + z0 * w1 + x0 * y1 - y0 * x1,
    ]
}

/// A `rotation` reset draw on the quaternion `q` (numpy's order: the angle, then the axis,
/// then the parallel orientation's index).
pub(crate) fn rotation_draw(
    q: [f64; 4],
    r: &envspec::ir::Rotation,
    set: bool,
    rng: &mut crate::rng::NumpyRng,
    profile: Profile,
) -> [f64; 4] {
    let a = rng.uniform(r.angle.0, r.angle.1);
    let axis = r
        .axis
        .unwrap_or_else(|| [(); 3].map(|()| rng.uniform(-1.0, 1.0)));
    let mut d = quat_from_angle_and_axis(a, axis, profile);
    if r.parallel {
        d = quat_mul(d, PARALLEL[rng.integers(0, PARALLEL.len() as i64) as usize]);
    }
    if set { d } else { quat_mul(q, d) }
}

/// Where the elements of each goal distance of reward kernel `kind` lie in a goal row, when the
/// distance compares elements of `[goal] achieved` with the same elements of the goal vector
/// (`desired = "goal"`, or `goal[...]` against the matching achieved elements); None otherwise
/// (the reward is then not a function of the goals).
pub(crate) fn goal_positions(
    spec: &ResolvedSpec,
    kind: &envspec::ir::TermKind,
) -> Option<Vec<Vec<usize>>> {
    use envspec::ir::{Desired, GoalCheck, TermKind};
    let goal = spec.manipulation.goal.as_ref()?;
    let one = |g: &envspec::ir::GoalDistance| -> Option<Vec<usize>> {
        match &g.desired {
            Desired::Goal => (g.achieved == goal.achieved).then(|| (0..g.len()).collect()),
            Desired::Select(d) if d.field == Field::Goal => {
                let same = d.indices.iter().zip(&g.achieved.indices).all(|(&p, &i)| {
                    goal.achieved.field == g.achieved.field
                        && goal.achieved.indices.get(p) == Some(&i)
                });
                same.then(|| d.indices.clone())
            }
            Desired::Select(_) => None,
        }
    };
    match kind {
        TermKind::GoalSparse(GoalCheck { distance: g, .. })
        | TermKind::GoalMissed(GoalCheck { distance: g, .. })
        | TermKind::GoalDense(g)
        | TermKind::GoalDistance(g) => Some(vec![one(g)?]),
        TermKind::GoalsMissed(cs) => cs.iter().map(|c| one(&c.distance)).collect(),
        _ => None,
    }
}

/// A `rotation` or `unit_quaternion` reset step on its quaternion in `target`.
pub(crate) fn quaternion_step(
    step: &envspec::ir::ResetStep,
    target: &mut [f64],
    rng: &mut crate::rng::NumpyRng,
    profile: Profile,
) {
    let ix = &step.target.indices;
    let q = [target[ix[0]], target[ix[1]], target[ix[2]], target[ix[3]]];
    let q = match &step.dist {
        envspec::ir::Distribution::Rotation(r) => rotation_draw(q, r, step.set, rng, profile),
        _ => unit_quaternion(q, profile),
    };
    for (k, &i) in ix.iter().enumerate() {
        target[i] = q[k];
    }
}

/// The 24 axis-aligned orientations of Gymnasium-Robotics' `get_parallel_rotations`, as its
/// `euler2quat` gives them (w first), bit for bit: the `parallel` rotations of a reset step.
const PARALLEL: [[f64; 4]; 24] = [
    [
        f(0x3ff0000000000000),
        f(0x0000000000000000),
        f(0x8000000000000000),
        f(0x0000000000000000),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0x0000000000000000),
        f(0x8000000000000000),
        f(0x3fe6a09e667f3bcc),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0x0000000000000000),
        f(0x0000000000000000),
        f(0xbfe6a09e667f3bcc),
    ],
    [
        f(0x3c91a62633145c07),
        f(0x0000000000000000),
        f(0x8000000000000000),
        f(0x3ff0000000000000),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0x0000000000000000),
        f(0x3fe6a09e667f3bcc),
        f(0x0000000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0x3fdffffffffffffe),
        f(0x3fe0000000000000),
        f(0x3fe0000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0xbfdffffffffffffe),
        f(0x3fe0000000000000),
        f(0xbfe0000000000000),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0x3fe6a09e667f3bcc),
        f(0x3c88f5a0be038ed5),
        f(0x3fe6a09e667f3bcd),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0x0000000000000000),
        f(0xbfe6a09e667f3bcc),
        f(0x0000000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0xbfdffffffffffffe),
        f(0xbfe0000000000000),
        f(0x3fe0000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0x3fdffffffffffffe),
        f(0xbfe0000000000000),
        f(0xbfe0000000000000),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0xbfe6a09e667f3bcc),
        f(0xbc88f5a0be038ed5),
        f(0x3fe6a09e667f3bcd),
    ],
    [
        f(0x393377ce858a5d48),
        f(0x3c91a62633145c07),
        f(0xbff0000000000000),
        f(0x3c91a62633145c07),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0x3fe6a09e667f3bcd),
        f(0x3fe6a09e667f3bcc),
        f(0xbc88f5a0be038ed5),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0x3fe6a09e667f3bcd),
        f(0xbfe6a09e667f3bcc),
        f(0x3c88f5a0be038ed5),
    ],
    [
        f(0x3c91a62633145c07),
        f(0x3ff0000000000000),
        f(0x0000000000000000),
        f(0x0000000000000000),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0x3fe6a09e667f3bcc),
        f(0x8000000000000000),
        f(0x0000000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0x3fe0000000000000),
        f(0xbfdffffffffffffe),
        f(0x3fe0000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0x3fe0000000000000),
        f(0x3fdffffffffffffe),
        f(0xbfe0000000000000),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0x3c88f5a0be038ed5),
        f(0xbfe6a09e667f3bcc),
        f(0x3fe6a09e667f3bcd),
    ],
    [
        f(0x3c88f5a0be038ed7),
        f(0xbc88f5a0be038ed5),
        f(0x3fe6a09e667f3bcc),
        f(0x3fe6a09e667f3bcd),
    ],
    [
        f(0x3fe0000000000001),
        f(0xbfe0000000000000),
        f(0xbfdffffffffffffe),
        f(0xbfe0000000000000),
    ],
    [
        f(0x3fe0000000000001),
        f(0xbfe0000000000000),
        f(0x3fdffffffffffffe),
        f(0x3fe0000000000000),
    ],
    [
        f(0x3fe6a09e667f3bcd),
        f(0xbfe6a09e667f3bcc),
        f(0x8000000000000000),
        f(0x8000000000000000),
    ],
];

const fn f(bits: u64) -> f64 {
    f64::from_bits(bits)
}
