//! Dataset errors, with stable codes from `docs/errors.md` (E12xx).

use std::path::PathBuf;

use envc::EnvError;

/// Why writing, reading or collecting a Minari dataset failed; every variant has a stable code.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// The id is not `[namespace/]name-vN` (E1201).
    #[error("error[E1201]: `{id}` is not a Minari dataset id: {why}")]
    BadId {
        /// The id given.
        id: String,
        /// What is wrong with it.
        why: String,
    },
    /// A dataset of this id already exists (E1202).
    #[error("error[E1202]: dataset `{id}` already exists at {}; Minari datasets are never overwritten, bump the version (-vN)", path.display())]
    Exists {
        /// The id.
        id: String,
        /// Where the existing dataset is.
        path: PathBuf,
    },
    /// A file or directory could not be read or written (E1203).
    // `error`, not `source`: the message says why, and a source would be printed again after it.
    #[error("error[E1203]: {}: {error}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// The files are not a Minari dataset envc can read (E1204).
    #[error("error[E1204]: {}: not a readable Minari dataset: {why}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// A valid dataset that uses something envc does not support (E1205).
    #[error("error[E1205]: {0}")]
    Unsupported(String),
    /// The dataset is stored in a backend this build lacks (E1206).
    #[error(
        "error[E1206]: the {0} backend is not compiled into this build (enable the `hdf5` feature of the envc crate)"
    )]
    BackendMissing(&'static str),
    /// Writing the dataset failed in its backend (E1207).
    #[error("error[E1207]: writing {}: {why}", path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// The backend's error.
        why: String,
    },
    /// The id would put the dataset inside another dataset or around one (E1208).
    #[error("error[E1208]: dataset id `{id}` would put a dataset at {}, {why}; choose an id outside every existing dataset", path.display())]
    Nested {
        /// The id.
        id: String,
        /// Where it would go.
        path: PathBuf,
        /// Which dataset it would nest with.
        why: String,
    },
    /// The staging directory changed under the collection (E1209).
    #[error("error[E1209]: the staging directory {} was removed or replaced while this collection was writing to it; nothing was published", path.display())]
    StagingLost {
        /// The staging directory.
        path: PathBuf,
    },
    /// The written episodes failed the check before publishing (E1210).
    #[error("error[E1210]: the episodes written to {} do not match the metadata: {why}; nothing was published", path.display())]
    Unverified {
        /// The staged dataset.
        path: PathBuf,
        /// What does not match.
        why: String,
    },
    /// The collection, estimated from its first episodes, would not fit on the disk (E1211).
    #[error(
        "error[E1211]: {episodes} episodes would need about {need} in {}, where {free} are free (estimated from the first {sample} episodes); nothing was published",
        path.display()
    )]
    DiskTooSmall {
        /// The staging directory.
        path: PathBuf,
        /// Episodes asked for.
        episodes: u64,
        /// Episodes the estimate is from.
        sample: u64,
        /// The estimate, human-readable.
        need: String,
        /// Free space, human-readable.
        free: String,
    },
    /// An episode grew past the memory budget (E1402).
    #[error(
        "error[E1402]: an episode reached {steps} steps, about {gib:.2} GiB in memory, beyond what this process may safely allocate ({budget_gib:.2} GiB); nothing was published"
    )]
    EpisodeTooLong {
        /// Steps recorded so far.
        steps: u64,
        /// Their size in memory, GiB.
        gib: f64,
        /// The budget, GiB.
        budget_gib: f64,
    },
    /// A shard of a sharded collection is missing or damaged (E1600).
    #[error("error[E1600]: episode {index} of a sharded collection is missing or damaged ({}: {why}); its worker died or the staging directory is not shared by every worker; nothing was published", path.display())]
    ShardMissing {
        /// The shard file.
        path: PathBuf,
        /// The episode's index.
        index: u64,
        /// What is wrong with it.
        why: String,
    },
    /// The policy returned an error (E1601).
    #[error(
        "error[E1601]: the policy failed in episode {episode}: {why}; nothing was written for it"
    )]
    PolicyFailed {
        /// The episode's index.
        episode: u64,
        /// The policy's error.
        why: String,
    },
    /// A dataset spec that cannot be read, located at its line and column when known.
    #[error("error[E1801]: {}{}: {why}", path.display(), if *line > 0 { format!(":{line}:{col}") } else { String::new() })]
    BadSpec {
        /// The dataset spec.
        path: PathBuf,
        /// 1-based line, or 0 when the problem has no place in the file.
        line: usize,
        /// 1-based column.
        col: usize,
        /// What is wrong.
        why: String,
    },
    /// A policy file that cannot be read or does not fit the env.
    #[error("error[E1802]: policy {}: {why}", path.display())]
    BadPolicy {
        /// The policy file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// The spec found at the recorded id or path is not the one that made the dataset (E1212).
    #[error(
        "error[E1212]: the spec `{spec}` differs from the one dataset `{dataset}` was recorded with: {changes}; recover with the dataset's own copy (`use_recorded_spec`), or accept the current one (`accept_changed_spec`)"
    )]
    SpecChanged {
        /// The dataset's id.
        dataset: String,
        /// The recorded id or path.
        spec: String,
        /// Each file that changed or is gone, with how.
        changes: String,
    },
    /// The spec recorded in the dataset cannot be recorded or rebuilt (E1213).
    #[error("error[E1213]: {why}")]
    Provenance {
        /// What is missing or wrong.
        why: String,
    },
    /// Refused: the dataset was made with another MuJoCo version (E1214).
    #[error(
        "error[E1214]: dataset `{dataset}` was made with MuJoCo {recorded}; this process runs MuJoCo {running}, so its physics may differ (refused: `refuse_other_mujoco`)"
    )]
    OtherMujoco {
        /// The dataset's id.
        dataset: String,
        /// The version recorded.
        recorded: String,
        /// The loaded library's.
        running: String,
    },
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
            DatasetError::DiskTooSmall { .. } => "E1211".into(),
            DatasetError::SpecChanged { .. } => "E1212".into(),
            DatasetError::Provenance { .. } => "E1213".into(),
            DatasetError::OtherMujoco { .. } => "E1214".into(),
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
