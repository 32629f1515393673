//! `envc.collect` and the sharded collection under `envc.ray`: Minari datasets written by the same
//! code as `envc collect`. A sharded collection is a driver (`ShardedCollection`: claims the
//! staging directory, holds its lock, publishes) and workers (`collect_shard`: record episode
//! ranges straight into that directory); see datasets/src/shard.rs.

use std::path::PathBuf;

use envc_datasets::{
    CollectOptions, Collector, DatasetError, DatasetInfo, EpisodePolicy, Format, Plan, PlanActor,
    PlanPolicy, Recordable, ShardEpisode,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;

use crate::{convert, errors};

fn plan_policy(policy: &str, actions: Option<Vec<f32>>, has_fn: bool) -> PyResult<PlanPolicy> {
    Ok(match (policy, actions, has_fn) {
        ("zero", None, false) => PlanPolicy::Zero,
        ("random", None, false) => PlanPolicy::Random,
        ("replay", Some(a), false) => PlanPolicy::Replay(a),
        ("callable", None, true) => PlanPolicy::Callable,
        ("replay", None, _) => return Err(errors::argument("policy='replay' needs actions")),
        (_, Some(_), _) => {
            return Err(errors::argument(
                "actions are only used with policy='replay'",
            ));
        }
        (other, _, _) => {
            return Err(errors::argument(format!(
                "policy={other:?}: expected 'zero', 'random', 'replay' or a callable policy(obs, rng) -> action"
            )));
        }
    })
}

/// At most `limits::MAX_EPISODES`, as `envc collect --episodes`.
fn check_episodes(episodes: u64) -> PyResult<()> {
    let max = envspec::limits::MAX_EPISODES;
    if episodes == 0 || episodes > max {
        return Err(errors::argument(format!(
            "episodes={episodes}: expected 1 to {max} (envspec::limits::MAX_EPISODES)"
        )));
    }
    Ok(())
}

fn format(name: &str) -> PyResult<Format> {
    match name {
        "arrow" => Ok(Format::Arrow),
        "hdf5" => Ok(Format::Hdf5),
        other => Err(errors::argument(format!(
            "format={other:?}: expected 'arrow' or 'hdf5'"
        ))),
    }
}

/// The env of a collection: a task or a maze with a time limit.
fn open_env(
    id_or_path: &str,
    overrides: &[(String, String)],
) -> PyResult<(Box<dyn Recordable + Send>, String)> {
    let env = envc::open(id_or_path, &convert::overrides(overrides)).map_err(errors::env_error)?;
    let env = envc_datasets::recordable(env).map_err(|_| {
        errors::coded(
            "E0602",
            format!(
                "error[E0602]: `{id_or_path}` is a multi-agent spec; Minari datasets are single-agent (collect its base task)"
            ),
        )
    })?;
    let id = env.joint().id().to_string();
    if env.joint().max_episode_steps().is_none() {
        // E1401, as `envc collect`: an episode might never end.
        return Err(errors::coded(
            "E1401",
            format!(
                "error[E1401]: `{id}` has no time limit, so collect might never end an episode; pass max_episode_steps=N as an override"
            ),
        ));
    }
    Ok((env, id))
}

/// A Python `policy(obs, rng) -> action`, called with the GIL for each step; `rng` is episode i's
/// `numpy.random.default_rng([seed, i])`. An exception (or a wrong action) is kept and reported
/// after the episode, which is then never written.
struct PyPolicy {
    f: Py<PyAny>,
    rng: Option<Py<PyAny>>,
    episode: u64,
    err: Option<PyErr>,
}

impl PyPolicy {
    fn new(f: Py<PyAny>) -> PyPolicy {
        PyPolicy {
            f,
            rng: None,
            episode: 0,
            err: None,
        }
    }
    fn call(&mut self, obs: &[f64], action: &mut [f32]) -> PyResult<()> {
        Python::attach(|py| {
            let o = PyArray1::from_slice(py, obs);
            let rng = self.rng.as_ref().map(|r| r.bind(py).clone());
            let out = self.f.bind(py).call1((o, rng))?;
            let np = py.import("numpy")?;
            let a = np
                .call_method1("asarray", (out, "float32"))?
                .call_method0("ravel")?;
            let a = a.cast_into::<PyArray1<f32>>()?;
            let ro = a.readonly();
            let v = ro.as_slice()?;
            if v.len() != action.len() {
                return Err(errors::coded(
                    "E1601",
                    format!(
                        "error[E1601]: the policy returned {} action values; the action space has {}",
                        v.len(),
                        action.len()
                    ),
                ));
            }
            action.copy_from_slice(v);
            Ok(())
        })
    }
}

impl EpisodePolicy for PyPolicy {
    fn begin(&mut self, seed: u64, episode: u64) {
        self.episode = episode;
        if self.err.is_some() {
            return;
        }
        let made = Python::attach(|py| -> PyResult<Py<PyAny>> {
            let rng = py
                .import("numpy.random")?
                .call_method1("default_rng", (vec![seed, episode],))?;
            Ok(rng.unbind())
        });
        match made {
            Ok(r) => self.rng = Some(r),
            Err(e) => self.err = Some(e),
        }
    }
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        if self.err.is_none()
            && let Err(e) = self.call(obs, action)
        {
            self.err = Some(e);
        }
        if self.err.is_some() {
            action.fill(0.0);
        }
    }
    fn check(&mut self) -> Result<(), DatasetError> {
        match &self.err {
            None => Ok(()),
            Some(e) => Err(DatasetError::PolicyFailed {
                episode: self.episode,
                why: e.to_string(),
            }),
        }
    }
}

