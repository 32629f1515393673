//! A whole recording as `envc collect` and `envc.collect` (Python) make it: episodes of an env
//! under a zero, uniformly random or replayed float32 policy, seeded as Minari's DataCollector
//! seeds (episode i with `seed + i`, else OS entropy), written through the one [`Collector`].

use std::path::PathBuf;

use super::collector::{CollectOptions, Collector};
use super::error::DatasetError;
use super::recordable::Recordable;
use crate::rng::NumpyRng;

/// Which actions the recording takes.
#[derive(Clone, Debug)]
pub enum PlanPolicy {
    /// All-zero actions.
    Zero,
    /// Uniform in the action space's bounds (float32), from its own stream seeded with the seed.
    Random,
    /// Rows of an action matrix (flat, row-major), in order across episodes, from the start again
    /// when they run out.
    Replay(Vec<f32>),
}

impl PlanPolicy {
    pub fn name(&self) -> &'static str {
        match self {
            PlanPolicy::Zero => "zero",
            PlanPolicy::Random => "random",
            PlanPolicy::Replay(_) => "replay",
        }
    }
}

/// What to record.
#[derive(Clone, Debug)]
pub struct Plan {
    pub episodes: u64,
    pub policy: PlanPolicy,
    /// Episode i is reset with `seed + i` (and the random policy is seeded with `seed`); `None`:
    /// seeds from OS entropy. Either way they are stored.
    pub seed: Option<u64>,
}

/// The recording's outcome.
#[derive(Clone, Debug)]
pub struct Recording {
    pub dir: PathBuf,
    pub steps: u64,
    pub warnings: Vec<String>,
    /// Staging directories of interrupted collections removed before this one started.
    pub cleaned: Vec<PathBuf>,
    /// Directories in the staging root without a lock file, left alone.
    pub unlocked: Vec<PathBuf>,
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

/// Record `plan` from `env` into the dataset `options` names; `progress(episodes, steps)` is
/// called after every episode. The dataset appears only when every episode is written.
pub fn record<E: Recordable>(
    env: E,
    plan: &Plan,
    mut options: CollectOptions,
    mut progress: impl FnMut(u64, u64),
) -> Result<Recording, DatasetError> {
    let space = env.action_space().clone();
    let act_dim = space.dim();
    if let PlanPolicy::Replay(rows) = &plan.policy
        && (rows.is_empty() || rows.len() % act_dim.max(1) != 0)
    {
        // Not whole rows of the action: the action-length error (E1101).
        return Err(DatasetError::Env(crate::EnvError::ActionLength {
            env: "the replayed actions".into(),
            expected: act_dim,
            got: rows.len() % act_dim.max(1),
        }));
    }
    if options.info.algorithm_name.is_none() {
        options.info.algorithm_name = Some(plan.policy.name().to_string());
    }
    let mut collector = Collector::new(env, options)?;
    let mut seed_rng = NumpyRng::from_entropy();
    let mut policy_rng = NumpyRng::from_seed(plan.seed.unwrap_or_else(|| seed_rng.next_u64()));
    let mut cursor = 0usize;
    let mut policy = |_obs: &E::Obs, a: &mut [f32]| match &plan.policy {
        PlanPolicy::Zero => a.fill(0.0),
        PlanPolicy::Random => {
            for (i, x) in a.iter_mut().enumerate() {
                *x = policy_rng.uniform(space.low[i], space.high[i]) as f32;
            }
        }
        PlanPolicy::Replay(rows) => {
            if cursor + act_dim > rows.len() {
                cursor = 0;
            }
            a.copy_from_slice(&rows[cursor..cursor + act_dim]);
            cursor += act_dim;
        }
    };
    let mut steps = 0u64;
    for ep in 0..plan.episodes {
        let seed = match plan.seed {
            Some(s) => s.wrapping_add(ep),
            None => seed_rng.next_u64(),
        };
        steps += collector.episode(seed, &mut policy)?.steps as u64;
        progress(ep + 1, steps);
    }
    let warnings = collector.env().warnings().to_vec();
    let cleaned = collector.writer().cleaned().to_vec();
    let unlocked = collector.writer().unlocked().to_vec();
    let dir = collector.finish()?;
    Ok(Recording {
        dir,
        steps,
        warnings,
        cleaned,
        unlocked,
    })
}
