//! Writing a dataset: episodes stream into a hidden staging directory inside the datasets root,
//! owned through a lock (`staging`); `finish` writes `metadata.json`, reads the staged dataset back
//! and checks it against what was written, syncs, and renames the directory into place in one
//! step. A collection that fails or is dropped removes its staging directory; one that is killed
//! leaves only a hidden `.envc-staging/…` directory, which Minari neither lists nor loads and which
//! the next `DatasetWriter` in the same root removes once the lock is free.

use std::fs;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use crate::episode::EpisodeRecord;
use crate::error::{DatasetError, io};
use crate::id::DatasetId;
use crate::layout::{SHARDS_DIR, STAGING_DIR, default_root, dir_size};
use crate::reader::Dataset;
use crate::shard_episode::{ShardEpisode, read_shard_episode};
use crate::space::Space;
use crate::staging::{self, Staging};
use crate::{Format, MINARI_VERSION, arrow_io};

/// What goes into `metadata.json` besides the counts.
#[derive(Clone, Debug, Default)]
pub struct DatasetInfo {
    /// Authors' names.
    pub author: Vec<String>,
    /// Their e-mail addresses.
    pub author_email: Vec<String>,
    /// The algorithm that made the data.
    pub algorithm_name: Option<String>,
    /// A link to the code that made the data.
    pub code_permalink: Option<String>,
    /// Free text about the dataset.
    pub description: Option<String>,
    /// Gymnasium `EnvSpec.to_json()` text (see [`crate::env_spec_json`]).
    pub env_spec: Option<String>,
    /// pip requirements that `recover_environment` checks (warnings only).
    pub requirements: Vec<String>,
    /// The numerics profile the data was computed under (`envc_numerics` in metadata.json);
    /// replaying under it reproduces the data bit for bit on any machine.
    pub numerics: Option<String>,
    /// Gymnasium `EnvSpec` JSON of the evaluation env (`eval_env_spec`).
    pub eval_env_spec: Option<String>,
    /// Minari's `ref_min_score`, `ref_max_score`, `num_episodes_average_score`.
    pub reference_scores: Option<crate::RefScores>,
    /// What made the dataset (`envc_provenance`: the spec's files and hashes, the versions);
    /// see `dataset::provenance`.
    pub provenance: Option<Value>,
}

enum Backend {
    Arrow,
    #[cfg(feature = "hdf5")]
    Hdf5(crate::hdf5_io::Hdf5Writer),
}

/// Streams episodes to disk; nothing is visible as a dataset until [`DatasetWriter::finish`].
pub struct DatasetWriter {
    id: DatasetId,
    root: PathBuf,
    /// `root/.envc-staging/<unique>`, held by its lock; the dataset directory is `staging/ds`.
    staging: Staging,
    /// Staging directories of dead collections removed when this one started.
    cleaned: Vec<PathBuf>,
    /// Directories in the staging root without a lock file, left alone.
    unlocked: Vec<PathBuf>,
    /// Each written episode's length, checked against the disk before publishing.
    lengths: Vec<u64>,
    data: PathBuf,
    format: Format,
    backend: Option<Backend>,
    obs_space: Space,
    act_space: Space,
    info: DatasetInfo,
    episodes: u64,
    steps: u64,
    /// Arrow episodes adopted from workers, each already read back and measured by its worker:
    /// their total size. `finish` then checks that every one is in place (one directory
    /// listing) instead of reading or `stat`ing them all again.
    shard_bytes: Option<u64>,
}

/// Refuse an id whose directory would sit inside another dataset (Minari would read the new one's
/// files as the outer dataset's episodes, or the outer one's as its own) or that names an existing
/// directory which is not a dataset (a namespace holding datasets). `target` exists as a dataset:
/// E1202.
fn check_place(root: &Path, id: &DatasetId) -> Result<(), DatasetError> {
    let text = id.as_string();
    let target = root.join(&text);
    let nested = |why: String| DatasetError::Nested {
        id: text.clone(),
        path: target.clone(),
        why,
    };
    // The root itself too: `--root` pointing into a dataset.
    let levels = std::iter::once(String::new()).chain(id.namespace_levels());
    for level in levels {
        let dir = if level.is_empty() {
            root.to_path_buf()
        } else {
            root.join(&level)
        };
        let place = if level.is_empty() {
            "the datasets root".to_string()
        } else {
            format!("`{level}`")
        };
        for meta in [
            dir.join("metadata.json"),
            dir.join("data").join("metadata.json"),
        ] {
            if meta.exists() {
                return Err(nested(format!(
                    "inside {place}, which holds a dataset ({})",
                    meta.display()
                )));
            }
        }
    }
    if target.join("data").join("metadata.json").is_file() {
        return Err(DatasetError::Exists {
            id: text,
            path: target,
        });
    }
    if fs::symlink_metadata(&target).is_ok() {
        return Err(nested(
            "which exists and is not a dataset (a namespace holding other datasets?)".into(),
        ));
    }
    Ok(())
}

