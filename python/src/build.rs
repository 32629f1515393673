//! `envc.datasets`: datasets built from their dataset specs by the runner `envc dataset build`
//! uses (`envc_datasets::Build`), in one process or as a Ray driver and its workers, and the
//! spec's policy as a Python callable (for reference scores).

use std::path::PathBuf;

use envc_datasets::{Budget, Build, BuildOptions, Format, MlpPolicy, PolicyMode};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::errors;

fn open(spec: &str, steps: Option<u64>) -> PyResult<Build> {
    let spec = envc_datasets::open_spec(spec).map_err(errors::dataset_error)?;
    Build::new(spec, steps).map_err(errors::dataset_error)
}

fn options(
    steps: Option<u64>,
    root: Option<PathBuf>,
    format: Option<&str>,
    dataset_id: Option<String>,
) -> PyResult<BuildOptions> {
    let format = match format {
        None => None,
        Some("arrow") => Some(Format::Arrow),
        Some("hdf5") => Some(Format::Hdf5),
        Some(other) => {
            return Err(errors::argument(format!(
                "format={other:?}: expected 'arrow' or 'hdf5'"
            )));
        }
    };
    Ok(BuildOptions {
        steps,
        root,
        format,
        dataset_id,
    })
}

/// Build a dataset in this process: `(directory, steps, episodes)`.
#[pyfunction]
#[pyo3(signature = (spec, steps = None, root = None, format = None, dataset_id = None))]
pub fn build_dataset(
    py: Python<'_>,
    spec: &str,
    steps: Option<u64>,
    root: Option<PathBuf>,
    format: Option<&str>,
    dataset_id: Option<String>,
) -> PyResult<(String, u64, u64)> {
    let build = open(spec, steps)?;
    let opts = options(steps, root, format, dataset_id)?;
    let mut episodes = 0;
    let r = py
        .detach(|| build.record(&opts, |e, _| episodes = e))
        .map_err(errors::dataset_error)?;
    Ok((r.dir.display().to_string(), r.steps, episodes))
}

/// What a sharded build's driver needs: `(seed, budget kind "steps"|"episodes", budget,
/// max_episode_steps, format)`.
#[pyfunction]
#[pyo3(signature = (spec, steps = None, format = None))]
pub fn dataset_build_plan(
    spec: &str,
    steps: Option<u64>,
    format: Option<&str>,
) -> PyResult<(u64, &'static str, u64, u64, &'static str)> {
    let build = open(spec, steps)?;
    let opts = options(steps, None, format, None)?;
    let (kind, n) = match build.budget {
        Budget::Steps(n) => ("steps", n),
        Budget::Episodes(n) => ("episodes", n),
    };
    let format = opts.format.unwrap_or(build.spec.format.into()).name();
    Ok((build.spec.seed, kind, n, build.max_episode_steps, format))
}

/// A worker's episodes `start..end` of a sharded build into the driver's `staging`.
#[pyfunction]
#[pyo3(signature = (spec, staging, start, end, format))]
pub fn build_shard(
    py: Python<'_>,
    spec: &str,
    staging: PathBuf,
    start: u64,
    end: u64,
    format: &str,
) -> PyResult<Vec<(u64, u64)>> {
    let build = open(spec, None)?;
    let format = options(None, None, Some(format), None)?
        .format
        .unwrap_or(Format::Arrow);
    let r = py
        .detach(|| build.record_shard(&staging, format, start, end.max(start)))
        .map_err(errors::dataset_error)?;
    Ok(r.into_iter().map(|e| (e.steps, e.bytes)).collect())
}

/// The driver's side of a sharded build: a `ShardedCollection` holding the staging directory.
#[pyfunction]
#[pyo3(signature = (spec, steps = None, root = None, format = None, dataset_id = None))]
pub fn build_driver(
    spec: &str,
    steps: Option<u64>,
    root: Option<PathBuf>,
    format: Option<&str>,
    dataset_id: Option<String>,
) -> PyResult<crate::collect::ShardedCollection> {
    let build = open(spec, steps)?;
    let opts = options(steps, root, format, dataset_id)?;
    let c = build.driver(&opts).map_err(errors::dataset_error)?;
    Ok(crate::collect::ShardedCollection::of(
        c.boxed(),
        build.spec.seed,
    ))
}

/// A dataset spec's policy as `policy(obs) -> action` (float32): deterministic, or with noise
/// from `numpy.random.default_rng(seed)` (one stream over every call).
#[pyclass(module = "envc._envc", unsendable)]
pub struct SpecPolicy {
    policy: MlpPolicy,
    rng: Option<envc::rng::NumpyRng>,
}

#[pymethods]
impl SpecPolicy {
    #[new]
    #[pyo3(signature = (spec, seed = 123, deterministic = None))]
    fn new(spec: &str, seed: u64, deterministic: Option<bool>) -> PyResult<SpecPolicy> {
        let build = open(spec, None)?;
        let env = build.env().map_err(errors::dataset_error)?;
        build.actor(&env).map_err(errors::dataset_error)?;
        let policy = MlpPolicy::load(&build.spec.policy_file).map_err(errors::dataset_error)?;
        let det = deterministic.unwrap_or(build.spec.mode == PolicyMode::Deterministic);
        Ok(SpecPolicy {
            policy,
            rng: (!det).then(|| envc::rng::NumpyRng::from_seed(seed)),
        })
    }

    fn __call__<'py>(
        &mut self,
        py: Python<'py>,
        obs: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let obs = obs.as_slice()?;
        if obs.len() != self.policy.obs_dim() {
            return Err(errors::argument(format!(
                "the policy takes {} observation values, got {}",
                self.policy.obs_dim(),
                obs.len()
            )));
        }
        let mut a = vec![0f32; self.policy.act_dim()];
        self.policy.act(obs, self.rng.as_mut(), &mut a);
        Ok(PyArray1::from_vec(py, a))
    }
}

/// The bundled dataset specs' directory (`specs/datasets` of the bundle).
#[pyfunction]
pub fn datasets_dir() -> String {
    envc_datasets::datasets_dir().display().to_string()
}
