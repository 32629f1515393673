//! The simulation an env runs (`Sim`): MuJoCo's model and data, the values the env derives from
//! them, and the readers reward terms, info entries and observations use.

use std::sync::Arc;

use envspec::ir::*;
use envspec::{Field, ResolvedSpec, Selection};
use mujoco_rs::prelude::{MjData, MjModel};

use crate::error::EnvError;
use crate::mj::{self, Call};
use crate::numerics::{Profile, norm, pairwise_sum};

/// The simulation and the values specs can read from it.
pub(super) struct Sim {
    pub(super) model: Arc<MjModel>,
    pub(super) data: MjData<Arc<MjModel>>,
    pub(super) action: Vec<f64>,
    pub(super) mass_center: [f64; 3],
    /// The dense tendon Jacobian (ntendon × nv), kept up to date when the model has tendons.
    pub(super) ten_j: Vec<f64>,
    /// numpy's pairwise `body_mass.sum()`, computed once.
    pub(super) mass_sum: f64,
    pub(super) nq: usize,
    pub(super) nv: usize,
    pub(super) nu: usize,
    pub(super) nsite: usize,
    /// Whose arithmetic the CPU-dependent reductions (norms) follow.
    pub(super) numerics: Profile,
    /// The env-held goal vector (`desired = "goal"`; `spec.goal_dim` entries).
    pub(super) goal: Vec<f64>,
    /// The `[derived.*]` values (`spec.derived_dim` entries; `runtime/src/derived.rs`).
    pub(super) derived: Vec<f64>,
    /// Per `[derived.*]` table, the ids a `contact` table watches.
    pub(super) contact_ids: Vec<Option<crate::derived::ContactIds>>,
    /// Commands, PD actions and legged-term state (`runtime/src/legged.rs`).
    pub(super) legged: crate::legged::Legged,
    /// `[init]`, `[end_effector]`, `[hold.*]` and the fields they read
    /// (`runtime/src/manipulation.rs`).
    pub(super) manip: crate::manipulation::Manip,
    /// A `[goal]` of parts: the checklist (`runtime/src/goal_parts.rs`).
    pub(super) parts: Option<crate::goal_parts::Checklist>,
}

impl Sim {
    /// The simulation of `spec` over `model` and its fresh `data`, with the mass sum computed.
    pub(super) fn new(
        spec: &ResolvedSpec,
        model: &Arc<MjModel>,
        data: MjData<Arc<MjModel>>,
        numerics: Profile,
    ) -> Result<Sim, EnvError> {
        let m = model.ffi();
        let size = |x: i64| x as usize;
        let mut sim = Sim {
            numerics,
            goal: vec![0.0; spec.goal_dim],
            parts: spec
                .manipulation
                .goal
                .as_ref()
                .and_then(|g| g.parts.as_ref())
                .map(crate::goal_parts::Checklist::new),
            derived: vec![0.0; spec.derived_dim],
            contact_ids: crate::derived::contact_ids(spec, model.ffi())?,
            nq: size(m.nq),
            nv: size(m.nv),
            nu: size(m.nu),
            nsite: size(m.nsite),
            action: vec![0.0; spec.act_dim()],
            mass_center: [0.0; 3],
            ten_j: vec![0.0; size(m.ntendon) * size(m.nv)],
            mass_sum: 0.0,
            legged: crate::legged::Legged::new(spec, model)?,
            manip: crate::manipulation::Manip::new(spec, model)?,
            model: Arc::clone(model),
            data,
        };
        let mass = model.body_mass();
        sim.mass_sum = pairwise_sum(mass.len(), &|i| mass[i]);
        Ok(sim)
    }

    /// A MuJoCo call on this model and data that may raise `mju_error` (which ends the process
    /// unless caught): the error's message comes back as `Err`, and the data is reset so it is
    /// never used in MuJoCo's mid-error state.
    pub(super) fn call(&mut self, call: Call) -> Result<(), String> {
        mj::call(&mut self.data, call)
    }

    /// Where every reset starts: the `[init]` time (when the spec has `[init]`), `qpos`, `qvel`.
    pub(super) fn restart(&mut self, init: bool, qpos0: &[f64], qvel0: &[f64]) {
        if init {
            mj::manip::set_time(&mut self.data, self.manip.init_time);
        }
        let [qpos, qvel, ..] = mj::state::state_mut(&mut self.data);
        qpos.copy_from_slice(qpos0);
        qvel.copy_from_slice(qvel0);
    }

    /// A `settle` reset step: whether its check holds (the records it names are read again).
    pub(super) fn settle(
        &mut self,
        s: &Settle,
        init: Option<&envspec::manipulation::Init>,
        frame_skip: u32,
    ) -> Result<bool, String> {
        for _ in 0..s.steps {
            let ctrl = self.data.ctrl_mut();
            self.legged.write_ctrl_by(|_| 0.0, ctrl);
            self.call(Call::Step {
                n: frame_skip,
                rne: false,
            })?;
        }
        if let Some((watch, above)) = &s.require {
            self.call(Call::Forward)?;
            self.manip.update(&self.data, self.numerics);
            if self.get(watch, 0).partial_cmp(above) != Some(std::cmp::Ordering::Greater) {
                return Ok(false);
            }
        }
        self.manip.update(&self.data, self.numerics);
        if let Some(init) = init {
            self.manip.refresh_records(init, &self.data, &s.records);
        }
        Ok(true)
    }