/// The text of an error found while checking the staged dataset, without its own code (it is
/// reported under E1210).
fn cause(e: &DatasetError) -> String {
    match e {
        DatasetError::Malformed { path, why } => format!("{}: {why}", path.display()),
        DatasetError::Io { path, error } => format!("{}: {error}", path.display()),
        other => other.to_string(),
    }
}

/// Create `path` with `bytes` whole or not at all (a full disk never leaves a truncated file that
/// Minari would fail to parse), and never over a file that appeared meanwhile.
fn write_new(path: &Path, bytes: &[u8]) -> Result<(), DatasetError> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(
        ".{}.envc-{}.tmp",
        name.unwrap_or_default(),
        std::process::id()
    ));
    let linked = fs::write(&tmp, bytes).and_then(|()| match fs::hard_link(&tmp, path) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        other => other,
    });
    let _ = fs::remove_file(&tmp);
    linked.map_err(io(path))
}

/// Flush everything under `dir`'s file system to stable storage (one `syncfs`, not one fsync per
/// episode file), so the rename that publishes the dataset never reaches the disk before its data.
fn sync_fs(dir: &Path) -> Result<(), DatasetError> {
    envc::os::sync_fs(dir).map_err(io(dir))
}

impl DatasetWriter {
    /// Start a dataset `id` under `root` (`None`: [`default_root`]). Fails at once if the id is
    /// malformed or already taken.
    pub fn create(
        root: Option<&Path>,
        id: &str,
        format: Format,
        obs_space: Space,
        act_space: Space,
        info: DatasetInfo,
    ) -> Result<DatasetWriter, DatasetError> {
        let id = DatasetId::parse(id)?;
        if format == Format::Hdf5 && !cfg!(feature = "hdf5") {
            return Err(DatasetError::BackendMissing("hdf5"));
        }
        let root = root.map(Path::to_path_buf).unwrap_or_else(default_root);
        check_place(&root, &id)?;
        let staging_root = root.join(STAGING_DIR);
        let swept = staging::sweep(&staging_root);
        let staging = Staging::claim(&staging_root, &format!("{}-v{}", id.name, id.version))?;
        let data = staging.dir().join("ds").join("data");
        fs::create_dir_all(&data).map_err(io(&data))?;
        let backend = match format {
            Format::Arrow => Backend::Arrow,
            #[cfg(feature = "hdf5")]
            Format::Hdf5 => Backend::Hdf5(crate::hdf5_io::Hdf5Writer::create(
                &data.join("main_data.hdf5"),
            )?),
            #[cfg(not(feature = "hdf5"))]
            Format::Hdf5 => return Err(DatasetError::BackendMissing("hdf5")),
        };
        Ok(DatasetWriter {
            id,
            root,
            staging,
            cleaned: swept.removed,
            unlocked: swept.unlocked,
            lengths: vec![],
            data,
            format,
            backend: Some(backend),
            obs_space,
            act_space,
            info,
            episodes: 0,
            steps: 0,
            shard_bytes: None,
        })
    }

    /// The dataset's id.
    pub fn id(&self) -> &DatasetId {
        &self.id
    }
    /// Episodes written so far.
    pub fn episodes(&self) -> u64 {
        self.episodes
    }
    /// Steps written so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// Where the dataset will be once finished.
    pub fn target(&self) -> PathBuf {
        self.root.join(self.id.as_string())
    }
    /// The staging directory (hidden) episodes are written to.
    pub fn staging(&self) -> &Path {
        self.staging.dir()
    }
    /// Staging directories of interrupted collections (their lock free) this writer removed.
    pub fn cleaned(&self) -> &[PathBuf] {
        &self.cleaned
    }
    /// Directories in the staging root without a lock file (an older envc's, or not envc's):
    /// never removed, since nothing proves their collection is gone.
    pub fn unlocked(&self) -> &[PathBuf] {
        &self.unlocked
    }

