//! Reading a Minari dataset (written by envc or by Python's `DataCollector`).

use std::path::{Path, PathBuf};

use ndarray::Array1;
use serde_json::{Map, Value};

use crate::error::{DatasetError, io, malformed};
use crate::json::parse_lenient;
use crate::layout::default_root;
use crate::space::Space;
use crate::tensor::{Data, Episode, Tensor};
use crate::{Format, arrow_io};

/// An opened dataset: its metadata, ready to read episodes one at a time.
pub struct Dataset {
    /// The `data/` directory.
    pub data_path: PathBuf,
    /// The dataset's id.
    pub dataset_id: String,
    /// The storage backend.
    pub format: Format,
    /// The Minari version that wrote it.
    pub minari_version: String,
    /// Episodes stored.
    pub total_episodes: u64,
    /// Steps stored over all episodes.
    pub total_steps: u64,
    /// The observation space as stored.
    pub observation_space: Space,
    /// The action space as stored.
    pub action_space: Space,
    /// The Gymnasium env spec (parsed), if stored.
    pub env_spec: Option<Value>,
    /// Every key of `metadata.json`.
    pub metadata: Map<String, Value>,
    #[cfg(feature = "hdf5")]
    hdf5: Option<crate::hdf5_io::Hdf5Reader>,
}

/// An episode's own record of its length (`total_steps` attribute / per-episode metadata),
/// when stored, must match its arrays.
fn check_recorded_length(
    path: &Path,
    index: u64,
    recorded: Option<&Value>,
    len: usize,
) -> Result<(), DatasetError> {
    match recorded.and_then(Value::as_u64) {
        Some(n) if n != len as u64 => Err(malformed(
            path,
            format!("episode {index} holds {len} steps but records total_steps {n}"),
        )),
        _ => Ok(()),
    }
}

fn to_bool1(t: Tensor, path: &Path, what: &str) -> Result<Array1<bool>, DatasetError> {
    let a = match t {
        Tensor::Bool(a) => a,
        other => other.to_f64().mapv(|x| x != 0.0),
    };
    a.into_dimensionality()
        .map_err(|_| malformed(path, format!("{what} is not 1-D")))
}

impl Dataset {
    /// Open a dataset by path (its directory or its `data/` directory) or by id under the datasets
    /// root (`MINARI_DATASETS_PATH`, default `~/.minari/datasets`).
    pub fn open(path_or_id: &str) -> Result<Dataset, DatasetError> {
        let p = Path::new(path_or_id);
        let candidates = [
            p.join("data"),
            p.to_path_buf(),
            default_root().join(path_or_id).join("data"),
        ];
        let data = candidates
            .iter()
            .find(|c| c.join("metadata.json").is_file())
            .cloned()
            .ok_or_else(|| {
                malformed(
                    p,
                    format!(
                        "no data/metadata.json here nor under {}",
                        default_root().join(path_or_id).display()
                    ),
                )
            })?;
        Dataset::open_data(&data)
    }

