//! A whole recording as `envc collect`, `envc.collect` and `envc.ray.collect` make it: episodes of
//! an env under a zero, uniformly random, replayed float32 or caller-supplied policy. Episode `i`
//! depends on `(seed, i)` only: it is reset with `seed + i` (as Minari's DataCollector seeds), its
//! random actions come from numpy's `default_rng([seed, i])` and replayed actions restart at row 0.
//! So any split of the episodes over processes or machines records the same episodes
//! ([`record_shard`]), and [`record`] is the one-process case.

use std::ops::Range;
use std::path::Path;

use crate::Format;
use crate::collector::{CollectOptions, Collector, Policy, Recording};
use crate::error::DatasetError;
use crate::recordable::{Recordable, policy_fits};
use crate::shard::ShardCollector;
use crate::shard_episode::ShardEpisode;
use envc::BoxSpace;
use envc::rng::{NumpyRng, SeedSequence};

/// Which actions the recording takes.
#[derive(Clone, Debug)]
pub enum PlanPolicy {
    /// All-zero actions.
    Zero,
    /// Uniform in the action space's bounds (float32); episode i draws from
    /// `numpy.random.default_rng([seed, i])`.
    Random,
    /// Rows of an action matrix (flat, row-major): every episode starts at row 0 and starts over
    /// when the rows run out.
    Replay(Vec<f32>),
    /// Actions from a caller's [`EpisodePolicy`] (a Python callable in `envc.collect`); the
    /// caller must derive its randomness from `(seed, i)` too.
    Callable,
}

impl PlanPolicy {
    /// The policy's name as `envc collect --policy` takes it.
    pub fn name(&self) -> &'static str {
        match self {
            PlanPolicy::Zero => "zero",
            PlanPolicy::Random => "random",
            PlanPolicy::Replay(_) => "replay",
            PlanPolicy::Callable => "callable",
        }
    }
}

/// What to record.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Episodes to record.
    pub episodes: u64,
    /// Where the actions come from.
    pub policy: PlanPolicy,
    /// Every episode derives from it (see the module doc); `None`: one seed is drawn from OS
    /// entropy ([`Plan::resolve_seed`]) and stored as episode 0's seed.
    pub seed: Option<u64>,
}

impl Plan {
    /// The seed itself, or one fresh draw from OS entropy (below 2^63, so that every consumer's
    /// signed 64-bit integers hold it).
    pub fn resolve_seed(&self) -> u64 {
        self.seed
            .unwrap_or_else(|| NumpyRng::from_entropy().next_u64() >> 1)
    }
}

/// Episode `episode`'s reset seed: `seed + episode` (wrapping), as Minari's DataCollector.
pub fn episode_seed(seed: u64, episode: u64) -> u64 {
    seed.wrapping_add(episode)
}

/// Episode `episode`'s policy stream: numpy's `default_rng([seed, episode])`.
pub fn episode_rng(seed: u64, episode: u64) -> NumpyRng {
    NumpyRng::from_seed_sequence(&SeedSequence::from_ints(&[seed, episode]))
}

/// Chooses the actions of whole episodes: [`EpisodePolicy::begin`] is called before each one
/// with the plan's seed and the episode's index in the dataset, so a policy can restart its
/// state from `(seed, i)` and give the same actions whichever worker runs the episode.
pub trait EpisodePolicy {
    /// Restart for episode `episode` of a plan seeded with `seed`.
    fn begin(&mut self, seed: u64, episode: u64);
    /// Write the action for `obs` (as [`Policy::act`]) into `action`.
    fn act(&mut self, obs: &[f64], action: &mut [f32]);
    /// Whether the actions depend on the observation: such a policy needs an env with a flat one
    /// ([`Recordable::flat_obs`]), which the recording checks before its first episode.
    fn reads_obs(&self) -> bool {
        true
    }
    /// Called after each episode, before it is written: a policy that failed on the way (a
    /// Python callable that raised) says so here, and the episode is never written (E1601).
    fn check(&mut self) -> Result<(), DatasetError> {
        Ok(())
    }
    /// Asked before every step: true stops the episode and the collection (a caller's Ctrl-C).
    fn interrupted(&mut self) -> bool {
        false
    }
}