    /// Write one whole episode to disk.
    pub fn write_episode(&mut self, ep: &EpisodeRecord<'_>) -> Result<(), DatasetError> {
        let t = ep.steps();
        let obs_dim = self.obs_space.flat_len().unwrap_or(0);
        let act_dim = self.act_space.flat_len().unwrap_or(0);
        let bad = |what: String| DatasetError::Write {
            path: self.data.clone(),
            why: what,
        };
        if t == 0 {
            return Err(bad("an episode needs at least one step".into()));
        }
        if ep.observations.len() != (t + 1) * obs_dim
            || ep.actions.len() != t * act_dim
            || ep.terminations.len() != t
            || ep.truncations.len() != t
        {
            return Err(bad(format!("episode arrays disagree with {t} steps")));
        }
        if let Some(c) = ep
            .infos
            .iter()
            .find(|c| c.values.len() != (t + 1) * c.width)
        {
            return Err(bad(format!(
                "info `{}` does not have {} rows",
                c.key,
                t + 1
            )));
        }
        // HDF5 would go on writing into a removed (unlinked) file: check ownership every episode.
        self.staging.check_owned()?;
        let index = self.episodes;
        let written = match self.backend.as_mut() {
            Some(Backend::Arrow) => {
                arrow_io::write_episode(&self.data, index, ep, &self.obs_space, act_dim)
            }
            #[cfg(feature = "hdf5")]
            Some(Backend::Hdf5(w)) => w.write_episode(index, ep, &self.obs_space, act_dim),
            None => return Err(bad("the writer is finished".into())),
        };
        // A write that failed because the directory vanished says so, not "no such file".
        if let Err(e) = written {
            return Err(self.lost_or(e));
        }
        self.lengths.push(t as u64);
        self.episodes += 1;
        self.steps += t as u64;
        Ok(())
    }