/// A policy that also looks for a pending signal (Ctrl-C) every 50 ms of stepping, taking the GIL
/// for it: the GIL is released while episodes run, so Python would see the signal only when the
/// whole collection returned. A signal's exception (`KeyboardInterrupt`) stops the episode and
/// the collection; nothing is published.
struct Interruptible<P> {
    inner: P,
    steps: u32,
    last: std::time::Instant,
    signal: Option<PyErr>,
}

impl<P> Interruptible<P> {
    fn new(inner: P) -> Self {
        Interruptible {
            inner,
            steps: 0,
            last: std::time::Instant::now(),
            signal: None,
        }
    }
}

impl<P: EpisodePolicy> EpisodePolicy for Interruptible<P> {
    fn begin(&mut self, seed: u64, episode: u64) {
        self.inner.begin(seed, episode)
    }
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        self.inner.act(obs, action)
    }
    fn reads_obs(&self) -> bool {
        self.inner.reads_obs()
    }
    fn check(&mut self) -> Result<(), DatasetError> {
        if self.signal.is_some() {
            return Err(DatasetError::PolicyFailed {
                episode: 0,
                why: "interrupted".into(),
            });
        }
        self.inner.check()
    }
    fn interrupted(&mut self) -> bool {
        if self.signal.is_some() {
            return true;
        }
        self.steps = self.steps.wrapping_add(1);
        if !self.steps.is_multiple_of(64)
            || self.last.elapsed() < std::time::Duration::from_millis(50)
        {
            return false;
        }
        self.last = std::time::Instant::now();
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.signal = Some(e);
            return true;
        }
        false
    }
}

/// The Python exception for a collection error: a signal's (Ctrl-C), else the policy's own
/// exception when it raised, else the coded dataset error.
fn collect_error(e: DatasetError, signal: Option<PyErr>, policy: Option<&mut PyPolicy>) -> PyErr {
    if let Some(err) = signal {
        return err;
    }
    if let Some(err) = policy.and_then(|p| p.err.take()) {
        return err;
    }
    errors::dataset_error(e)
}

