//! `envc collect ID|SPEC --dataset-id ns/name-v0 --episodes N --policy zero|random|replay
//! [--actions A.npy] [--seed S] [--format arrow|hdf5] [--set k=v ...]`: record a Minari dataset.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use envc::dataset::{CollectOptions, Collector, DatasetInfo, Format, Recordable};
use envc::rng::NumpyRng;
use indicatif::{ProgressBar, ProgressStyle};

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id.
    spec: String,
    /// Minari dataset id, `(namespace/)name-vN`.
    #[arg(long)]
    dataset_id: String,
    #[arg(long, default_value_t = 10)]
    episodes: u64,
    #[arg(long, value_enum, default_value = "random")]
    policy: PolicyKind,
    /// With `--policy replay`: a float32 or float64 `.npy` array [T, act_dim]; episodes take rows
    /// in order (the next episode continues where the last stopped) and reuse them from the start
    /// when they run out.
    #[arg(long, value_name = "A.npy")]
    actions: Option<PathBuf>,
    /// Episode i is reset with seed S+i (and the random policy is seeded with S). Without it,
    /// seeds come from OS entropy, as Minari's DataCollector draws them; either way they are stored.
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

fn read_actions(path: &Path, act_dim: usize) -> Result<Vec<f32>> {
    let a = envc::npy::read_matrix(path)?.into_f32();
    if a.ncols() != act_dim || a.nrows() == 0 {
        bail!(
            "{} is [{}, {}]; expected [T ≥ 1, {act_dim}]",
            path.display(),
            a.nrows(),
            a.ncols()
        );
    }
    Ok(a.iter().copied().collect())
}

pub fn run(args: Args) -> Result<Outcome> {
    let format = match args.format {
        FormatArg::Arrow => Format::Arrow,
        FormatArg::Hdf5 => Format::Hdf5,
    };
    // One collector for every kind that has a Minari form.
    let env = crate::target::env(&args.spec, &args.set)?;
    let id = env.id().to_string();
    match env {
        envc::AnyEnv::Task(env) => record(env, &id, &args, format),
        envc::AnyEnv::Maze(env) => record(*env, &id, &args, format),
        envc::AnyEnv::Agents(env) => Err(crate::target::unsupported(
            "collect",
            &id,
            envspec::Kind::Agents,
            "records single-agent Minari datasets",
            &format!(
                "collect its base task instead: `envc collect {} ...`",
                env.spec().base.id
            ),
        )),
    }
}

fn record<E: Recordable>(env: E, id: &str, args: &Args, format: Format) -> Result<Outcome> {
    let act_dim = env.action_space().dim();
    let space = env.action_space().clone();
    let actions = match (args.policy, &args.actions) {
        (PolicyKind::Replay, Some(p)) => read_actions(p, act_dim)?,
        (PolicyKind::Replay, None) => bail!("--policy replay needs --actions A.npy"),
        (_, Some(_)) => bail!("--actions is only used with --policy replay"),
        _ => vec![],
    };
    let description = args.description.clone().unwrap_or_else(|| {
        format!(
            "{} episodes of {} with a {} policy, collected by envc {}",
            args.episodes,
            id,
            policy_name(args.policy),
            env!("CARGO_PKG_VERSION")
        )
    });
    let info = DatasetInfo {
        author: vec![args.author.clone()],
        author_email: args.author_email.iter().cloned().collect(),
        algorithm_name: Some(policy_name(args.policy).to_string()),
        code_permalink: args.code_permalink.clone(),
        description: Some(description),
        ..DatasetInfo::default()
    };
    let opts = CollectOptions {
        root: args.root.clone(),
        dataset_id: args.dataset_id.clone(),
        format,
        info,
    };
    let mut collector = Collector::new(env, opts).map_err(|e| anyhow::anyhow!("{e}"))?;
    let base_seed = args.seed;
    let mut seed_rng = NumpyRng::from_entropy();
    let mut policy_rng = NumpyRng::from_seed(args.seed.unwrap_or_else(|| seed_rng.next_u64()));
    let mut cursor = 0usize;
    let kind = args.policy;
    let mut policy = |_obs: &E::Obs, a: &mut [f32]| match kind {
        PolicyKind::Zero => a.fill(0.0),
        PolicyKind::Random => {
            for (i, x) in a.iter_mut().enumerate() {
                *x = policy_rng.uniform(space.low[i], space.high[i]) as f32;
            }
        }
        PolicyKind::Replay => {
            if cursor + act_dim > actions.len() {
                cursor = 0;
            }
            a.copy_from_slice(&actions[cursor..cursor + act_dim]);
            cursor += act_dim;
        }
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
    let mut steps = 0u64;
    for ep in 0..args.episodes {
        let seed = match base_seed {
            Some(s) => s.wrapping_add(ep),
            None => seed_rng.next_u64(),
        };
        let s = collector
            .episode(seed, &mut policy)
            .map_err(|e| anyhow::anyhow!("episode {ep}: {e}"))?;
        steps += s.steps as u64;
        bar.set_prefix(steps.to_string());
        bar.inc(1);
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    let warnings: Vec<String> = collector.env().warnings().to_vec();
    let dir = collector.finish().map_err(|e| anyhow::anyhow!("{e}"))?;
    println!(
        "{}: {} episodes, {steps} steps ({:.0} steps/s) written to {}",
        args.dataset_id,
        args.episodes,
        steps as f64 / secs.max(1e-9),
        dir.display()
    );
    for w in warnings {
        println!("  MuJoCo warning: {w}");
    }
    Ok(Outcome::Ok)
}

fn policy_name(p: PolicyKind) -> &'static str {
    match p {
        PolicyKind::Zero => "zero",
        PolicyKind::Random => "random",
        PolicyKind::Replay => "replay",
    }
}
