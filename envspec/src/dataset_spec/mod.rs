//! Dataset specs (`specs/datasets/**.toml`): a Minari dataset declared as data. Each names the
//! env spec and its parameters, the tier, the policy file and how to run it, the budget, the seed
//! (episode k is reset with `seed + k`), the metadata, and optionally the reference scores;
//! `[train]` is read by the training script only. Every mistake is E1801 at its line and column.
//!
//! The file is read through [`crate::source`], so it is bounded, refused when it is not a regular
//! file, and recorded like every other spec input. What only a dataset writer checks (the id as
//! Minari parses it) is the datasets crate's; the reference-score rewrite is [`edit`].

pub mod edit;

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;
use toml::de::{DeTable, DeValue};

use crate::diagnostic::{Code, Diagnostic, Location, SourceFile};
use crate::limits::{MAX_DATASET_STEPS, MAX_EPISODES, MAX_SPEC_BYTES};

/// How the policy's actions are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PolicyMode {
    /// The mean action (SAC/TQC: tanh(mu) scaled to the bounds; PPO: the mean, clipped).
    Deterministic,
    /// Gaussian noise from episode k's `default_rng([seed, k])` only.
    Stochastic,
}

/// The storage a dataset spec asks for (`format = "arrow"` unless `"hdf5"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StorageFormat {
    /// Arrow IPC files: the same bytes on every build.
    Arrow,
    /// One HDF5 file.
    Hdf5,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    dataset: DatasetTable,
    policy: PolicyTable,
    metadata: MetadataTable,
    #[serde(default)]
    reference_scores: Option<RefScores>,
    /// Training settings (scripts/train_policy.py); kept in `document` only.
    #[serde(default)]
    #[allow(dead_code)]
    train: Option<toml::Table>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DatasetTable {
    id: String,
    tier: String,
    env: String,
    #[serde(default)]
    params: toml::Table,
    steps: Option<u64>,
    episodes: Option<u64>,
    seed: u64,
    #[serde(default)]
    format: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PolicyTable {
    file: String,
    mode: PolicyMode,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MetadataTable {
    algorithm_name: String,
    author: Vec<String>,
    #[serde(default)]
    author_email: Vec<String>,
    code_permalink: Option<String>,
    description: String,
    eval_env: Option<String>,
    #[serde(default)]
    eval_params: toml::Table,
}

/// Minari's reference scores: the mean return over `num_episodes_average_score` episodes of the
/// evaluation env, of a random policy (min) and of the expert tier's policy (max).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefScores {
    /// The random policy's mean return.
    pub ref_min_score: f64,
    /// The expert policy's mean return.
    pub ref_max_score: f64,
    /// Episodes averaged for each.
    pub num_episodes_average_score: u64,
}

/// The budget: a step budget is filled as the original scripts did, episode by episode, starting
/// a new one only while at least `max_episode_steps` steps remain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Budget {
    /// At most this many steps, in whole episodes.
    Steps(u64),
    /// Exactly this many episodes.
    Episodes(u64),
}

