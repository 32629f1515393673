//! Writing a dataset: episodes stream into a hidden staging directory inside the datasets root;
//! `finish` writes `metadata.json` last and renames the directory into place in one step. A
//! collection that fails or is dropped removes its staging directory; one that is killed leaves
//! only a hidden `.envc-staging/…` directory without `metadata.json`, which Minari neither lists
//! nor loads (and which the next `DatasetWriter` in the same root removes once its process is gone).

use std::fs;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use super::episode::EpisodeRecord;
use super::error::{DatasetError, io};
use super::id::DatasetId;
use super::space::Space;
use super::{Format, MINARI_VERSION, arrow_io};

/// Name of the staging directory inside the datasets root (hidden: Minari skips it).
pub const STAGING_DIR: &str = ".envc-staging";

/// What goes into `metadata.json` besides the counts.
#[derive(Clone, Debug, Default)]
pub struct DatasetInfo {
    pub author: Vec<String>,
    pub author_email: Vec<String>,
    pub algorithm_name: Option<String>,
    pub code_permalink: Option<String>,
    pub description: Option<String>,
    /// Gymnasium `EnvSpec.to_json()` text (see [`super::env_spec_json`]).
    pub env_spec: Option<String>,
    /// pip requirements that `recover_environment` checks (warnings only).
    pub requirements: Vec<String>,
    /// The numerics profile the data was computed under (`envc_numerics` in metadata.json);
    /// replaying under it reproduces the data bit for bit on any machine.
    pub numerics: Option<String>,
}

enum Backend {
    Arrow,
    #[cfg(feature = "hdf5")]
    Hdf5(super::hdf5_io::Hdf5Writer),
}

/// Streams episodes to disk; nothing is visible as a dataset until [`DatasetWriter::finish`].
pub struct DatasetWriter {
    id: DatasetId,
    root: PathBuf,
    /// `root/.envc-staging/<unique>`; the dataset directory is `staging/ds`.
    staging: PathBuf,
    data: PathBuf,
    format: Format,
    backend: Option<Backend>,
    obs_space: Space,
    act_space: Space,
    info: DatasetInfo,
    episodes: u64,
    steps: u64,
    done: bool,
}

/// `MINARI_DATASETS_PATH`, or Minari's default `~/.minari/datasets`.
pub fn default_root() -> PathBuf {
    match std::env::var_os("MINARI_DATASETS_PATH") {
        Some(p) if !p.is_empty() => PathBuf::from(p),
        _ => {
            let home = std::env::var_os("HOME")
                .map(PathBuf::from)
                .unwrap_or_else(|| PathBuf::from("."));
            home.join(".minari").join("datasets")
        }
    }
}

fn pid_alive(pid: u32) -> bool {
    Path::new("/proc").join(pid.to_string()).exists()
}