    /// Open the `data/` directory of a dataset.
    pub fn open_data(data: &Path) -> Result<Dataset, DatasetError> {
        let meta_path = data.join("metadata.json");
        crate::error::regular_file(&meta_path)?;
        let text = std::fs::read_to_string(&meta_path).map_err(io(&meta_path))?;
        let metadata = match parse_lenient(&text) {
            Ok(Value::Object(m)) => m,
            Ok(_) => return Err(malformed(&meta_path, "not a JSON object")),
            Err(e) => return Err(malformed(&meta_path, e.to_string())),
        };
        let need = |k: &str| {
            metadata
                .get(k)
                .ok_or_else(|| malformed(&meta_path, format!("`{k}` is missing")))
        };
        let int = |k: &str| {
            need(k)?
                .as_u64()
                .ok_or_else(|| malformed(&meta_path, format!("`{k}` is not a count")))
        };
        let string = |k: &str| {
            need(k)?
                .as_str()
                .map(str::to_string)
                .ok_or_else(|| malformed(&meta_path, format!("`{k}` is not a string")))
        };
        let format = match string("data_format")?.as_str() {
            "arrow" => Format::Arrow,
            "hdf5" => Format::Hdf5,
            other => {
                return Err(DatasetError::Unsupported(format!(
                    "data_format `{other}` (envc reads arrow and hdf5)"
                )));
            }
        };
        let space = |k: &str| -> Result<Space, DatasetError> {
            Space::parse(&string(k).map_err(|_| {
                DatasetError::Unsupported(format!(
                    "{}: `{k}` is not stored (Minari would rebuild it from the env)",
                    meta_path.display()
                ))
            })?)
            .map_err(|why| malformed(&meta_path, format!("{k}: {why}")))
        };
        let env_spec = metadata
            .get("env_spec")
            .and_then(Value::as_str)
            .and_then(|s| parse_lenient(s).ok());
        #[cfg(feature = "hdf5")]
        let hdf5 = if format == Format::Hdf5 {
            Some(crate::hdf5_io::Hdf5Reader::open(data)?)
        } else {
            None
        };
        #[cfg(not(feature = "hdf5"))]
        if format == Format::Hdf5 {
            return Err(DatasetError::BackendMissing("hdf5"));
        }
        Ok(Dataset {
            data_path: data.to_path_buf(),
            dataset_id: string("dataset_id")?,
            format,
            minari_version: string("minari_version")?,
            total_episodes: int("total_episodes")?,
            total_steps: int("total_steps")?,
            observation_space: space("observation_space")?,
            action_space: space("action_space")?,
            env_spec,
            metadata,
            #[cfg(feature = "hdf5")]
            hdf5,
        })
    }

    /// The numerics profile envc recorded the data under (`envc_numerics`; absent in datasets
    /// written by Python). Replaying under it reproduces the data on any machine.
    pub fn numerics(&self) -> Option<envc::numerics::Profile> {
        envc::numerics::Profile::parse(self.metadata.get("envc_numerics")?.as_str()?)
    }

    /// The MuJoCo version the dataset was made with (`mujoco_version`; absent in datasets of an
    /// older envc and in Python `DataCollector`'s).
    pub fn mujoco_version(&self) -> Option<&str> {
        self.metadata.get("mujoco_version")?.as_str()
    }

    /// What made the dataset (`envc_provenance`: the spec's files, their hashes, the versions);
    /// absent in datasets of an older envc and in Python `DataCollector`'s.
    pub fn provenance(&self) -> Option<&Value> {
        self.metadata.get("envc_provenance")
    }

    /// The env that made the dataset, as [`crate::recover`] finds its spec (E1212 when the spec at
    /// the recorded id or path changed, E1213 when the record cannot be rebuilt), with the stored
    /// parameters and time limit, and the coded warnings (W1212, W1214). A dataset without a
    /// record opens the spec its env spec names (`spec_id`, else its id), as it did before.
    pub fn recover(
        &self,
        opts: crate::RecoverOptions,
    ) -> Result<(envc::AnyEnv, Vec<String>), DatasetError> {
        let (target, warnings) = match self.provenance() {
            Some(p) => {
                let r = crate::recover(&self.dataset_id, p, opts)?;
                (r.target, r.warnings)
            }
            None => {
                let mut w = vec![];
                crate::provenance::check_mujoco(
                    &self.dataset_id,
                    self.mujoco_version(),
                    opts,
                    &mut w,
                )?;
                (self.stored_spec_arg()?, w)
            }
        };
        let overrides = self.stored_overrides();
        Ok((envc::open(&target, &overrides)?, warnings))
    }

