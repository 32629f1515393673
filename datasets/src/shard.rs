//! Sharded collection: workers (processes, Ray actors, machines sharing the datasets root) record
//! episode ranges straight into the staging directory of a collection whose driver holds the lock
//! (`staging.rs`); the driver then publishes them with `Collector::finish_shards`.
//!
//! Arrow: an episode is written to the worker's `<staging>/tmp/0.<pid>.<nanos>/<i>/`, read back
//! (the worker's share of the E1210 check), and renamed to `<staging>/ds/data/<i>` in one step, so
//! `data/` only ever holds whole episodes, each the same bytes as one process would write. HDF5 keeps every episode in one file, which only the driver
//! can write: a worker writes `<staging>/shards/<i>.episode` (the episode's arrays, raw, renamed
//! into place the same way) and the driver appends them in index order with the one HDF5 writer.
//! A worker killed mid-episode leaves only a `tmp` entry, never inside the dataset; a rerun of an
//! episode that is already there keeps the first copy (same bytes).

use std::fs;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use crate::Format;
use crate::arrow_io;
use crate::collector::{Buffers, Policy};
use crate::episode::{EpisodeRecord, InfoColumn};
use crate::error::{DatasetError, io};
use crate::recordable::Recordable;
use crate::space::Space;

/// What a worker reports of each episode it recorded: all the driver needs to merge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShardEpisode {
    /// Steps the episode took.
    pub steps: u64,
    /// Bytes of its Arrow files (`dataset_size` is their sum); 0 for HDF5, where the driver
    /// measures the one file it writes.
    pub bytes: u64,
}

/// Where a worker writes raw HDF5-bound episodes inside the staging directory.
pub(crate) const SHARDS_DIR: &str = "shards";

/// Records episodes of one env into a sharded collection's staging directory.
pub(crate) struct ShardCollector<E, K> {
    env: E,
    kind: PhantomData<fn() -> K>,
    buffers: Buffers,
    staging: PathBuf,
    format: Format,
    obs_space: Space,
    act_dim: usize,
    /// The reset seed of the episode in the buffers.
    seed: u64,
    /// `<staging>/tmp/<pid>.<nanos>/`: episodes are written here, then renamed into place.
    tmp: Option<PathBuf>,
}

fn unique(n: u64) -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    format!("{n}.{}.{nanos}", std::process::id())
}

/// `dir` inside `staging`, created if missing, but never the staging directory itself: one that
/// is gone (its driver died and a sweep removed it) stays gone.
fn subdir(staging: &Path, name: &str) -> Result<PathBuf, DatasetError> {
    let dir = staging.join(name);
    if !staging.is_dir() {
        return Err(DatasetError::StagingLost {
            path: staging.to_path_buf(),
        });
    }
    match fs::create_dir(&dir) {
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => Err(io(&dir)(e)),
        _ => Ok(dir),
    }
}

/// Rename `from` to `to`; `to` already there (a finished earlier attempt) is kept and `from`
/// removed.
fn publish(from: &Path, to: &Path) -> Result<(), DatasetError> {
    match fs::rename(from, to) {
        Ok(()) => Ok(()),
        Err(e) if matches!(e.raw_os_error(), Some(libc::ENOTEMPTY | libc::EEXIST)) => {
            let _ = fs::remove_dir_all(from).or_else(|_| fs::remove_file(from));
            Ok(())
        }
        Err(e) => Err(io(to)(e)),
    }
}

impl<E: Recordable<K>, K> ShardCollector<E, K> {
    pub(crate) fn new(
        env: E,
        staging: &Path,
        format: Format,
    ) -> Result<ShardCollector<E, K>, DatasetError> {
        if format == Format::Hdf5 && !format.available() {
            return Err(DatasetError::BackendMissing("hdf5"));
        }
        if !staging.join("ds").join("data").is_dir() {
            return Err(DatasetError::StagingLost {
                path: staging.to_path_buf(),
            });
        }
        Ok(ShardCollector {
            buffers: Buffers::new(&env),
            obs_space: env.observation_space(),
            act_dim: env.action_space().dim(),
            env,
            kind: PhantomData,
            staging: staging.to_path_buf(),
            format,
            seed: 0,
            tmp: None,
        })
    }

