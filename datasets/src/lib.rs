//! envc's Minari datasets: collect episodes from any envc env and write them in Minari 0.5.4's
//! on-disk format, so `minari.load_dataset` loads them as its own; read Minari datasets back
//! (envc's or Python `DataCollector`'s) as typed arrays. Also the sharded collection's Rust side
//! (`envc.ray`), dataset specs (`specs/datasets/**.toml`) and the MLP policies they name. The
//! runtime (`envc`) runs envs; this crate records them and never the reverse.
//!
//! The Arrow backend (pure Rust) is always built; feature `hdf5` adds the HDF5 backend (links
//! libhdf5), `hdf5-static` builds HDF5 from source and links it in (the wheel's build).
//!
//! ```no_run
//! use envc::Env;
//! use envc_datasets::{Collector, CollectOptions, Dataset, Format, DatasetInfo};
//! let env = Env::make("Hopper-v5", &[])?;
//! let opts = CollectOptions { root: None, dataset_id: "envc/hopper/zero-v0".into(), format: Format::Arrow, info: DatasetInfo::default() };
//! let mut c = Collector::new(env, opts)?;
//! for seed in 0..10 {
//!     c.episode(seed, &mut |_obs: &[f64], a: &mut [f32]| a.fill(0.0))?;
//! }
//! let dir = c.finish()?;
//! let ds = Dataset::open(dir.to_str().unwrap())?;
//! for ep in ds.episodes() {
//!     let ep = ep?;
//!     println!("{} steps, seed {:?}", ep.len(), ep.seed);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Format details and the choices made are in `docs/datasets.md`.

#![warn(missing_docs)]

mod arrow_io;
mod build;
mod build_spec;
mod collector;
mod episode;
mod error;
mod gym_spec;
#[cfg(feature = "hdf5")]
mod hdf5_io;
mod id;
mod json;
mod layout;
mod mlp;
mod plan;
mod provenance;
mod reader;
mod recordable;
mod shard;
mod shard_episode;
mod space;
mod staging;
mod tensor;
mod writer;

pub use build::{Build, BuildOptions, SpecActor};
pub use build_spec::{
    Budget, DatasetSpec, PolicyMode, RefScores, StorageFormat, bundled, datasets_dir, open_spec,
    parse_spec,
};
pub use collector::{CollectOptions, Collector, EpisodeSummary, Policy, Recording, STOP};
pub use episode::{EpisodeRecord, InfoColumn};
pub use error::DatasetError;
pub use gym_spec::env_spec_json;
pub use id::DatasetId;
pub use layout::{STAGING_DIR, default_root};
pub use mlp::MlpPolicy;
pub use plan::{
    EpisodePolicy, Plan, PlanActor, PlanPolicy, default_description, episode_rng, episode_seed,
    record, record_shard, record_with,
};
pub use provenance::{RecoverOptions, RecoveredSpec, recover};
pub use reader::Dataset;
pub use recordable::{MazeRecording, Recordable, check_recordable, policy_fits, recordable};
pub use shard_episode::ShardEpisode;
pub use space::{Dtype, Space};
pub use tensor::{Data, Episode, Tensor};
pub use writer::{DatasetInfo, DatasetWriter};

/// The format tag written as `minari_version`. Minari checks it against a fixed set: "0.5.4" is
/// what the pinned reader (0.5.4) writes itself; see docs/datasets.md for older readers.
pub const MINARI_VERSION: &str = "0.5.4";

/// Minari storage backends envc writes and reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Arrow IPC files, one per episode (pure Rust).
    Arrow,
    /// One HDF5 file (feature `hdf5`).
    Hdf5,
}

impl Format {
    /// The name Minari's metadata uses (`arrow`, `hdf5`).
    pub fn name(self) -> &'static str {
        match self {
            Format::Arrow => "arrow",
            Format::Hdf5 => "hdf5",
        }
    }
    /// Whether this build can write and read the format.
    pub fn available(self) -> bool {
        match self {
            Format::Arrow => true,
            Format::Hdf5 => cfg!(feature = "hdf5"),
        }
    }
}