    /// What an env spec without a record names: envc's `spec_id`, else the reference id.
    fn stored_spec_arg(&self) -> Result<String, DatasetError> {
        let spec = self.env_spec.as_ref();
        let arg = spec
            .and_then(|s| s.get("kwargs")?.get("spec_id")?.as_str())
            .or_else(|| spec?.get("id")?.as_str())
            .ok_or_else(|| DatasetError::Provenance {
                why: format!(
                    "dataset `{}` stores neither envc_provenance nor an env spec; nothing names the env that made it",
                    self.dataset_id
                ),
            })?;
        Ok(arg.strip_prefix("envc/").unwrap_or(arg).to_string())
    }

    /// The env spec's kwargs and time limit as overrides.
    fn stored_overrides(&self) -> Vec<envspec::Override> {
        let Some(spec) = self.env_spec.as_ref() else {
            return vec![];
        };
        let mut out: Vec<envspec::Override> = spec
            .get("kwargs")
            .and_then(Value::as_object)
            .into_iter()
            .flatten()
            .filter(|(k, _)| !matches!(k.as_str(), "spec_id" | "envc_provenance"))
            .filter_map(|(k, v)| Some(envspec::Override::text(k, &toml_text(v)?)))
            .collect();
        if let Some(n) = spec.get("max_episode_steps").and_then(Value::as_u64) {
            out.push(envspec::Override::text("max_episode_steps", &n.to_string()));
        }
        out
    }

    /// The env id in the stored env spec.
    pub fn env_id(&self) -> Option<&str> {
        self.env_spec.as_ref()?.get("id")?.as_str()
    }

    /// The number of episodes.
    pub fn len(&self) -> usize {
        self.total_episodes as usize
    }
    /// Whether the dataset holds no episodes.
    pub fn is_empty(&self) -> bool {
        self.total_episodes == 0
    }

    /// Read episode `index`.
    pub fn episode(&self, index: u64) -> Result<Episode, DatasetError> {
        if index >= self.total_episodes {
            return Err(malformed(
                &self.data_path,
                format!(
                    "episode {index} requested; the dataset has {}",
                    self.total_episodes
                ),
            ));
        }
        let path = &self.data_path;
        match self.format {
            Format::Arrow => {
                let (batch, meta) = arrow_io::read_episode(path, index)?;
                let rows = batch.num_rows();
                if rows == 0 {
                    return Err(malformed(path, format!("episode {index} has no rows")));
                }
                let t = rows - 1;
                let col = |name: &str| {
                    batch.column_by_name(name).ok_or_else(|| {
                        malformed(path, format!("episode {index}: column `{name}` is missing"))
                    })
                };
                let observations = arrow_io::decode(
                    col("observations")?.as_ref(),
                    Some(&self.observation_space),
                    None,
                    path,
                )?;
                let actions = arrow_io::decode(
                    col("actions")?.as_ref(),
                    Some(&self.action_space),
                    None,
                    path,
                )?
                .head(t);
                let scalar = |name: &str| -> Result<Tensor, DatasetError> {
                    match arrow_io::decode(col(name)?.as_ref(), None, None, path)? {
                        Data::Tensor(x) => Ok(x.head(t)),
                        Data::Dict(_) => {
                            Err(malformed(path, format!("`{name}` is not a flat column")))
                        }
                    }
                };
                let infos = match batch.column_by_name("infos") {
                    Some(c) => match arrow_io::decode(c.as_ref(), None, None, path)? {
                        Data::Dict(items) => items,
                        Data::Tensor(_) => {
                            return Err(malformed(path, "`infos` is not a struct column"));
                        }
                    },
                    None => vec![],
                };
                check_recorded_length(path, index, meta.get("total_steps"), t)?;
                Ok(Episode {
                    id: index,
                    seed: meta.get("seed").and_then(Value::as_u64),
                    observations,
                    actions,
                    rewards: scalar("rewards")?,
                    terminations: to_bool1(scalar("terminations")?, path, "terminations")?,
                    truncations: to_bool1(scalar("truncations")?, path, "truncations")?,
                    infos,
                })
            }
            #[cfg(feature = "hdf5")]
            Format::Hdf5 => {
                let r = self
                    .hdf5
                    .as_ref()
                    .ok_or_else(|| malformed(path, "main_data.hdf5 is not open"))?;
                let raw = r.episode(index, &self.observation_space, &self.action_space)?;
                check_recorded_length(
                    path,
                    index,
                    raw.attrs.get("total_steps"),
                    raw.terminations.rows(),
                )?;
                Ok(Episode {
                    id: index,
                    seed: raw.attrs.get("seed").and_then(Value::as_u64),
                    observations: raw.observations,
                    actions: raw.actions,
                    rewards: raw.rewards,
                    terminations: to_bool1(raw.terminations, path, "terminations")?,
                    truncations: to_bool1(raw.truncations, path, "truncations")?,
                    infos: raw.infos,
                })
            }
            #[cfg(not(feature = "hdf5"))]
            Format::Hdf5 => Err(DatasetError::BackendMissing("hdf5")),
        }
    }

