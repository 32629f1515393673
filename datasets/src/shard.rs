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
use std::path::{Path, PathBuf};

use crate::Format;
use crate::arrow_io;
use crate::collector::{Buffers, Policy};
use crate::error::{DatasetError, io};
use crate::layout::{SHARDS_DIR, dir_size};
use crate::recordable::Recordable;
use crate::shard_episode::{ShardEpisode, encode};
use crate::space::Space;

/// Records episodes of one env into a sharded collection's staging directory.
pub(crate) struct ShardCollector<E> {
    env: E,
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

impl<E: Recordable> ShardCollector<E> {
    pub(crate) fn new(
        env: E,
        staging: &Path,
        format: Format,
    ) -> Result<ShardCollector<E>, DatasetError> {
        crate::recordable::check_recordable(&env)?;
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
            act_dim: env.joint().act_dim(),
            env,
            staging: staging.to_path_buf(),
            format,
            seed: 0,
            tmp: None,
        })
    }

    /// Run one episode (reset with `seed`) into the buffers.
    pub(crate) fn run(&mut self, seed: u64, policy: &mut impl Policy) -> Result<(), DatasetError> {
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
                    .and_then(|()| dir_size(&from).map_err(io(&from)))
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

impl<E> Drop for ShardCollector<E> {
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
