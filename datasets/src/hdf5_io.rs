//! The HDF5 backend: `data/main_data.hdf5`, one group `episode_<i>` per episode with datasets
//! `observations [T+1, obs]`, `actions [T, act]`, `rewards [T]`, `terminations [T]`,
//! `truncations [T]` (bool = h5py's `enum<int8>{FALSE, TRUE}`), an `infos` group (always present,
//! T+1 rows per key) and attributes `id`, `total_steps`, `seed` (int64, uint64 at ≥ 2^63) and
//! Minari's reward statistics. Links the system libhdf5 through `hdf5-metno`.

use std::path::{Path, PathBuf};

use h5::types::{FloatSize, IntSize, TypeDescriptor};
use hdf5_metno as h5;
use ndarray::{ArrayView1, ArrayView2};
use serde_json::{Map, Value, json};

use crate::episode::EpisodeRecord;
use crate::error::{DatasetError, malformed};
use crate::space::Space;
use crate::tensor::{Data, Tensor};

pub struct Hdf5Writer {
    path: PathBuf,
    file: h5::File,
}

fn werr(path: &Path) -> impl Fn(h5::Error) -> DatasetError + '_ {
    move |e| h5_error(path, &e.to_string())
}

/// libhdf5's error text spans lines and embeds the OS error as `errno = N`: report that as the OS
/// error on the path (E1203, e.g. a full disk), anything else on one line (E1207).
fn h5_error(path: &Path, text: &str) -> DatasetError {
    let errno = text
        .split("errno = ")
        .nth(1)
        .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|digits| digits.parse::<i32>().ok());
    match errno {
        Some(n) if n > 0 => DatasetError::Io {
            path: path.to_path_buf(),
            error: std::io::Error::from_raw_os_error(n),
        },
        _ => DatasetError::Write {
            path: path.to_path_buf(),
            why: text.split_whitespace().collect::<Vec<_>>().join(" "),
        },
    }
}

impl Hdf5Writer {
    pub fn create(path: &Path) -> Result<Hdf5Writer, DatasetError> {
        let file = h5::File::create(path).map_err(werr(path))?;
        Ok(Hdf5Writer {
            path: path.to_path_buf(),
            file,
        })
    }

