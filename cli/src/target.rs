//! Resolving a command's SPEC|ID argument and its `--set key=value` overrides.

use std::path::PathBuf;

use anyhow::Result;
use envc::{Env, Override};

/// Parse `--set key=value` arguments.
pub fn overrides(sets: &[String]) -> Result<Vec<Override>> {
    sets.iter()
        .map(|s| Override::parse(s).map_err(|d| anyhow::anyhow!("--set {s}: {}", d.message)))
        .collect()
}

/// A bundled env id or a spec file path.
pub fn spec_path(id_or_path: &str) -> Result<PathBuf> {
    envc::registry::find(id_or_path).map_err(|e| match &e {
        // One line: the message and the suggestion.
        envc::EnvError::Spec(d) if !d.is_empty() => {
            let d = &d.0[0];
            match &d.help {
                Some(h) => anyhow::anyhow!("{} ({h})", d.message),
                None => anyhow::anyhow!("{}", d.message),
            }
        }
        other => anyhow::anyhow!("{other}"),
    })
}

/// Build an env.
pub fn env(id_or_path: &str, sets: &[String]) -> Result<Env> {
    let path = spec_path(id_or_path)?;
    let o = overrides(sets)?;
    Env::from_spec_file(&path, &o).map_err(|e| anyhow::anyhow!("{e}"))
}
