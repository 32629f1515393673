//! The Arrow backend: `data/<i>/part-0.arrow` (an Arrow IPC *file* with one record batch of T+1
//! rows; actions, rewards, terminations and truncations padded with one zero row) and
//! `data/<i>/metadata.json` (`id`, `total_steps`, `seed`, reward statistics).

use std::collections::HashMap;
use std::fs::{self, File};
use std::io::BufWriter;
use std::path::Path;
use std::sync::Arc;

use arrow_array::{
    Array, ArrayRef, BooleanArray, FixedSizeListArray, Float32Array, Float64Array, RecordBatch,
    StructArray, cast::AsArray, types,
};
use arrow_schema::{DataType, Field, Fields, Schema};
use ndarray::{ArrayD, IxDyn};
use serde_json::{Map, Value, json};

use crate::episode::{EpisodeRecord, InfoColumn};
use crate::error::{DatasetError, io, malformed};
use crate::space::Space;
use crate::tensor::{Data, Tensor};

/// pyarrow's scanner re-chunks batches above this many rows, which misaligns Minari's reader.
pub const MAX_ARROW_STEPS: usize = 131_071;

fn list_field(dt: DataType) -> Arc<Field> {
    Arc::new(Field::new("item", dt, true))
}

fn fixed_list(
    dt: DataType,
    values: ArrayRef,
    width: usize,
) -> Result<FixedSizeListArray, arrow_schema::ArrowError> {
    FixedSizeListArray::try_new(list_field(dt), width as i32, values, None)
}

/// The observation column: fixed-size lists of float64 rows, or for Dict observations a struct
/// with one fixed-size-list field per key, cut from the concatenated rows (Minari decodes struct
/// fields by name).
fn obs_column(
    observations: &[f64],
    obs_space: &Space,
    obs_dim: usize,
) -> Result<ArrayRef, arrow_schema::ArrowError> {
    let Space::Dict(items) = obs_space else {
        let values = Arc::new(Float64Array::from(observations.to_vec()));
        return Ok(Arc::new(fixed_list(DataType::Float64, values, obs_dim)?));
    };
    let (mut fields, mut cols, mut off) = (vec![], vec![], 0);
    for (key, sub) in items {
        let w = sub.flat_len().unwrap_or(0);
        let values: Vec<f64> = observations
            .chunks(obs_dim.max(1))
            .flat_map(|row| row[off..off + w].iter().copied())
            .collect();
        let col = fixed_list(DataType::Float64, Arc::new(Float64Array::from(values)), w)?;
        fields.push(Field::new(key, col.data_type().clone(), true));
        cols.push(Arc::new(col) as ArrayRef);
        off += w;
    }
    Ok(Arc::new(StructArray::try_new(
        Fields::from(fields),
        cols,
        None,
    )?))
}

/// The `infos` struct column (None without info keys): float64 for one value per row, else a
/// fixed-size list with its width as the field's `shape` metadata.
fn info_column(infos: &[InfoColumn]) -> Result<Option<StructArray>, arrow_schema::ArrowError> {
    if infos.is_empty() {
        return Ok(None);
    }
    let mut info_fields = vec![];
    let mut info_cols: Vec<ArrayRef> = vec![];
    for c in infos {
        let values = Arc::new(Float64Array::from(c.values.clone()));
        if c.width == 1 {
            info_fields.push(Field::new(&c.key, DataType::Float64, true));
            info_cols.push(values);
        } else {
            let col = fixed_list(DataType::Float64, values, c.width)?;
            let meta = HashMap::from([("shape".to_string(), c.width.to_string())]);
            info_fields.push(Field::new(&c.key, col.data_type().clone(), true).with_metadata(meta));
            info_cols.push(Arc::new(col));
        }
    }
    StructArray::try_new(Fields::from(info_fields), info_cols, None).map(Some)
}

