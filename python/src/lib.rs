//! `envc._envc`: the native core of the `envc` Python package. Every spec opens through the one
//! door (`envc::open`); each kind gets a core object that steps with numpy arrays: one base class,
//! `EnvCore` (`env_core.rs`: what every kind shares, through `envc::JointEnv`), with a subclass per
//! kind that holds the kind's env (`TaskCore`, `MazeCore`, `MultiAgentCore`). The Gymnasium, vector
//! and PettingZoo classes are Python (`python/envc/`), thin over these cores.

use envc::JointEnv;
use pyo3::prelude::*;

mod build;
mod collect;
mod convert;
mod dataset_spec;
mod env_core;
mod errors;
mod gpu;
mod joint_methods;
mod maze;
mod mujoco_timer;
mod multi_agent;
mod render;
mod task;
mod vector;

/// Open a bundled id or a spec file of any kind with overrides (`(name, TOML literal)` pairs).
/// Returns `(kind, core)` with kind `"task"`, `"maze"` or `"agents"`.
#[pyfunction]
#[pyo3(signature = (id_or_path, overrides = Vec::new()))]
fn open(
    py: Python<'_>,
    id_or_path: &str,
    overrides: Vec<(String, String)>,
) -> PyResult<(String, Py<PyAny>)> {
    let o = convert::overrides(&overrides);
    let env = errors::no_panic(
        &mut (),
        |_| envc::open(id_or_path, &o).map_err(errors::env_error),
        |_| {},
    )?;
    let kind = env.kind();
    let base = PyClassInitializer::from(env_core::EnvCore);
    let made = match env {
        envc::AnyEnv::Task(env) => {
            Py::new(py, base.add_subclass(task::TaskCore { env }))?.into_any()
        }
        envc::AnyEnv::Maze(env) => {
            Py::new(py, base.add_subclass(maze::MazeCore { env }))?.into_any()
        }
        envc::AnyEnv::MultiAgent(env) => {
            Py::new(py, base.add_subclass(multi_agent::MultiAgentCore { env }))?.into_any()
        }
    };
    Ok((kind_name(kind).into(), made))
}

/// Every known id as `(id, kind, max_episode_steps or None, example, reward_threshold or None)`:
/// the bundled ones sorted by id, then the user's (`ENVC_SPEC_PATH`, `register`).
type RegistryRow = (String, String, Option<u64>, bool, Option<f64>);

/// `only`: just those ids (registering a few files reads only them, not every spec again).
#[pyfunction]
#[pyo3(signature = (only = None))]
fn registry(only: Option<Vec<String>>) -> Vec<RegistryRow> {
    envspec::registry::all_entries()
        .into_iter()
        .filter(|e| only.as_ref().is_none_or(|o| o.contains(&e.id)))
        .map(|e| {
            // A task's time limit and threshold come from its text; other kinds are opened.
            let (max, threshold) = envspec::registry::task_registration(e).unwrap_or_else(|| {
                match envspec::open(&e.id, &[]) {
                    Ok(envc::AnySpec::Task(t)) => (t.max_episode_steps, t.reward_threshold),
                    Ok(envc::AnySpec::Maze(m)) => (m.max_episode_steps, None),
                    Ok(envc::AnySpec::MultiAgent(a)) => (a.base.max_episode_steps, None),
                    Err(_) => (None, None),
                }
            });
            (
                e.id.clone(),
                kind_name(e.kind).into(),
                max,
                e.example,
                threshold,
            )
        })
        .collect()
}

/// What a spec is without building it, under the given overrides (`(name, TOML literal)` pairs:
/// a spec whose default model is elsewhere resolves only with its `xml_file`): `(kind, id,
/// max_episode_steps or None)`.
#[pyfunction]
#[pyo3(signature = (id_or_path, overrides = Vec::new()))]
fn describe(
    id_or_path: &str,
    overrides: Vec<(String, String)>,
) -> PyResult<(String, String, Option<u64>)> {
    let o = convert::overrides(&overrides);
    let spec = errors::no_panic(
        &mut (),
        |_| envspec::open(id_or_path, &o).map_err(errors::diagnostics),
        |_| {},
    )?;
    let max = match &spec {
        envc::AnySpec::Task(t) => t.max_episode_steps,
        envc::AnySpec::Maze(m) => m.max_episode_steps,
        envc::AnySpec::MultiAgent(a) => a.base.max_episode_steps,
    };
    Ok((kind_name(spec.kind()).into(), spec.id().to_string(), max))
}

pub(crate) fn kind_name(k: envspec::Kind) -> &'static str {
    match k {
        envspec::Kind::Task => "task",
        envspec::Kind::Maze => "maze",
        envspec::Kind::MultiAgent => "agents",
    }
}

/// Registers the ids of a spec file, or of every spec file under a directory; returns them.
/// An id that is bundled, or registered from another file, is a `SpecError` (E0603).
#[pyfunction]
fn register(path: std::path::PathBuf) -> PyResult<Vec<String>> {
    envspec::registry::register(&path).map_err(|d| errors::diagnostics(d.into()))
}