    /// Take over the episodes workers wrote into the staging directory (`shard.rs`): Arrow
    /// episodes are already in `data/`; HDF5 ones are appended from their shard files in index
    /// order. `lengths[i]` is episode i's step count as its worker reported it; [`finish`]
    /// checks them against the disk.
    ///
    /// [`finish`]: DatasetWriter::finish
    /// Remove staged shard episodes with an index of `keep` or more (recorded ahead of a budget
    /// that turned out to end before them), so that [`Self::adopt_shards`] sees episodes
    /// `0..keep` only.
    pub fn discard_shards_from(&mut self, keep: u64) -> Result<(), DatasetError> {
        self.staging.check_owned()?;
        let dirs = [
            (self.staging.dir().join("ds").join("data"), ""),
            (self.staging.dir().join(SHARDS_DIR), ".episode"),
        ];
        for (dir, suffix) in dirs {
            let Ok(rd) = fs::read_dir(&dir) else { continue };
            for e in rd.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                let index = name
                    .strip_suffix(suffix)
                    .and_then(|n| n.parse::<u64>().ok());
                if index.is_some_and(|i| i >= keep) {
                    let p = e.path();
                    let gone = if p.is_dir() {
                        fs::remove_dir_all(&p)
                    } else {
                        fs::remove_file(&p)
                    };
                    gone.map_err(io(&p))?;
                }
            }
        }
        Ok(())
    }

    /// Takes the episodes workers staged as this dataset's, in order (the driver of a sharded
    /// build).
    pub fn adopt_shards(&mut self, episodes: &[ShardEpisode]) -> Result<(), DatasetError> {
        if self.episodes != 0 {
            return Err(DatasetError::Write {
                path: self.data.clone(),
                why: "shards can only be adopted by a writer that wrote no episode itself".into(),
            });
        }
        self.staging.check_owned()?;
        match self.format {
            Format::Arrow => {
                self.lengths = episodes.iter().map(|e| e.steps).collect();
                self.episodes = episodes.len() as u64;
                self.steps = self.lengths.iter().sum();
                self.shard_bytes = Some(episodes.iter().map(|e| e.bytes).sum());
            }
            Format::Hdf5 => {
                for (i, e) in episodes.iter().enumerate() {
                    let ep = read_shard_episode(self.staging.dir(), i as u64)?;
                    if ep.rewards.len() as u64 != e.steps {
                        return Err(DatasetError::Unverified {
                            path: self.staging.dir().to_path_buf(),
                            why: format!(
                                "shard episode {i} holds {} steps; its worker reported {}",
                                ep.rewards.len(),
                                e.steps
                            ),
                        });
                    }
                    self.write_episode(&ep.record())?;
                    // The shard file is no longer needed once in the HDF5 file: free the disk.
                    let _ = fs::remove_file(
                        self.staging
                            .dir()
                            .join(SHARDS_DIR)
                            .join(format!("{i}.episode")),
                    );
                }
            }
        }
        Ok(())
    }

    /// Write `metadata.json` and move the dataset into place. Returns its directory.
    pub fn finish(mut self) -> Result<PathBuf, DatasetError> {
        match self.backend.take() {
            #[cfg(feature = "hdf5")]
            Some(Backend::Hdf5(w)) => {
                if let Err(e) = w.close() {
                    return Err(self.lost_or(e));
                }
            }
            _ => {}
        }
        self.staging.check_owned()?;
        let target = self.target();
        if self.episodes == 0 {
            return Err(DatasetError::Write {
                path: target,
                why: "no episodes were recorded".into(),
            });
        }
        let size = match self.shard_bytes {
            Some(bytes) => bytes,
            None => dir_size(&self.data).map_err(|e| self.lost_or(io(&self.data)(e)))?,
        };
        let mut m = Map::new();
        m.insert("total_episodes".into(), json!(self.episodes));
        m.insert("total_steps".into(), json!(self.steps));
        m.insert("data_format".into(), json!(self.format.name()));
        m.insert("jpeg_encoding".into(), json!(false));
        m.insert(
            "observation_space".into(),
            json!(self.obs_space.to_json_string()),
        );
        m.insert(
            "action_space".into(),
            json!(self.act_space.to_json_string()),
        );
        if let Some(spec) = &self.info.env_spec {
            m.insert("env_spec".into(), json!(spec));
        }
        if let Some(spec) = &self.info.eval_env_spec {
            m.insert("eval_env_spec".into(), json!(spec));
        }
        if let Some(r) = &self.info.reference_scores {
            m.insert("ref_min_score".into(), json!(r.ref_min_score));
            m.insert("ref_max_score".into(), json!(r.ref_max_score));
            m.insert(
                "num_episodes_average_score".into(),
                json!(r.num_episodes_average_score),
            );
        }
        // np.round(bytes / 1e6, 1), over the data directory (metadata.json is tiny).
        m.insert(
            "dataset_size".into(),
            json!((size as f64 / 1e6 * 10.0).round() / 10.0),
        );
        m.insert("dataset_id".into(), json!(self.id.as_string()));
        let opt = |s: &Option<String>| s.clone().map(Value::String).unwrap_or(Value::Null);
        m.insert("code_permalink".into(), opt(&self.info.code_permalink));
        m.insert("author".into(), json!(self.info.author));
        m.insert("author_email".into(), json!(self.info.author_email));
        m.insert("algorithm_name".into(), opt(&self.info.algorithm_name));
        m.insert("description".into(), opt(&self.info.description));
        if !self.info.requirements.is_empty() {
            m.insert("requirements".into(), json!(self.info.requirements));
        }
        if let Some(p) = &self.info.numerics {
            m.insert("envc_numerics".into(), json!(p));
        }
        if let Some(p) = &self.info.provenance {
            m.insert("envc_provenance".into(), p.clone());
        }
        m.insert("minari_version".into(), json!(MINARI_VERSION));
        m.insert("envc_version".into(), json!(env!("CARGO_PKG_VERSION")));
        m.insert("mujoco_version".into(), json!(envc::mujoco_version()));
        m.retain(|_, v| !v.is_null());
        let meta_path = self.data.join("metadata.json");
        let text = serde_json::to_string(&Value::Object(m)).map_err(|e| DatasetError::Write {
            path: meta_path.clone(),
            why: e.to_string(),
        })?;
        fs::write(&meta_path, text).map_err(|e| self.lost_or(io(&meta_path)(e)))?;

        // The metadata must describe exactly the episodes on disk, read back as a reader will.
        self.verify_staged()?;
        sync_fs(&self.data)?;
        self.staging.check_owned()?;

        // Checked again: another dataset may have appeared around the id since we started.
        check_place(&self.root, &self.id)?;
        // Namespaces (each level gets namespace_metadata.json, as Minari's create_dataset does).
        for level in self.id.namespace_levels() {
            let dir = self.root.join(&level);
            fs::create_dir_all(&dir).map_err(io(&dir))?;
            let f = dir.join("namespace_metadata.json");
            if !f.exists() {
                write_new(&f, b"{}")?;
            }
        }
        // One rename: the dataset appears complete or not at all. Onto a directory another
        // collection of the same id just published, it fails (ENOTEMPTY): never overwritten.
        if let Err(e) = fs::rename(self.staging.dir().join("ds"), &target) {
            return Err(
                if matches!(e.raw_os_error(), Some(libc::ENOTEMPTY | libc::EEXIST)) {
                    DatasetError::Exists {
                        id: self.id.as_string(),
                        path: target,
                    }
                } else {
                    io(&target)(e)
                },
            );
        }
        if let Some(parent) = target.parent() {
            // The rename itself reaches the disk (best effort: the dataset is already in place).
            let _ = fs::File::open(parent).and_then(|d| d.sync_all());
        }
        Ok(target)
    }

    /// `e`, or E1209 when it comes from the staging directory having been taken away: it is no
    /// longer ours, or a path we created inside it is gone (seen mid-way through an `rm -rf`).
    fn lost_or(&self, e: DatasetError) -> DatasetError {
        let missing = matches!(&e, DatasetError::Io { error, .. }
            if error.kind() == std::io::ErrorKind::NotFound);
        match self.staging.check_owned() {
            Err(lost) => lost,
            Ok(()) if missing => DatasetError::StagingLost {
                path: self.staging.dir().to_path_buf(),
            },
            Ok(()) => e,
        }
    }

    /// Read the staged dataset back and compare it with what was written.
    fn verify_staged(&self) -> Result<(), DatasetError> {
        let unverified = |why: String| DatasetError::Unverified {
            path: self.staging.dir().to_path_buf(),
            why,
        };
        if self.shard_bytes.is_some() {
            return self.verify_in_place();
        }
        let lengths = Dataset::open_data(&self.data)
            .and_then(|ds| {
                if ds.total_episodes != self.episodes || ds.total_steps != self.steps {
                    return Err(DatasetError::Write {
                        path: self.data.clone(),
                        why: "metadata.json was not written as recorded".into(),
                    });
                }
                ds.verify()
            })
            .map_err(|e| match self.staging.check_owned() {
                // A vanished directory is reported as such.
                Err(lost) => lost,
                Ok(()) => unverified(cause(&e)),
            })?;
        if let Some(i) = (0..self.lengths.len()).find(|&i| lengths[i] != self.lengths[i]) {
            return Err(unverified(format!(
                "episode {i} holds {} steps on disk; {} were written",
                lengths[i], self.lengths[i]
            )));
        }
        Ok(())
    }
}

