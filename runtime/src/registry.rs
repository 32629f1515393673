//! The bundled ids, as the runtime uses them. The registry itself (every task, maze and
//! multi-agent id, scanned once) is `envspec::registry`; this adds the task views and the README
//! table.

use std::path::PathBuf;

pub use envspec::registry::{Entry, Kind, entries, examples_dir, lookup, specs_dir};
use envspec::{Code, Diagnostic, Diagnostics};

use crate::error::EnvError;

fn tasks(example: bool) -> Vec<(String, PathBuf)> {
    entries()
        .iter()
        .filter(|e| e.task && e.example == example)
        .map(|e| (e.id.clone(), e.path.clone()))
        .collect()
}

/// Every bundled spec that opens as a single-agent env and whose model ships with envc, as
/// (env id, path), sorted by id.
pub fn bundled() -> Vec<(String, PathBuf)> {
    tasks(false)
}

/// The example task specs of `specs/examples/` (models not shipped), as (env id, path).
pub fn examples() -> Vec<(String, PathBuf)> {
    tasks(true)
}

/// The task spec file of an id or path (`Env::make`, `VecEnv::make`): a maze id, or a
/// multi-agent spec without an `[env]` of its own, is E0602 (open those with `envc::open`).
pub fn find(id_or_path: &str) -> Result<PathBuf, EnvError> {
    let t = envspec::open::locate(id_or_path)?;
    let kind = match &t.id {
        Some(id) => lookup(id)
            .map(|e| (e.kind, e.task))
            .map_err(Diagnostics::from)?,
        None => match envspec::open::Document::read(&t.path) {
            Ok(doc) => {
                let top = doc.root.as_table().unwrap_or(&[]);
                (doc.kind, top.iter().any(|e| e.key == "env"))
            }
            // Unreadable or not TOML: the task reader reports it with its location.
            Err(_) => (Kind::Task, true),
        },
    };
    match kind {
        (_, true) => Ok(t.path),
        (kind, false) => Err(EnvError::Spec(
            Diagnostic::new(
                Code::E0602,
                format!("`{id_or_path}` is a {kind} spec, not a single-agent task"),
            )
            .help("open it with `envc::open` (or `MazeEnv` / `MultiAgentEnv`)")
            .into(),
        )),
    }
}

/// The README's table of bundled envs (id, observation and action sizes, dt, episode limit),
/// generated from the specs. `tests/readme.rs` keeps the README in sync with it.
pub fn env_table_markdown() -> Result<String, EnvError> {
    let mut out = String::from(
        "| id | obs dim | action dim | dt (s) | max steps | spec |\n|---|---:|---:|---:|---:|---|\n",
    );
    let root = specs_dir();
    for (id, path) in bundled() {
        let spec = envspec::load(&path, &[])?;
        let rel = path
            .strip_prefix(&root)
            .unwrap_or(&path)
            .display()
            .to_string();
        let max = spec
            .max_episode_steps
            .map(|m| m.to_string())
            .unwrap_or_else(|| "none".into());
        out.push_str(&format!(
            "| {id} | {} | {} | {} | {max} | `specs/{rel}` |\n",
            spec.obs_dim,
            spec.act_dim(),
            spec.dt()
        ));
    }
    Ok(out)
}
