//! Throughput against the physics ceiling (`envc bench`).
//!
//! Four measurements per env, interleaved in rounds (the order rotates every round, so slow
//! phases of a shared machine hit all of them alike); medians are reported:
//! * **ceiling**: a raw `MjData` of the same compiled model, `frame_skip × mj_step` per env step
//!   (+ `mj_rnePostConstraint` when the spec reads contact forces), same actions, reset at the
//!   env's observed mean episode length. Where the env's action is not its controls (`[actions]`,
//!   `[end_effector]`), the raw loop replays the controls and mocap poses the env applied over
//!   the same actions, and sets the `[hold.*]` joints with the `mj_forward` after them, so both
//!   run the MuJoCo work the reference's step does;
//! * **single**: one [`Env`](crate::Env) stepped with the same actions, autoreset on termination/truncation;
//! * **vector**: a [`VecEnv`] of `envs` envs on `threads` threads (autoreset slots not counted);
//! * **parallel ceiling**: `threads` raw loops at once, wall time: the multi-core ceiling as the
//!   machine's current load allows, so the vector overhead can be told apart from that load.
//!
//! Single-thread rates use the thread's CPU time (preemption by other processes is not billed);
//! the vector rate uses wall time, as a caller experiences it. Ratios are the medians of the
//! per-round ratios (paired measurements), the vector ratio against `threads × ceiling`.

use std::sync::Arc;
use std::time::{Duration, Instant};

use envspec::{Override, ResolvedSpec};

use mujoco_rs::prelude::{MjData, MjModel};

use crate::error::EnvError;
use crate::rng::NumpyRng;
use crate::vector::{Autoreset, VecEnv};
use crate::{AnyEnv, JointAction, JointEnv};

/// What `envc bench` measures and for how long.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Envs in the vectorized measurement.
    pub envs: usize,
    /// Threads of the vectorized measurement.
    pub threads: usize,
    /// Total measuring time per env (all rounds and all four measurements).
    pub seconds: f64,
    /// Interleaved rounds; more rounds give steadier medians.
    pub rounds: usize,
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            envs: 8,
            threads: 2,
            seconds: 6.0,
            rounds: 5,
        }
    }
}

/// One env's rates and ratios, as `envc bench` reports them.
#[derive(Clone, Debug)]
pub struct BenchResult {
    /// The env's id.
    pub id: String,
    /// MuJoCo steps per env step.
    pub frame_skip: usize,
    /// Whether each step also runs `mj_rnePostConstraint` (the spec reads contact forces).
    pub rne_post_constraint: bool,
    /// Envs in the vector env.
    pub envs: usize,
    /// Threads of the vector env.
    pub threads: usize,
    /// Interleaved rounds measured.
    pub rounds: usize,
    /// The raw `MjData` loop's env steps per second; every rate is a median over rounds.
    pub ceiling: f64,
    /// One `Env`'s steps per second (thread CPU time).
    pub single: f64,
    /// The `VecEnv`'s steps per second (wall time).
    pub vector: f64,
    /// `threads` raw `MjData` loops run in parallel, wall time: what the machine gives right now
    /// (the 2-core ceiling as load from other processes allows).
    pub parallel_ceiling: f64,
    /// vector ÷ parallel_ceiling (median of per-round ratios).
    pub vector_parallel_ratio: f64,
    /// single ÷ ceiling (median of per-round ratios).
    pub single_ratio: f64,
    /// vector ÷ (threads × ceiling), likewise.
    pub vector_ratio: f64,
    /// Mean episode length seen by the single env (the ceiling resets at this period).
    pub episode_len: f64,
}

/// Actions drawn uniformly in the control range, reused cyclically (drawing is not timed).
#[derive(Clone)]
struct Actions {
    data: Vec<f64>,
    act_dim: usize,
    rows: usize,
}