impl DatasetWriter {
    /// Sharded Arrow episodes: each was read back by its worker before it was renamed into
    /// `data/`, so what is left is that `data/` holds exactly episodes `0..N` (one directory
    /// listing) and that the metadata parses as a reader's.
    fn verify_in_place(&self) -> Result<(), DatasetError> {
        let unverified = |why: String| DatasetError::Unverified {
            path: self.staging.dir().to_path_buf(),
            why,
        };
        let ds = Dataset::open_data(&self.data).map_err(|e| unverified(cause(&e)))?;
        if ds.total_episodes != self.episodes || ds.total_steps != self.steps {
            return Err(unverified(
                "metadata.json was not written as recorded".into(),
            ));
        }
        let mut seen = vec![false; self.episodes as usize];
        let entries = fs::read_dir(&self.data).map_err(|e| self.lost_or(io(&self.data)(e)))?;
        for e in entries {
            let e = e.map_err(|e| self.lost_or(io(&self.data)(e)))?;
            let name = e.file_name();
            let Some(i) = name.to_str().and_then(|n| n.parse::<usize>().ok()) else {
                continue; // metadata.json
            };
            match seen.get_mut(i) {
                Some(s) => *s = true,
                None => {
                    return Err(unverified(format!(
                        "episode {i} is stored but total_episodes is {}",
                        self.episodes
                    )));
                }
            }
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(match self.staging.check_owned() {
                Err(lost) => lost,
                Ok(()) => unverified(format!("episode {i} is missing")),
            });
        }
        Ok(())
    }
}