/// A read dataset spec, paths resolved against its file.
#[derive(Clone, Debug)]
pub struct DatasetSpec {
    /// The spec file.
    pub path: PathBuf,
    /// The Minari id, `namespace/name-vN` (checked as Minari parses it by the datasets crate).
    pub dataset_id: String,
    /// Where the id was written, for that check's error.
    pub dataset_id_at: Location,
    /// `expert`, `medium` or `simple`.
    pub tier: String,
    /// A bundled env id, or a spec file's path.
    pub env: String,
    /// `(name, TOML literal)` overrides, stored as the env spec's kwargs.
    pub params: Vec<(String, String)>,
    /// How much to record.
    pub budget: Budget,
    /// Episode k resets with `seed + k`.
    pub seed: u64,
    /// Arrow or HDF5.
    pub format: StorageFormat,
    /// The `.npz` policy, resolved against the spec's directory.
    pub policy_file: PathBuf,
    /// Deterministic, or seeded-stochastic from episode k's generator.
    pub mode: PolicyMode,
    /// Minari's `algorithm_name` metadata.
    pub algorithm_name: String,
    /// Minari's `author` metadata.
    pub author: Vec<String>,
    /// Minari's `author_email` metadata.
    pub author_email: Vec<String>,
    /// Minari's `code_permalink` metadata.
    pub code_permalink: Option<String>,
    /// The published tier description.
    pub description: String,
    /// The env reference scores are measured on (Minari's `eval_env_spec`).
    pub eval_env: String,
    /// That env's overrides.
    pub eval_params: Vec<(String, String)>,
    /// Minari's reference scores, once measured.
    pub reference_scores: Option<RefScores>,
    /// The whole file as TOML data, `[train]` included, as written (nothing resolved): what
    /// the Python package and the scripts read.
    pub document: toml::Table,
}

/// The bundled dataset specs' directory (`specs/datasets`).
pub fn datasets_dir() -> PathBuf {
    crate::registry::specs_dir().join("datasets")
}

/// Every bundled dataset spec, sorted by path.
pub fn bundled() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "toml") {
                out.push(p);
            }
        }
    }
    let mut out = vec![];
    walk(&datasets_dir(), &mut out);
    out.sort();
    out
}

/// The file `what` names: itself when it is a file (or ends in `.toml`), else the bundled
/// dataset of that id (`mujoco/hopper/simple-v0`); and whether it was named as a file.
pub fn path_of(what: &str) -> (PathBuf, bool) {
    let p = Path::new(what);
    if p.is_file() || what.ends_with(".toml") {
        (p.to_path_buf(), true)
    } else {
        (datasets_dir().join(format!("{what}.toml")), false)
    }
}

/// A dataset spec file, or a bundled dataset's id (`mujoco/hopper/simple-v0`).
pub fn open(what: &str) -> Result<DatasetSpec, Diagnostic> {
    let (path, named_file) = path_of(what);
    read(&path).map_err(|d| match d.location {
        None if !named_file => Diagnostic::new(
            Code::E1801,
            format!(
                "`{what}` is neither a dataset spec file nor a bundled dataset id ({})",
                d.message
            ),
        ),
        _ => d,
    })
}

/// Read a dataset spec file (bounded, regular files only: a FIFO would block the read for ever),
/// recording the read with the installed [`crate::source::Reader`].
pub fn read(path: &Path) -> Result<DatasetSpec, Diagnostic> {
    parse(&read_file(path)?)
}

/// The file's text, read through [`crate::source`]; every failure is E1801, a file too large
/// included (E0110 for other spec files): the dataset spec's one code.
fn read_file(path: &Path) -> Result<Arc<SourceFile>, Diagnostic> {
    crate::source::read_source(path, MAX_SPEC_BYTES, Code::E1801, "dataset spec", |e| {
        Diagnostic::new(Code::E1801, e.to_string())
    })
}