impl Actions {
    fn new(model: &MjModel, rows: usize) -> Actions {
        let nu = model.ffi().nu as usize;
        let range = model.actuator_ctrlrange().as_flattened();
        let mut rng = NumpyRng::from_seed(0);
        let data = (0..rows * nu)
            .map(|k| rng.uniform(range[2 * (k % nu)], range[2 * (k % nu) + 1]))
            .collect();
        Actions {
            data,
            act_dim: nu,
            rows,
        }
    }
    /// Uniform draws in an action space of another length than the controls (an end-effector
    /// action).
    fn in_space(space: &crate::env::BoxSpace, rows: usize) -> Actions {
        let n = space.dim();
        let mut rng = NumpyRng::from_seed(0);
        let data = (0..rows * n)
            .map(|k| rng.uniform(space.low[k % n], space.high[k % n]))
            .collect();
        Actions {
            data,
            act_dim: n,
            rows,
        }
    }
    /// The controls (and mocap poses) an env whose action is not its controls applied over `rows`
    /// steps of `actions` from its seed-0 reset, resetting where it ends an episode: what the
    /// raw loops replay, so the ceiling is the physics the env runs (random controls would
    /// leave a welded arm still, or throw a PD robot about).
    fn replayed(env: &mut AnyEnv, actions: &Actions, rows: usize) -> Result<Actions, EnvError> {
        use envspec::Field;
        env.try_reset(Some(0))?;
        let width = |e: &AnyEnv| {
            let p = e.physics_env();
            p.field(Field::Ctrl).len()
                + p.field(Field::MocapPos).len()
                + p.field(Field::MocapQuat).len()
        };
        let act_dim = width(env);
        let mut data = Vec::with_capacity(rows * act_dim);
        for r in 0..rows {
            let done = match env.step_joint(JointAction::F64(actions.rows(r, 1))) {
                Ok(s) => s.terminated || s.truncated,
                Err(_) => true,
            };
            let p = env.physics_env();
            for f in [Field::Ctrl, Field::MocapPos, Field::MocapQuat] {
                data.extend_from_slice(p.field(f));
            }
            if done {
                env.try_reset(None)?;
            }
        }
        Ok(Actions {
            data,
            act_dim,
            rows,
        })
    }
    /// `count` consecutive rows starting at row `i` (wrapping is avoided by the row count).
    fn rows(&self, i: usize, count: usize) -> &[f64] {
        let start = (i % (self.rows - count + 1)) * self.act_dim;
        &self.data[start..start + count * self.act_dim]
    }
}

/// CPU time of the calling thread.
fn thread_cpu() -> Duration {
    crate::os::thread_cpu()
}

/// Run `chunk` until `slice` of the clock has passed; returns units of work per second.
fn rate(slice: Duration, clock: fn() -> Duration, mut chunk: impl FnMut() -> u64) -> f64 {
    let start = clock();
    let mut work = 0;
    loop {
        work += chunk();
        let t = clock() - start;
        if t >= slice {
            return work as f64 / t.as_secs_f64();
        }
    }
}

fn wall() -> Duration {
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    START.get_or_init(Instant::now).elapsed()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => (v[n / 2 - 1] + v[n / 2]) / 2.0,
    }
}

/// Env steps between two clock reads.
const CHUNK: usize = 16;

/// The env's first reset state, from which the raw loops restart: `mj_resetData` alone would put a
/// maze's robot at the world origin (often inside a wall), not in a reset cell.
struct StartState {
    qpos: Vec<f64>,
    qvel: Vec<f64>,
}

/// Put `raw` back at the start state (`mj_forward` after).
fn restart(raw: &mut MjData<Arc<MjModel>>, s: &StartState) -> Result<(), String> {
    raw.reset();
    // The lengths of the env's state of the same model.
    raw.qpos_mut().copy_from_slice(&s.qpos);
    raw.qvel_mut().copy_from_slice(&s.qvel);
    crate::mj::call(raw, crate::mj::Call::Forward)
}

