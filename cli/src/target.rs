//! Resolving a command's SPEC|ID argument and its `--set key=value` overrides.

use std::path::PathBuf;

use anyhow::{Context, Result};
use envc::{Env, Override, ResolvedSpec};

/// Parse `--set key=value` arguments.
pub fn overrides(sets: &[String]) -> Result<Vec<Override>> {
    sets.iter().map(|s| Override::parse(s).map_err(|d| anyhow::anyhow!("--set {s}: {}", d.message))).collect()
}

/// A bundled env id or a spec file path.
pub fn spec_path(id_or_path: &str) -> Result<PathBuf> {
    envc::registry::find(id_or_path).map_err(|e| anyhow::anyhow!("{}", first_line(&e.to_string())))
}

/// Resolve a spec with overrides (errors keep their full rendering).
pub fn resolve(id_or_path: &str, sets: &[String]) -> Result<ResolvedSpec> {
    let path = spec_path(id_or_path)?;
    let o = overrides(sets)?;
    envspec::load(&path, &o).map_err(|d| anyhow::anyhow!("{d}")).with_context(|| format!("in {}", path.display()))
}

/// Build an env.
pub fn env(id_or_path: &str, sets: &[String]) -> Result<Env> {
    let path = spec_path(id_or_path)?;
    let o = overrides(sets)?;
    Env::from_spec_file(&path, &o).map_err(|e| anyhow::anyhow!("{e}"))
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").trim_start_matches("error[E0600]: ").to_string()
}
