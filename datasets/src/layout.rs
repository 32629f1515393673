//! Where things are in a datasets root and a collection's staging directory, shared by the
//! readers, the writer and the shard workers.

use std::fs;
use std::path::{Path, PathBuf};

/// Name of the staging directory inside the datasets root (hidden: Minari skips it).
pub const STAGING_DIR: &str = ".envc-staging";

/// Where a worker writes raw HDF5-bound episodes inside the staging directory.
pub(crate) const SHARDS_DIR: &str = "shards";

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