/// Read a dataset spec's text; its path locates errors and resolves the policy file.
pub fn parse(file: &Arc<SourceFile>) -> Result<DatasetSpec, Diagnostic> {
    let text = file.text.as_str();
    let err = |span: Range<usize>, why: String| {
        Diagnostic::new(Code::E1801, why).at(Location::new(file, span))
    };
    // Parsed straight from the text, so a schema error (an unknown or missing key, a wrong type)
    // keeps its span; the same text again as plain data for `document`.
    let spanned =
        |e: toml::de::Error| err(e.span().unwrap_or(0..0), e.message().trim().to_string());
    let parsed: File = toml::from_str(text).map_err(spanned)?;
    let document: toml::Table = toml::from_str(text).map_err(spanned)?;
    let key = |key: &str| key_span(text, "dataset", key).unwrap_or(0..0);
    let d = parsed.dataset;
    let budget = budget(d.steps, d.episodes).map_err(|(k, why)| err(key(k), why))?;
    let format = match d.format.as_deref() {
        None | Some("arrow") => StorageFormat::Arrow,
        Some("hdf5") => StorageFormat::Hdf5,
        Some(other) => {
            return Err(err(
                key("format"),
                format!("format = {other:?}: expected \"arrow\" or \"hdf5\""),
            ));
        }
    };
    if let Some(r) = parsed.reference_scores
        && !(r.ref_min_score.is_finite()
            && r.ref_max_score.is_finite()
            && r.ref_max_score != r.ref_min_score)
    {
        return Err(err(
            key_span(text, "reference_scores", "ref_max_score").unwrap_or(0..0),
            "reference scores must be finite and differ".into(),
        ));
    }
    let dir = file.path.parent().unwrap_or(Path::new("."));
    // An env named by a path is relative to this file; otherwise it is a bundled id.
    let env_at = |name: &str| {
        let p = dir.join(name);
        if name.ends_with(".toml") || p.is_file() {
            p.display().to_string()
        } else {
            name.to_string()
        }
    };
    let m = parsed.metadata;
    Ok(DatasetSpec {
        path: file.path.clone(),
        dataset_id_at: Location::new(file, key("id")),
        dataset_id: d.id,
        tier: d.tier,
        env: env_at(&d.env),
        params: literal(&d.params),
        budget,
        seed: d.seed,
        format,
        policy_file: dir.join(&parsed.policy.file),
        mode: parsed.policy.mode,
        algorithm_name: m.algorithm_name,
        author: m.author,
        author_email: m.author_email,
        code_permalink: m.code_permalink,
        description: m.description,
        eval_env: env_at(m.eval_env.as_deref().unwrap_or(&d.env)),
        eval_params: if m.eval_env.is_some() {
            literal(&m.eval_params)
        } else {
            literal(&d.params)
        },
        reference_scores: parsed.reference_scores,
        document,
    })
}

/// The budget from `steps` and `episodes`; a refusal names the key to point at.
fn budget(steps: Option<u64>, episodes: Option<u64>) -> Result<Budget, (&'static str, String)> {
    match (steps, episodes) {
        (Some(0), _) => Err(("steps", "steps must be ≥ 1".into())),
        (_, Some(0)) => Err(("episodes", "episodes must be ≥ 1".into())),
        (_, Some(e)) if e > MAX_EPISODES => Err((
            "episodes",
            format!("episodes = {e} is beyond envc's limit of {MAX_EPISODES}"),
        )),
        (Some(s), _) if s > MAX_DATASET_STEPS => Err((
            "steps",
            format!("steps = {s} is beyond envc's limit of {MAX_DATASET_STEPS}"),
        )),
        (Some(s), None) => Ok(Budget::Steps(s)),
        (None, Some(e)) => Ok(Budget::Episodes(e)),
        (Some(_), Some(_)) => Err(("episodes", "give `steps` or `episodes`, not both".into())),
        (None, None) => Err((
            "[dataset]",
            "[dataset] needs a budget: `steps = N` or `episodes = N`".into(),
        )),
    }
}

/// The span of `key` in the top-level table `table` (`"[dataset]"` as the key: the table's own
/// name in its header), for checks made after parsing.
fn key_span(text: &str, table: &str, key: &str) -> Option<Range<usize>> {
    let root = DeTable::parse(text).ok()?;
    let (name, value) = root
        .get_ref()
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == table)?;
    if key == format!("[{table}]") {
        return Some(name.span());
    }
    let DeValue::Table(t) = value.get_ref() else {
        return None;
    };
    t.iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(k, _)| k.span())
}

fn literal(params: &toml::Table) -> Vec<(String, String)> {
    params
        .iter()
        .map(|(k, v)| (k.clone(), v.to_string()))
        .collect()
}
