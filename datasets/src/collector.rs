//! Recording whole episodes of any envc env that has a Minari form (tasks, typed or dynamic, and
//! mazes: see [`Recordable`]) under any policy. One collector for every kind.

use std::path::{Path, PathBuf};

use crate::Format;
use crate::episode::{EpisodeRecord, InfoColumn};
use crate::error::DatasetError;
use crate::recordable::Recordable;
use crate::shard_episode::ShardEpisode;
use crate::space::{Dtype, Space};
use crate::writer::{DatasetInfo, DatasetWriter};

/// Chooses actions. Actions are float32, as in Gymnasium's action spaces; the env is stepped with
/// exactly the stored values (`step_f32`), so a replay in Gymnasium reproduces the episode.
pub trait Policy {
    /// Write the action for `obs` (the env's flat observation, [`Recordable::flat_obs`]; empty
    /// for an env without one, which only a policy that reads none drives) into `action`.
    fn act(&mut self, obs: &[f64], action: &mut [f32]);
    /// Asked before every step: true stops the episode (E1601, nothing written), so that a
    /// caller's Ctrl-C ends a long episode at once.
    fn interrupted(&mut self) -> bool {
        false
    }
}

impl<F: FnMut(&[f64], &mut [f32])> Policy for F {
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        self(obs, action)
    }
}

/// Set by a caller that was asked to stop (the `envc` command's SIGINT, SIGTERM and SIGHUP
/// handlers): every collection stops before its next step with E1601, publishes nothing and
/// removes its staging directory, as a policy's `interrupted` does.
pub static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Where and how to write: `root` `None` is `MINARI_DATASETS_PATH` (default `~/.minari/datasets`).
#[derive(Clone, Debug)]
pub struct CollectOptions {
    /// The datasets directory.
    pub root: Option<PathBuf>,
    /// The id to publish under.
    pub dataset_id: String,
    /// The storage backend.
    pub format: Format,
    /// Metadata besides the counts.
    pub info: DatasetInfo,
}

/// The recording's outcome.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The published dataset's directory.
    pub dir: PathBuf,
    /// Steps recorded over all episodes.
    pub steps: u64,
    /// The seed every episode derived from (the plan's, or the one drawn).
    pub seed: u64,
    /// MuJoCo warnings raised while recording.
    pub warnings: Vec<String>,
    /// Staging directories of interrupted collections removed before this one started.
    pub cleaned: Vec<PathBuf>,
    /// Directories in the staging root without a lock file, left alone.
    pub unlocked: Vec<PathBuf>,
}

/// Summary of one recorded episode.
#[derive(Clone, Copy, Debug)]
pub struct EpisodeSummary {
    /// Steps the episode took.
    pub steps: usize,
    /// The sum of its rewards.
    pub episode_return: f64,
    /// Whether it ended in a terminal state (else it was truncated).
    pub terminated: bool,
}

/// Wraps an env and records episodes into a dataset. Buffers hold one episode and are reused, so
/// memory stays flat however many episodes are collected; each episode is on disk when
/// [`Collector::episode`] returns. A `Collector<Env>` records a task, a
/// `Collector<Box<dyn Recordable + Send>>` whatever [`crate::recordable`] gave.
pub struct Collector<E> {
    env: E,
    writer: DatasetWriter,
    buffers: Buffers,
}

/// One episode's arrays, reused from episode to episode.
pub(crate) struct Buffers {
    obs: Vec<f64>,
    actions: Vec<f32>,
    action: Vec<f32>,
    rewards: Vec<f64>,
    terminations: Vec<bool>,
    truncations: Vec<bool>,
    infos: Vec<InfoColumn>,
    /// Bytes an episode's observations and actions may take: a quarter of what the process may
    /// still allocate when it starts (a growing vector briefly holds old and new, and the writer
    /// copies once more), so a long episode is an error, not an abort part-way.
    budget: u64,
}

impl Buffers {
    pub(crate) fn new<E: Recordable + ?Sized>(env: &E) -> Buffers {
        Buffers {
            budget: envc::memory::available().map_or(u64::MAX, |b| b / 4),
            obs: vec![],
            actions: vec![],
            action: vec![0.0; env.joint().act_dim()],
            rewards: vec![],
            terminations: vec![],
            truncations: vec![],
            infos: env.info_columns(),
        }
    }

    /// Run one whole episode of `env` from `reset(seed)`; returns whether it terminated.
    pub(crate) fn run<E: Recordable + ?Sized>(
        &mut self,
        env: &mut E,
        seed: u64,
        policy: &mut impl Policy,
    ) -> Result<bool, DatasetError> {
        self.obs.clear();
        self.actions.clear();
        self.rewards.clear();
        self.terminations.clear();
        self.truncations.clear();
        for c in &mut self.infos {
            c.values.clear();
        }
        env.record_reset(seed, &mut self.obs, &mut self.infos)?;
        Ok(loop {
            if policy.interrupted() || STOP.load(std::sync::atomic::Ordering::Relaxed) {
                return Err(DatasetError::PolicyFailed {
                    episode: 0,
                    why: "interrupted".into(),
                });
            }
            policy.act(env.flat_obs().unwrap_or(&[]), &mut self.action);
            let s = env.record_step(&self.action, &mut self.obs, &mut self.infos)?;
            self.actions.extend_from_slice(&self.action);
            self.rewards.push(s.reward);
            self.terminations.push(s.terminated);
            self.truncations.push(s.truncated);
            if s.terminated || s.truncated {
                break s.terminated;
            }
            let bytes =
                (self.obs.len() * 8 + self.actions.len() * 4 + self.rewards.len() * 10) as u64;
            if bytes > self.budget {
                let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
                return Err(DatasetError::EpisodeTooLong {
                    steps: self.rewards.len() as u64,
                    gib: gib(bytes),
                    budget_gib: gib(self.budget),
                });
            }
        })
    }