/// What one raw env step runs: `fs × mj_step`, `mj_rnePostConstraint` with `rne`, and the
/// `[hold.*]` joints set after the physics with the `mj_forward` the reference calls then.
#[derive(Clone, Debug)]
struct RawStep {
    fs: u32,
    rne: bool,
    /// Per `[hold.*]` table: its qpos addresses and value.
    holds: Vec<(Vec<usize>, f64)>,
}

/// One env step of raw physics on `raw` with `action`; MuJoCo's errors returned (the data is then
/// reset by the next `restart`).
fn raw_step(raw: &mut MjData<Arc<MjModel>>, action: &[f64], how: &RawStep) -> Result<(), String> {
    // A replayed row: the controls, then the mocap positions and quaternions.
    let nu = raw.ctrl().len();
    raw.ctrl_mut().copy_from_slice(&action[..nu]);
    if action.len() > nu {
        let (pos, quat, _, _) = crate::mj::manip::mocap_mut(raw);
        let np = pos.len();
        pos.copy_from_slice(&action[nu..nu + np]);
        quat.copy_from_slice(&action[nu + np..]);
    }
    let (n, rne) = (how.fs, how.rne);
    crate::mj::call(raw, crate::mj::Call::Step { n, rne })?;
    if how.holds.is_empty() {
        return Ok(());
    }
    let qpos = raw.qpos_mut();
    for (adr, value) in &how.holds {
        for &a in adr {
            qpos[a] = *value;
        }
    }
    crate::mj::call(raw, crate::mj::Call::Forward)
}

/// `threads` raw loops (`frame_skip × mj_step` + post-step kernel) in parallel for `slice` of
/// wall time; env steps per second summed over threads.
#[allow(clippy::too_many_arguments)]
fn parallel_ceiling(
    model: &Arc<MjModel>,
    actions: &Actions,
    threads: usize,
    slice: Duration,
    how: &RawStep,
    ep_len: u64,
    start_state: &StartState,
) -> Result<f64, String> {
    let start = Instant::now();
    let steps: u64 = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    let Ok(mut raw) = MjData::try_new(Arc::clone(model)) else {
                        return Ok(0);
                    };
                    let mut n = 0u64;
                    while start.elapsed() < slice {
                        for _ in 0..CHUNK {
                            if n.is_multiple_of(ep_len) {
                                restart(&mut raw, start_state)?;
                            }
                            let a = actions.rows(t * 997 + n as usize, 1);
                            raw_step(&mut raw, a, how)?;
                            n += 1;
                        }
                    }
                    Ok(n)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or(Ok(0)))
            .sum::<Result<u64, String>>()
    })?;
    Ok(steps as f64 / start.elapsed().as_secs_f64())
}

/// Benchmark one env (bundled id or spec path).
pub fn bench(
    id_or_path: &str,
    overrides: &[Override],
    cfg: &BenchConfig,
) -> Result<BenchResult, EnvError> {
    let mut b = Bench::new(id_or_path, overrides, cfg)?;
    let rounds = cfg.rounds.max(1);
    let slice = Duration::from_secs_f64((cfg.seconds / (4 * rounds) as f64).max(0.01));
    let (mut c, mut s, mut v, mut sr, mut vr) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut p, mut pr) = (vec![], vec![]);
    let threads = b.threads;

    // Round 0 is a warm-up (caches, page faults, first episode lengths) and is not reported.
    for round in 0..=rounds {
        let slice = if round == 0 { slice / 4 } else { slice };
        let mut got = [0.0; 4];
        for k in 0..4 {
            let which = (k + round) % 4;
            got[which] = b.measure(which, slice);
        }
        b.take_error()?;
        if round > 0 {
            c.push(got[0]);
            s.push(got[1]);
            v.push(got[2]);
            p.push(got[3]);
            pr.push(got[2] / got[3]);
            sr.push(got[1] / got[0]);
            vr.push(got[2] / (threads as f64 * got[0]));
        }
    }
    Ok(BenchResult {
        id: b.id,
        frame_skip: b.how.fs as usize,
        rne_post_constraint: b.how.rne,
        envs: b.envs,
        threads,
        rounds,
        ceiling: median(c),
        single: median(s),
        vector: median(v),
        parallel_ceiling: median(p),
        vector_parallel_ratio: median(pr),
        single_ratio: median(sr),
        vector_ratio: median(vr),
        episode_len: if b.episodes > 0 {
            b.steps as f64 / b.episodes as f64
        } else {
            f64::NAN
        },
    })
}