/// Record `episodes` episodes of a task or maze spec into a Minari dataset; returns
/// `(dataset directory, steps, seed)`. The GIL is released while the episodes run (a callable
/// policy takes it for each step). `env_spec`: the Gymnasium `EnvSpec` JSON to store instead of
/// the reference's (the Python layer's `"envc"`).
#[pyfunction]
#[pyo3(signature = (id_or_path, dataset_id, episodes, policy = "random", seed = None, format = "arrow", root = None, overrides = Vec::new(), actions = None, author = None, description = None, env_spec = None, policy_fn = None))]
#[allow(clippy::too_many_arguments)]
pub fn collect(
    py: Python<'_>,
    id_or_path: &str,
    dataset_id: &str,
    episodes: u64,
    policy: &str,
    seed: Option<u64>,
    format: &str,
    root: Option<PathBuf>,
    overrides: Vec<(String, String)>,
    actions: Option<Vec<f32>>,
    author: Option<String>,
    description: Option<String>,
    env_spec: Option<String>,
    policy_fn: Option<Py<PyAny>>,
) -> PyResult<(String, u64, u64)> {
    check_episodes(episodes)?;
    let plan = Plan {
        episodes,
        policy: plan_policy(policy, actions, policy_fn.is_some())?,
        seed,
    };
    let format = self::format(format)?;
    let (env, id) = open_env(id_or_path, &overrides)?;
    let opts = options(
        &plan,
        &id,
        dataset_id,
        format,
        root,
        author,
        description,
        env_spec,
    );
    let mut py_policy = policy_fn.map(PyPolicy::new);
    let mut signal = None;
    let r = errors::no_panic(
        &mut (),
        |_| {
            Ok(py.detach(|| {
                with_policy(
                    env,
                    &plan.policy,
                    py_policy.as_mut(),
                    &mut signal,
                    |e, p| envc_datasets::record_with(e, &plan, opts, p, |_, _| {}),
                )
            }))
        },
        |_| {},
    )?;
    let r = r.map_err(|e| collect_error(e, signal, py_policy.as_mut()))?;
    Ok((r.dir.display().to_string(), r.steps, r.seed))
}

#[allow(clippy::too_many_arguments)]
fn options(
    plan: &Plan,
    id: &str,
    dataset_id: &str,
    format: Format,
    root: Option<PathBuf>,
    author: Option<String>,
    description: Option<String>,
    env_spec: Option<String>,
) -> CollectOptions {
    let info = DatasetInfo {
        author: vec![author.unwrap_or_else(|| "envc".into())],
        description: Some(
            description.unwrap_or_else(|| envc_datasets::default_description(plan, id)),
        ),
        algorithm_name: Some(plan.policy.name().to_string()),
        env_spec,
        ..DatasetInfo::default()
    };
    CollectOptions {
        root,
        dataset_id: dataset_id.to_string(),
        format,
        info,
    }
}

/// Run `record` with the collection's one policy: the caller's callable, else the plan's built-in
/// one, either stopping at a pending signal (kept in `signal`).
fn with_policy<R>(
    env: Box<dyn Recordable + Send>,
    plan: &PlanPolicy,
    callable: Option<&mut PyPolicy>,
    signal: &mut Option<PyErr>,
    record: impl FnOnce(
        Box<dyn Recordable + Send>,
        &mut Interruptible<&mut dyn EpisodePolicy>,
    ) -> Result<R, DatasetError>,
) -> Result<R, DatasetError> {
    let mut actor;
    let inner: &mut dyn EpisodePolicy = match callable {
        Some(p) => p,
        None => {
            actor = PlanActor::new(plan, env.joint().action_space())?;
            &mut actor
        }
    };
    let mut p = Interruptible::new(inner);
    let r = record(env, &mut p);
    *signal = p.signal.take();
    r
}

/// The driver of a sharded collection: claims the dataset's staging directory (and holds its
/// lock) on creation, so workers can write into `staging`; `finish(lengths)` checks and
/// publishes. Dropped unfinished (or its process killed), nothing is published and the next
/// collection in the root removes the staging directory.
#[pyclass(module = "envc._envc", unsendable)]
pub struct ShardedCollection {
    collector: Option<Collector<Box<dyn Recordable + Send>>>,
    seed: u64,
    staging: String,
}

impl ShardedCollection {
    /// The driver of a collector made elsewhere (a dataset spec's build).
    pub fn of(c: Collector<Box<dyn Recordable + Send>>, seed: u64) -> ShardedCollection {
        let staging = c.staging().display().to_string();
        ShardedCollection {
            collector: Some(c),
            seed,
            staging,
        }
    }
}