pub fn write_episode(
    data: &Path,
    index: u64,
    ep: &EpisodeRecord<'_>,
    obs_space: &Space,
    act_dim: usize,
) -> Result<(), DatasetError> {
    let t = ep.steps();
    let obs_dim = obs_space.flat_len().unwrap_or(0);
    let dir = data.join(index.to_string());
    let path = dir.join("part-0.arrow");
    // An I/O failure (a full disk) is reported as the OS error on the path (E1203), not as an
    // Arrow error wrapping it.
    let werr = |e: arrow_schema::ArrowError| match e {
        arrow_schema::ArrowError::IoError(_, error) => DatasetError::Io {
            path: path.clone(),
            error,
        },
        other => DatasetError::Write {
            path: path.clone(),
            why: other.to_string(),
        },
    };
    if t > MAX_ARROW_STEPS {
        return Err(DatasetError::Unsupported(format!(
            "an episode of {t} steps in the arrow format (Minari's reader splits episodes above {MAX_ARROW_STEPS} steps); use --format hdf5"
        )));
    }
    // Not `create_dir_all`: a removed staging directory must not be silently recreated.
    fs::create_dir(&dir).map_err(io(&dir))?;

    let obs = obs_column(ep.observations, obs_space, obs_dim).map_err(werr)?;
    let mut act = Vec::with_capacity((t + 1) * act_dim);
    act.extend_from_slice(ep.actions);
    act.resize((t + 1) * act_dim, 0.0);
    let act = fixed_list(
        DataType::Float32,
        Arc::new(Float32Array::from(act)),
        act_dim,
    )
    .map_err(werr)?;
    let pad_f = |v: &[f64]| Float64Array::from_iter_values(v.iter().copied().chain([0.0]));
    let pad_b =
        |v: &[bool]| BooleanArray::from(v.iter().copied().chain([false]).collect::<Vec<_>>());

    let mut fields = vec![
        Field::new("observations", obs.data_type().clone(), true),
        Field::new("actions", act.data_type().clone(), true),
        Field::new("rewards", DataType::Float64, true),
        Field::new("terminations", DataType::Boolean, true),
        Field::new("truncations", DataType::Boolean, true),
    ];
    let mut columns: Vec<ArrayRef> = vec![
        obs,
        Arc::new(act),
        Arc::new(pad_f(ep.rewards)),
        Arc::new(pad_b(ep.terminations)),
        Arc::new(pad_b(ep.truncations)),
    ];
    if let Some(infos) = info_column(ep.infos).map_err(werr)? {
        fields.push(Field::new("infos", infos.data_type().clone(), true));
        columns.push(Arc::new(infos));
    }
    let schema = Arc::new(Schema::new(fields));
    let batch = RecordBatch::try_new(schema.clone(), columns).map_err(werr)?;
    let file = File::create(&path).map_err(io(&path))?;
    let mut w =
        arrow_ipc::writer::FileWriter::try_new(BufWriter::new(file), &schema).map_err(werr)?;
    w.write(&batch).map_err(werr)?;
    w.finish().map_err(werr)?;
    let mut inner = w.into_inner().map_err(werr)?;
    std::io::Write::flush(&mut inner).map_err(io(&path))?;

    let mut m = Map::new();
    m.insert("id".into(), json!(index));
    m.insert("total_steps".into(), json!(t));
    if let Some(s) = ep.seed {
        m.insert("seed".into(), json!(s));
    }
    for (k, v) in ep.reward_stats() {
        m.insert(k.into(), json!(v));
    }
    let meta = dir.join("metadata.json");
    fs::write(&meta, Value::Object(m).to_string()).map_err(io(&meta))?;
    Ok(())
}

/// The one data file of an episode directory (Minari reads every file not named `metadata.json`
/// and not starting with `_` or `.`).
fn data_file(dir: &Path, ext: &str) -> Result<std::path::PathBuf, DatasetError> {
    let mut found = vec![];
    for e in fs::read_dir(dir).map_err(io(dir))?.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name != "metadata.json" && !name.starts_with('_') && !name.starts_with('.') {
            found.push(e.path());
        }
    }
    match found.as_slice() {
        [one] if one.extension().is_some_and(|x| x == ext) => Ok(one.clone()),
        [one] => Err(DatasetError::Unsupported(format!(
            "{} (only Arrow IPC `.arrow` episode files are read)",
            one.display()
        ))),
        [] => Err(malformed(dir, "no episode data file")),
        _ => Err(malformed(dir, "more than one episode data file")),
    }
}

/// Read episode `index`: the columns with T+1 rows (pads still attached) and its metadata.json.
pub fn read_episode(
    data: &Path,
    index: u64,
) -> Result<(RecordBatch, Map<String, Value>), DatasetError> {
    let dir = data.join(index.to_string());
    let path = data_file(&dir, "arrow")?;
    crate::error::regular_file(&path)?;
    let file = File::open(&path).map_err(io(&path))?;
    let bad = |e: arrow_schema::ArrowError| malformed(&path, e.to_string());
    let reader =
        arrow_ipc::reader::FileReader::try_new(std::io::BufReader::new(file), None).map_err(bad)?;
    let schema = reader.schema();
    let batches = reader.collect::<Result<Vec<_>, _>>().map_err(bad)?;
    let batch = arrow_select_concat(&schema, &batches).map_err(bad)?;
    let meta_path = dir.join("metadata.json");
    if meta_path.exists() {
        crate::error::regular_file(&meta_path)?;
    }
    let meta = match fs::read_to_string(&meta_path) {
        Ok(text) => match serde_json::from_str(&text) {
            Ok(Value::Object(m)) => m,
            _ => return Err(malformed(&meta_path, "not a JSON object")),
        },
        Err(_) => Map::new(),
    };
    Ok((batch, meta))
}

