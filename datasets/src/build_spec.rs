//! Dataset specs (`specs/datasets/**.toml`): a Minari dataset declared as data. Each names the
//! env spec and its parameters, the tier, the policy file and how to run it, the budget, the seed
//! (episode k is reset with `seed + k`), the metadata, and optionally the reference scores;
//! `[train]` is read by the training script only. Every mistake is E1801 at its line and column.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::Format;
use crate::error::DatasetError;

/// How the policy's actions are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PolicyMode {
    /// The mean action (SAC/TQC: tanh(mu) scaled to the bounds; PPO: the mean, clipped).
    Deterministic,
    /// Gaussian noise from episode k's `default_rng([seed, k])` only.
    Stochastic,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    dataset: DatasetTable,
    policy: PolicyTable,
    metadata: MetadataTable,
    #[serde(default)]
    reference_scores: Option<RefScores>,
    /// Training settings (scripts/train_policy.py); not used to build.
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
    /// The Minari id, `namespace/name-vN`.
    pub dataset_id: String,
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
    pub format: Format,
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
}

fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, col)
}

/// Where `key = ` is first written (for checks made after parsing).
fn key_at(text: &str, key: &str) -> (usize, usize) {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if t.starts_with(key) && t[key.len()..].trim_start().starts_with('=') {
            return line_col(text, at + (line.len() - t.len()));
        }
        at += line.len();
    }
    (1, 1)
}

fn literal(params: &toml::Table) -> Vec<(String, String)> {
    params
        .iter()
        .map(|(k, v)| (k.clone(), v.to_string()))
        .collect()
}

/// The bundled dataset specs' directory (`specs/datasets`).
pub fn datasets_dir() -> PathBuf {
    envc::registry::specs_dir().join("datasets")
}

use envspec::limits::{MAX_DATASET_STEPS, MAX_EPISODES};

impl DatasetSpec {
    /// A dataset spec file, or a bundled dataset's id (`mujoco/hopper/simple-v0`).
    pub fn open(what: &str) -> Result<DatasetSpec, DatasetError> {
        let p = Path::new(what);
        let path = if p.is_file() || what.ends_with(".toml") {
            p.to_path_buf()
        } else {
            datasets_dir().join(format!("{what}.toml"))
        };
        // A FIFO or device would block the read for ever: regular files only, bounded.
        let text =
            envspec::limits::read_text(&path, envspec::limits::MAX_SPEC_BYTES).map_err(|e| {
                DatasetError::BadSpec {
                    path: path.clone(),
                    line: 0,
                    col: 0,
                    why: if p.is_file() || what.ends_with(".toml") {
                        e.to_string()
                    } else {
                        format!(
                            "`{what}` is neither a dataset spec file nor a bundled dataset id ({e})"
                        )
                    },
                }
            })?;
        DatasetSpec::parse(&path, &text)
    }

