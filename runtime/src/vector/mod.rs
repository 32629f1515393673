//! Vectorized envs: N envs of one spec sharing one compiled model, stepped in parallel by a
//! persistent pool, with Gymnasium 1.x `SyncVectorEnv` semantics.
//!
//! * `reset(Some(s))` seeds env i with `s + i`; `reset(None)` leaves each env's stream going.
//! * Autoreset [`Autoreset::NextStep`] (Gymnasium's default): the step after an env ended resets it
//!   (no seed) instead of stepping it, with reward 0 and both flags false. [`Autoreset::SameStep`]:
//!   the ending step resets at once; the batch holds the reset obs, the ending obs goes to
//!   [`VecEnv::final_obs`] and its info stays readable through [`VecEnv::final_info`].
//! * Observations, rewards, terminated and truncated live in contiguous batch buffers
//!   (env-major) that the caller reads in place. A goal-conditioned task (`[goal]`) has two more,
//!   the achieved and desired goals ([`VecEnv::achieved_goals`], [`VecEnv::desired_goals`]),
//!   written with the observation, SameStep's final ones included.
//! * [`VecEnv::step_f32`] steps a float32 action batch as a float32 policy steps the reference
//!   (each env through `Env::step_f32`).
//!
//! `threads = M` means M threads run envs: the caller plus M − 1 pool workers that live as long
//! as the `VecEnv`. The caller works too, so a step costs one wake-up hand-off, not two. Envs are
//! claimed one at a time from a shared counter (load balancing: episodes end and reset at
//! different times), and every env writes only its own slots, so the results do not depend on M
//! or on which thread ran which env.
//!
//! `pool` holds the threads, the raw views of the batch buffers and the caller's side of a step;
//! `memory` the memory checks made before any env is built.

use std::sync::Arc;
use std::sync::atomic::Ordering::*;
use std::thread::JoinHandle;

use envspec::{Override, ResolvedSpec};

use crate::env::{Env, Info, compile};
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv};

mod memory;
mod pool;

use pool::Shared;

/// When an ended env is reset (Gymnasium's `AutoresetMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Autoreset {
    /// On the next `step` call (Gymnasium 1.x's default).
    #[default]
    NextStep,
    /// In the ending step itself; the ending observation goes to `final_obs`.
    SameStep,
}

/// How an interruptible step ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[must_use]
pub enum Stepped {
    /// Every env stepped; the batch buffers hold the results.
    Done,
    /// Stopped part-way because the caller's check said so: envs not started were skipped, the
    /// batch is a mix of stepped and unstepped envs, and `step` refuses (E1103) until a reset.
    Interrupted,
}

/// N envs of one spec, stepped in parallel.
pub struct VecEnv {
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
    // Written only through the `Job` pointers (`Vec::as_mut_ptr` keeps them valid alongside
    // reads through the Vecs); never resized.
    envs: Vec<Env>,
    obs: Vec<f64>,
    rewards: Vec<f64>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    final_obs: Vec<f64>,
    goals: GoalRows,
    has_final: Vec<bool>,
    pending: Vec<bool>,
    has_reset: bool,
    /// What each env costs in memory, as checked at construction.
    per_env: crate::env::Footprint,
    /// The process that started the workers (a forked child has none to join).
    pid: u32,
}

/// `[goal]`: each env's achieved and desired goal, `num_envs × goal_dim` each (empty without
/// `[goal]`), and the ones SameStep's ending envs ended on.
struct GoalRows {
    achieved: Vec<f64>,
    desired: Vec<f64>,
    final_achieved: Vec<f64>,
    final_desired: Vec<f64>,
}

/// The length of `spec`'s goal vectors: 0 without `[goal]`.
fn goal_dim(spec: &ResolvedSpec) -> usize {
    if spec.manipulation.goal.is_some() {
        spec.goal_dim
    } else {
        0
    }
}

impl VecEnv {
    /// After a failure the batch cannot be trusted: `step` refuses (E1103) until the next
    /// `reset`.
    pub fn require_reset(&mut self) {
        self.has_reset = false;
    }

    /// `num_envs` envs of a bundled id or spec path (with overrides), run on `threads` threads.
    /// The spec opens through the one door ([`crate::open`]); a maze or a multi-agent spec is
    /// E0602.
    pub fn make(
        id_or_path: &str,
        overrides: &[Override],
        num_envs: usize,
        threads: usize,
        mode: Autoreset,
    ) -> Result<VecEnv, EnvError> {
        VecEnv::make_checked(id_or_path, overrides, num_envs, threads, mode, |_| Ok(()))
    }

