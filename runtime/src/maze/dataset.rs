//! Minari datasets of maze envs (feature `dataset`): dict observations (`achieved_goal`,
//! `desired_goal`, `observation`, as Gymnasium's `spaces.Dict` orders them), float32 actions,
//! `success` and the robot's info as info columns.
//!
//! ```no_run
//! use envc::dataset::{CollectOptions, DatasetInfo, Format};
//! use envc::maze::{MazeEnv, dataset::MazeCollector};
//! let env = MazeEnv::make("PointMaze_UMaze-v3", &[])?;
//! let opts = CollectOptions { root: None, dataset_id: "envc/pointmaze-umaze/random-v0".into(), format: Format::Arrow, info: DatasetInfo::default() };
//! let mut c = MazeCollector::new(env, opts)?;
//! c.episode(0, &mut |_obs, a: &mut [f32]| a.fill(0.5))?;
//! let dir = c.finish()?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::PathBuf;

use super::{MazeEnv, MazeObs};
use crate::dataset::{
    CollectOptions, DatasetError, DatasetWriter, Dtype, EpisodeRecord, EpisodeSummary, InfoColumn,
    Space,
};

/// Collects episodes of a maze env into a Minari dataset.
pub struct MazeCollector {
    env: MazeEnv,
    writer: DatasetWriter,
    obs: Vec<f64>,
    actions: Vec<f32>,
    action: Vec<f32>,
    rewards: Vec<f64>,
    terminations: Vec<bool>,
    truncations: Vec<bool>,
    infos: Vec<InfoColumn>,
}

fn unbounded(n: usize) -> Space {
    Space::box1(
        Dtype::F64,
        &vec![f64::NEG_INFINITY; n],
        &vec![f64::INFINITY; n],
    )
}

/// The observation space as the reference's `spaces.Dict` (keys sorted).
pub fn observation_space(env: &MazeEnv) -> Space {
    Space::Dict(vec![
        ("achieved_goal".into(), unbounded(2)),
        ("desired_goal".into(), unbounded(2)),
        ("observation".into(), unbounded(env.observation_dim())),
    ])
}

impl MazeCollector {
    pub fn new(env: MazeEnv, mut options: CollectOptions) -> Result<MazeCollector, DatasetError> {
        options.info.numerics = Some(env.numerics().to_string());
        let a = env.action_space();
        let act_space = Space::box1(Dtype::F32, &a.low, &a.high);
        let writer = DatasetWriter::create(
            options.root.as_deref(),
            &options.dataset_id,
            options.format,
            observation_space(&env),
            act_space,
            options.info,
        )?;
        // `success`, then every key the robot reports after a step (reset rows are padded with
        // zeros for step-only keys).
        let mut infos = vec![InfoColumn {
            key: "success".into(),
            width: 1,
            values: vec![],
        }];
        infos.extend(env.robot().spec().info.iter().map(|i| InfoColumn {
            key: i.key.clone(),
            width: i.len.max(1),
            values: vec![],
        }));
        let act_dim = env.act_dim();
        Ok(MazeCollector {
            env,
            writer,
            obs: vec![],
            actions: vec![],
            action: vec![0.0; act_dim],
            rewards: vec![],
            terminations: vec![],
            truncations: vec![],
            infos,
        })
    }

    pub fn env(&self) -> &MazeEnv {
        &self.env
    }

    fn push_obs(buf: &mut Vec<f64>, o: &MazeObs) {
        buf.extend_from_slice(&o.achieved_goal);
        buf.extend_from_slice(&o.desired_goal);
        buf.extend_from_slice(&o.observation);
    }

    fn push_info(infos: &mut [InfoColumn], success: bool, info: crate::Info<'_>) {
        for c in infos.iter_mut() {
            if c.key == "success" {
                c.values.push(if success { 1.0 } else { 0.0 });
                continue;
            }
            match info.get(&c.key) {
                Some(v) if v.len() == c.width => c.values.extend_from_slice(v),
                _ => c.values.extend(std::iter::repeat_n(0.0, c.width)),
            }
        }
    }

    /// Reset with `seed`, run `policy` (it sees the dict observation) until the episode ends, and
    /// write the episode.
    pub fn episode(
        &mut self,
        seed: u64,
        policy: &mut dyn FnMut(&MazeObs, &mut [f32]),
    ) -> Result<EpisodeSummary, DatasetError> {
        self.obs.clear();
        self.actions.clear();
        self.rewards.clear();
        self.terminations.clear();
        self.truncations.clear();
        for c in &mut self.infos {
            c.values.clear();
        }
        let (o, success) = self.env.reset(Some(seed), None)?;
        Self::push_obs(&mut self.obs, o);
        let info = self.env.robot().reset_info();
        Self::push_info(&mut self.infos, success, info);
        let mut last = self.env.obs().clone();
        let terminated = loop {
            policy(&last, &mut self.action);
            let s = self.env.step_f32(&self.action)?;
            let (reward, term, trunc, success) = (s.reward, s.terminated, s.truncated, s.success);
            Self::push_info(&mut self.infos, success, s.robot_info);
            self.actions.extend_from_slice(&self.action);
            Self::push_obs(&mut self.obs, self.env.obs());
            self.rewards.push(reward);
            self.terminations.push(term);
            self.truncations.push(trunc);
            last.clone_from(self.env.obs());
            if term || trunc {
                break term;
            }
        };
        let record = EpisodeRecord {
            seed: Some(seed),
            observations: &self.obs,
            actions: &self.actions,
            rewards: &self.rewards,
            terminations: &self.terminations,
            truncations: &self.truncations,
            infos: &self.infos,
        };
        self.writer.write_episode(&record)?;
        Ok(EpisodeSummary {
            steps: self.rewards.len(),
            episode_return: self.rewards.iter().sum(),
            terminated,
        })
    }

    /// Finish the dataset; returns its directory.
    pub fn finish(self) -> Result<PathBuf, DatasetError> {
        self.writer.finish()
    }
}
