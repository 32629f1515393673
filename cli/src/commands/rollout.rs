//! `envc rollout SPEC|ID --seed S (--actions A.npy | --policy zero|random --steps N) --out T.npz
//! [--set k=v ...] [--auto-reset]`: run one action sequence and save the trajectory (format in the
//! README, "Trajectory files"). `--policy` needs no numpy to try an env.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use envc::npy::{Matrix, read_matrix};
use ndarray::{Array, Array1, Array2, ArrayD, IxDyn};
use ndarray_npy::NpzWriter;

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id.
    spec: String,
    /// Seed of the first reset (omit for OS entropy, as `reset()` without a seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Actions: a `.npy` array [T, act_dim] of float64 (float32 is stepped as a float32 policy).
    #[arg(long, value_name = "A.npy", required_unless_present = "policy", conflicts_with_all = ["policy", "steps"])]
    actions: Option<PathBuf>,
    /// Instead of `--actions`: all-zero actions, or float32 actions uniform in the action
    /// space's bounds (drawn from numpy's PCG64 seeded with `--seed`, else 0).
    #[arg(long, value_enum, requires = "steps")]
    policy: Option<Policy>,
    /// With `--policy`: how many steps.
    #[arg(long, value_name = "N", requires = "policy", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    steps: Option<usize>,
    /// Output `.npz` file.
    #[arg(long, value_name = "T.npz")]
    out: PathBuf,
    /// Parameter overrides (`key=value`, TOML literal values).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// After an episode ends, `reset()` without a seed and go on through all actions.
    #[arg(long)]
    auto_reset: bool,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum Policy {
    Zero,
    Random,
}

/// `steps` actions of `policy` for an action space (float32, as a Box(float32) samples them).
fn policy_actions(policy: Policy, steps: usize, space: &envc::BoxSpace, seed: u64) -> Matrix {
    let n = space.dim();
    let mut rng = envc::rng::NumpyRng::from_seed(seed);
    let values = (0..steps * n)
        .map(|k| match policy {
            Policy::Zero => 0.0,
            Policy::Random => rng.uniform(space.low[k % n], space.high[k % n]) as f32,
        })
        .collect();
    Matrix::F32(Array2::from_shape_vec((steps, n), values).expect("steps × act_dim values"))
}

/// Per-key info values collected over steps.
#[derive(Default)]
struct InfoColumns {
    keys: Vec<(String, usize)>,
    values: BTreeMap<String, Vec<f64>>,
}

impl InfoColumns {
    fn push(&mut self, info: envc::Info<'_>) {
        if self.keys.is_empty() {
            self.keys = info.iter().map(|(k, v)| (k.to_string(), v.len())).collect();
        }
        for (k, v) in info.iter() {
            self.values
                .entry(k.to_string())
                .or_default()
                .extend_from_slice(v);
        }
    }
    /// `[n]` for scalar keys, `[n, k]` for vector keys.
    fn arrays(&self, prefix: &str) -> Result<Vec<(String, ArrayD<f64>)>> {
        let mut out = vec![];
        for (k, len) in &self.keys {
            let v = self.values[k].clone();
            let n = v.len() / len;
            let shape = if *len == 1 { vec![n] } else { vec![n, *len] };
            out.push((
                format!("{prefix}.{k}"),
                Array::from_shape_vec(IxDyn(&shape), v)?,
            ));
        }
        Ok(out)
    }
}

/// E1402: a trajectory of `steps` steps would not fit envc's in-memory limit.
fn check_size(steps: usize, env: &envc::AnyEnv) -> Result<()> {
    // envc's limit, or half of what the process may still allocate (the arrays are copied
    // once more while the .npz is written), whichever is smaller.
    let free = envc::memory::available().map(|b| b / 2);
    let limit = free.map_or(envspec::limits::MAX_TRAJECTORY_BYTES, |f| {
        f.min(envspec::limits::MAX_TRAJECTORY_BYTES)
    });
    let which = if limit < envspec::limits::MAX_TRAJECTORY_BYTES {
        "half the memory this process may still allocate"
    } else {
        "envc's limit"
    };
    // Observation, action, reward, flags and a few info numbers per step (an estimate).
    let per_step = (env.physics_env().obs_dim() + env.act_dim() + 8) as u64 * 8;
    if (steps as u64).saturating_mul(per_step) <= limit {
        return Ok(());
    }
    Err(anyhow::anyhow!(
        "{}",
        envspec::Diagnostic::new(
            envspec::Code::E1402,
            format!(
                "a rollout of {steps} steps of {} would hold about {:.2} GiB in memory, beyond {which} ({:.2} GiB)",
                env.id(),
                (steps as u64).saturating_mul(per_step) as f64 / (1u64 << 30) as f64,
                limit as f64 / (1u64 << 30) as f64
            ),
        )
        .help(format!("at most {} steps; split it into several rollouts (see docs/limits.md)", limit / per_step))
    ))
}