    /// [`make`](Self::make), with `check` run on the first env before the others are built (a
    /// binding refusing what it cannot present, without building `num_envs` envs first).
    pub fn make_checked(
        id_or_path: &str,
        overrides: &[Override],
        num_envs: usize,
        threads: usize,
        mode: Autoreset,
        check: impl FnOnce(&Env) -> Result<(), EnvError>,
    ) -> Result<VecEnv, EnvError> {
        match crate::open(id_or_path, overrides)? {
            crate::AnyEnv::Task(first) => {
                check(&first)?;
                VecEnv::from_env(first, num_envs, threads, mode)
            }
            other => Err(EnvError::Spec(
                envspec::Diagnostic::new(
                    envspec::Code::E0602,
                    format!(
                        "`{id_or_path}` is a {} spec: vector envs step single-agent tasks",
                        other.kind()
                    ),
                )
                .into(),
            )),
        }
    }

    /// Compile the model once and build `num_envs` envs over it. `threads` is clamped to
    /// `1..=num_envs` (more threads than envs would only idle).
    pub fn new(
        spec: Arc<ResolvedSpec>,
        num_envs: usize,
        threads: usize,
        mode: Autoreset,
    ) -> Result<VecEnv, EnvError> {
        VecEnv::check_count(&spec, num_envs)?;
        let model = Arc::new(compile(&spec)?);
        VecEnv::from_env(Env::with_model(spec, model)?, num_envs, threads, mode)
    }

    /// `num_envs` envs sharing the model of `first` (which is the first of them).
    pub fn from_env(
        first: Env,
        num_envs: usize,
        threads: usize,
        mode: Autoreset,
    ) -> Result<VecEnv, EnvError> {
        let spec = Arc::clone(first.spec());
        let model = Arc::clone(first.model());
        VecEnv::check_count(&spec, num_envs)?;
        // Refuse before allocating them all rather than fail (or be killed) part-way.
        let per_env = VecEnv::per_env(&first);
        VecEnv::check_memory(&spec.id, num_envs, threads, per_env)?;
        let envs = std::iter::once(Ok(first))
            .chain((1..num_envs).map(|_| Env::with_model(Arc::clone(&spec), Arc::clone(&model))))
            .collect::<Result<Vec<Env>, _>>()?;
        let (n, od, ad, gd) = (num_envs, spec.obs_dim, spec.act_dim(), goal_dim(&spec));
        let mut v = VecEnv {
            shared: Arc::new(Shared::new(n, (od, ad, gd), mode)),
            workers: vec![],
            envs,
            obs: vec![0.0; n * od],
            rewards: vec![0.0; n],
            terminated: vec![false; n],
            truncated: vec![false; n],
            final_obs: vec![0.0; n * od],
            goals: GoalRows {
                achieved: vec![0.0; n * gd],
                desired: vec![0.0; n * gd],
                final_achieved: vec![0.0; n * gd],
                final_desired: vec![0.0; n * gd],
            },
            has_final: vec![false; n],
            pending: vec![false; n],
            has_reset: false,
            per_env,
            pid: std::process::id(),
        };
        v.start_pool(threads, &spec)?;
        Ok(v)
    }