/// The problems of `ENVC_SPEC_PATH` (unreadable or unparsable files, bad or taken ids), as
/// messages: the entries left out of the registry.
#[pyfunction]
fn spec_path_problems() -> Vec<String> {
    if std::env::var_os("ENVC_SPEC_PATH").is_none_or(|v| v.is_empty()) {
        return vec![];
    }
    envspec::registry::spec_path_problems()
        .into_iter()
        .map(|d| match d.position() {
            Some(at) => format!("{at}: {}: {}", d.code, d.message),
            None => format!("{}: {}", d.code, d.message),
        })
        .collect()
}

/// The spec to open for a dataset's `envc_provenance` (JSON text): `(id or path, warnings)`.
/// The spec at the recorded place when it is unchanged (E1212 when it changed, unless
/// `accept_changed_spec`: W1212), else (or with `use_recorded_spec`) a copy written from the
/// record (E1213 when it cannot be);
/// another MuJoCo version warns (W1214) or, with `refuse_other_mujoco`, is E1214.
#[pyfunction]
#[pyo3(signature = (dataset_id, provenance, accept_changed_spec = false, refuse_other_mujoco = false, use_recorded_spec = false))]
fn recover_spec(
    dataset_id: &str,
    provenance: &str,
    accept_changed_spec: bool,
    refuse_other_mujoco: bool,
    use_recorded_spec: bool,
) -> PyResult<(String, Vec<String>)> {
    let record: serde_json::Value = serde_json::from_str(provenance).map_err(|e| {
        errors::dataset_error(envc_datasets::DatasetError::Provenance {
            why: format!("envc_provenance is not JSON: {e}"),
        })
    })?;
    let opts = envc_datasets::RecoverOptions {
        accept_changed_spec,
        refuse_other_mujoco,
        use_recorded_spec,
    };
    let r = envc_datasets::recover(dataset_id, &record, opts).map_err(errors::dataset_error)?;
    Ok((r.target, r.warnings))
}

/// Names the directory holding the bundled `specs/` and `assets/` (the package's data). Only
/// before the first lookup; returns whether it took effect.
#[pyfunction]
fn set_bundle_root(path: std::path::PathBuf) -> bool {
    envspec::bundle::set_root(&path)
}

/// Runs the `envc` command line `argv` (the program name first) in this process and returns its
/// exit status: the wheel's `envc` console script (`envc/_cli.py`), so the wheel carries one
/// native build per MuJoCo version rather than an extension and a binary each.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<std::ffi::OsString>) -> u8 {
    py.detach(|| envc_cli::main_with(argv))
}

/// Where the bundled specs and models come from: `(root or None, origin or error)`.
#[pyfunction]
fn bundle_root() -> (Option<String>, String) {
    match envspec::bundle::root() {
        Ok((p, o)) => (Some(p.display().to_string()), o.describe().to_string()),
        Err(e) => (None, e.to_string()),
    }
}

/// The parameters of a spec: `(name, type name, default as TOML text, doc)`.
#[pyfunction]
fn parameters(id_or_path: &str) -> PyResult<Vec<(String, String, String, String)>> {
    task::parameters(id_or_path)
}

#[pymodule]
fn _envc(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(open, m)?)?;
    m.add_function(wrap_pyfunction!(registry, m)?)?;
    m.add_function(wrap_pyfunction!(parameters, m)?)?;
    m.add_function(wrap_pyfunction!(describe, m)?)?;
    m.add_function(wrap_pyfunction!(register, m)?)?;
    m.add_function(wrap_pyfunction!(spec_path_problems, m)?)?;
    m.add_function(wrap_pyfunction!(set_bundle_root, m)?)?;
    m.add_function(wrap_pyfunction!(recover_spec, m)?)?;
    m.add_function(wrap_pyfunction!(bundle_root, m)?)?;
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(collect::collect, m)?)?;
    m.add_function(wrap_pyfunction!(collect::collect_shard, m)?)?;
    m.add_function(wrap_pyfunction!(build::build_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(build::dataset_build_plan, m)?)?;
    m.add_function(wrap_pyfunction!(build::build_shard, m)?)?;
    m.add_function(wrap_pyfunction!(build::build_driver, m)?)?;
    m.add_class::<build::SpecPolicy>()?;
    m.add_function(wrap_pyfunction!(build::datasets_dir, m)?)?;
    m.add_function(wrap_pyfunction!(dataset_spec::read_dataset_spec, m)?)?;
    m.add_function(wrap_pyfunction!(dataset_spec::with_reference_scores, m)?)?;
    m.add_function(wrap_pyfunction!(gpu::gpu_plan, m)?)?;
    m.add_class::<collect::ShardedCollection>()?;
    m.add_class::<env_core::EnvCore>()?;
    m.add_class::<task::TaskCore>()?;
    m.add_class::<maze::MazeCore>()?;
    m.add_class::<multi_agent::MultiAgentCore>()?;
    m.add_class::<vector::VecCore>()?;
    // The Python hierarchy's SpecError, for code that catches `_envc.SpecError`.
    m.add(
        "SpecError",
        m.py().import("envc._errors")?.getattr("SpecError")?,
    )?;
    m.add("__mujoco_version__", envc::mujoco_version())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
