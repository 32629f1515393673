//! Vectorized envs: N envs of one spec sharing one compiled model, stepped in parallel by a
//! persistent pool, with Gymnasium 1.x `SyncVectorEnv` semantics.
//!
//! * `reset(Some(s))` seeds env i with `s + i`; `reset(None)` leaves each env's stream going.
//! * Autoreset [`Autoreset::NextStep`] (Gymnasium's default): the step after an env ended resets it
//!   (no seed) instead of stepping it, with reward 0 and both flags false. [`Autoreset::SameStep`]:
//!   the ending step resets at once; the batch holds the reset obs, the ending obs goes to
//!   [`VecEnv::final_obs`] and its info stays readable through [`VecEnv::final_info`].
//! * Observations, rewards, terminated and truncated live in contiguous batch buffers
//!   (env-major) that the caller reads in place.
//! * [`VecEnv::step_f32`] steps a float32 action batch as a float32 policy steps the reference
//!   (each env through `Env::step_f32`).
//!
//! `threads = M` means M threads run envs: the caller plus M − 1 pool workers that live as long
//! as the `VecEnv`. The caller works too, so a step costs one wake-up hand-off, not two. Envs are
//! claimed one at a time from a shared counter (load balancing: episodes end and reset at
//! different times), and every env writes only its own slots, so the results do not depend on M
//! or on which thread ran which env.

use std::any::Any;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use envspec::{Override, ResolvedSpec};

use crate::env::{Env, Info, compile};
use crate::error::EnvError;
use crate::joint_env::{JointAction, JointEnv};

/// When an ended env is reset (Gymnasium's `AutoresetMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Autoreset {
    /// On the next `step` call (Gymnasium 1.x's default).
    #[default]
    NextStep,
    /// In the ending step itself; the ending observation goes to `final_obs`.
    SameStep,
}

/// How long an idle thread spins before sleeping: a futex wake-up costs 25–35 µs on the
/// development VM, more than a whole cheap env step.
const SPIN: Duration = Duration::from_micros(50);

/// Observation rows per env a caller may hold beyond the vector's own two (see `VecEnv::per_env`):
/// the Python binding returns fresh arrays (the last two alive at once, and the next step's made
/// ahead while the workers step), and Gymnasium's batched observation space holds low and high
/// bounds and two masks over the whole batch.
const CALLER_OBS_ROWS: usize = 6;

/// Address space a worker thread maps (its stack, guard page and thread-local data).
const THREAD_MAPPED_BYTES: u64 = 8 << 20;

/// How often an interruptible step ([`VecEnv::step_interruptible`]) asks whether to stop: often
/// enough that Ctrl-C lands well within a second, rarely enough to cost nothing measurable.
const POLL: Duration = Duration::from_millis(50);

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

/// Raw views of the env array and batch buffers. Fixed at construction (the buffers are never
/// resized, so the pointers stay valid while the `VecEnv` lives, however it moves), but for the
/// action batch: the caller's own rows, borrowed for one step (no copy), null between steps.
struct Job {
    envs: *mut Env,
    actions: AtomicPtr<f64>,
    /// The float32 rows of [`VecEnv::step_f32`] (the same layout as `actions`).
    actions_f32: AtomicPtr<f32>,
    obs: *mut f64,
    rewards: *mut f64,
    terminated: *mut bool,
    truncated: *mut bool,
    final_obs: *mut f64,
    has_final: *mut bool,
    /// Env i ended in the previous step (NextStep resets it now).
    pending: *mut bool,
    n: usize,
    obs_dim: usize,
    act_dim: usize,
    mode: Autoreset,
}

// SAFETY: a Job is only dereferenced for env indices claimed from `Shared::next`, each claimed by
// exactly one thread per step, and the caller touches the buffers only while no step runs.
unsafe impl Send for Job {}
// SAFETY: as for `Send`.
unsafe impl Sync for Job {}

struct Shared {
    job: Job,
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
    jitter: AtomicU64,
    /// The first env error or panic of the step, by env index (both are internal bugs after the
    /// caller's checks; kept so they surface on the caller, not on a worker).
    failure: Mutex<Option<(usize, Failure)>>,
}

enum Failure {
    Error(EnvError),
    Panic(Box<dyn Any + Send>),
}