impl<P: EpisodePolicy + ?Sized> EpisodePolicy for &mut P {
    fn begin(&mut self, seed: u64, episode: u64) {
        (**self).begin(seed, episode)
    }
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        (**self).act(obs, action)
    }
    fn reads_obs(&self) -> bool {
        (**self).reads_obs()
    }
    fn check(&mut self) -> Result<(), DatasetError> {
        (**self).check()
    }
    fn interrupted(&mut self) -> bool {
        (**self).interrupted()
    }
}

/// An [`EpisodePolicy`] as the collector's per-episode [`Policy`].
struct Steps<'a, P>(&'a mut P);

impl<P: EpisodePolicy> Policy for Steps<'_, P> {
    fn act(&mut self, obs: &[f64], action: &mut [f32]) {
        self.0.act(obs, action)
    }
    fn interrupted(&mut self) -> bool {
        self.0.interrupted()
    }
}

/// The built-in policies (zero, random, replay) as an [`EpisodePolicy`].
pub struct PlanActor {
    policy: PlanPolicy,
    low: Vec<f64>,
    high: Vec<f64>,
    rng: NumpyRng,
    cursor: usize,
}

impl PlanActor {
    /// Fails for a replay matrix that is not whole rows of the action (E1101) and for
    /// [`PlanPolicy::Callable`], which needs the caller's policy.
    pub fn new(policy: &PlanPolicy, space: &BoxSpace) -> Result<PlanActor, DatasetError> {
        let act_dim = space.dim();
        match policy {
            PlanPolicy::Replay(rows) if rows.is_empty() || rows.len() % act_dim.max(1) != 0 => {
                // Not whole rows of the action: the action-length error (E1101).
                return Err(DatasetError::Env(envc::EnvError::ActionLength {
                    env: "the replayed actions".into(),
                    expected: act_dim,
                    got: rows.len() % act_dim.max(1),
                }));
            }
            PlanPolicy::Callable => {
                return Err(DatasetError::Unsupported(
                    "a callable policy needs the caller's policy object".into(),
                ));
            }
            _ => {}
        }
        Ok(PlanActor {
            policy: policy.clone(),
            low: space.low.clone(),
            high: space.high.clone(),
            rng: NumpyRng::from_seed(0),
            cursor: 0,
        })
    }
}

impl EpisodePolicy for PlanActor {
    fn begin(&mut self, seed: u64, episode: u64) {
        self.rng = episode_rng(seed, episode);
        self.cursor = 0;
    }
    fn reads_obs(&self) -> bool {
        false
    }
    fn act(&mut self, _obs: &[f64], a: &mut [f32]) {
        match &self.policy {
            PlanPolicy::Zero | PlanPolicy::Callable => a.fill(0.0),
            PlanPolicy::Random => {
                for (i, x) in a.iter_mut().enumerate() {
                    *x = self.rng.uniform(self.low[i], self.high[i]) as f32;
                }
            }
            PlanPolicy::Replay(rows) => {
                let n = a.len();
                if self.cursor + n > rows.len() {
                    self.cursor = 0;
                }
                a.copy_from_slice(&rows[self.cursor..self.cursor + n]);
                self.cursor += n;
            }
        }
    }
}

/// The description a dataset gets when none is given.
pub fn default_description(plan: &Plan, env_id: &str) -> String {
    format!(
        "{} episodes of {env_id} with a {} policy, collected by envc {}",
        plan.episodes,
        plan.policy.name(),
        env!("CARGO_PKG_VERSION")
    )
}

/// Record `plan` from `env` into the dataset `options` names with the built-in policy;
/// `progress(episodes, steps)` is called after every episode. The dataset appears only when
/// every episode is written.
pub fn record<E: Recordable>(
    env: E,
    plan: &Plan,
    options: CollectOptions,
    progress: impl FnMut(u64, u64),
) -> Result<Recording, DatasetError> {
    let actor = PlanActor::new(&plan.policy, env.joint().action_space())?;
    record_with(env, plan, options, actor, progress)
}