/// One benchmark's env, raw data and the counters its four measurements share.
struct Bench {
    id: String,
    spec: Arc<ResolvedSpec>,
    model: Arc<MjModel>,
    env: crate::AnyEnv,
    /// The vector env (None where vector envs do not run the spec's kind).
    vec: Option<VecEnv>,
    raw: MjData<Arc<MjModel>>,
    start_state: StartState,
    /// Actions in the control range, for the raw loops.
    actions: Actions,
    /// The env's own actions (an end effector's, where they are not the controls).
    env_actions: Actions,
    envs: usize,
    threads: usize,
    /// What the raw loops run per env step.
    how: RawStep,
    /// The action row, shared so every measurement sees the same stream.
    cursor: usize,
    /// Steps and episodes of the single env: the raw loops reset at its mean episode length.
    steps: u64,
    episodes: u64,
    raw_since_reset: u64,
    /// A MuJoCo error in the raw loops (the env's own come back from `step`).
    mujoco_error: Option<String>,
    env_error: Option<EnvError>,
}

impl Bench {
    /// Open the env (any kind: a maze steps its robot in the maze world, a multi-agent spec its
    /// factorized task, and the ceiling is that same model), its vector env where the kind has
    /// one, and the raw data; reset them all.
    fn new(id_or_path: &str, overrides: &[Override], cfg: &BenchConfig) -> Result<Bench, EnvError> {
        // Vector envs run tasks only; the others report NaN there.
        let mut env = crate::open(id_or_path, overrides)?;
        let spec: Arc<ResolvedSpec> = Arc::clone(env.physics_env().spec());
        let model = Arc::clone(env.physics_env().model());
        let envs = cfg.envs.max(1);
        let rows = 4096.max(envs * 4);
        let mut actions = Actions::new(&model, rows);
        // The env's own actions where they are not the controls (an end-effector action).
        let env_actions = if env.physics_env().act_dim() == model.ffi().nu as usize {
            actions.clone()
        } else {
            Actions::in_space(env.physics_env().action_space(), rows)
        };
        // Where the action is not the controls (PD targets, an end effector, a position delta),
        // the raw loops replay the controls the env applied.
        let manip = &spec.manipulation;
        if spec.actions.is_some()
            || manip.end_effector.is_some()
            || env_actions.act_dim != actions.act_dim
        {
            actions = Actions::replayed(&mut env, &env_actions, rows)?;
        }
        let mut vec = match env.kind() {
            crate::Kind::Task => Some(VecEnv::new(
                Arc::clone(&spec),
                envs,
                cfg.threads,
                Autoreset::NextStep,
            )?),
            _ => None,
        };
        let threads = vec.as_ref().map_or(cfg.threads.max(1), |v| v.threads());
        let id = env.id().to_string();
        let raw = MjData::try_new(Arc::clone(&model)).map_err(|e| EnvError::Compile {
            path: spec.model_path.clone(),
            message: format!("cannot allocate mjData: {e}"),
        })?;
        let how = RawStep {
            fs: spec.frame_skip,
            rne: spec.needs_rne_post_constraint,
            holds: (spec.manipulation.hold.iter())
                .map(|h| (h.qpos.clone(), h.value))
                .collect(),
        };
        env.try_reset(Some(0))?;
        let start_state = {
            let (qpos, qvel) = env.physics_env().state();
            StartState {
                qpos: qpos.to_vec(),
                qvel: qvel.to_vec(),
            }
        };
        if let Some(v) = &mut vec {
            v.reset(Some(0));
        }
        Ok(Bench {
            id,
            spec,
            model,
            env,
            vec,
            raw,
            start_state,
            actions,
            env_actions,
            envs,
            threads,
            how,
            cursor: 0,
            steps: 0,
            episodes: 0,
            raw_since_reset: 0,
            mujoco_error: None,
            env_error: None,
        })
    }