    /// Reads a dataset spec's text; `path` locates errors and resolves the policy file.
    pub fn parse(path: &Path, text: &str) -> Result<DatasetSpec, DatasetError> {
        let err = |(line, col): (usize, usize), why: String| DatasetError::BadSpec {
            path: path.to_path_buf(),
            line,
            col,
            why,
        };
        let file: File = toml::from_str(text).map_err(|e| {
            let at = e.span().map_or((1, 1), |s| line_col(text, s.start));
            err(at, e.message().trim().to_string())
        })?;
        let d = file.dataset;
        let budget = match (d.steps, d.episodes) {
            (Some(0), _) => return Err(err(key_at(text, "steps"), "steps must be ≥ 1".into())),
            (_, Some(0)) => {
                return Err(err(key_at(text, "episodes"), "episodes must be ≥ 1".into()));
            }
            (_, Some(e)) if e > MAX_EPISODES => {
                return Err(err(
                    key_at(text, "episodes"),
                    format!("episodes = {e} is beyond envc's limit of {MAX_EPISODES}"),
                ));
            }
            (Some(s), _) if s > MAX_DATASET_STEPS => {
                return Err(err(
                    key_at(text, "steps"),
                    format!("steps = {s} is beyond envc's limit of {MAX_DATASET_STEPS}"),
                ));
            }
            (Some(s), None) => Budget::Steps(s),
            (None, Some(e)) => Budget::Episodes(e),
            (Some(_), Some(_)) => {
                return Err(err(
                    key_at(text, "episodes"),
                    "give `steps` or `episodes`, not both".into(),
                ));
            }
            (None, None) => {
                return Err(err(
                    key_at(text, "[dataset]"),
                    "[dataset] needs a budget: `steps = N` or `episodes = N`".into(),
                ));
            }
        };
        let format = match d.format.as_deref() {
            None | Some("arrow") => Format::Arrow,
            Some("hdf5") => Format::Hdf5,
            Some(other) => {
                return Err(err(
                    key_at(text, "format"),
                    format!("format = {other:?}: expected \"arrow\" or \"hdf5\""),
                ));
            }
        };
        crate::DatasetId::parse(&d.id)
            .map_err(|e| err(key_at(text, "id"), format!("id = {:?}: {e}", d.id)))?;
        let dir = path.parent().unwrap_or(Path::new("."));
        // An env named by a path is relative to this file; otherwise it is a bundled id.
        let env_at = |name: &str| {
            let p = dir.join(name);
            if name.ends_with(".toml") || p.is_file() {
                p.display().to_string()
            } else {
                name.to_string()
            }
        };
        if let Some(r) = file.reference_scores
            && !(r.ref_min_score.is_finite()
                && r.ref_max_score.is_finite()
                && r.ref_max_score != r.ref_min_score)
        {
            return Err(err(
                key_at(text, "ref_max_score"),
                "reference scores must be finite and differ".into(),
            ));
        }
        let m = file.metadata;
        Ok(DatasetSpec {
            path: path.to_path_buf(),
            dataset_id: d.id,
            tier: d.tier,
            env: env_at(&d.env),
            params: literal(&d.params),
            budget,
            seed: d.seed,
            format,
            policy_file: dir.join(&file.policy.file),
            mode: file.policy.mode,
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
            reference_scores: file.reference_scores,
        })
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published suite: 28 ids, with the generation scripts' budgets and algorithms.
    const PUBLISHED: &[(&str, u64, &str)] = &[
        ("mujoco/ant/expert-v0", 2_000_000, "SB3/SAC"),
        ("mujoco/ant/medium-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/ant/simple-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/halfcheetah/expert-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/halfcheetah/medium-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/halfcheetah/simple-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/hopper/expert-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/hopper/medium-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/hopper/simple-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/humanoid/expert-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/humanoid/medium-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/humanoid/simple-v0", 1_000_000, "SB3/TQC"),
        ("mujoco/humanoidstandup/expert-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/humanoidstandup/medium-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/humanoidstandup/simple-v0", 1_000_000, "SB3/SAC"),
        (
            "mujoco/inverteddoublependulum/expert-v0",
            100_000,
            "SB3/SAC",
        ),
        (
            "mujoco/inverteddoublependulum/medium-v0",
            100_000,
            "SB3/SAC",
        ),
        ("mujoco/invertedpendulum/expert-v0", 100_000, "SB3/SAC"),
        ("mujoco/invertedpendulum/medium-v0", 100_000, "SB3/SAC"),
        ("mujoco/pusher/expert-v0", 500_000, "SB3/SAC"),
        ("mujoco/pusher/medium-v0", 500_000, "SB3/SAC"),
        ("mujoco/reacher/expert-v0", 500_000, "SB3/SAC"),
        ("mujoco/reacher/medium-v0", 500_000, "SB3/SAC"),
        ("mujoco/swimmer/expert-v0", 1_000_000, "SB3/PPO"),
        ("mujoco/swimmer/medium-v0", 1_000_000, "SB3/PPO"),
        ("mujoco/walker2d/expert-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/walker2d/medium-v0", 1_000_000, "SB3/SAC"),
        ("mujoco/walker2d/simple-v0", 1_000_000, "SB3/SAC"),
    ];

    #[test]
    fn the_bundled_suite_is_the_published_one() {
        let specs: Vec<DatasetSpec> = DatasetSpec::bundled()
            .iter()
            .map(|p| DatasetSpec::open(p.to_str().unwrap()).unwrap())
            .collect();
        let got: Vec<(&str, u64, &str)> = specs
            .iter()
            .map(|s| {
                let Budget::Steps(n) = s.budget else {
                    panic!("{}: a step budget", s.dataset_id)
                };
                (s.dataset_id.as_str(), n, s.algorithm_name.as_str())
            })
            .collect();
        assert_eq!(got, PUBLISHED);
        for s in &specs {
            // The file sits at its id; the tier is the id's name; episode k is reset with 123 + k
            // (ant/expert's own script: 12345).
            assert!(s.path.ends_with(format!("{}.toml", s.dataset_id)));
            assert!(s.dataset_id.ends_with(&format!("/{}-v0", s.tier)));
            let seed = if s.dataset_id == "mujoco/ant/expert-v0" {
                12345
            } else {
                123
            };
            assert_eq!(s.seed, seed, "{}", s.dataset_id);
            assert!(!s.description.is_empty());
        }
    }

    #[test]
    fn mistakes_are_located() {
        let text = "[dataset]\nid = \"t/x-v0\"\ntier = \"x\"\nenv = \"Hopper-v5\"\nsteps = 10\nepisodes = 2\nseed = 1\n[policy]\nfile = \"p.npz\"\nmode = \"deterministic\"\n[metadata]\nalgorithm_name = \"a\"\nauthor = []\ndescription = \"d\"\n";
        let e = DatasetSpec::parse(Path::new("d.toml"), text).unwrap_err();
        assert_eq!(e.code(), "E1801");
        assert!(e.to_string().contains("d.toml:6:1"), "{e}");
        let typo = text.replace("mode = ", "mood = ");
        let e = DatasetSpec::parse(Path::new("d.toml"), &typo).unwrap_err();
        assert!(e.to_string().contains("d.toml:10:1"), "{e}");
        assert!(e.to_string().contains("mood"), "{e}");
    }

    #[test]
    fn budgets_beyond_the_limits_and_fifos_are_refused() {
        let text = "[dataset]\nid = \"t/x-v0\"\ntier = \"x\"\nenv = \"Hopper-v5\"\nepisodes = 1000000000\nseed = 1\n[policy]\nfile = \"p.npz\"\nmode = \"deterministic\"\n[metadata]\nalgorithm_name = \"a\"\nauthor = []\ndescription = \"d\"\n";
        let e = DatasetSpec::parse(Path::new("d.toml"), text).unwrap_err();
        assert_eq!(e.code(), "E1801");
        assert!(e.to_string().contains("beyond envc's limit"), "{e}");
        let steps = text.replace("episodes = 1000000000", "steps = 100000000000");
        let e = DatasetSpec::parse(Path::new("d.toml"), &steps).unwrap_err();
        assert!(e.to_string().contains("d.toml:5:1"), "{e}");
        // A FIFO is refused before it is opened (opening it would block).
        let dir = std::env::temp_dir().join(format!("envc-fifo-spec-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("d.toml");
        let _ = std::fs::remove_file(&fifo);
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            let e = DatasetSpec::open(fifo.to_str().unwrap()).unwrap_err();
            assert_eq!(e.code(), "E1801");
            assert!(e.to_string().contains("not a regular file"), "{e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