/// [`record`] with the caller's policy.
pub fn record_with<E: Recordable, P: EpisodePolicy>(
    env: E,
    plan: &Plan,
    mut options: CollectOptions,
    mut policy: P,
    mut progress: impl FnMut(u64, u64),
) -> Result<Recording, DatasetError> {
    policy_fits(&env, policy.reads_obs())?;
    if options.info.algorithm_name.is_none() {
        options.info.algorithm_name = Some(plan.policy.name().to_string());
    }
    let seed = plan.resolve_seed();
    let mut collector = Collector::new(env, options)?;
    let mut steps = 0u64;
    for ep in 0..plan.episodes {
        policy.begin(seed, ep);
        // A failed policy's episode is written to staging at most, which the error discards.
        let summary = collector.episode(episode_seed(seed, ep), &mut Steps(&mut policy));
        policy.check()?;
        steps += summary?.steps as u64;
        progress(ep + 1, steps);
        if ep + 1 == DISK_SAMPLE.min(plan.episodes) {
            disk_fits(collector.staging(), ep + 1, plan.episodes)?;
        }
    }
    collector.finish_recording(steps, seed)
}

/// Episodes after which a collection checks that the rest will fit on the disk.
pub(crate) const DISK_SAMPLE: u64 = 8;

/// E1211 when `episodes` episodes, at the size of the first `done` in `staging`, would not fit in
/// the space left (with 10 % to spare): refused early rather than after filling the disk.
pub(crate) fn disk_fits(staging: &Path, done: u64, episodes: u64) -> Result<(), DatasetError> {
    if done >= episodes {
        return Ok(());
    }
    let (Ok(used), Some(free)) = (disk_usage(staging), envc::os::free_bytes(staging)) else {
        return Ok(());
    };
    let need = (used as f64 / done as f64) * (episodes - done) as f64 * 1.1;
    if need <= free as f64 {
        return Ok(());
    }
    let human = |b: f64| match b {
        b if b >= (1u64 << 30) as f64 => format!("{:.1} GiB", b / (1u64 << 30) as f64),
        b if b >= (1u64 << 20) as f64 => format!("{:.1} MiB", b / (1u64 << 20) as f64),
        b => format!("{:.0} KiB", b / 1024.0),
    };
    Err(DatasetError::DiskTooSmall {
        path: staging.to_path_buf(),
        episodes,
        sample: done,
        need: human(need),
        free: human(free as f64),
    })
}

/// Bytes `dir` takes on the disk, its directories' blocks included (a collection of short
/// episodes is mostly directories).
fn disk_usage(dir: &Path) -> std::io::Result<u64> {
    use std::os::unix::fs::MetadataExt;
    let mut total = std::fs::symlink_metadata(dir)?.blocks() * 512;
    for e in std::fs::read_dir(dir)? {
        let e = e?;
        let meta = e.metadata()?;
        total += if meta.is_dir() {
            disk_usage(&e.path())?
        } else {
            meta.blocks() * 512
        };
    }
    Ok(total)
}

/// Record episodes `range` of a plan (with its resolved `seed`) into the staging directory of a
/// sharded collection ([`crate::Collector::staging`] of the driver's collector, on storage every
/// worker shares); returns each episode's steps and bytes, in order. Episodes already there (from an
/// attempt that died after writing them) are recorded again and left as they were: they are the
/// same bytes.
pub fn record_shard<E: Recordable, P: EpisodePolicy>(
    env: E,
    seed: u64,
    range: Range<u64>,
    staging: &Path,
    format: Format,
    mut policy: P,
) -> Result<Vec<ShardEpisode>, DatasetError> {
    policy_fits(&env, policy.reads_obs())?;
    let mut shard = ShardCollector::new(env, staging, format)?;
    let mut lengths = Vec::with_capacity((range.end - range.start) as usize);
    for ep in range {
        policy.begin(seed, ep);
        let run = shard.run(episode_seed(seed, ep), &mut Steps(&mut policy));
        // Checked before writing: episodes in a shared staging directory are never rewritten.
        policy.check()?;
        run?;
        lengths.push(shard.write(ep)?);
    }
    Ok(lengths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_collection_the_disk_cannot_hold_is_e1211_from_its_first_episodes() {
        let dir = std::env::temp_dir().join(format!("envc-disk-fits-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("episode_0")).unwrap();
        std::fs::write(dir.join("episode_0/data"), vec![1u8; 1 << 20]).unwrap();
        assert!(disk_fits(&dir, 1, 2).is_ok());
        let e = disk_fits(&dir, 1, 1 << 40).unwrap_err();
        assert_eq!(e.code(), "E1211");
        assert!(e.to_string().contains("free"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
