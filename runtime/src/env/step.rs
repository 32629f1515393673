//! The step: the action → the physics → health, reward terms, info, termination → the interval
//! events → the observation, in the reference's draw order.

use super::info::{Info, write_info};
use super::{Env, Step};
use crate::error::EnvError;
use crate::mj::log as mujoco_log;
use crate::mj::{self, Call};

impl Env {
    /// Advance one control step. The action is used as given (MuJoCo clamps it to ctrlrange inside
    /// the dynamics; costs see the raw values), as in the reference.
    pub fn step(&mut self, action: &[f64]) -> Result<Step<'_>, EnvError> {
        self.check_action(crate::JointAction::F64(action))?;
        self.sim.action.copy_from_slice(action);
        self.action_f32 = false;
        self.advance()
    }

    /// `step` with a float32 action, as a float32 policy calls the reference: the dynamics are
    /// the same (the conversion to float64 is exact), but costs computed from `action` are
    /// computed in float32 as numpy does (square, pairwise sum and weight in float32; reference
    /// trap T3), so their info values are float32 numbers.
    pub fn step_f32(&mut self, action: &[f32]) -> Result<Step<'_>, EnvError> {
        self.check_action(crate::JointAction::F32(action))?;
        for (a, &x) in self.sim.action.iter_mut().zip(action) {
            *a = x as f64;
        }
        self.action_f32 = true;
        self.advance()
    }

    /// Interval events due after this step (draw order step 5); when any fired, `mj_forward` so
    /// what the observation reads agrees with the kicked velocities and new fields.
    fn interval_events(&mut self) -> Result<(), EnvError> {
        let (Some(ev), Some(rng)) = (self.events.as_mut(), self.rng.as_mut()) else {
            return Ok(());
        };
        let mut t = crate::events::Target {
            // As in `reset_events`.
            m: mj::model_edit::ModelValues::env_copy(&self.sim.model),
            qvel: self.sim.data.qvel_mut(),
            rng,
            profile: self.sim.numerics,
        };
        if !ev.step(&mut t, self.dt) {
            return Ok(());
        }
        let timestep = ev.changes_timestep;
        self.model_changed(false, timestep);
        if let Err(message) = self.sim.call(Call::Forward) {
            return Err(self.step_failed(message));
        }
        self.derive_after_physics();
        Ok(())
    }

    /// A MuJoCo error in a step: the state is MuJoCo's mid-error state, so no step before the
    /// next reset.
    fn step_failed(&mut self, message: String) -> EnvError {
        self.has_reset = false;
        EnvError::Mujoco {
            env: self.spec.id.clone(),
            during: "in a step (reset before stepping again)",
            message,
        }
    }

    /// Refuse a step before a valid reset, or an action of another length or with a non-finite
    /// value.
    fn check_action(&self, action: crate::JointAction<'_>) -> Result<(), EnvError> {
        crate::joint_env::check_action(&self.spec.id, self.sim.action.len(), action, || {
            (!self.has_reset).then(|| self.reset_error().unwrap_or(EnvError::NotReset))
        })
    }

    /// The step proper, with the action already in `sim.action`.
    fn advance(&mut self) -> Result<Step<'_>, EnvError> {
        if let Some(l) = &mut self.latency {
            l.apply(&mut self.sim.action);
        }
        for (k, s) in self.velocity_sources.iter().enumerate() {
            self.before[k] = self.sim.get(s, 0);
        }
        // Terms with `at = "before"` see the state the previous step (or the reset) left.
        self.score_terms(true, true);
        self.run_physics()?;
        let healthy = self.spec.health.iter().all(|c| self.check(c));
        self.evaluate_parts();
        self.score_terms(false, healthy);
        let reward = self.sum(&self.spec.reward_sum);
        let parts_done = self.commit_parts();
        self.sim.legged.commit_contacts();
        // Draw order step 4: commands due are redrawn (the info below shows the new ones).
        if !self.spec.commands.is_empty() {
            let rng = self.rng.as_mut().expect("a reset came first");
            self.sim.legged.resample(&self.spec, rng);
        }
        self.write_step_info();
        self.elapsed += 1;
        let terminated = (!healthy && self.spec.terminate_when_unhealthy)
            || parts_done
            || self
                .spec
                .termination
                .iter()
                .any(|t| self.sim.goal_reached(&t.reached));
        let truncated = self
            .spec
            .max_episode_steps
            .is_some_and(|m| self.elapsed >= m);
        // Draw order step 5: interval events after reward, termination and info, before the
        // observation.
        if self.events.is_some() {
            self.interval_events()?;
        }
        // `[physics] forward_before_observation` (mjlab's step): the observation reads the new
        // state's kinematics, where reward and termination read the last substep's.
        if self.spec.model_edits.forward_before_observation {
            if let Err(message) = self.sim.call(Call::Forward) {
                return Err(self.step_failed(message));
            }
            self.derive_after_physics();
            self.sim.legged.update_sites(&self.sim.data);
        }
        // Draw order step 6: the observation (noise, delay); it holds the previous action as
        // `last_action`, which becomes this step's action only after it is written.
        self.write_obs();
        self.sim.legged.end_step(&self.sim.action);
        mujoco_log::drain_into(&mut self.warnings);
        Ok(Step {
            obs: &self.obs,
            reward,
            terminated,
            truncated,
            info: Info {
                slots: &self.step_info,
                values: &self.step_info_values,
            },
        })
    }

    /// The signed values of the terms evaluated before the physics (`before`) or after it, and
    /// their weight-1 values where an `unweighted` info entry reports them.
    fn score_terms(&mut self, before: bool, healthy: bool) {
        let n_terms = self.spec.reward.len();
        for (i, t) in self.spec.reward.iter().enumerate() {
            if t.before != before {
                continue;
            }
            let v = self.term(i, t, self.term_slot[i], healthy, t.weight);
            self.term_values[i] = if t.cost { -v } else { v };
            if self.unweighted_terms[i] {
                let u = self.term(i, t, self.term_slot[i], healthy, 1.0);
                self.term_values[n_terms + i] = if t.cost { -u } else { u };
            }
        }
    }

    /// The action to `ctrl`, `frame_skip` physics steps, the `[hold.*]` joints, then what the env
    /// derives from the new state and the contacts the reward reads.
    fn run_physics(&mut self) -> Result<(), EnvError> {
        if let Some(e) = &self.spec.manipulation.end_effector {
            self.sim
                .manip
                .apply_action(e, &self.sim.action, self.action_f32, &mut self.sim.data);
        } else if let Some(d) = self.spec.actions.as_ref().and_then(|a| a.delta.as_ref()) {
            // From the position the agent last saw: the observation still holds it.
            let seg = &self.spec.observation[d.segment];
            let observed = &self.obs[seg.offset..seg.offset + seg.len()];
            let ctrl = self.sim.data.ctrl_mut();
            self.sim
                .legged
                .write_ctrl_delta(d, &self.sim.action, observed, self.dt, ctrl);
        } else {
            let ctrl = self.sim.data.ctrl_mut();
            self.sim.legged.write_ctrl(&self.sim.action, ctrl);
        }
        let (n, rne) = (self.spec.frame_skip, self.spec.needs_rne_post_constraint);
        let stepped = if self.sim.legged.landings.active() {
            // Substep by substep: mjlab's contact sensors are updated after each one.
            self.sim.legged.landings.begin_step();
            let mut stepped = Ok(());
            for k in 0..n {
                let rne = rne && k + 1 == n;
                stepped = self.sim.call(Call::Step { n: 1, rne });
                if stepped.is_err() {
                    break;
                }
                self.sim.legged.landings.substep(&self.sim.data);
            }
            stepped
        } else {
            self.sim.call(Call::Step { n, rne })
        };
        if let Err(message) = stepped {
            return Err(self.step_failed(message));
        }
        // `[hold.*]`: joints set after the physics, then `mj_forward` (the reference's step
        // callback).
        if !self.spec.manipulation.hold.is_empty() {
            let (qpos, _) = mj::state::qpos_qvel_mut(&mut self.sim.data);
            for h in &self.spec.manipulation.hold {
                for &a in &h.qpos {
                    qpos[a] = h.value;
                }
            }
            if let Err(message) = self.sim.call(Call::Forward) {
                return Err(self.step_failed(message));
            }
        }
        self.derive_after_physics();
        self.sim.legged.update_sites(&self.sim.data);
        self.sim.legged.update_contacts(&self.sim.data, self.dt);
        self.sim.legged.landings.before_reward(&self.sim.data);
        Ok(())
    }

    /// The step info, entry by entry in spec order.
    fn write_step_info(&mut self) {
        let mut off = 0;
        for (j, item) in self.spec.info.iter().enumerate() {
            let out = &mut self.step_info_values[off..off + item.len];
            let slot = self.info_slot[j];
            write_info(
                &self.sim,
                &self.before,
                &self.term_values,
                self.dt,
                item,
                slot,
                out,
            );
            off += item.len;
        }
    }

    /// The observation after a step or `set_state` (no delay buffers filled).
    pub(super) fn write_obs(&mut self) {
        self.write_obs_at(false);
    }

    /// The observation, with noise and delay where the spec declares them (`reset`: fill the
    /// delay buffers).
    pub(super) fn write_obs_at(&mut self, reset: bool) {
        let sim = &self.sim;
        match (&mut self.obs_noise, &mut self.rng) {
            (Some(n), Some(rng)) => {
                n.write(&self.spec, |f| sim.field(f), &mut self.obs, rng, reset)
            }
            _ => crate::observe::write_segments(
                &self.spec.observation,
                |f| sim.field(f),
                &mut self.obs,
            ),
        }
    }
}