/// Remove staging directories left by killed collections (their pid is gone).
fn sweep_stale(staging_root: &Path) {
    let Ok(entries) = fs::read_dir(staging_root) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let pid = name.rsplit('.').nth(1).and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid
            && pid != std::process::id()
            && !pid_alive(pid)
        {
            let _ = fs::remove_dir_all(e.path());
        }
    }
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
        let target = root.join(id.as_string());
        if target.exists() {
            return Err(DatasetError::Exists {
                id: id.as_string(),
                path: target,
            });
        }
        let staging_root = root.join(STAGING_DIR);
        fs::create_dir_all(&staging_root).map_err(io(&staging_root))?;
        sweep_stale(&staging_root);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        let unique = format!("{}-v{}.{}.{nanos}", id.name, id.version, std::process::id());
        let staging = staging_root.join(unique);
        let data = staging.join("ds").join("data");
        fs::create_dir_all(&data).map_err(io(&data))?;
        let backend = match format {
            Format::Arrow => Backend::Arrow,
            #[cfg(feature = "hdf5")]
            Format::Hdf5 => Backend::Hdf5(super::hdf5_io::Hdf5Writer::create(
                &data.join("main_data.hdf5"),
            )?),
            #[cfg(not(feature = "hdf5"))]
            Format::Hdf5 => return Err(DatasetError::BackendMissing("hdf5")),
        };
        Ok(DatasetWriter {
            id,
            root,
            staging,
            data,
            format,
            backend: Some(backend),
            obs_space,
            act_space,
            info,
            episodes: 0,
            steps: 0,
            done: false,
        })
    }

    pub fn id(&self) -> &DatasetId {
        &self.id
    }
    pub fn episodes(&self) -> u64 {
        self.episodes
    }
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// Where the dataset will be once finished.
    pub fn target(&self) -> PathBuf {
        self.root.join(self.id.as_string())
    }
    /// The staging directory (hidden) episodes are written to.
    pub fn staging(&self) -> &Path {
        &self.staging
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
        let index = self.episodes;
        match self.backend.as_mut() {
            Some(Backend::Arrow) => {
                arrow_io::write_episode(&self.data, index, ep, &self.obs_space, act_dim)?
            }
            #[cfg(feature = "hdf5")]
            Some(Backend::Hdf5(w)) => w.write_episode(index, ep, &self.obs_space, act_dim)?,
            None => return Err(bad("the writer is finished".into())),
        }
        self.episodes += 1;
        self.steps += t as u64;
        Ok(())
    }

    /// Write `metadata.json` and move the dataset into place. Returns its directory.
    pub fn finish(mut self) -> Result<PathBuf, DatasetError> {
        match self.backend.take() {
            #[cfg(feature = "hdf5")]
            Some(Backend::Hdf5(w)) => w.close()?,
            _ => {}
        }
        let target = self.target();
        if self.episodes == 0 {
            return Err(DatasetError::Write {
                path: target,
                why: "no episodes were recorded".into(),
            });
        }
        let size = dir_size(&self.data).map_err(io(&self.data))?;
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
        m.insert("minari_version".into(), json!(MINARI_VERSION));
        m.insert("envc_version".into(), json!(env!("CARGO_PKG_VERSION")));
        m.retain(|_, v| !v.is_null());
        let meta_path = self.data.join("metadata.json");
        let text = serde_json::to_string(&Value::Object(m)).map_err(|e| DatasetError::Write {
            path: meta_path.clone(),
            why: e.to_string(),
        })?;
        fs::write(&meta_path, text).map_err(io(&meta_path))?;

        // Namespaces (each level gets namespace_metadata.json, as Minari's create_dataset does).
        for level in self.id.namespace_levels() {
            let dir = self.root.join(&level);
            fs::create_dir_all(&dir).map_err(io(&dir))?;
            let f = dir.join("namespace_metadata.json");
            if !f.exists() {
                fs::write(&f, "{}").map_err(io(&f))?;
            }
        }
        if let Some(parent) = target.parent() {
            fs::create_dir_all(parent).map_err(io(parent))?;
        }
        if target.exists() {
            return Err(DatasetError::Exists {
                id: self.id.as_string(),
                path: target,
            });
        }
        // One rename: the dataset appears complete or not at all.
        fs::rename(self.staging.join("ds"), &target).map_err(io(&target))?;
        self.done = true;
        let _ = fs::remove_dir_all(&self.staging);
        let _ = fs::remove_dir(self.root.join(STAGING_DIR));
        Ok(target)
    }
}

impl Drop for DatasetWriter {
    fn drop(&mut self) {
        if !self.done {
            self.backend = None; // close files before removing them
            let _ = fs::remove_dir_all(&self.staging);
            let _ = fs::remove_dir(self.root.join(STAGING_DIR));
        }
    }
}

/// Total size of the files under `dir`.
pub fn dir_size(dir: &Path) -> std::io::Result<u64> {
    let mut total = 0;
    for e in fs::read_dir(dir)? {
        let e = e?;
        let meta = e.metadata()?;
        total += if meta.is_dir() {
            dir_size(&e.path())?
        } else {
            meta.len()
        };
    }
    Ok(total)
}