pub fn run(args: Args) -> Result<Outcome> {
    if let Some(a) = &args.actions {
        crate::output::refuse_input(&args.out, &[("--actions", a)])?;
    }
    let any = crate::target::env(&args.spec, &args.set)?;
    if let Some(steps) = args.steps {
        check_size(steps, &any)?;
    }
    let (actions, path) = match (&args.actions, args.policy, args.steps) {
        (Some(p), _, _) => (read_matrix(p)?, p.clone()),
        (None, Some(policy), Some(steps)) => {
            let seed = args.seed.unwrap_or(0);
            let name = match policy {
                Policy::Zero => "--policy zero",
                Policy::Random => "--policy random",
            };
            (
                policy_actions(policy, steps, any.action_space(), seed),
                PathBuf::from(name),
            )
        }
        _ => bail!("give --actions A.npy, or --policy zero|random with --steps N"),
    };
    check_size(actions.dim().0, &any)?;
    crate::target::action_file_shape(&path, actions.dim(), any.id(), any.act_dim())?;
    // Mazes and multi-agent specs step float64 (their references have no float32 cost path).
    let as_f64 = || actions.clone().into_f64();
    let (seed, out, auto) = (args.seed, &args.out, args.auto_reset);
    let mut env = match any {
        envc::AnyEnv::Task(env) => env,
        envc::AnyEnv::Maze(env) => {
            return crate::commands::maze::rollout(*env, seed, &as_f64(), out, auto);
        }
        envc::AnyEnv::Agents(env) => {
            return crate::commands::multi_agent::rollout(env, seed, &as_f64(), out, auto);
        }
    };
    let t_max = actions.dim().0;
    let obs_dim = env.obs_dim();

    let mut obs: Vec<f64> = vec![];
    let (mut reward, mut terminated, mut truncated) = (vec![], vec![], vec![]);
    let mut step_info = InfoColumns::default();
    let mut reset_obs: Vec<f64> = vec![];
    let mut reset_at: Vec<i64> = vec![];
    let mut first_reset = InfoColumns::default();

    let (o, info) = env.reset(args.seed);
    obs.extend_from_slice(o);
    reset_obs.extend_from_slice(o);
    reset_at.push(0);
    first_reset.push(info);

    for t in 0..t_max {
        let s = match &actions {
            Matrix::F64(a) => env.step(a.row(t).as_slice().context("actions must be in C order")?),
            Matrix::F32(a) => {
                env.step_f32(a.row(t).as_slice().context("actions must be in C order")?)
            }
        }
        .map_err(|e| anyhow::anyhow!("step {t}: {e}"))?;
        obs.extend_from_slice(s.obs);
        reward.push(s.reward);
        terminated.push(s.terminated);
        truncated.push(s.truncated);
        let done = s.terminated || s.truncated;
        step_info.push(s.info);
        if done {
            if !args.auto_reset {
                break;
            }
            if t + 1 < t_max {
                let (o, _) = env.reset(None);
                reset_obs.extend_from_slice(o);
                reset_at.push(t as i64 + 1);
            }
        }
    }

    let n = reward.len();
    let (dest, file) = crate::output::Output::create(&args.out)?;
    let mut npz = NpzWriter::new(file);
    npz.add_array("obs", &Array2::from_shape_vec((n + 1, obs_dim), obs)?)?;
    npz.add_array("reward", &Array1::from(reward))?;
    npz.add_array("terminated", &Array1::from(terminated))?;
    npz.add_array("truncated", &Array1::from(truncated))?;
    for (name, a) in step_info.arrays("info")? {
        npz.add_array(name.as_str(), &a)?;
    }
    for (name, a) in first_reset.arrays("reset_info")? {
        // The first reset's info: one value per key ([] for scalars, [k] for vectors).
        let a = a.index_axis_move(ndarray::Axis(0), 0);
        npz.add_array(name.as_str(), &a)?;
    }
    if args.auto_reset {
        let r = reset_at.len();
        npz.add_array(
            "reset_obs",
            &Array2::from_shape_vec((r, obs_dim), reset_obs)?,
        )?;
        npz.add_array("reset_at", &Array1::from(reset_at))?;
    }
    dest.commit(npz.finish()?)?;
    let warnings = env.warnings();
    for w in warnings {
        eprintln!("MuJoCo warning: {w}");
    }
    eprintln!(
        "{}: {n} steps written to {}",
        env.spec().id,
        args.out.display()
    );
    Ok(Outcome::Ok)
}