/// Minari writes one batch per episode; several are joined (by copying) for robustness.
fn arrow_select_concat(
    schema: &Arc<Schema>,
    batches: &[RecordBatch],
) -> Result<RecordBatch, arrow_schema::ArrowError> {
    match batches {
        [one] => Ok(one.clone()),
        [] => Ok(RecordBatch::new_empty(schema.clone())),
        _ => Err(arrow_schema::ArrowError::InvalidArgumentError(format!(
            "{} record batches in one episode file (Minari expects exactly one)",
            batches.len()
        ))),
    }
}

fn prim_tensor(
    a: &dyn Array,
    rows: usize,
    inner: &[usize],
    path: &Path,
) -> Result<Tensor, DatasetError> {
    let mut shape = vec![rows];
    shape.extend_from_slice(inner);
    let sh = IxDyn(&shape);
    let want: usize = shape.iter().product();
    if a.len() != want {
        return Err(malformed(
            path,
            format!(
                "column has {} values, expected {want} for shape {shape:?}",
                a.len()
            ),
        ));
    }
    if a.null_count() > 0 {
        return Err(malformed(path, "null values in a numeric column"));
    }
    let fail = |e: ndarray::ShapeError| malformed(path, e.to_string());
    Ok(match a.data_type() {
        DataType::Float64 => Tensor::F64(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Float64Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Float32 => Tensor::F32(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Float32Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Int64 => Tensor::I64(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Int64Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Int32 => Tensor::I32(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Int32Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Int16 => Tensor::I16(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Int16Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Int8 => Tensor::I8(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::Int8Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::UInt8 => Tensor::U8(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::UInt8Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::UInt64 => Tensor::U64(
            ArrayD::from_shape_vec(sh, a.as_primitive::<types::UInt64Type>().values().to_vec())
                .map_err(fail)?,
        ),
        DataType::Boolean => Tensor::Bool(
            ArrayD::from_shape_vec(
                sh,
                a.as_boolean().iter().map(|b| b.unwrap_or(false)).collect(),
            )
            .map_err(fail)?,
        ),
        other => {
            return Err(DatasetError::Unsupported(format!(
                "Arrow column type {other} in {}",
                path.display()
            )));
        }
    })
}

/// Decode a column (T+1 rows) against its space; `None` space: decode by the Arrow type alone
/// (infos), using the `shape` field metadata of fixed-size lists.
pub fn decode(
    a: &dyn Array,
    space: Option<&Space>,
    meta_shape: Option<&str>,
    path: &Path,
) -> Result<Data, DatasetError> {
    let rows = a.len();
    match (a.data_type(), space) {
        (DataType::Struct(fields), sp) => {
            let s = a.as_struct();
            let mut out = vec![];
            for (i, f) in fields.iter().enumerate() {
                let sub = match sp {
                    Some(Space::Dict(items)) => Some(
                        &items
                            .iter()
                            .find(|(k, _)| k == f.name())
                            .ok_or_else(|| {
                                malformed(path, format!("key `{}` is not in the space", f.name()))
                            })?
                            .1,
                    ),
                    Some(Space::Tuple(items)) => {
                        f.name().parse::<usize>().ok().and_then(|k| items.get(k))
                    }
                    _ => None,
                };
                let shape = f.metadata().get("shape").map(String::as_str);
                out.push((
                    f.name().clone(),
                    decode(s.column(i).as_ref(), sub, shape, path)?,
                ));
            }
            Ok(Data::Dict(out))
        }
        (DataType::FixedSizeList(_, width), sp) => {
            let l = a.as_fixed_size_list();
            let inner: Vec<usize> = match (sp, meta_shape) {
                (Some(Space::Box { shape, .. }), _) => shape.clone(),
                (_, Some(text)) if !text.is_empty() => text
                    .split(',')
                    .map(|d| d.trim().parse::<usize>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| malformed(path, format!("bad shape metadata `{text}`")))?,
                _ => vec![*width as usize],
            };
            // The child values of the rows in view (the list may be a slice).
            let w = *width as usize;
            let values = l.values().slice(l.offset() * w, rows * w);
            Ok(Data::Tensor(prim_tensor(
                values.as_ref(),
                rows,
                &inner,
                path,
            )?))
        }
        (_, Some(Space::Box { shape, .. })) if shape.is_empty() => {
            Ok(Data::Tensor(prim_tensor(a, rows, &[], path)?))
        }
        _ => Ok(Data::Tensor(prim_tensor(a, rows, &[], path)?)),
    }
}