#[pymethods]
impl ShardedCollection {
    #[new]
    #[pyo3(signature = (id_or_path, dataset_id, episodes, policy = "random", seed = None, format = "arrow", root = None, overrides = Vec::new(), actions = None, author = None, description = None, env_spec = None, callable = false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        id_or_path: &str,
        dataset_id: &str,
        episodes: u64,
        policy: &str,
        seed: Option<u64>,
        format: &str,
        root: Option<PathBuf>,
        overrides: Vec<(String, String)>,
        actions: Option<Vec<f32>>,
        author: Option<String>,
        description: Option<String>,
        env_spec: Option<String>,
        callable: bool,
    ) -> PyResult<ShardedCollection> {
        check_episodes(episodes)?;
        let plan = Plan {
            episodes,
            policy: plan_policy(policy, actions, callable)?,
            seed,
        };
        let seed = plan.resolve_seed();
        let format = self::format(format)?;
        let (env, id) = open_env(id_or_path, &overrides)?;
        let opts = options(
            &plan,
            &id,
            dataset_id,
            format,
            root,
            author,
            description,
            env_spec,
        );
        let err = errors::dataset_error;
        envc_datasets::policy_fits(&*env, callable).map_err(err)?;
        if let PlanPolicy::Replay(_) = &plan.policy {
            PlanActor::new(&plan.policy, env.joint().action_space()).map_err(err)?;
        }
        let collector = Collector::new(env, opts).map_err(err)?;
        let staging = collector.staging().display().to_string();
        Ok(ShardedCollection {
            collector: Some(collector),
            seed,
            staging,
        })
    }

    /// The seed every episode derives from (the given one, or the one drawn).
    #[getter]
    fn seed(&self) -> u64 {
        self.seed
    }

    /// The staging directory workers write into (hidden in the datasets root).
    #[getter]
    fn staging(&self) -> &str {
        &self.staging
    }

    /// Publish: `episodes[i]` is `(steps, bytes)` as episode i's worker reported it
    /// (`collect_shard`). Returns the dataset's directory.
    #[pyo3(signature = (episodes, trim = false))]
    fn finish(
        &mut self,
        py: Python<'_>,
        episodes: Vec<(u64, u64)>,
        trim: bool,
    ) -> PyResult<String> {
        let episodes: Vec<ShardEpisode> = episodes
            .into_iter()
            .map(|(steps, bytes)| ShardEpisode { steps, bytes })
            .collect();
        let c = self
            .collector
            .take()
            .ok_or_else(|| errors::argument("the collection is already finished or aborted"))?;
        let dir = py
            .detach(|| match trim {
                true => c.finish_shards_trimmed(&episodes),
                false => c.finish_shards(&episodes),
            })
            .map_err(errors::dataset_error)?;
        Ok(dir.display().to_string())
    }

    /// Give up: the staging directory is removed, nothing is published.
    fn abort(&mut self) {
        self.collector = None;
    }
}

/// A worker's part of a sharded collection: episodes `start..end` of the plan (same arguments as
/// the driver's, and its resolved `seed`) recorded into `staging`; returns each episode's
/// `(steps, bytes)` for the driver's `finish`.
#[pyfunction]
#[pyo3(signature = (id_or_path, staging, start, end, seed, policy = "random", format = "arrow", overrides = Vec::new(), actions = None, policy_fn = None))]
#[allow(clippy::too_many_arguments)]
pub fn collect_shard(
    py: Python<'_>,
    id_or_path: &str,
    staging: PathBuf,
    start: u64,
    end: u64,
    seed: u64,
    policy: &str,
    format: &str,
    overrides: Vec<(String, String)>,
    actions: Option<Vec<f32>>,
    policy_fn: Option<Py<PyAny>>,
) -> PyResult<Vec<(u64, u64)>> {
    let plan_policy = plan_policy(policy, actions, policy_fn.is_some())?;
    let format = self::format(format)?;
    let (env, _) = open_env(id_or_path, &overrides)?;
    let mut py_policy = policy_fn.map(PyPolicy::new);
    let range = start..end.max(start);
    let mut signal = None;
    let r = errors::no_panic(
        &mut (),
        |_| {
            Ok(py.detach(|| {
                with_policy(
                    env,
                    &plan_policy,
                    py_policy.as_mut(),
                    &mut signal,
                    |e, p| envc_datasets::record_shard(e, seed, range, &staging, format, p),
                )
            }))
        },
        |_| {},
    )?;
    let episodes = r.map_err(|e| collect_error(e, signal, py_policy.as_mut()))?;
    Ok(episodes.into_iter().map(|e| (e.steps, e.bytes)).collect())
}