impl Drop for DatasetWriter {
    fn drop(&mut self) {
        // Close files before `staging` (dropped next) removes them, unless already published.
        self.backend = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::Dtype;

    fn writer(tag: &str) -> (PathBuf, DatasetWriter) {
        let root = std::env::temp_dir().join(format!("envc-writer-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&root);
        let obs = Space::box1(Dtype::F64, &[-1.0; 2], &[1.0; 2]);
        let act = Space::box1(Dtype::F32, &[-1.0], &[1.0]);
        let w = DatasetWriter::create(
            Some(&root),
            "ns/x-v0",
            Format::Arrow,
            obs,
            act,
            DatasetInfo::default(),
        )
        .unwrap();
        (root, w)
    }

    fn write(w: &mut DatasetWriter, steps: usize) {
        let obs = vec![0.5; (steps + 1) * 2];
        let actions = vec![0.25f32; steps];
        let rewards = vec![1.0; steps];
        let flags = vec![false; steps];
        w.write_episode(&EpisodeRecord {
            seed: Some(0),
            observations: &obs,
            actions: &actions,
            rewards: &rewards,
            terminations: &flags,
            truncations: &flags,
            infos: &[],
        })
        .unwrap();
    }

    /// Episodes damaged on disk after they were written: the metadata would lie, so nothing is
    /// published (E1210), and the staging directory is removed.
    #[test]
    fn a_dataset_that_disagrees_with_its_metadata_is_not_published() {
        for damage in ["missing episode", "wrong length"] {
            let (root, mut w) = writer(&damage.replace(' ', "-"));
            for steps in [3, 5, 4] {
                write(&mut w, steps);
            }
            let data = w.staging().join("ds").join("data");
            match damage {
                "missing episode" => fs::remove_dir_all(data.join("1")).unwrap(),
                _ => {
                    // Episode 0's file (3 steps) and metadata in place of episode 1's (5 steps).
                    for f in ["part-0.arrow", "metadata.json"] {
                        fs::copy(data.join("0").join(f), data.join("1").join(f)).unwrap();
                    }
                }
            }
            let target = w.target();
            let e = w.finish().unwrap_err();
            assert_eq!(e.code(), "E1210", "{damage}: {e}");
            let why = e.to_string();
            match damage {
                "missing episode" => assert!(
                    why.contains("2 episodes are stored but total_episodes is 3"),
                    "{why}"
                ),
                _ => assert!(
                    why.contains("the episodes hold 10 steps but total_steps is 12"),
                    "{why}"
                ),
            }
            assert!(!target.exists());
            assert!(!root.join(STAGING_DIR).exists());
            let _ = fs::remove_dir_all(&root);
        }
    }

    #[test]
    fn ids_inside_a_dataset_are_refused_before_anything_is_written() {
        let (root, mut w) = writer("nested");
        write(&mut w, 2);
        w.finish().unwrap();
        let inside = root.join("ns").join("x-v0").join("data");
        for (root, id) in [
            (&root, "ns/x-v0/data/0/y-v0"),
            (&root, "ns/x-v0/y-v0"),
            (&root, "ns/x-v0/data/y-v0"),
            (&inside, "y-v0"),
            (&inside.join("0"), "y-v0"),
        ] {
            let obs = Space::box1(Dtype::F64, &[-1.0; 2], &[1.0; 2]);
            let act = Space::box1(Dtype::F32, &[-1.0], &[1.0]);
            let e = DatasetWriter::create(
                Some(root),
                id,
                Format::Arrow,
                obs,
                act,
                DatasetInfo::default(),
            )
            .err()
            .unwrap();
            assert_eq!(e.code(), "E1208", "{id}: {e}");
        }
        assert!(!root.join(STAGING_DIR).exists());
        let _ = fs::remove_dir_all(&root);
    }
}
