//! `envc dataset show PATH|ID`: summary of a Minari dataset (envc's or Python's).
//! `envc dataset build SPEC [--steps N]`: build a dataset from its dataset spec (docs/datasets.md).

use anyhow::{Result, bail};
use envc_datasets::Dataset;

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(clap::Subcommand)]
enum Sub {
    /// Metadata, spaces, and episode length / return statistics (reads every episode).
    Show {
        /// Dataset directory, its data/ directory, or an id under $MINARI_DATASETS_PATH.
        dataset: String,
        /// Only the metadata (don't read the episodes).
        #[arg(long)]
        no_episodes: bool,
    },
    /// Build a Minari dataset from its dataset spec (a file, or a bundled id such as
    /// `mujoco/hopper/simple-v0`): the same bytes as `envc.datasets.build` in Python, with or
    /// without Ray workers.
    Build {
        spec: String,
        /// A step budget instead of the spec's (a small build of a tier).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        steps: Option<u64>,
        /// Datasets root (default: $MINARI_DATASETS_PATH, else ~/.minari/datasets).
        #[arg(long, alias = "out")]
        root: Option<std::path::PathBuf>,
        /// A dataset id instead of the spec's.
        #[arg(long)]
        dataset_id: Option<String>,
        /// Storage format instead of the spec's.
        #[arg(long, value_parser = ["arrow", "hdf5"])]
        format: Option<String>,
        /// Build on the Ray cluster at ADDRESS (HOST:PORT or `auto`): runs
        /// `$ENVC_PYTHON -m envc.datasets build` (default `python3`), which writes the same bytes.
        #[arg(long, value_name = "ADDRESS")]
        ray: Option<String>,
        /// With `--ray`: Ray actors (one CPU each).
        #[arg(long, default_value_t = 2, requires = "ray", value_parser = clap::value_parser!(u32).range(1..))]
        workers: u32,
    },
}

pub fn run(args: Args) -> Result<Outcome> {
    match args.command {
        Sub::Show {
            dataset,
            no_episodes,
        } => show(&dataset, no_episodes),
        Sub::Build {
            spec,
            steps,
            root,
            dataset_id,
            format,
            ray: Some(address),
            workers,
        } => exec_ray(&spec, steps, root, dataset_id, format, &address, workers),
        Sub::Build {
            spec,
            steps,
            root,
            dataset_id,
            format,
            ray: None,
            ..
        } => build(&spec, steps, root, dataset_id, format.as_deref()),
    }
}

/// `envc dataset build --ray ADDRESS`: the same arguments to `python -m envc.datasets build`.
fn exec_ray(
    spec: &str,
    steps: Option<u64>,
    root: Option<std::path::PathBuf>,
    dataset_id: Option<String>,
    format: Option<String>,
    address: &str,
    workers: u32,
) -> Result<Outcome> {
    use std::os::unix::process::CommandExt;
    let python = std::env::var_os("ENVC_PYTHON").unwrap_or_else(|| "python3".into());
    let mut cmd = std::process::Command::new(&python);
    cmd.args(["-m", "envc.datasets", "build", spec]);
    if let Some(n) = steps {
        cmd.args(["--steps", &n.to_string()]);
    }
    if let Some(r) = root {
        cmd.arg("--root").arg(r);
    }
    if let Some(d) = dataset_id {
        cmd.args(["--dataset-id", &d]);
    }
    if let Some(f) = format {
        cmd.args(["--format", &f]);
    }
    cmd.args(["--workers", &workers.to_string(), "--address", address]);
    let e = cmd.exec();
    bail!(
        "--ray: could not run {} -m envc.datasets ({e}); set ENVC_PYTHON to a Python with envc and ray installed",
        std::path::Path::new(&python).display()
    )
}

fn build(
    spec: &str,
    steps: Option<u64>,
    root: Option<std::path::PathBuf>,
    dataset_id: Option<String>,
    format: Option<&str>,
) -> Result<Outcome> {
    use envc_datasets::{Build, BuildOptions, Format};
    let err = |e: envc_datasets::DatasetError| anyhow::anyhow!("{e}");
    let spec = envc_datasets::open_spec(spec).map_err(err)?;
    let id = dataset_id
        .clone()
        .unwrap_or_else(|| spec.dataset_id.clone());
    let build = Build::new(spec, steps).map_err(err)?;
    let opts = BuildOptions {
        steps,
        root,
        format: format.map(|f| {
            if f == "hdf5" {
                Format::Hdf5
            } else {
                Format::Arrow
            }
        }),
        dataset_id,
    };
    let start = std::time::Instant::now();
    let mut episodes = 0;
    crate::stop_collections_on_signals();
    let r = build.record(&opts, |e, _| episodes = e).map_err(err)?;
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{id}: {}, {} ({:.0} steps/s, seed {}) written to {}",
        crate::plural(episodes, "episode", "episodes"),
        crate::plural(r.steps, "step", "steps"),
        r.steps as f64 / secs.max(1e-9),
        r.seed,
        r.dir.display()
    );
    for w in r.warnings {
        println!("  MuJoCo warning: {w}");
    }
    Ok(Outcome::Ok)
}