    /// How many episodes are stored on disk (whatever `total_episodes` says): numbered episode
    /// directories (arrow) or `episode_<i>` groups (hdf5).
    pub fn stored_episodes(&self) -> Result<u64, DatasetError> {
        match self.format {
            Format::Arrow => {
                let entries = std::fs::read_dir(&self.data_path).map_err(io(&self.data_path))?;
                let mut n = 0;
                for e in entries {
                    let e = e.map_err(io(&self.data_path))?;
                    let name = e.file_name();
                    let name = name.to_string_lossy();
                    if !name.is_empty() && name.bytes().all(|b| b.is_ascii_digit()) {
                        n += 1;
                    }
                }
                Ok(n)
            }
            #[cfg(feature = "hdf5")]
            Format::Hdf5 => self
                .hdf5
                .as_ref()
                .ok_or_else(|| malformed(&self.data_path, "main_data.hdf5 is not open"))?
                .episode_count(),
            #[cfg(not(feature = "hdf5"))]
            Format::Hdf5 => Err(DatasetError::BackendMissing("hdf5")),
        }
    }

    /// Read every episode and check the dataset is what its metadata says: exactly
    /// `total_episodes` episodes stored, each readable and as long as its own record says, their
    /// steps summing to `total_steps`. Returns each episode's length. A dataset that `open`s but
    /// fails this would load in Minari and fail when iterated.
    pub fn verify(&self) -> Result<Vec<u64>, DatasetError> {
        let stored = self.stored_episodes()?;
        if stored != self.total_episodes {
            return Err(malformed(
                &self.data_path,
                format!(
                    "{stored} episodes are stored but total_episodes is {}",
                    self.total_episodes
                ),
            ));
        }
        let mut lengths = Vec::with_capacity(self.len());
        for ep in self.episodes() {
            lengths.push(ep?.len() as u64);
        }
        let steps: u64 = lengths.iter().sum();
        if steps != self.total_steps {
            return Err(malformed(
                &self.data_path,
                format!(
                    "the episodes hold {steps} steps but total_steps is {}",
                    self.total_steps
                ),
            ));
        }
        Ok(lengths)
    }

    /// Every episode in order, read lazily.
    pub fn episodes(&self) -> impl Iterator<Item = Result<Episode, DatasetError>> + '_ {
        (0..self.total_episodes).map(|i| self.episode(i))
    }
}

/// A stored kwarg as TOML text (Python's `Infinity` markers included); tables are not stored.
fn toml_text(v: &Value) -> Option<String> {
    Some(match v {
        Value::Bool(b) => b.to_string(),
        Value::Number(n) if n.is_i64() || n.is_u64() => n.to_string(),
        Value::Array(a) => {
            let items: Option<Vec<String>> = a.iter().map(toml_text).collect();
            format!("[{}]", items?.join(", "))
        }
        Value::String(s) => match crate::json::number(v) {
            Some(x) => float_text(x),
            None => Value::String(s.clone()).to_string(),
        },
        _ => float_text(crate::json::number(v)?),
    })
}

fn float_text(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:?}")
    }
}
