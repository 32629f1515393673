//! The pool that steps a vector's envs: its threads, the raw views of the batch buffers they
//! write, the claiming of envs one at a time, and the caller's side of a step.

use std::any::Any;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use envspec::ResolvedSpec;

use super::{Autoreset, Stepped, VecEnv};
use crate::env::Env;
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv};

/// How long an idle thread spins before sleeping: a futex wake-up costs 25–35 µs on the
/// development VM, more than a whole cheap env step.
const SPIN: Duration = Duration::from_micros(50);

/// How often an interruptible step ([`VecEnv::step_interruptible`]) asks whether to stop: often
/// enough that Ctrl-C lands well within a second, rarely enough to cost nothing measurable.
const POLL: Duration = Duration::from_millis(50);

/// Raw views of the env array and batch buffers. Fixed at construction (the buffers are never
/// resized, so the pointers stay valid while the `VecEnv` lives, however it moves), but for the
/// action batch: the caller's own rows, borrowed for one step (no copy), null between steps.
pub(super) struct Job {
    pub(super) envs: *mut Env,
    actions: AtomicPtr<f64>,
    /// The float32 rows of [`VecEnv::step_f32`] (the same layout as `actions`).
    actions_f32: AtomicPtr<f32>,
    pub(super) obs: *mut f64,
    pub(super) rewards: *mut f64,
    pub(super) terminated: *mut bool,
    pub(super) truncated: *mut bool,
    final_obs: *mut f64,
    /// `[goal]`: each env's achieved and desired goal (`n × goal_dim`), and SameStep's final ones.
    achieved: *mut f64,
    desired: *mut f64,
    final_achieved: *mut f64,
    final_desired: *mut f64,
    pub(super) has_final: *mut bool,
    /// Env i ended in the previous step (NextStep resets it now).
    pub(super) pending: *mut bool,
    pub(super) n: usize,
    pub(super) obs_dim: usize,
    pub(super) act_dim: usize,
    /// 0 without `[goal]`.
    pub(super) goal_dim: usize,
    pub(super) mode: Autoreset,
}

impl Job {
    /// Copy env i's observation (and goals) as they are now into its rows of the batch, or of
    /// SameStep's final rows (`last`).
    ///
    /// # Safety
    /// `i < n`, and no other thread touches env i's rows meanwhile (a claimed env, or no step
    /// running); the buffers are live.
    pub(super) unsafe fn observe(&self, i: usize, env: &Env, last: bool) {
        let (od, gd) = (self.obs_dim, self.goal_dim);
        let (obs, achieved, desired) = if last {
            (self.final_obs, self.final_achieved, self.final_desired)
        } else {
            (self.obs, self.achieved, self.desired)
        };
        // SAFETY: env i's rows of buffers of n × obs_dim and n × goal_dim numbers, touched by
        // this thread alone (the contract above).
        unsafe {
            std::slice::from_raw_parts_mut(obs.add(i * od), od).copy_from_slice(env.obs());
            if gd > 0 {
                let row = std::slice::from_raw_parts_mut(achieved.add(i * gd), gd);
                env.write_achieved_goal(row);
                std::slice::from_raw_parts_mut(desired.add(i * gd), gd)
                    .copy_from_slice(&env.goal()[..gd]);
            }
        }
    }
}

// SAFETY: a Job is only dereferenced for env indices claimed from `Shared::next`, each claimed by
// exactly one thread per step, and the caller touches the buffers only while no step runs.
unsafe impl Send for Job {}
// SAFETY: as for `Send`.
unsafe impl Sync for Job {}

/// What the caller and the pool's workers share: the job, the step's counters and the wake-ups.
pub(super) struct Shared {
    pub(super) job: Job,
    /// Next env index to claim in the current step.
    next: AtomicUsize,
    /// Envs finished in the current step.
    done: AtomicUsize,
    /// Bumped once per step to wake the workers.
    epoch: AtomicU64,
    shutdown: AtomicBool,
    /// Workers asleep on `work`; the caller only pays for a notify when one is.
    sleepers: AtomicUsize,
    caller_asleep: AtomicBool,
    lock: Mutex<()>,
    work: Condvar,
    finished: Condvar,
    /// The current step's actions are float32 (`actions_f32`), stepped with `Env::step_f32`.
    action_f32: AtomicBool,
    /// Set by an interrupted step: envs claimed after it are skipped (counted, not run).
    cancel: AtomicBool,
    /// Test hook: a nonzero seed delays each env by a pseudo-random few µs, shuffling completion.
    pub(super) jitter: AtomicU64,
    /// The first env error or panic of the step, by env index (both are internal bugs after the
    /// caller's checks; kept so they surface on the caller, not on a worker).
    failure: Mutex<Option<(usize, Failure)>>,
}