    pub(crate) fn record(&self, seed: u64) -> EpisodeRecord<'_> {
        EpisodeRecord {
            seed: Some(seed),
            observations: &self.obs,
            actions: &self.actions,
            rewards: &self.rewards,
            terminations: &self.terminations,
            truncations: &self.truncations,
            infos: &self.infos,
        }
    }
}

impl<E: Recordable> Collector<E> {
    /// Start a dataset for `env`. The Gymnasium env spec (with overridden parameters as kwargs) is
    /// stored when its spec names an `[env] entry_point`; `options.info.env_spec` set by the caller
    /// wins.
    pub fn new(env: E, mut options: CollectOptions) -> Result<Collector<E>, DatasetError> {
        crate::recordable::check_recordable(&env)?;
        options.info.numerics = Some(env.joint().numerics().to_string());
        if options.info.env_spec.is_none() {
            options.info.env_spec = env.env_spec();
        }
        if options.info.provenance.is_none() {
            options.info.provenance = env.provenance().transpose()?;
            if let Some(serde_json::Value::Object(p)) = &mut options.info.provenance {
                p.insert("dataset_id".into(), options.dataset_id.clone().into());
            }
        }
        // envc's own env creator checks the record when Minari's `recover_environment` calls it.
        if let (Some(spec), Some(p)) = (&options.info.env_spec, &options.info.provenance) {
            options.info.env_spec = Some(crate::gym_spec::with_provenance(spec, p));
        }
        if options.info.env_spec.is_some() && options.info.requirements.is_empty() {
            options.info.requirements = vec![
                "gymnasium[mujoco]==1.4.0".into(),
                format!("mujoco=={}", envc::MUJOCO_VERSION),
            ];
        }
        let a = env.joint().action_space();
        let act_space = Space::box1(Dtype::F32, &a.low, &a.high);
        let writer = DatasetWriter::create(
            options.root.as_deref(),
            &options.dataset_id,
            options.format,
            env.observation_space(),
            act_space,
            options.info,
        )?;
        let buffers = Buffers::new(&env);
        Ok(Collector {
            env,
            writer,
            buffers,
        })
    }

    /// The same collector over its env as a trait object (one type for every kind).
    pub fn boxed(self) -> Collector<Box<dyn Recordable + Send>>
    where
        E: Send + 'static,
    {
        Collector {
            env: Box::new(self.env),
            writer: self.writer,
            buffers: self.buffers,
        }
    }

    /// The env being recorded.
    pub fn env(&self) -> &E {
        &self.env
    }
    /// The dataset being written.
    pub fn writer(&self) -> &DatasetWriter {
        &self.writer
    }

    /// Record one episode from a reset with `seed`, actions from `policy`.
    pub fn episode(
        &mut self,
        seed: u64,
        policy: &mut impl Policy,
    ) -> Result<EpisodeSummary, DatasetError> {
        let terminated = self.buffers.run(&mut self.env, seed, policy)?;
        let record = self.buffers.record(seed);
        self.writer.write_episode(&record)?;
        Ok(EpisodeSummary {
            steps: record.steps(),
            episode_return: record.rewards.iter().sum(),
            terminated,
        })
    }

    /// Publish the episodes workers wrote into this collector's staging directory
    /// ([`crate::record_shard`]): `episodes[i]` is what episode i's worker reported. They are
    /// checked against the disk (E1210) before the rename, as [`Collector::finish`].
    pub fn finish_shards(mut self, episodes: &[ShardEpisode]) -> Result<PathBuf, DatasetError> {
        self.writer.adopt_shards(episodes)?;
        self.writer.finish()
    }

    /// [`Collector::finish_shards`] after removing staged episodes beyond `episodes` (recorded
    /// ahead of a step budget that ended before them).
    pub fn finish_shards_trimmed(
        mut self,
        episodes: &[ShardEpisode],
    ) -> Result<PathBuf, DatasetError> {
        self.writer.discard_shards_from(episodes.len() as u64)?;
        self.finish_shards(episodes)
    }

    /// [`Collector::finish`], with what the caller reports of the recording: its steps and seed,
    /// the env's warnings and the writer's clean-up notes.
    pub fn finish_recording(self, steps: u64, seed: u64) -> Result<Recording, DatasetError> {
        let warnings = self.env().joint().warnings().to_vec();
        let cleaned = self.writer().cleaned().to_vec();
        let unlocked = self.writer().unlocked().to_vec();
        let dir = self.finish()?;
        Ok(Recording {
            dir,
            steps,
            seed,
            warnings,
            cleaned,
            unlocked,
        })
    }

    /// Finish the dataset (metadata, then one rename into place); returns its directory.
    pub fn finish(self) -> Result<PathBuf, DatasetError> {
        self.writer.finish()
    }

    /// Give the env back, discarding the unfinished dataset.
    pub fn abort(self) -> E {
        self.env
    }

    /// Where the dataset will be once finished.
    pub fn target(&self) -> PathBuf {
        self.writer.target()
    }
    /// The staging directory episodes are written into until `finish`.
    pub fn staging(&self) -> &Path {
        self.writer.staging()
    }
}
