//! `envc collect ID|SPEC --dataset-id ns/name-v0 --episodes N --policy zero|random|replay
//! [--actions A.npy] [--seed S] [--format arrow|hdf5] [--set k=v ...]`: record a Minari dataset.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use envc_datasets::{
    CollectOptions, DatasetInfo, Format, Plan, PlanPolicy, Recordable, default_description,
};
use indicatif::{ProgressBar, ProgressStyle};

use crate::Outcome;
use envc::JointEnv;

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id.
    spec: String,
    /// Minari dataset id, `(namespace/)name-vN`.
    #[arg(long)]
    dataset_id: String,
    /// Episodes to record (1 to 10,000,000; Minari's largest MuJoCo datasets hold a few thousand).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    episodes: u64,
    #[arg(long, value_enum, default_value = "random")]
    policy: PolicyKind,
    /// With `--policy replay`: a float32 or float64 `.npy` array [T, act_dim]; every episode
    /// starts at row 0 and starts over from row 0 when the rows run out.
    #[arg(long, value_name = "A.npy")]
    actions: Option<PathBuf>,
    /// Episode i is reset with seed S+i (as Minari's DataCollector) and its random actions come
    /// from numpy's default_rng([S, i]): episode i depends on (S, i) only, so a sharded
    /// collection (envc.ray) records the same dataset. Without it, one S is drawn from OS
    /// entropy and printed; episode i's stored seed is S+i either way.
    #[arg(long)]
    seed: Option<u64>,
    #[arg(long, value_enum, default_value = "arrow")]
    format: FormatArg,
    /// Datasets root (default: $MINARI_DATASETS_PATH, else ~/.minari/datasets).
    #[arg(long)]
    root: Option<PathBuf>,
    /// Parameter overrides (`key=value`, TOML literal values); stored as the env spec's kwargs.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, default_value = "envc")]
    author: String,
    #[arg(long)]
    author_email: Option<String>,
    #[arg(long)]
    description: Option<String>,
    #[arg(long)]
    code_permalink: Option<String>,
    /// Collect on the Ray cluster at ADDRESS (HOST:PORT or `auto`): runs
    /// `$ENVC_PYTHON -m envc.ray collect` (default `python3`) with these arguments, which writes
    /// the same dataset (docs/datasets.md, "Sharded collection").
    #[arg(long, value_name = "ADDRESS")]
    ray: Option<String>,
    /// With `--ray`: Ray actors (one CPU each).
    #[arg(long, default_value_t = 2, requires = "ray", value_parser = clap::value_parser!(u32).range(1..))]
    workers: u32,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum PolicyKind {
    /// All-zero actions.
    Zero,
    /// Uniform in the action space's bounds (float32).
    Random,
    /// Rows of `--actions`.
    Replay,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum FormatArg {
    Arrow,
    Hdf5,
}

fn read_actions(path: &Path, id: &str, act_dim: usize) -> Result<Vec<f32>> {
    let a = envc::npy::read_matrix(path)?.into_f32();
    crate::target::action_file_shape(path, a.dim(), id, act_dim)?;
    Ok(a.iter().copied().collect())
}

/// `envc collect --ray ADDRESS`: the same arguments to `python -m envc.ray collect`, exec'd.
fn exec_ray(args: &Args, address: &str) -> Result<Outcome> {
    use std::os::unix::process::CommandExt;
    if args.author_email.is_some() || args.code_permalink.is_some() {
        bail!("--author-email and --code-permalink are not passed to --ray collections yet");
    }
    let python = std::env::var_os("ENVC_PYTHON").unwrap_or_else(|| "python3".into());
    let mut cmd = std::process::Command::new(&python);
    cmd.args([
        "-m",
        "envc.ray",
        "collect",
        &args.spec,
        "--dataset-id",
        &args.dataset_id,
    ]);
    cmd.args(["--episodes", &args.episodes.to_string()]);
    let policy = match args.policy {
        PolicyKind::Zero => "zero",
        PolicyKind::Random => "random",
        PolicyKind::Replay => "replay",
    };
    cmd.args(["--policy", policy]);
    if let Some(a) = &args.actions {
        cmd.arg("--actions").arg(a);
    }
    if let Some(s) = args.seed {
        cmd.args(["--seed", &s.to_string()]);
    }
    cmd.args([
        "--format",
        match args.format {
            FormatArg::Arrow => "arrow",
            FormatArg::Hdf5 => "hdf5",
        },
    ]);
    if let Some(r) = &args.root {
        cmd.arg("--root").arg(r);
    }
    for kv in &args.set {
        cmd.args(["--set", kv]);
    }
    cmd.args(["--workers", &args.workers.to_string(), "--address", address]);
    cmd.args(["--author", &args.author]);
    if let Some(d) = &args.description {
        cmd.args(["--description", d]);
    }
    let e = cmd.exec();
    bail!(
        "--ray: could not run {} -m envc.ray ({e}); set ENVC_PYTHON to a Python with envc and ray installed",
        std::path::Path::new(&python).display()
    )
}

pub fn run(args: Args) -> Result<Outcome> {
    if let Some(address) = &args.ray {
        return exec_ray(&args, address);
    }
    let format = match args.format {
        FormatArg::Arrow => Format::Arrow,
        FormatArg::Hdf5 => Format::Hdf5,
    };
    // One collector for every kind that has a Minari form.
    let env = crate::target::env(&args.spec, &args.set)?;
    let id = env.id().to_string();
    if env.max_episode_steps().is_none() {
        return Err(crate::target::needs_max_steps("collect", &id, ""));
    }
    match envc_datasets::recordable(env) {
        Ok(env) => record(env, &id, &args, format),
        Err(env) => Err(crate::target::unsupported(
            "collect",
            &id,
            envspec::Kind::MultiAgent,
            "records single-agent Minari datasets",
            &format!(
                "collect its base task instead: `envc collect {} ...`",
                crate::target::runnable_name(&env.spec().base.id, &env.spec().base.spec_path)
            ),
        )),
    }
}

fn record(
    env: Box<dyn Recordable + Send>,
    id: &str,
    args: &Args,
    format: Format,
) -> Result<Outcome> {
    let act_dim = env.joint().act_dim();
    let policy = match (args.policy, &args.actions) {
        (PolicyKind::Replay, Some(p)) => PlanPolicy::Replay(read_actions(p, &args.spec, act_dim)?),
        (PolicyKind::Replay, None) => bail!("--policy replay needs --actions A.npy"),
        (_, Some(_)) => bail!("--actions is only used with --policy replay"),
        (PolicyKind::Zero, None) => PlanPolicy::Zero,
        (PolicyKind::Random, None) => PlanPolicy::Random,
    };
    let plan = Plan {
        episodes: args.episodes,
        policy,
        seed: args.seed,
    };
    let info = DatasetInfo {
        author: vec![args.author.clone()],
        author_email: args.author_email.iter().cloned().collect(),
        code_permalink: args.code_permalink.clone(),
        description: Some(
            args.description
                .clone()
                .unwrap_or_else(|| default_description(&plan, id)),
        ),
        ..DatasetInfo::default()
    };
    let opts = CollectOptions {
        root: args.root.clone(),
        dataset_id: args.dataset_id.clone(),
        format,
        info,
    };
    let bar = ProgressBar::new(args.episodes);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:30}] {pos}/{len} episodes, {prefix} steps ({elapsed}, eta {eta})",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.set_message(format!("{id} → {}", args.dataset_id));
    let start = Instant::now();
    crate::stop_collections_on_signals();
    let r = envc_datasets::record(env, &plan, opts, |episodes, steps| {
        bar.set_prefix(steps.to_string());
        bar.set_position(episodes);
    })
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{}: {}, {} ({:.0} steps/s, seed {}) written to {}",
        args.dataset_id,
        crate::plural(args.episodes, "episode", "episodes"),
        crate::plural(r.steps, "step", "steps"),
        r.steps as f64 / secs.max(1e-9),
        r.seed,
        r.dir.display()
    );
    for c in &r.cleaned {
        println!(
            "  removed the staging directory of an interrupted collection: {}",
            c.display()
        );
    }
    for d in &r.unlocked {
        println!(
            "  left alone (no lock file: an older envc's or not envc's; remove it once no collection runs there): {}",
            d.display()
        );
    }
    for w in r.warnings {
        println!("  MuJoCo warning: {w}");
    }
    Ok(Outcome::Ok)
}