/// Why an env's step failed: an error, or a panic caught on the thread that ran it.
enum Failure {
    Error(EnvError),
    Panic(Box<dyn Any + Send>),
}

impl Shared {
    /// The pool's state for `n` envs, before the batch buffers are bound (`start_pool`): no step
    /// running, every env claimed.
    pub(super) fn new(n: usize, (od, ad, gd): (usize, usize, usize), mode: Autoreset) -> Shared {
        Shared {
            job: Job {
                envs: std::ptr::null_mut(),
                actions: AtomicPtr::new(std::ptr::null_mut()),
                actions_f32: AtomicPtr::new(std::ptr::null_mut()),
                obs: std::ptr::null_mut(),
                rewards: std::ptr::null_mut(),
                terminated: std::ptr::null_mut(),
                truncated: std::ptr::null_mut(),
                final_obs: std::ptr::null_mut(),
                achieved: std::ptr::null_mut(),
                desired: std::ptr::null_mut(),
                final_achieved: std::ptr::null_mut(),
                final_desired: std::ptr::null_mut(),
                has_final: std::ptr::null_mut(),
                pending: std::ptr::null_mut(),
                n,
                obs_dim: od,
                act_dim: ad,
                goal_dim: gd,
                mode,
            },
            next: AtomicUsize::new(n),
            done: AtomicUsize::new(0),
            epoch: AtomicU64::new(0),
            shutdown: AtomicBool::new(false),
            sleepers: AtomicUsize::new(0),
            caller_asleep: AtomicBool::new(false),
            lock: Mutex::new(()),
            work: Condvar::new(),
            finished: Condvar::new(),
            action_f32: AtomicBool::new(false),
            cancel: AtomicBool::new(false),
            jitter: AtomicU64::new(0),
            failure: Mutex::new(None),
        }
    }

    /// Claim and run envs until none is left in this step. The caller passes `poll`, asked
    /// about every [`POLL`] between envs; when it says stop, the remaining envs are skipped.
    fn work(&self, mut poll: Option<&mut dyn FnMut() -> bool>) {
        let n = self.job.n;
        let mut asked = Instant::now();
        loop {
            let i = self.next.fetch_add(1, AcqRel);
            if i >= n {
                return;
            }
            if let Some(p) = poll.as_mut()
                && asked.elapsed() >= POLL
            {
                asked = Instant::now();
                if p() {
                    self.cancel.store(true, SeqCst);
                }
            }
            if self.cancel.load(Acquire) {
                self.finish_one(n);
                continue;
            }
            let jitter = self.jitter.load(Relaxed);
            if jitter != 0 {
                let h = splitmix(jitter ^ self.epoch.load(Relaxed) << 20 ^ i as u64);
                std::thread::sleep(Duration::from_micros(h % 300));
            }
            // SAFETY: index i was claimed by this thread alone for this step.
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| unsafe {
                run_one(&self.job, i, self.action_f32.load(Relaxed))
            }));
            let failure = match r {
                Ok(Ok(())) => None,
                Ok(Err(e)) => Some(Failure::Error(e)),
                Err(p) => Some(Failure::Panic(p)),
            };
            if let Some(f) = failure
                && let Ok(mut slot) = self.failure.lock()
                && slot.as_ref().is_none_or(|(j, _)| i < *j)
            {
                *slot = Some((i, f));
            }
            self.finish_one(n);
        }
    }

    /// Count one env of the step as finished, waking the caller after the last.
    fn finish_one(&self, n: usize) {
        if self.done.fetch_add(1, SeqCst) + 1 == n && self.caller_asleep.load(SeqCst) {
            let _g = self.lock.lock();
            self.finished.notify_one();
        }
    }

    fn worker_loop(&self) {
        let mut seen = 0;
        loop {
            let start = Instant::now();
            let mut spins = 0u32;
            while self.epoch.load(Acquire) == seen && !self.shutdown.load(Acquire) {
                std::hint::spin_loop();
                spins += 1;
                if spins.is_multiple_of(64) && start.elapsed() > SPIN {
                    let Ok(mut g) = self.lock.lock() else { return };
                    self.sleepers.fetch_add(1, SeqCst);
                    while self.epoch.load(SeqCst) == seen && !self.shutdown.load(SeqCst) {
                        g = match self.work.wait(g) {
                            Ok(g) => g,
                            Err(_) => return,
                        };
                    }
                    self.sleepers.fetch_sub(1, SeqCst);
                    break;
                }
            }
            if self.shutdown.load(Acquire) {
                return;
            }
            seen = self.epoch.load(Acquire);
            self.work(None);
        }
    }
}