fn show(what: &str, no_episodes: bool) -> Result<Outcome> {
    let ds = match Dataset::open(what) {
        Ok(ds) => ds,
        Err(e) => {
            // A spec or env id is not a dataset: say which command makes one of it.
            if let Ok(spec) = envspec::open(what, &[]) {
                let help = match spec.kind() {
                    envspec::Kind::MultiAgent => format!(
                        "Minari datasets are single-agent: record the base task with `envc collect {} --dataset-id ...`",
                        match &spec {
                            envc::AnySpec::MultiAgent(a) => {
                                crate::target::runnable_name(&a.base.id, &a.base.spec_path)
                            }
                            _ => what.to_string(),
                        }
                    ),
                    _ => format!("record one with `envc collect {what} --dataset-id ...`"),
                };
                return Err(crate::target::unsupported(
                    "dataset show",
                    what,
                    spec.kind(),
                    "reads datasets, not specs",
                    &help,
                ));
            }
            return Err(anyhow::anyhow!("{e}"));
        }
    };
    let text = |k: &str| {
        ds.metadata.get(k).map(|v| {
            v.as_str()
                .map(str::to_string)
                .unwrap_or_else(|| v.to_string())
        })
    };
    // Verified before anything is printed: a damaged dataset gets its error, not a summary.
    let summary = if no_episodes || ds.is_empty() {
        vec![]
    } else {
        episode_summary(&ds)?
    };
    println!("{} ({})", ds.dataset_id, ds.data_path.display());
    println!(
        "  format            {} (minari_version {})",
        ds.format.name(),
        ds.minari_version
    );
    println!("  episodes          {}", ds.total_episodes);
    println!("  steps             {}", ds.total_steps);
    println!("  observation space {}", ds.observation_space.describe());
    println!("  action space      {}", ds.action_space.describe());
    println!(
        "  env               {}",
        ds.env_id().unwrap_or("(no env spec)")
    );
    println!(
        "  numerics          {}",
        ds.numerics().map_or_else(
            || "(not recorded: written by Python; as the machine that wrote it)".to_string(),
            |p| format!("{p} (replay with --numerics {p})")
        )
    );
    println!(
        "  made with         MuJoCo {}, envc {}",
        ds.mujoco_version().unwrap_or("(not recorded)"),
        text("envc_version").unwrap_or_else(|| "(not recorded)".into())
    );
    if let Some(p) = ds.provenance() {
        let files = p
            .get("files")
            .and_then(|f| f.as_array())
            .map_or(0, Vec::len);
        let spec = p.get("spec").and_then(|s| s.as_str()).unwrap_or("?");
        println!("  spec              {spec} ({files} files recorded)");
    }
    for (label, key) in [
        ("size (MB)", "dataset_size"),
        ("author", "author"),
        ("algorithm", "algorithm_name"),
        ("description", "description"),
    ] {
        if let Some(v) = text(key) {
            println!("  {label:<17} {v}");
        }
    }
    for line in summary {
        println!("{line}");
    }
    Ok(Outcome::Ok)
}

/// Every episode read and checked against the metadata; the summary lines of their lengths,
/// returns, terminations and info keys.
fn episode_summary(ds: &Dataset) -> Result<Vec<String>> {
    // Loadable is not enough: every stored episode must be the one the metadata counts.
    let stored = ds.stored_episodes().map_err(|e| anyhow::anyhow!("{e}"))?;
    if stored != ds.total_episodes {
        bail!(
            "{}",
            envc_datasets::DatasetError::Malformed {
                path: ds.data_path.clone(),
                why: format!(
                    "{stored} episodes are stored but total_episodes is {}",
                    ds.total_episodes
                ),
            }
        );
    }
    let (mut lens, mut rets, mut terms) = (vec![], vec![], 0u64);
    let mut info_keys: Vec<String> = vec![];
    for ep in ds.episodes() {
        let ep = ep.map_err(|e| anyhow::anyhow!("{e}"))?;
        if info_keys.is_empty() {
            info_keys = ep.infos.iter().map(|(k, _)| k.clone()).collect();
        }
        lens.push(ep.len() as f64);
        rets.push(ep.episode_return());
        terms += ep.terminations.iter().any(|t| *t) as u64;
    }
    let stat = |x: &[f64]| {
        let n = x.len().max(1) as f64;
        let m = x.iter().sum::<f64>() / n;
        let sd = (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n).sqrt();
        let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        format!("mean {m:.3}  std {sd:.3}  min {lo:.3}  max {hi:.3}")
    };
    let steps: f64 = lens.iter().sum();
    if steps as u64 != ds.total_steps {
        bail!(
            "{}",
            envc_datasets::DatasetError::Malformed {
                path: ds.data_path.clone(),
                why: format!(
                    "the episodes hold {steps} steps but total_steps is {}",
                    ds.total_steps
                ),
            }
        );
    }
    Ok(vec![
        format!("  length            {}", stat(&lens)),
        format!("  return            {}", stat(&rets)),
        format!(
            "  terminated        {terms} of {}",
            crate::plural(lens.len() as u64, "episode", "episodes")
        ),
        format!(
            "  infos             {}",
            if info_keys.is_empty() {
                "(none)".to_string()
            } else {
                info_keys.join(", ")
            }
        ),
    ])
}
