//! Building a dataset from its spec ([`DatasetSpec`]): the one runner behind `envc dataset build`,
//! `envc.datasets.build` and its Ray workers. Episode k is reset with `seed + k` and takes its
//! action noise from `default_rng([seed, k])` only, so a build is the same bytes on any machine
//! and any number of workers. Infos are recorded; the stored env spec carries the parameters.

use std::path::{Path, PathBuf};

use crate::build_spec::{Budget, DatasetSpec, PolicyMode};
use crate::collector::{CollectOptions, Collector};
use crate::error::DatasetError;
use crate::mlp::MlpPolicy;
use crate::plan::{EpisodePolicy, episode_rng, episode_seed};
use crate::recordable::Recordable;
use crate::shard_episode::ShardEpisode;
use crate::writer::DatasetInfo;
use crate::{Format, Recording};
use envc::rng::NumpyRng;
use envc::{Env, JointEnv, Override};

/// What a build may change from its spec.
#[derive(Clone, Debug, Default)]
pub struct BuildOptions {
    /// A step budget instead of the spec's (a small build of a tier).
    pub steps: Option<u64>,
    /// The datasets root (default `$MINARI_DATASETS_PATH`, else `~/.minari/datasets`).
    pub root: Option<PathBuf>,
    /// A storage format instead of the spec's.
    pub format: Option<Format>,
    /// A dataset id instead of the spec's.
    pub dataset_id: Option<String>,
}

/// The spec's policy as an [`EpisodePolicy`]: its noise stream restarts from episode k's
/// generator at every episode.
pub struct SpecActor {
    policy: MlpPolicy,
    mode: PolicyMode,
    rng: NumpyRng,
}

impl EpisodePolicy for SpecActor {
    fn begin(&mut self, seed: u64, episode: u64) {
        self.rng = episode_rng(seed, episode);
    }
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        let noise = match self.mode {
            PolicyMode::Deterministic => None,
            PolicyMode::Stochastic => Some(&mut self.rng),
        };
        self.policy.act(obs, noise, action);
    }
}

fn overrides(params: &[(String, String)]) -> Vec<Override> {
    params.iter().map(|(k, v)| Override::text(k, v)).collect()
}

fn open_task(what: &str, params: &[(String, String)]) -> Result<Env, DatasetError> {
    match envc::open(what, &overrides(params))? {
        envc::AnyEnv::Task(e) => Ok(e),
        other => Err(DatasetError::Unsupported(format!(
            "`{}`: dataset specs build task envs (flat observations), not {:?} specs",
            other.id(),
            other.kind()
        ))),
    }
}

/// A build's resolved parts: the env, the policy, and how much to record.
pub struct Build {
    /// The dataset spec as read.
    pub spec: DatasetSpec,
    /// The budget in force: the spec's, or the `steps` a small build asked for.
    pub budget: Budget,
    /// The env's time limit, which a step budget keeps room for.
    pub max_episode_steps: u64,
}

impl Build {
    /// Resolves a spec: opens its env and checks the budget against the env's time limit.
    pub fn new(spec: DatasetSpec, steps: Option<u64>) -> Result<Build, DatasetError> {
        let env = open_task(&spec.env, &spec.params)?;
        let max_episode_steps = env.spec().max_episode_steps.ok_or_else(|| {
            DatasetError::Unsupported(format!(
                "`{}` has no time limit; a dataset spec needs max_episode_steps",
                spec.env
            ))
        })?;
        let budget = steps.map_or(spec.budget, Budget::Steps);
        if let Budget::Steps(n) = budget
            && n < max_episode_steps
        {
            return Err(DatasetError::Unsupported(format!(
                "a budget of {n} steps holds no episode: a new episode starts only while at least max_episode_steps = {max_episode_steps} steps remain"
            )));
        }
        Ok(Build {
            spec,
            budget,
            max_episode_steps,
        })
    }

    /// The env every episode runs in.
    pub fn env(&self) -> Result<Env, DatasetError> {
        open_task(&self.spec.env, &self.spec.params)
    }