// The pool moves envs across threads.
const _: () = {
    const fn send<T: Send>() {}
    send::<Env>();
};

/// The pool's lock guards no data, so a poisoned one is as good as any.
fn relock(lock: &Mutex<()>) -> MutexGuard<'_, ()> {
    lock.lock().unwrap_or_else(PoisonError::into_inner)
}

/// SplitMix64's mixer: the test hook's pseudo-random delays.
pub(super) fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Step (or autoreset) env i and write its slots of the batch buffers.
///
/// # Safety
/// `i < job.n`, claimed by the calling thread alone, and the buffers are live.
unsafe fn run_one(job: &Job, i: usize, f32_actions: bool) -> Result<(), EnvError> {
    let ad = job.act_dim;
    // SAFETY (all below): disjoint per-env slots of buffers sized n, n×obs_dim or n×act_dim.
    // SAFETY: env i was claimed by this thread alone (`run_one`'s contract); `envs` holds n envs.
    let env = unsafe { &mut *job.envs.add(i) };
    // SAFETY: as above; `pending` holds n flags.
    let pending = unsafe { &mut *job.pending.add(i) };
    // SAFETY: as above; the reward and flag buffers hold n entries.
    let (reward, terminated, truncated) = unsafe {
        (
            &mut *job.rewards.add(i),
            &mut *job.terminated.add(i),
            &mut *job.truncated.add(i),
        )
    };
    if job.mode == Autoreset::NextStep && *pending {
        env.reset(None);
        // SAFETY: env i is this thread's (`run_one`'s contract).
        unsafe { job.observe(i, env, false) };
        *reward = 0.0;
        *terminated = false;
        *truncated = false;
        *pending = false;
        return Ok(());
    }
    // The batch was published before `next` was reset for this step (`VecEnv::run`), and the
    // claim of index i read that reset.
    let action = if f32_actions {
        let a = job.actions_f32.load(Relaxed);
        // SAFETY: as above; the borrowed batch holds n × act_dim numbers and outlives the step.
        JointAction::F32(unsafe { std::slice::from_raw_parts(a.add(i * ad), ad) })
    } else {
        let a = job.actions.load(Relaxed);
        // SAFETY: as above.
        JointAction::F64(unsafe { std::slice::from_raw_parts(a.add(i * ad), ad) })
    };
    let s = env.step_joint(action)?;
    *reward = s.reward;
    *terminated = s.terminated;
    *truncated = s.truncated;
    let ended = s.terminated || s.truncated;
    match job.mode {
        Autoreset::NextStep => {
            // SAFETY: as above.
            unsafe { job.observe(i, env, false) };
            *pending = ended;
        }
        Autoreset::SameStep => {
            // SAFETY: as above; `has_final` holds n flags.
            let has_final = unsafe { &mut *job.has_final.add(i) };
            *has_final = ended;
            if ended {
                // SAFETY: as above.
                unsafe { job.observe(i, env, true) };
                env.reset(None);
            }
            // SAFETY: as above.
            unsafe { job.observe(i, env, false) };
        }
    }
    Ok(())
}
impl VecEnv {
    /// Point the pool at the batch buffers and start its `threads − 1` workers (the caller is the
    /// other thread).
    pub(super) fn start_pool(
        &mut self,
        threads: usize,
        spec: &ResolvedSpec,
    ) -> Result<(), EnvError> {
        let n = self.shared.job.n;
        // The Arc was just created and no worker holds it yet.
        let job = &mut Arc::get_mut(&mut self.shared).expect("unshared").job;
        job.envs = self.envs.as_mut_ptr();
        job.obs = self.obs.as_mut_ptr();
        job.rewards = self.rewards.as_mut_ptr();
        job.terminated = self.terminated.as_mut_ptr();
        job.truncated = self.truncated.as_mut_ptr();
        job.final_obs = self.final_obs.as_mut_ptr();
        job.achieved = self.goals.achieved.as_mut_ptr();
        job.desired = self.goals.desired.as_mut_ptr();
        job.final_achieved = self.goals.final_achieved.as_mut_ptr();
        job.final_desired = self.goals.final_desired.as_mut_ptr();
        job.has_final = self.has_final.as_mut_ptr();
        job.pending = self.pending.as_mut_ptr();
        for k in 1..threads.clamp(1, n.max(1)) {
            let shared = Arc::clone(&self.shared);
            let w = std::thread::Builder::new()
                .name(format!("envc-vec-{k}"))
                .spawn(move || shared.worker_loop())
                .map_err(|e| EnvError::Compile {
                    path: spec.model_path.clone(),
                    message: format!("cannot start a vector env worker thread: {e}"),
                })?;
            self.workers.push(w);
        }
        Ok(())
    }