impl Shared {
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

fn splitmix(mut x: u64) -> u64 {
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
    let (od, ad) = (job.obs_dim, job.act_dim);
    // SAFETY (all below): disjoint per-env slots of buffers sized n, n×obs_dim or n×act_dim.
    // SAFETY: env i was claimed by this thread alone (`run_one`'s contract); `envs` holds n envs.
    let env = unsafe { &mut *job.envs.add(i) };
    // SAFETY: as above; `obs` holds n × obs_dim numbers.
    let obs = unsafe { std::slice::from_raw_parts_mut(job.obs.add(i * od), od) };
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
        obs.copy_from_slice(env.reset(None).0);
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
            obs.copy_from_slice(env.obs());
            *pending = ended;
        }
        Autoreset::SameStep => {
            // SAFETY: as above; `has_final` holds n flags.
            let has_final = unsafe { &mut *job.has_final.add(i) };
            *has_final = ended;
            if ended {
                // SAFETY: as above; `final_obs` holds n × obs_dim numbers.
                unsafe { std::slice::from_raw_parts_mut(job.final_obs.add(i * od), od) }
                    .copy_from_slice(env.obs());
                obs.copy_from_slice(env.reset(None).0);
            } else {
                obs.copy_from_slice(env.obs());
            }
        }
    }
    Ok(())
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
    has_final: Vec<bool>,
    pending: Vec<bool>,
    has_reset: bool,
    /// What each env costs in memory, as checked at construction.
    per_env: crate::env::Footprint,
    /// The process that started the workers (a forked child has none to join).
    pid: u32,
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
        match crate::open(id_or_path, overrides)? {
            crate::AnyEnv::Task(first) => VecEnv::from_env(first, num_envs, threads, mode),
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

    /// E1403: more envs than envc's limit.
    fn check_count(spec: &ResolvedSpec, num_envs: usize) -> Result<(), EnvError> {
        if num_envs > envspec::limits::MAX_VEC_ENVS {
            return Err(EnvError::TooLarge {
                env: spec.id.clone(),
                what: format!(
                    "{num_envs} envs are beyond envc's limit of {} per vector env",
                    envspec::limits::MAX_VEC_ENVS
                ),
            });
        }
        Ok(())
    }

    /// What each env costs: its own footprint and its rows of the batch buffers (observations
    /// twice here, and [`CALLER_OBS_ROWS`] times more for a caller that copies the batch out).
    fn per_env(first: &Env) -> crate::env::Footprint {
        let spec = first.spec();
        let rows = ((2 + CALLER_OBS_ROWS) * spec.obs_dim * 8 + spec.act_dim() * 12 + 64) as u64;
        let f = first.footprint();
        crate::env::Footprint {
            resident: f.resident.saturating_add(rows),
            mapped: f.mapped.saturating_add(rows),
        }
    }

    /// E1403: `num_envs` envs of `per_env` each do not fit in the memory left, or in the
    /// address space `ulimit -v` leaves.
    fn check_memory(
        id: &str,
        num_envs: usize,
        threads: usize,
        per_env: crate::env::Footprint,
    ) -> Result<(), EnvError> {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        let budget = crate::memory::budget();
        let n = num_envs as u64;
        let resident = per_env.resident.saturating_mul(n);
        // Each worker thread maps its stack.
        let mapped = per_env
            .mapped
            .saturating_mul(n)
            .saturating_add(threads.min(num_envs) as u64 * THREAD_MAPPED_BYTES);
        let refuse = |need: u64, each: u64, free: u64, what: &str| EnvError::TooLarge {
            env: id.to_string(),
            what: format!(
                "{num_envs} envs need about {:.1} GiB of {what} ({:.2} MiB each), and {:.1} GiB is available; use fewer envs",
                gib(need),
                mib(each),
                gib(free)
            ),
        };
        if let Some(free) = budget.memory
            && resident > free
        {
            return Err(refuse(resident, per_env.resident, free, "memory"));
        }
        if let Some(free) = budget.address_space
            && mapped > free
        {
            return Err(refuse(
                mapped,
                per_env.mapped,
                free,
                "address space under this process's limit (ulimit -v or the kernel's commit limit)",
            ));
        }
        if let Some(cap) = budget.mapped_cap
            && mapped > cap
        {
            return Err(refuse(
                mapped,
                per_env.mapped,
                cap,
                "address space, mostly MuJoCo arenas (at most 8 times the machine's memory and swap may be mapped)",
            ));
        }
        Ok(())
    }

    /// What each env of this vector costs in memory, as [`VecEnv::make`] checked it before
    /// making them (resident and mapped bytes).
    pub fn footprint_per_env(&self) -> crate::env::Footprint {
        self.per_env
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
        if spec.manipulation.goal.is_some() {
            // The batch buffers are flat observations; a goal task's are dicts.
            return Err(EnvError::Spec(
                envspec::Diagnostic::new(
                    envspec::Code::E0602,
                    format!(
                        "`{}` is a goal-conditioned task ([goal]): envc's vector envs do not batch dict observations yet; use gymnasium.vector.SyncVectorEnv over envc.make",
                        spec.id
                    ),
                )
                .into(),
            ));
        }
        VecEnv::check_count(&spec, num_envs)?;
        // Refuse before allocating them all rather than fail (or be killed) part-way.
        let per_env = VecEnv::per_env(&first);
        VecEnv::check_memory(&spec.id, num_envs, threads, per_env)?;
        let envs = std::iter::once(Ok(first))
            .chain((1..num_envs).map(|_| Env::with_model(Arc::clone(&spec), Arc::clone(&model))))
            .collect::<Result<Vec<Env>, _>>()?;
        let (n, od, ad) = (num_envs, spec.obs_dim, spec.act_dim());
        let mut v = VecEnv {
            shared: Arc::new(Shared {
                job: Job {
                    envs: std::ptr::null_mut(),
                    actions: AtomicPtr::new(std::ptr::null_mut()),
                    actions_f32: AtomicPtr::new(std::ptr::null_mut()),
                    obs: std::ptr::null_mut(),
                    rewards: std::ptr::null_mut(),
                    terminated: std::ptr::null_mut(),
                    truncated: std::ptr::null_mut(),
                    final_obs: std::ptr::null_mut(),
                    has_final: std::ptr::null_mut(),
                    pending: std::ptr::null_mut(),
                    n,
                    obs_dim: od,
                    act_dim: ad,
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
            }),
            workers: vec![],
            envs,
            obs: vec![0.0; n * od],
            rewards: vec![0.0; n],
            terminated: vec![false; n],
            truncated: vec![false; n],
            final_obs: vec![0.0; n * od],
            has_final: vec![false; n],
            pending: vec![false; n],
            has_reset: false,
            per_env,
            pid: std::process::id(),
        };
        // The Arc was just created and no worker holds it yet.
        let job = &mut Arc::get_mut(&mut v.shared).expect("unshared").job;
        job.envs = v.envs.as_mut_ptr();
        job.obs = v.obs.as_mut_ptr();
        job.rewards = v.rewards.as_mut_ptr();
        job.terminated = v.terminated.as_mut_ptr();
        job.truncated = v.truncated.as_mut_ptr();
        job.final_obs = v.final_obs.as_mut_ptr();
        job.has_final = v.has_final.as_mut_ptr();
        job.pending = v.pending.as_mut_ptr();
        for k in 1..threads.clamp(1, n.max(1)) {
            let shared = Arc::clone(&v.shared);
            let w = std::thread::Builder::new()
                .name(format!("envc-vec-{k}"))
                .spawn(move || shared.worker_loop())
                .map_err(|e| EnvError::Compile {
                    path: spec.model_path.clone(),
                    message: format!("cannot start a vector env worker thread: {e}"),
                })?;
            v.workers.push(w);
        }
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
        let od = job.obs_dim;
        for (i, seed) in seeds.into_iter().take(job.n).enumerate() {
            // SAFETY: no step is running; i < n; slots sized as in `run_one`.
            unsafe {
                let (obs, _) = (*job.envs.add(i)).reset(seed);
                std::ptr::copy_nonoverlapping(obs.as_ptr(), job.obs.add(i * od), od);
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
        let od = job.obs_dim;
        let masked = seeds.into_iter().take(job.n).enumerate().zip(mask);
        for ((i, seed), _) in masked.filter(|(_, m)| **m) {
            // SAFETY: no step is running; i < n; slots sized as in `run_one`.
            unsafe {
                let (obs, _) = (*job.envs.add(i)).reset(seed);
                std::ptr::copy_nonoverlapping(obs.as_ptr(), job.obs.add(i * od), od);
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

    /// Run one step of every env over `actions` (checked), borrowed until every env is done;
    /// `meanwhile` runs on the caller once the workers are woken, before it claims envs.
    fn run(
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

#[cfg(test)]
mod tests {
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