    /// The policy, checked against the env's spaces (E1802).
    pub fn actor(&self, env: &Env) -> Result<SpecActor, DatasetError> {
        let policy = MlpPolicy::load(&self.spec.policy_file)?;
        let a = env.action_space();
        policy.check_spaces(env.obs_dim(), &a.low, &a.high)?;
        Ok(SpecActor {
            policy,
            mode: self.spec.mode,
            rng: NumpyRng::from_seed(0),
        })
    }

    /// Where and with which metadata the dataset is written.
    pub fn options(&self, opts: &BuildOptions) -> Result<CollectOptions, DatasetError> {
        let s = &self.spec;
        let eval = open_task(&s.eval_env, &s.eval_params)?;
        let info = DatasetInfo {
            author: s.author.clone(),
            author_email: s.author_email.clone(),
            algorithm_name: Some(s.algorithm_name.clone()),
            code_permalink: s.code_permalink.clone(),
            description: Some(s.description.clone()),
            eval_env_spec: eval.env_spec(),
            reference_scores: s.reference_scores,
            ..DatasetInfo::default()
        };
        Ok(CollectOptions {
            root: opts.root.clone(),
            dataset_id: opts
                .dataset_id
                .clone()
                .unwrap_or_else(|| s.dataset_id.clone()),
            format: opts.format.unwrap_or(s.format.into()),
            info,
        })
    }

    /// Whether episode `next` is recorded, after `steps` steps in episodes before it.
    pub fn wants(&self, next: u64, steps: u64) -> bool {
        match self.budget {
            Budget::Episodes(n) => next < n,
            Budget::Steps(b) => b.saturating_sub(steps) >= self.max_episode_steps,
        }
    }

    /// How many more episodes are surely recorded after `done` episodes of `steps` steps (each
    /// at most `max_episode_steps` long): a sharded build runs them in one round.
    pub fn surely_next(&self, done: u64, steps: u64) -> u64 {
        match self.budget {
            Budget::Episodes(n) => n.saturating_sub(done),
            Budget::Steps(b) => b.saturating_sub(steps) / self.max_episode_steps.max(1),
        }
    }

    /// Record the whole dataset in this process; `progress(episodes, steps)` after each episode.
    pub fn record(
        &self,
        opts: &BuildOptions,
        mut progress: impl FnMut(u64, u64),
    ) -> Result<Recording, DatasetError> {
        let env = self.env()?;
        let mut actor = self.actor(&env)?;
        let mut collector = Collector::new(env, self.options(opts)?)?;
        let seed = self.spec.seed;
        let (mut ep, mut steps) = (0u64, 0u64);
        while self.wants(ep, steps) {
            actor.begin(seed, ep);
            let s = collector
                .episode(episode_seed(seed, ep), &mut |o: &[f64], a: &mut [f32]| {
                    actor.act(o, a)
                })?;
            steps += s.steps as u64;
            ep += 1;
            progress(ep, steps);
            if ep == crate::plan::DISK_SAMPLE {
                // Episodes the budget will take, at the length of these.
                let total = match self.budget {
                    Budget::Episodes(n) => n,
                    Budget::Steps(b) => b.div_ceil(steps.div_ceil(ep).max(1)),
                };
                crate::plan::disk_fits(collector.staging(), ep, total)?;
            }
        }
        collector.finish_recording(steps, seed)
    }

    /// A worker's share of a sharded build: episodes `start..end` into the driver's `staging`.
    pub fn record_shard(
        &self,
        staging: &Path,
        format: Format,
        start: u64,
        end: u64,
    ) -> Result<Vec<ShardEpisode>, DatasetError> {
        let env = self.env()?;
        let actor = self.actor(&env)?;
        crate::plan::record_shard(env, self.spec.seed, start..end, staging, format, actor)
    }

    /// The driver's collector of a sharded build (claims the staging directory).
    pub fn driver(&self, opts: &BuildOptions) -> Result<Collector<Env>, DatasetError> {
        let env = self.env()?;
        self.actor(&env)?;
        Collector::new(env, self.options(opts)?)
    }
}