    pub fn write_episode(
        &mut self,
        index: u64,
        ep: &EpisodeRecord<'_>,
        obs_space: &Space,
        act_dim: usize,
    ) -> Result<(), DatasetError> {
        let obs_dim = obs_space.flat_len().unwrap_or(0);
        let e = werr(&self.path);
        let shape_err = |x: ndarray::ShapeError| DatasetError::Write {
            path: self.path.clone(),
            why: x.to_string(),
        };
        let t = ep.steps();
        let g = self
            .file
            .create_group(&format!("episode_{index}"))
            .map_err(&e)?;
        g.new_attr::<i64>()
            .create("id")
            .map_err(&e)?
            .write_scalar(&(index as i64))
            .map_err(&e)?;
        g.new_attr::<i64>()
            .create("total_steps")
            .map_err(&e)?
            .write_scalar(&(t as i64))
            .map_err(&e)?;
        if let Some(seed) = ep.seed {
            if let Ok(s) = i64::try_from(seed) {
                g.new_attr::<i64>()
                    .create("seed")
                    .map_err(&e)?
                    .write_scalar(&s)
                    .map_err(&e)?;
            } else {
                g.new_attr::<u64>()
                    .create("seed")
                    .map_err(&e)?
                    .write_scalar(&seed)
                    .map_err(&e)?;
            }
        }
        for (k, v) in ep.reward_stats() {
            g.new_attr::<f64>()
                .create(k)
                .map_err(&e)?
                .write_scalar(&v)
                .map_err(&e)?;
        }
        let obs = ArrayView2::from_shape((t + 1, obs_dim), ep.observations).map_err(shape_err)?;
        if let Space::Dict(items) = obs_space {
            // Dict observations: a group with one dataset per key (Minari's layout).
            let og = g.create_group("observations").map_err(&e)?;
            let mut off = 0;
            for (key, sub) in items {
                let w = sub.flat_len().unwrap_or(0);
                let part = obs.slice(ndarray::s![.., off..off + w]).to_owned();
                og.new_dataset_builder()
                    .with_data(&part)
                    .create(key.as_str())
                    .map_err(&e)?;
                off += w;
            }
        } else {
            g.new_dataset_builder()
                .with_data(&obs)
                .create("observations")
                .map_err(&e)?;
        }
        let act = ArrayView2::from_shape((t, act_dim), ep.actions).map_err(shape_err)?;
        g.new_dataset_builder()
            .with_data(&act)
            .create("actions")
            .map_err(&e)?;
        g.new_dataset_builder()
            .with_data(&ArrayView1::from(ep.rewards))
            .create("rewards")
            .map_err(&e)?;
        g.new_dataset_builder()
            .with_data(&ArrayView1::from(ep.terminations))
            .create("terminations")
            .map_err(&e)?;
        g.new_dataset_builder()
            .with_data(&ArrayView1::from(ep.truncations))
            .create("truncations")
            .map_err(&e)?;
        let infos = g.create_group("infos").map_err(&e)?;
        for c in ep.infos {
            if c.width == 1 {
                infos
                    .new_dataset_builder()
                    .with_data(&ArrayView1::from(&c.values[..]))
                    .create(c.key.as_str())
                    .map_err(&e)?;
            } else {
                let v =
                    ArrayView2::from_shape((t + 1, c.width), &c.values[..]).map_err(shape_err)?;
                infos
                    .new_dataset_builder()
                    .with_data(&v)
                    .create(c.key.as_str())
                    .map_err(&e)?;
            }
        }
        // Each finished episode reaches the disk before the next begins.
        self.file.flush().map_err(&e)?;
        Ok(())
    }

    pub fn close(self) -> Result<(), DatasetError> {
        let path = self.path.clone();
        self.file.close().map_err(werr(&path))
    }
}