    /// Run one episode (reset with `seed`) into the buffers.
    pub(crate) fn run(
        &mut self,
        seed: u64,
        policy: &mut impl Policy<E::Obs>,
    ) -> Result<(), DatasetError> {
        self.seed = seed;
        self.buffers.run(&mut self.env, seed, policy).map(|_| ())
    }

    /// This worker's own directory under `<staging>/tmp`, made once (not per episode).
    fn tmp(&mut self) -> Result<PathBuf, DatasetError> {
        if let Some(t) = &self.tmp {
            return Ok(t.clone());
        }
        let t = subdir(&self.staging, "tmp")?.join(unique(0));
        fs::create_dir(&t).map_err(io(&t))?;
        self.tmp = Some(t.clone());
        Ok(t)
    }

    /// Write the episode just run as episode `index`.
    pub(crate) fn write(&mut self, index: u64) -> Result<ShardEpisode, DatasetError> {
        let tmp = self.tmp()?;
        let record = self.buffers.record(self.seed);
        match self.format {
            Format::Arrow => {
                let written =
                    arrow_io::write_episode(&tmp, index, &record, &self.obs_space, self.act_dim)
                        .and_then(|()| read_back(&tmp, index, record.steps()));
                let from = tmp.join(index.to_string());
                let target = self.staging.join("ds").join("data").join(index.to_string());
                let published = written
                    .and_then(|()| crate::writer::dir_size(&from).map_err(io(&from)))
                    .and_then(|bytes| publish(&from, &target).map(|()| bytes));
                if published.is_err() {
                    let _ = fs::remove_dir_all(&from);
                }
                return Ok(ShardEpisode {
                    steps: record.steps() as u64,
                    bytes: published?,
                });
            }
            Format::Hdf5 => {
                let dir = subdir(&self.staging, SHARDS_DIR)?;
                let from = tmp.join(format!("{index}.episode"));
                fs::write(&from, encode(&record)).map_err(io(&from))?;
                publish(&from, &dir.join(format!("{index}.episode")))?;
            }
        }
        Ok(ShardEpisode {
            steps: record.steps() as u64,
            bytes: 0,
        })
    }
}

impl<E, K> Drop for ShardCollector<E, K> {
    fn drop(&mut self) {
        if let Some(t) = &self.tmp {
            let _ = fs::remove_dir_all(t);
        }
    }
}

/// The worker's share of the read-back check (E1210): the episode just written reads back, from
/// the shared storage, with its T+1 rows and its own `total_steps`. The driver then only checks
/// that every episode is in place, so the merge never reads the episode data (docs/SCALING.md).
fn read_back(tmp: &Path, index: u64, steps: usize) -> Result<(), DatasetError> {
    let (batch, meta) = arrow_io::read_episode(tmp, index)?;
    let stored = meta.get("total_steps").and_then(|v| v.as_u64());
    if batch.num_rows() != steps + 1 || stored != Some(steps as u64) {
        return Err(DatasetError::Unverified {
            path: tmp.join(index.to_string()),
            why: format!(
                "episode {index} reads back with {} rows and total_steps {stored:?}; {steps} steps were written",
                batch.num_rows()
            ),
        });
    }
    Ok(())
}

/// An episode read back from a shard file.
pub(crate) struct OwnedEpisode {
    pub seed: Option<u64>,
    pub observations: Vec<f64>,
    pub actions: Vec<f32>,
    pub rewards: Vec<f64>,
    pub terminations: Vec<bool>,
    pub truncations: Vec<bool>,
    pub infos: Vec<InfoColumn>,
}

impl OwnedEpisode {
    pub(crate) fn record(&self) -> EpisodeRecord<'_> {
        EpisodeRecord {
            seed: self.seed,
            observations: &self.observations,
            actions: &self.actions,
            rewards: &self.rewards,
            terminations: &self.terminations,
            truncations: &self.truncations,
            infos: &self.infos,
        }
    }
}

const MAGIC: &[u8; 8] = b"envcep01";

