//! The env's state: reading and setting it from outside, and what the env derives from it after
//! MuJoCo moved it (only what the spec reads).

use envspec::{Field, Selection};
use mujoco_rs::mujoco_c::mjData;

use super::Env;
use crate::error::EnvError;
use crate::mj::{self, Call};
use crate::numerics::pairwise_sum;

impl Env {
    /// Clip the current qvel to `±limit` and `mj_forward` (Gymnasium's `set_state(qpos, clip(qvel))`).
    pub(crate) fn clip_qvel(&mut self, limit: f64) -> Result<(), EnvError> {
        for v in self.sim.data.qvel_mut() {
            *v = crate::numerics::clip(*v, -limit, limit);
        }
        self.sim.call(Call::Forward).map_err(|message| {
            self.has_reset = false;
            EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in a step (reset before stepping again)",
                message,
            }
        })
    }

    /// Gymnasium's `MujocoEnv.set_state`: `qpos` and `qvel` are written, then `mj_forward`; the
    /// derived fields and the observation follow the new state (`[derived.*]` values measured at
    /// reset keep their values, as the reference's attributes do). E1105 for another length
    /// than the model's `nq` / `nv`.
    pub fn set_state(&mut self, qpos: &[f64], qvel: &[f64]) -> Result<(), EnvError> {
        for (what, got, expected) in [
            ("qpos", qpos.len(), self.sim.nq),
            ("qvel", qvel.len(), self.sim.nv),
        ] {
            if got != expected {
                return Err(EnvError::StateLength {
                    env: self.spec.id.clone(),
                    what,
                    expected,
                    got,
                });
            }
        }
        let (q, v) = mj::state::qpos_qvel_mut(&mut self.sim.data);
        q.copy_from_slice(qpos);
        v.copy_from_slice(qvel);
        if let Err(message) = self.sim.call(Call::Forward) {
            self.has_reset = false;
            return Err(EnvError::Mujoco {
                env: self.spec.id.clone(),
                during: "in set_state (reset before stepping again)",
                message,
            });
        }
        self.derive_after_physics();
        self.sim.legged.update_sites(&self.sim.data);
        self.write_obs();
        Ok(())
    }

    /// The MuJoCo data, read-only (checks of derived quantities against independent
    /// implementations read `cvel`, `subtree_com`, `site_xmat`, the contact list).
    pub fn data(&self) -> &mjData {
        self.sim.data.ffi()
    }
    /// Current `qpos` and `qvel`.
    pub fn state(&self) -> (&[f64], &[f64]) {
        (self.sim.field(Field::Qpos), self.sim.field(Field::Qvel))
    }
    /// The current contents of a simulation field, flattened row-major (multi-agent
    /// observations read it).
    pub fn field(&self, field: Field) -> &[f64] {
        self.sim.field(field)
    }
    /// Keep the derived fields `sources` read up to date too (a multi-agent env's agents may
    /// observe selections its spec does not). Contact forces are decided by the spec
    /// (`needs_rne_post_constraint`), before the env is built.
    pub(crate) fn read_also<'a>(&mut self, sources: impl Iterator<Item = &'a Selection>) {
        for s in sources {
            self.uses_mass_center |= s.field == Field::MassCenter;
            self.uses_subtree |= s.field.needs_subtree_vel();
            if s.field.is_site_frame() {
                self.sim.legged.enable_site_frames(self.sim.nsite);
            }
            self.sim.manip.read_also(s);
        }
    }

    /// What the env derives from the state after MuJoCo moved it (only what the spec reads).
    pub(super) fn derive_after_physics(&mut self) {
        if self.uses_mass_center {
            self.sim.update_mass_center();
        }
        if self.uses_subtree {
            // mj_subtreeVel reads only the kinematics the physics just computed and takes stack
            // space mj_step has already used; MuJoCo raises no error from it. A failure would
            // leave the data reset, which the next step reports.
            let _ = self.sim.call(Call::SubtreeVel);
        }
        self.sim.update_ten_j();
        let numerics = self.sim.numerics;
        self.sim.manip.update(&self.sim.data, numerics);
        self.update_derived(false);
    }

    /// `[derived.*]` from the current state (`reset`: the `at = "reset"` ones too).
    pub(super) fn update_derived(&mut self, reset: bool) {
        if self.spec.derived.is_empty() {
            return;
        }
        let mut out = std::mem::take(&mut self.sim.derived);
        let sim = &self.sim;
        crate::derived::update(
            &self.spec.derived,
            &sim.contact_ids,
            &sim.data,
            |f| sim.field(f),
            sim.numerics,
            reset,
            &mut out,
        );
        self.sim.derived = out;
    }

    /// What the env caches from the model: the mass sum (`mass_center`) and the timestep / dt.
    pub(super) fn model_changed(&mut self, mass: bool, timestep: bool) {
        if mass {
            let mass = self.sim.model.body_mass();
            self.sim.mass_sum = pairwise_sum(mass.len(), &|i| mass[i]);
        }
        if timestep {
            self.timestep = self.sim.m().opt.timestep;
            self.dt = self.timestep * self.spec.frame_skip as f64;
        }
    }
}