    /// Run one step of every env over `actions` (checked), borrowed until every env is done;
    /// `meanwhile` runs on the caller once the workers are woken, before it claims envs.
    pub(super) fn run(
        &mut self,
        actions: JointAction<'_>,
        mut poll: Option<&mut dyn FnMut() -> bool>,
        meanwhile: &mut dyn FnMut(),
    ) -> Result<Stepped, EnvError> {
        let s = &*self.shared;
        // Published by the `next` store below; the threads only read through these pointers.
        match actions {
            JointAction::F64(a) => s.job.actions.store(a.as_ptr().cast_mut(), SeqCst),
            JointAction::F32(a) => s.job.actions_f32.store(a.as_ptr().cast_mut(), SeqCst),
        }
        s.action_f32
            .store(matches!(actions, JointAction::F32(_)), SeqCst);
        s.cancel.store(false, SeqCst);
        s.done.store(0, SeqCst);
        s.next.store(0, SeqCst);
        if !self.workers.is_empty() {
            s.epoch.fetch_add(1, SeqCst);
            if s.sleepers.load(SeqCst) > 0 {
                let _g = s.lock.lock();
                s.work.notify_all();
            }
        }
        // The workers read the borrowed batch until every env is done: a panic here waits
        // for them before it goes on.
        let early = std::panic::catch_unwind(std::panic::AssertUnwindSafe(meanwhile)).err();
        s.work(poll.as_mut().map(|p| &mut **p as &mut dyn FnMut() -> bool));
        self.wait_done(poll);
        // Every env is done (or skipped): nothing reads the borrowed batch any more.
        s.job.actions.store(std::ptr::null_mut(), SeqCst);
        s.job.actions_f32.store(std::ptr::null_mut(), SeqCst);
        if let Some(p) = early {
            std::panic::resume_unwind(p);
        }
        let failure = s.failure.lock().ok().and_then(|mut f| f.take());
        match failure {
            None if s.cancel.load(SeqCst) => Ok(Stepped::Interrupted),
            None => Ok(Stepped::Done),
            Some((_, Failure::Error(e))) => Err(e),
            Some((_, Failure::Panic(p))) => std::panic::resume_unwind(p),
        }
    }

    /// Wait for the workers' last envs; `poll` is asked every [`POLL`] meanwhile (a stop skips
    /// the envs nobody has claimed yet; the ones running finish). Returns only once every env
    /// is done: the threads read the caller's borrowed action batch until then.
    fn wait_done(&self, mut poll: Option<&mut dyn FnMut() -> bool>) {
        let s = &*self.shared;
        let n = s.job.n;
        let start = Instant::now();
        let mut spins = 0u32;
        while s.done.load(Acquire) < n {
            std::hint::spin_loop();
            spins += 1;
            if spins.is_multiple_of(64) && start.elapsed() > SPIN {
                let mut g = relock(&s.lock);
                s.caller_asleep.store(true, SeqCst);
                while s.done.load(SeqCst) < n {
                    let Some(p) = poll.as_mut() else {
                        g = s.finished.wait(g).unwrap_or_else(PoisonError::into_inner);
                        continue;
                    };
                    let (g2, t) = s
                        .finished
                        .wait_timeout(g, POLL)
                        .unwrap_or_else(PoisonError::into_inner);
                    g = g2;
                    if t.timed_out() && s.done.load(SeqCst) < n {
                        // Asked without the lock: a worker finishing meanwhile must not wait on
                        // the caller's check (which takes Python's GIL in the binding).
                        drop(g);
                        if p() {
                            s.cancel.store(true, SeqCst);
                        }
                        g = relock(&s.lock);
                    }
                }
                s.caller_asleep.store(false, SeqCst);
                return;
            }
        }
    }
}

impl Drop for VecEnv {
    fn drop(&mut self) {
        if std::process::id() != self.pid {
            // A forked child (multiprocessing) inherits the handles but not the threads: there
            // is nothing to join. The parent's copy stops them.
            std::mem::forget(std::mem::take(&mut self.workers));
            return;
        }
        let s = &*self.shared;
        s.shutdown.store(true, SeqCst);
        {
            let _g = s.lock.lock();
            s.work.notify_all();
        }
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}