    /// The number of sub-envs.
    pub fn num_envs(&self) -> usize {
        self.envs.len()
    }
    /// Threads running envs during `step` (the caller included).
    pub fn threads(&self) -> usize {
        self.workers.len() + 1
    }
    /// When an ended sub-env is reset.
    pub fn autoreset(&self) -> Autoreset {
        self.shared.job.mode
    }
    /// One sub-env's observation length (a row of the batch).
    pub fn obs_dim(&self) -> usize {
        self.shared.job.obs_dim
    }
    /// The length of one sub-env's goal vectors (a row of [`VecEnv::achieved_goals`]): 0 for a
    /// task without `[goal]`.
    pub fn goal_dim(&self) -> usize {
        self.shared.job.goal_dim
    }
    /// One sub-env's action length.
    pub fn act_dim(&self) -> usize {
        self.shared.job.act_dim
    }
    /// The spec the sub-envs run (None for a vector of no envs).
    pub fn spec(&self) -> Option<&Arc<ResolvedSpec>> {
        self.envs.first().map(|e| e.spec())
    }
    /// Every sub-env computes as the reference does under `profile` (see `Env::set_numerics`).
    pub fn set_numerics(&mut self, profile: crate::numerics::Profile) {
        for e in &mut self.envs {
            e.set_numerics(profile);
        }
    }
    /// The sub-envs (read-only: spaces, state, warnings).
    pub fn envs(&self) -> &[Env] {
        &self.envs
    }
    /// Render env `index` (Gymnasium's vector `render()` renders each env in turn); each env has
    /// its own renderer, made on its first frame. Panics if `index >= num_envs()`.
    pub fn render(
        &mut self,
        index: usize,
        mode: crate::render::RenderMode,
    ) -> Result<crate::render::Frame<'_>, EnvError> {
        self.envs[index].render(mode)
    }

    /// Gymnasium `reset(seed=s)`: env i gets `s + i`; `None` continues each env's stream.
    pub fn reset(&mut self, seed: Option<u64>) -> &[f64] {
        let seeds = (0..self.envs.len()).map(|i| seed.map(|s| s.wrapping_add(i as u64)));
        self.reset_each(seeds)
    }

    /// Reset with one seed (or `None`) per env, like Gymnasium's `reset(seed=[...])`.
    pub fn reset_each(&mut self, seeds: impl IntoIterator<Item = Option<u64>>) -> &[f64] {
        let job = &self.shared.job;
        for (i, seed) in seeds.into_iter().take(job.n).enumerate() {
            // SAFETY: no step is running; i < n; slots sized as in `run_one`.
            unsafe {
                let env = &mut *job.envs.add(i);
                env.reset(seed);
                job.observe(i, env, false);
            }
        }
        // SAFETY: as above; each buffer has n entries.
        unsafe {
            std::ptr::write_bytes(job.rewards, 0, job.n);
            std::ptr::write_bytes(job.terminated, 0, job.n);
            std::ptr::write_bytes(job.truncated, 0, job.n);
            std::ptr::write_bytes(job.has_final, 0, job.n);
            std::ptr::write_bytes(job.pending, 0, job.n);
        }
        self.has_reset = true;
        &self.obs
    }

    /// Reset only the envs where `mask` is true, each with its seed (Gymnasium's
    /// `reset(options={"reset_mask": mask})`); the others keep their state, observation, flags
    /// and pending autoreset. Every env must have been reset once before.
    pub fn reset_masked(
        &mut self,
        seeds: impl IntoIterator<Item = Option<u64>>,
        mask: &[bool],
    ) -> Result<&[f64], EnvError> {
        if !self.has_reset {
            return Err(EnvError::NotReset);
        }
        let job = &self.shared.job;
        let masked = seeds.into_iter().take(job.n).enumerate().zip(mask);
        for ((i, seed), _) in masked.filter(|(_, m)| **m) {
            // SAFETY: no step is running; i < n; slots sized as in `run_one`.
            unsafe {
                let env = &mut *job.envs.add(i);
                env.reset(seed);
                job.observe(i, env, false);
                *job.rewards.add(i) = 0.0;
                *job.terminated.add(i) = false;
                *job.truncated.add(i) = false;
                *job.has_final.add(i) = false;
                *job.pending.add(i) = false;
            }
        }
        Ok(&self.obs)
    }

    /// Step every env with its row of `actions` (`num_envs × act_dim`, env-major). On return the
    /// batch buffers hold the results. The rows are read in place, not copied.
    pub fn step(&mut self, actions: &[f64]) -> Result<(), EnvError> {
        self.check_actions(JointAction::F64(actions))?;
        self.run(JointAction::F64(actions), None, &mut || {})
            .map(|_| ())
    }

    /// [`VecEnv::step`] with float32 actions, as a float32 policy steps the reference: each env
    /// steps with `Env::step_f32` (float32 action costs, as numpy computes them).
    pub fn step_f32(&mut self, actions: &[f32]) -> Result<(), EnvError> {
        self.check_actions(JointAction::F32(actions))?;
        self.run(JointAction::F32(actions), None, &mut || {})
            .map(|_| ())
    }

    /// [`VecEnv::step`] or [`VecEnv::step_f32`] that asks `interrupted` about every 50 ms,
    /// between envs, and stops part-way when it says true (a Python binding checks for Ctrl-C
    /// there). An interrupted step needs a reset before the next (E1103).
    pub fn step_interruptible(
        &mut self,
        actions: JointAction<'_>,
        interrupted: &mut dyn FnMut() -> bool,
    ) -> Result<Stepped, EnvError> {
        self.step_overlapped(actions, interrupted, &mut || {})
    }

    /// [`VecEnv::step_interruptible`] that runs `meanwhile` on the calling thread once the
    /// workers have started on the batch and before the caller joins them: work that does not
    /// need the results (a binding allocating the arrays it will hand out) overlaps the
    /// workers' envs instead of adding to the step. With one thread it runs before the envs.
    pub fn step_overlapped(
        &mut self,
        actions: JointAction<'_>,
        interrupted: &mut dyn FnMut() -> bool,
        meanwhile: &mut dyn FnMut(),
    ) -> Result<Stepped, EnvError> {
        self.check_actions(actions)?;
        let stepped = self.run(actions, Some(interrupted), meanwhile)?;
        if stepped == Stepped::Interrupted {
            self.has_reset = false;
        }
        Ok(stepped)
    }

    /// Checked before any env moves, so a bad action fails the whole batch.
    fn check_actions(&self, actions: JointAction<'_>) -> Result<(), EnvError> {
        let id = self.spec().map(|s| s.id.as_str()).unwrap_or_default();
        let len = self.shared.job.n * self.shared.job.act_dim;
        crate::joint_env::check_action(id, len, actions, || {
            (!self.has_reset).then_some(EnvError::NotReset)
        })
    }

    /// Observations, `num_envs × obs_dim`, env-major.
    pub fn obs(&self) -> &[f64] {
        &self.obs
    }
    /// The last step's rewards, one per sub-env.
    pub fn rewards(&self) -> &[f64] {
        &self.rewards
    }
    /// The last step's terminated flags, one per sub-env.
    pub fn terminated(&self) -> &[bool] {
        &self.terminated
    }
    /// The last step's truncated flags, one per sub-env.
    pub fn truncated(&self) -> &[bool] {
        &self.truncated
    }
    /// SameStep: the observation each env ended on in the last step, valid where
    /// [`VecEnv::has_final`] is true (`num_envs × obs_dim`).
    pub fn final_obs(&self) -> &[f64] {
        &self.final_obs
    }
    /// `[goal]`: each env's achieved goal with its observation, `num_envs × goal_dim` (empty
    /// without `[goal]`).
    pub fn achieved_goals(&self) -> &[f64] {
        &self.goals.achieved
    }
    /// `[goal]`: each env's desired goal (the goal vector its episode is after), as
    /// [`VecEnv::achieved_goals`].
    pub fn desired_goals(&self) -> &[f64] {
        &self.goals.desired
    }
    /// SameStep, `[goal]`: the achieved goals each env ended on, beside [`VecEnv::final_obs`].
    pub fn final_achieved_goals(&self) -> &[f64] {
        &self.goals.final_achieved
    }
    /// SameStep, `[goal]`: the desired goals each env ended with, beside [`VecEnv::final_obs`].
    pub fn final_desired_goals(&self) -> &[f64] {
        &self.goals.final_desired
    }
    /// SameStep: which envs ended (and were reset) in the last step.
    pub fn has_final(&self) -> &[bool] {
        &self.has_final
    }
    /// Env i's info for the last call, as Gymnasium reports it: the reset info where the env was
    /// (auto)reset, the step info otherwise.
    pub fn info(&self, i: usize) -> Option<Info<'_>> {
        let env = self.envs.get(i)?;
        // Any (auto)reset leaves the env at 0 elapsed steps; a step never does.
        Some(if env.elapsed_steps() == 0 {
            env.reset_info()
        } else {
            env.step_info()
        })
    }
    /// SameStep: the step info env i ended with (its `final_info`), where it ended.
    pub fn final_info(&self, i: usize) -> Option<Info<'_>> {
        (*self.has_final.get(i)?).then(|| self.envs[i].step_info())
    }

    #[doc(hidden)]
    /// Test hook: delay each env by a pseudo-random 0–300 µs (seeded; 0 turns it off) so threads
    /// finish in shuffled orders.
    pub fn set_completion_jitter(&mut self, seed: u64) {
        self.shared.jitter.store(seed, Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::pool::splitmix;
    use super::*;

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|v| v.to_bits()).collect()
    }

    fn pair(n: usize) -> (VecEnv, VecEnv) {
        let make = || VecEnv::make("Hopper-v5", &[], n, 2, Autoreset::NextStep).unwrap();
        let (mut a, mut b) = (make(), make());
        a.reset(Some(3));
        b.reset(Some(3));
        (a, b)
    }

    #[test]
    fn step_overlapped_runs_meanwhile_once_and_steps_as_step_does() {
        let (mut a, mut b) = pair(6);
        let mut seed = 0x1234_u64;
        for t in 0..60 {
            let act: Vec<f64> = (0..6 * 3)
                .map(|_| {
                    seed = splitmix(seed);
                    (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
                })
                .collect();
            let mut calls = 0;
            let stepped = a
                .step_overlapped(JointAction::F64(&act), &mut || false, &mut || calls += 1)
                .unwrap();
            assert_eq!((stepped, calls), (Stepped::Done, 1), "step {t}");
            b.step(&act).unwrap();
            assert_eq!(bits(a.obs()), bits(b.obs()), "step {t}");
            assert_eq!(bits(a.rewards()), bits(b.rewards()), "step {t}");
            assert_eq!(a.terminated(), b.terminated(), "step {t}");
            assert_eq!(a.truncated(), b.truncated(), "step {t}");
        }
    }

    #[test]
    fn a_panic_in_meanwhile_surfaces_once_every_env_has_stepped() {
        let (mut a, mut b) = pair(8);
        let act = vec![0.25; 8 * 3];
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            a.step_overlapped(JointAction::F64(&act), &mut || false, &mut || {
                panic!("meanwhile")
            })
        }));
        assert!(r.is_err());
        b.step(&act).unwrap();
        assert_eq!(bits(a.obs()), bits(b.obs()));
        a.step(&act).unwrap();
    }
}
