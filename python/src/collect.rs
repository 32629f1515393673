//! `envc.collect`: a Minari dataset written by the same code as `envc collect`.

use pyo3::prelude::*;

use crate::{convert, errors};

/// Record `episodes` episodes of a task or maze spec into a Minari dataset; returns
/// `(dataset directory, steps)`. The GIL is released while the episodes run. `env_spec`: the
/// Gymnasium `EnvSpec` JSON to store instead of the reference's (the Python layer's `"envc"`).
#[pyfunction]
#[pyo3(signature = (id_or_path, dataset_id, episodes, policy = "random", seed = None, format = "arrow", root = None, overrides = Vec::new(), actions = None, author = None, description = None, env_spec = None))]
#[allow(clippy::too_many_arguments)]
pub fn collect(
    py: Python<'_>,
    id_or_path: &str,
    dataset_id: &str,
    episodes: u64,
    policy: &str,
    seed: Option<u64>,
    format: &str,
    root: Option<std::path::PathBuf>,
    overrides: Vec<(String, String)>,
    actions: Option<Vec<f32>>,
    author: Option<String>,
    description: Option<String>,
    env_spec: Option<String>,
) -> PyResult<(String, u64)> {
    use envc::dataset::{CollectOptions, DatasetInfo, Format, Plan, PlanPolicy};
    use pyo3::exceptions::{PyTypeError, PyValueError};
    let policy = match (policy, actions) {
        ("zero", None) => PlanPolicy::Zero,
        ("random", None) => PlanPolicy::Random,
        ("replay", Some(a)) => PlanPolicy::Replay(a),
        ("replay", None) => return Err(PyValueError::new_err("policy='replay' needs actions")),
        ("zero" | "random", Some(_)) => {
            return Err(PyValueError::new_err(
                "actions are only used with policy='replay'",
            ));
        }
        (other, _) => {
            return Err(PyValueError::new_err(format!(
                "policy={other:?}: expected 'zero', 'random' or 'replay'"
            )));
        }
    };
    let format = match format {
        "arrow" => Format::Arrow,
        "hdf5" => Format::Hdf5,
        other => {
            return Err(PyValueError::new_err(format!(
                "format={other:?}: expected 'arrow' or 'hdf5'"
            )));
        }
    };
    let plan = Plan {
        episodes,
        policy,
        seed,
    };
    let env = envc::open(id_or_path, &convert::overrides(&overrides)).map_err(errors::env_error)?;
    let id = match &env {
        envc::AnyEnv::Agents(_) => {
            return Err(PyTypeError::new_err(format!(
                "`{id_or_path}` is a multi-agent spec; Minari datasets are single-agent (collect its base task)"
            )));
        }
        e => e.id().to_string(),
    };
    if env.max_episode_steps().is_none() {
        // E1401, as `envc collect`: an episode might never end.
        return Err(PyValueError::new_err(format!(
            "error[E1401]: `{id}` has no time limit, so collect might never end an episode; pass max_episode_steps=N as an override"
        )));
    }
    let info = DatasetInfo {
        author: vec![author.unwrap_or_else(|| "envc".into())],
        description: Some(
            description.unwrap_or_else(|| envc::dataset::default_description(&plan, &id)),
        ),
        env_spec,
        ..DatasetInfo::default()
    };
    let opts = CollectOptions {
        root,
        dataset_id: dataset_id.to_string(),
        format,
        info,
    };
    let r = py
        .detach(|| match env {
            envc::AnyEnv::Task(e) => envc::dataset::record(e, &plan, opts, |_, _| {}),
            envc::AnyEnv::Maze(e) => envc::dataset::record(*e, &plan, opts, |_, _| {}),
            envc::AnyEnv::Agents(_) => unreachable!("refused above"),
        })
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((r.dir.display().to_string(), r.steps))
}