fn read_tensor(ds: &h5::Dataset, path: &Path) -> Result<Tensor, DatasetError> {
    let bad = |e: h5::Error| malformed(path, format!("{}: {e}", ds.name()));
    let desc = ds.dtype().and_then(|d| d.to_descriptor()).map_err(bad)?;
    Ok(match desc {
        TypeDescriptor::Float(FloatSize::U8) => Tensor::F64(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Float(FloatSize::U4) => Tensor::F32(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Integer(IntSize::U8) => Tensor::I64(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Integer(IntSize::U4) => Tensor::I32(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Integer(IntSize::U2) => Tensor::I16(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Integer(IntSize::U1) => Tensor::I8(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Unsigned(IntSize::U1) => Tensor::U8(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Unsigned(IntSize::U8) => Tensor::U64(ds.read_dyn().map_err(bad)?),
        TypeDescriptor::Boolean => Tensor::Bool(ds.read_dyn().map_err(bad)?),
        other => {
            return Err(DatasetError::Unsupported(format!(
                "HDF5 type {other:?} of {} in {}",
                ds.name(),
                path.display()
            )));
        }
    })
}

fn read_node(
    g: &h5::Group,
    name: &str,
    space: Option<&Space>,
    path: &Path,
) -> Result<Data, DatasetError> {
    if let Ok(ds) = g.dataset(name) {
        return Ok(Data::Tensor(read_tensor(&ds, path)?));
    }
    let sub = g
        .group(name)
        .map_err(|_| malformed(path, format!("{}/{name} is missing", g.name())))?;
    read_group(&sub, space, path)
}

fn read_group(g: &h5::Group, space: Option<&Space>, path: &Path) -> Result<Data, DatasetError> {
    let names = g
        .member_names()
        .map_err(|e| malformed(path, e.to_string()))?;
    let mut out = vec![];
    match space {
        Some(Space::Tuple(items)) => {
            for (i, s) in items.iter().enumerate() {
                out.push((
                    i.to_string(),
                    read_node(g, &format!("_index_{i}"), Some(s), path)?,
                ));
            }
        }
        _ => {
            for n in names {
                let sub = match space {
                    Some(Space::Dict(items)) => Some(
                        &items
                            .iter()
                            .find(|(k, _)| *k == n)
                            .ok_or_else(|| {
                                malformed(path, format!("key `{n}` is not in the space"))
                            })?
                            .1,
                    ),
                    _ => None,
                };
                let d = read_node(g, &n, sub, path)?;
                out.push((n, d));
            }
        }
    }
    Ok(Data::Dict(out))
}

/// What one episode group holds.
pub struct RawEpisode {
    pub observations: Data,
    pub actions: Data,
    pub rewards: Tensor,
    pub terminations: Tensor,
    pub truncations: Tensor,
    pub infos: Vec<(String, Data)>,
    pub attrs: Map<String, Value>,
}

pub struct Hdf5Reader {
    path: PathBuf,
    file: h5::File,
}

impl Hdf5Reader {
    pub fn open(data: &Path) -> Result<Hdf5Reader, DatasetError> {
        let path = data.join("main_data.hdf5");
        if !path.is_file() {
            return Err(malformed(data, "main_data.hdf5 is missing"));
        }
        let file = h5::File::open(&path).map_err(|e| malformed(&path, e.to_string()))?;
        Ok(Hdf5Reader { path, file })
    }

    /// The number of `episode_<i>` groups in the file.
    pub fn episode_count(&self) -> Result<u64, DatasetError> {
        let names = self
            .file
            .member_names()
            .map_err(|e| malformed(&self.path, e.to_string()))?;
        Ok(names.iter().filter(|n| n.starts_with("episode_")).count() as u64)
    }

    pub fn episode(
        &self,
        index: u64,
        obs: &Space,
        act: &Space,
    ) -> Result<RawEpisode, DatasetError> {
        let p = &self.path;
        let g = self
            .file
            .group(&format!("episode_{index}"))
            .map_err(|_| malformed(p, format!("episode_{index} is missing")))?;
        let tensor = |name: &str| -> Result<Tensor, DatasetError> {
            read_tensor(
                &g.dataset(name)
                    .map_err(|_| malformed(p, format!("episode_{index}/{name} is missing")))?,
                p,
            )
        };
        let infos = match g.group("infos") {
            Ok(ig) => match read_group(&ig, None, p)? {
                Data::Dict(items) => items,
                Data::Tensor(_) => vec![],
            },
            Err(_) => vec![],
        };
        let mut attrs = Map::new();
        for name in g.attr_names().map_err(|e| malformed(p, e.to_string()))? {
            let Ok(a) = g.attr(&name) else { continue };
            let Ok(desc) = a.dtype().and_then(|d| d.to_descriptor()) else {
                continue;
            };
            let v = match desc {
                TypeDescriptor::Unsigned(_) => a.read_scalar::<u64>().ok().map(|x| json!(x)),
                TypeDescriptor::Integer(_) => a.read_scalar::<i64>().ok().map(|x| json!(x)),
                TypeDescriptor::Float(_) => a.read_scalar::<f64>().ok().map(|x| json!(x)),
                _ => None,
            };
            if let Some(v) = v {
                attrs.insert(name, v);
            }
        }
        Ok(RawEpisode {
            observations: read_node(&g, "observations", Some(obs), p)?,
            actions: read_node(&g, "actions", Some(act), p)?,
            rewards: tensor("rewards")?,
            terminations: tensor("terminations")?,
            truncations: tensor("truncations")?,
            infos,
            attrs,
        })
    }
}
