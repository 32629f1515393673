//! Dataset errors, with stable codes from `docs/errors.md` (E12xx).

use std::path::PathBuf;

use crate::error::EnvError;

#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    #[error("error[E1201]: `{id}` is not a Minari dataset id: {why}")]
    BadId { id: String, why: String },
    #[error("error[E1202]: dataset `{id}` already exists at {}; Minari datasets are never overwritten, bump the version (-vN)", path.display())]
    Exists { id: String, path: PathBuf },
    // `error`, not `source`: the message says why, and a source would be printed again after it.
    #[error("error[E1203]: {}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("error[E1204]: {}: not a readable Minari dataset: {why}", path.display())]
    Malformed { path: PathBuf, why: String },
    #[error("error[E1205]: {0}")]
    Unsupported(String),
    #[error(
        "error[E1206]: the {0} backend is not compiled into this build (enable the `hdf5` feature of the envc crate)"
    )]
    BackendMissing(&'static str),
    #[error("error[E1207]: writing {}: {why}", path.display())]
    Write { path: PathBuf, why: String },
    #[error("error[E1208]: dataset id `{id}` would put a dataset at {}, {why}; choose an id outside every existing dataset", path.display())]
    Nested {
        id: String,
        path: PathBuf,
        why: String,
    },
    #[error("error[E1209]: the staging directory {} was removed or replaced while this collection was writing to it; nothing was published", path.display())]
    StagingLost { path: PathBuf },
    #[error("error[E1210]: the episodes written to {} do not match the metadata: {why}; nothing was published", path.display())]
    Unverified { path: PathBuf, why: String },
    #[error(
        "error[E1402]: an episode reached {steps} steps, about {gib:.2} GiB in memory, beyond what this process may safely allocate ({budget_gib:.2} GiB); nothing was published"
    )]
    EpisodeTooLong {
        steps: u64,
        gib: f64,
        budget_gib: f64,
    },
    #[error("error[E1600]: episode {index} of a sharded collection is missing or damaged ({}: {why}); its worker died or the staging directory is not shared by every worker; nothing was published", path.display())]
    ShardMissing {
        path: PathBuf,
        index: u64,
        why: String,
    },
    #[error(
        "error[E1601]: the policy failed in episode {episode}: {why}; nothing was written for it"
    )]
    PolicyFailed { episode: u64, why: String },
    #[error("error[E1801]: {}{}: {why}", path.display(), if *line > 0 { format!(":{line}:{col}") } else { String::new() })]
    BadSpec {
        path: PathBuf,
        line: usize,
        col: usize,
        why: String,
    },
    #[error("error[E1802]: policy {}: {why}", path.display())]
    BadPolicy { path: PathBuf, why: String },
    /// The env failed during collection (its own code, e.g. E1102 for a NaN action).
    #[error("{0}")]
    Env(#[from] EnvError),
}

impl DatasetError {
    /// The stable code, e.g. `"E1201"`.
    pub fn code(&self) -> String {
        match self {
            DatasetError::BadId { .. } => "E1201".into(),
            DatasetError::Exists { .. } => "E1202".into(),
            DatasetError::Io { .. } => "E1203".into(),
            DatasetError::Malformed { .. } => "E1204".into(),
            DatasetError::Unsupported(_) => "E1205".into(),
            DatasetError::BackendMissing(_) => "E1206".into(),
            DatasetError::Write { .. } => "E1207".into(),
            DatasetError::Nested { .. } => "E1208".into(),
            DatasetError::StagingLost { .. } => "E1209".into(),
            DatasetError::Unverified { .. } => "E1210".into(),
            DatasetError::EpisodeTooLong { .. } => "E1402".into(),
            DatasetError::ShardMissing { .. } => "E1600".into(),
            DatasetError::PolicyFailed { .. } => "E1601".into(),
            DatasetError::BadSpec { .. } => "E1801".into(),
            DatasetError::BadPolicy { .. } => "E1802".into(),
            DatasetError::Env(e) => format!("{:?}", e.code()),
        }
    }
}

pub(crate) fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> DatasetError {
    let path = path.into();
    move |error| DatasetError::Io { path, error }
}

/// E1203 unless `path` is a regular file: opening a FIFO blocks until a writer comes, a device
/// may never end.
pub(crate) fn regular_file(path: &std::path::Path) -> Result<(), DatasetError> {
    envspec::limits::check_file(path, u64::MAX).map_err(|e| DatasetError::Io {
        path: path.to_path_buf(),
        error: match e {
            envspec::limits::ReadError::Io(e) => e,
            other => std::io::Error::other(other.to_string()),
        },
    })
}

pub(crate) fn malformed(path: impl Into<PathBuf>, why: impl Into<String>) -> DatasetError {
    DatasetError::Malformed {
        path: path.into(),
        why: why.into(),
    }
}