    /// One measurement for `slice`: 0 the ceiling, 1 the single env, 2 the vector env, 3 the
    /// parallel ceiling.
    fn measure(&mut self, which: usize, slice: Duration) -> f64 {
        match which {
            0 => self.ceiling(slice),
            1 => self.single(slice),
            3 => self.parallel(slice),
            _ => self.vector(slice),
        }
    }

    /// The episode length the raw loops reset at: the single env's mean so far.
    fn ep_len(&self) -> u64 {
        self.steps
            .checked_div(self.episodes)
            .unwrap_or(self.spec.max_episode_steps.unwrap_or(1000))
            .max(1)
    }

    /// The raw `MjData` loop, thread CPU time.
    fn ceiling(&mut self, slice: Duration) -> f64 {
        let ep_len = self.ep_len();
        rate(slice, thread_cpu, || {
            for _ in 0..CHUNK {
                let a = self.actions.rows(self.cursor, 1);
                self.cursor += 1;
                let mut stepped = Ok(());
                if self.raw_since_reset >= ep_len {
                    stepped = restart(&mut self.raw, &self.start_state);
                    self.raw_since_reset = 0;
                }
                if let Err(e) = stepped.and_then(|()| raw_step(&mut self.raw, a, &self.how)) {
                    self.mujoco_error.get_or_insert(e);
                    self.raw_since_reset = ep_len;
                }
                self.raw_since_reset += 1;
            }
            CHUNK as u64
        })
    }

    /// One env stepped with autoreset, thread CPU time.
    fn single(&mut self, slice: Duration) -> f64 {
        rate(slice, thread_cpu, || {
            for _ in 0..CHUNK {
                let a = self.env_actions.rows(self.cursor, 1);
                self.cursor += 1;
                // The action has the env's length and is finite: only MuJoCo can fail.
                let done = match self.env.step_joint(JointAction::F64(a)) {
                    Ok(s) => s.terminated || s.truncated,
                    Err(e) => {
                        self.env_error.get_or_insert(e);
                        true
                    }
                };
                self.steps += 1;
                if done {
                    self.episodes += 1;
                    let _ = self.env.try_reset(None);
                }
            }
            CHUNK as u64
        })
    }

    /// The vector env, wall time (NaN without one).
    fn vector(&mut self, slice: Duration) -> f64 {
        match &mut self.vec {
            None => f64::NAN,
            Some(vec) => rate(slice, wall, || {
                let mut real = 0;
                for _ in 0..CHUNK / 4 {
                    let a = self.env_actions.rows(self.cursor, self.envs);
                    self.cursor += 1;
                    if let Err(e) = vec.step(a) {
                        self.env_error.get_or_insert(e);
                        return 0;
                    }
                    // Autoreset slots (NextStep) leave the env at 0 elapsed steps.
                    real += vec.envs().iter().filter(|e| e.elapsed_steps() > 0).count();
                }
                real as u64
            }),
        }
    }

    /// `threads` raw loops at once, wall time.
    fn parallel(&mut self, slice: Duration) -> f64 {
        let ep_len = self.ep_len();
        parallel_ceiling(
            &self.model,
            &self.actions,
            self.threads,
            slice,
            &self.how,
            ep_len,
            &self.start_state,
        )
        .unwrap_or_else(|e| {
            self.mujoco_error.get_or_insert(e);
            f64::NAN
        })
    }

    /// The first error of the round's measurements, if any (the env's first).
    fn take_error(&mut self) -> Result<(), EnvError> {
        if let Some(e) = self.env_error.take() {
            return Err(e);
        }
        if let Some(message) = self.mujoco_error.take() {
            return Err(EnvError::Mujoco {
                env: self.id.clone(),
                during: "in the benchmark's raw mj_step loop",
                message,
            });
        }
        Ok(())
    }
}