    pub(super) fn m(&self) -> &mujoco_rs::mujoco_c::mjModel {
        self.model.ffi()
    }

    /// The current contents of a field, flattened row-major.
    pub(super) fn field(&self, f: Field) -> &[f64] {
        let d = &self.data;
        match f {
            Field::Qpos => d.qpos(),
            Field::Qvel => d.qvel(),
            Field::Qpos0 => self.model.qpos0(),
            Field::Action => &self.action,
            Field::Ctrl => d.ctrl(),
            Field::QfrcActuator => d.qfrc_actuator(),
            Field::QfrcConstraint => d.qfrc_constraint(),
            Field::CfrcExt => d.cfrc_ext().as_flattened(),
            Field::CfrcInt => d.cfrc_int().as_flattened(),
            Field::Cacc => d.cacc().as_flattened(),
            Field::Cinert => d.cinert().as_flattened(),
            Field::Cvel => d.cvel().as_flattened(),
            Field::Xpos => d.xpos().as_flattened(),
            Field::Xipos => d.xipos().as_flattened(),
            Field::SiteXpos => d.site_xpos().as_flattened(),
            Field::Xquat => d.xquat().as_flattened(),
            Field::SiteXmat => d.site_xmat().as_flattened(),
            Field::Goal => &self.goal,
            Field::Derived => &self.derived,
            Field::SensorData => d.sensordata(),
            Field::MocapPos => d.mocap_pos().as_flattened(),
            Field::MocapQuat => d.mocap_quat().as_flattened(),
            Field::SiteEuler | Field::SiteXvelp | Field::SiteXvelr | Field::BodyEuler => {
                self.manip.field(f).unwrap_or(&[])
            }
            Field::SubtreeLinvel => d.subtree_linvel().as_flattened(),
            Field::SubtreeAngmom => d.subtree_angmom().as_flattened(),
            Field::TenLength => d.ten_length(),
            Field::TenVelocity => d.ten_velocity(),
            Field::MassCenter => &self.mass_center,
            Field::TenJ => &self.ten_j,
            // One force per actuator (MuJoCo sizes the array by force outputs, at least nu).
            Field::ActuatorForce => {
                let f = d.actuator_force();
                &f[..self.nu.min(f.len())]
            }
            other => self.legged.field(other).unwrap_or(&[]),
        }
    }

    pub(super) fn get(&self, s: &Selection, k: usize) -> f64 {
        self.field(s.field)[s.indices[k]]
    }

    /// `(achievedₖ, desiredₖ)` of a goal distance.
    pub(super) fn goal_pair(&self, g: &GoalDistance, k: usize) -> (f64, f64) {
        let a = self.field(g.achieved.field)[g.achieved.indices[k]];
        match &g.desired {
            Desired::Select(d) => (a, self.field(d.field)[d.indices[k]]),
            Desired::Goal => (a, self.goal[k]),
        }
    }

    pub(super) fn goal_reached(&self, c: &GoalCheck) -> bool {
        crate::goal::reached_by(c, self.numerics, &|k| self.goal_pair(&c.distance, k))
    }

    pub(super) fn goals_reached(&self, cs: &[GoalCheck]) -> bool {
        crate::goal::all_reached(cs, self.numerics, &|i, k| {
            self.goal_pair(&cs[i].distance, k)
        })
    }

    /// Whether `quantity op value` holds on the current state (`only_if`, `condition` info).
    pub(super) fn condition_holds(&self, c: &Condition) -> bool {
        let x = match &c.quantity {
            Quantity::Value { source, minus } => {
                let x = self.get(source, 0);
                minus.as_ref().map_or(x, |m| x - self.get(m, 0))
            }
            Quantity::Norm { source, minus } => {
                let f = self.field(source.field);
                match minus {
                    Some(m) => {
                        let g = self.field(m.field);
                        norm(self.numerics, source.len(), &|k| {
                            f[source.indices[k]] - g[m.indices[k]]
                        })
                    }
                    None => norm(self.numerics, source.len(), &|k| f[source.indices[k]]),
                }
            }
        };
        c.holds_for(x)
    }

    /// Expand MuJoCo's sparse `ten_J` (rownnz / rowadr / colind) into `ten_j`.
    pub(super) fn update_ten_j(&mut self) {
        if self.ten_j.is_empty() {
            return;
        }
        let nv = self.nv;
        let (rownnz, rowadr) = (self.model.ten_j_rownnz(), self.model.ten_j_rowadr());
        let (colind, ten_j) = (self.model.ten_j_colind(), self.data.ten_j());
        self.ten_j.fill(0.0);
        for (r, (&adr, &nnz)) in rowadr.iter().zip(rownnz).enumerate() {
            let (adr, nnz) = (adr as usize, nnz as usize);
            for j in adr..adr + nnz {
                let c = colind[j] as usize;
                if c < nv {
                    self.ten_j[r * nv + c] = ten_j[j];
                }
            }
        }
    }

    /// `einsum("b,bj->j", body_mass, xipos) / body_mass.sum()`: sequential products and sums.
    pub(super) fn update_mass_center(&mut self) {
        let (mass, xipos) = (self.model.body_mass(), self.data.xipos().as_flattened());
        let mut c = [0.0f64; 3];
        for (b, &mb) in mass.iter().enumerate() {
            for (j, cj) in c.iter_mut().enumerate() {
                *cj += mb * xipos[b * 3 + j];
            }
        }
        self.mass_center = c.map(|x| x / self.mass_sum);
    }
}
