//! The bundled specs (`specs/` of the envc source tree), looked up by env id.

use std::path::{Path, PathBuf};

use envspec::{Code, Diagnostic, Spec};

use crate::error::EnvError;

/// The directory holding the bundled specs.
pub fn specs_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("specs");
    dir.canonicalize().unwrap_or(dir)
}

/// `specs/examples/`: example specs whose models are not shipped with envc (e.g. a robot from
/// MuJoCo Menagerie); building them needs an `xml_file` override or the documented checkout.
pub fn examples_dir() -> PathBuf {
    specs_dir().join("examples")
}

/// Every bundled spec whose model ships with envc, as (env id, path), sorted by id.
pub fn bundled() -> Vec<(String, PathBuf)> {
    let examples = examples_dir();
    scan(&specs_dir(), Some(&examples))
}

/// The example specs of `specs/examples/` (models not shipped), as (env id, path), sorted by id.
pub fn examples() -> Vec<(String, PathBuf)> {
    scan(&examples_dir(), None)
}

fn scan(root: &Path, skip: Option<&Path>) -> Vec<(String, PathBuf)> {
    let mut out = vec![];
    let mut dirs = vec![root.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                if skip != Some(p.as_path()) {
                    dirs.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "toml")
                && let Ok(spec) = Spec::load(&p)
            {
                out.push((spec.id, p));
            }
        }
    }
    out.sort();
    out
}

/// A bundled env id (e.g. `Ant-v5`) or a path to a spec file.
pub fn find(id_or_path: &str) -> Result<PathBuf, EnvError> {
    let p = Path::new(id_or_path);
    if p.extension().is_some_and(|x| x == "toml") || p.is_file() {
        return Ok(p.to_path_buf());
    }
    let mut all = bundled();
    all.extend(examples());
    match all.iter().find(|(id, _)| id == id_or_path) {
        Some((_, path)) => Ok(path.clone()),
        None => Err(EnvError::Spec(
            Diagnostic::new(
                Code::E0600,
                format!("no bundled env `{id_or_path}` and no such spec file"),
            )
            .label(format!(
                "expected a spec path or one of: {}",
                all.iter()
                    .map(|(i, _)| i.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
            .help_opt(envspec::diagnostic::suggest(
                id_or_path,
                all.iter().map(|(i, _)| i.as_str()),
            ))
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