/// Little-endian: magic, seed (u64::MAX + flag), then each array as a u64 length and its values;
/// infos as a count, then key, width and values each.
fn encode(ep: &EpisodeRecord<'_>) -> Vec<u8> {
    let mut b = Vec::with_capacity(8 * (ep.observations.len() + 4 * ep.rewards.len()) + 64);
    b.extend_from_slice(MAGIC);
    b.push(u8::from(ep.seed.is_some()));
    b.extend_from_slice(&ep.seed.unwrap_or(0).to_le_bytes());
    let len = |b: &mut Vec<u8>, n: usize| b.extend_from_slice(&(n as u64).to_le_bytes());
    len(&mut b, ep.observations.len());
    ep.observations
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    len(&mut b, ep.actions.len());
    ep.actions
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    len(&mut b, ep.rewards.len());
    ep.rewards
        .iter()
        .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    for flags in [ep.terminations, ep.truncations] {
        len(&mut b, flags.len());
        b.extend(flags.iter().map(|&f| u8::from(f)));
    }
    len(&mut b, ep.infos.len());
    for c in ep.infos {
        len(&mut b, c.key.len());
        b.extend_from_slice(c.key.as_bytes());
        len(&mut b, c.width);
        len(&mut b, c.values.len());
        c.values
            .iter()
            .for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    }
    b
}

struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> Option<&[u8]> {
        let s = self.b.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn len(&mut self) -> Option<usize> {
        let n = usize::try_from(self.u64()?).ok()?;
        // Never allocate more than the file could hold.
        (n <= self.b.len()).then_some(n)
    }
    fn f64s(&mut self) -> Option<Vec<f64>> {
        let n = self.len()?;
        let raw = self.take(n.checked_mul(8)?)?;
        Some(
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect(),
        )
    }
}

/// Read a shard episode file; `None` for a truncated or foreign file.
fn decode(b: &[u8]) -> Option<OwnedEpisode> {
    let mut c = Cursor { b, at: 0 };
    if c.take(8)? != MAGIC {
        return None;
    }
    let has_seed = c.take(1)?[0] == 1;
    let seed = c.u64()?;
    let observations = c.f64s()?;
    let n = c.len()?;
    let actions = c
        .take(n.checked_mul(4)?)?
        .chunks_exact(4)
        .map(|x| f32::from_le_bytes(x.try_into().unwrap_or([0; 4])))
        .collect();
    let rewards = c.f64s()?;
    let mut flags = || -> Option<Vec<bool>> {
        let n = c.len()?;
        Some(c.take(n)?.iter().map(|&x| x == 1).collect())
    };
    let terminations = flags()?;
    let truncations = flags()?;
    let n = c.len()?;
    let mut infos = Vec::with_capacity(n.min(64));
    for _ in 0..n {
        let k = c.len()?;
        let key = String::from_utf8(c.take(k)?.to_vec()).ok()?;
        let width = c.len()?;
        let values = c.f64s()?;
        infos.push(InfoColumn { key, width, values });
    }
    (c.at == b.len()).then_some(OwnedEpisode {
        seed: has_seed.then_some(seed),
        observations,
        actions,
        rewards,
        terminations,
        truncations,
        infos,
    })
}

/// Read shard episode `index` from `staging` (E1600 when missing or damaged).
pub(crate) fn read_shard_episode(staging: &Path, index: u64) -> Result<OwnedEpisode, DatasetError> {
    let path = staging.join(SHARDS_DIR).join(format!("{index}.episode"));
    let missing = |why: String| DatasetError::ShardMissing {
        path: path.clone(),
        index,
        why,
    };
    let bytes = fs::read(&path).map_err(|e| missing(e.to_string()))?;
    decode(&bytes).ok_or_else(|| missing("truncated or not an envc shard episode".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_episodes_round_trip_and_damage_is_refused() {
        let infos = vec![InfoColumn {
            key: "x_position".into(),
            width: 1,
            values: vec![0.5, -1.25, 3.0],
        }];
        let rec = EpisodeRecord {
            seed: Some(42),
            observations: &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            actions: &[0.25, -0.5],
            rewards: &[1.5, f64::MIN_POSITIVE],
            terminations: &[false, true],
            truncations: &[false, false],
            infos: &infos,
        };
        let bytes = encode(&rec);
        let back = decode(&bytes).unwrap();
        assert_eq!(back.seed, Some(42));
        assert_eq!(back.observations, rec.observations);
        assert_eq!(back.actions, rec.actions);
        assert_eq!(back.rewards, rec.rewards);
        assert_eq!(back.terminations, rec.terminations);
        assert_eq!(back.truncations, rec.truncations);
        assert_eq!(back.infos[0].key, "x_position");
        assert_eq!(back.infos[0].values, infos[0].values);
        for cut in [0, 7, 9, 30, bytes.len() - 1] {
            assert!(decode(&bytes[..cut]).is_none(), "cut at {cut}");
        }
    }
}
