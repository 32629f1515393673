//! `envc rollout SPEC|ID --seed S (--actions A.npy | --policy zero|random --steps N) --out T.npz
//! [--set k=v ...] [--auto-reset]`: run one action sequence and save the trajectory (format in the
//! README, "Trajectory files"). `--policy` needs no numpy to try an env.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use envc::npy::{Matrix, read_matrix};
use envc::{Env, JointAction, JointEnv, JointStep};
use ndarray::{Array1, Array2};
use ndarray_npy::NpzWriter;

use crate::Outcome;
use crate::output::Sticky;
pub(crate) use crate::trajectory::{InfoColumns, Trajectory};

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

/// Reset with `seed`, step through the rows of `actions` (float32 rows step as a float32 policy),
/// stop at the end of the episode or, with `auto_reset`, reset and go on; write the `.npz`.
pub(crate) fn roll<T: Trajectory>(
    env: &mut T::Env,
    mut rec: T,
    seed: Option<u64>,
    actions: &Matrix,
    out: &Path,
    auto_reset: bool,
) -> Result<Outcome> {
    let t_max = actions.dim().0;
    let (mut reward, mut terminated, mut truncated) = (vec![], vec![], vec![]);
    env.try_reset(seed).map_err(|e| anyhow::anyhow!("{e}"))?;
    rec.reset(env, None);
    for t in 0..t_max {
        let order = "actions must be in C order";
        let a = match actions {
            Matrix::F64(a) => JointAction::F64(a.row(t).to_slice().context(order)?),
            Matrix::F32(a) => JointAction::F32(a.row(t).to_slice().context(order)?),
        };
        let JointStep {
            reward: r,
            terminated: term,
            truncated: trunc,
        } = env
            .step_joint(a)
            .map_err(|e| anyhow::anyhow!("step {t}: {e}"))?;
        rec.step(env);
        reward.push(r);
        terminated.push(term);
        truncated.push(trunc);
        if term || trunc {
            if !auto_reset {
                break;
            }
            if t + 1 < t_max {
                env.try_reset(None).map_err(|e| anyhow::anyhow!("{e}"))?;
                rec.reset(env, Some(t + 1));
            }
        }
    }
    let n = reward.len();
    let (dest, file) = crate::output::Output::create(out)?;
    let mut npz = NpzWriter::new(file);
    rec.write_obs(&mut npz, env, n, auto_reset)?;
    npz.add_array("reward", &Array1::from(reward))?;
    npz.add_array("terminated", &Array1::from(terminated))?;
    npz.add_array("truncated", &Array1::from(truncated))?;
    // What made the file, as UTF-8 bytes (`bytes(z["mujoco_version"]).decode()`): the loaded
    // MuJoCo library's `mj_versionString` and envc's version.
    let text = |s: &str| Array1::from(s.as_bytes().to_vec());
    npz.add_array("mujoco_version", &text(&envc::mujoco_version()))?;
    npz.add_array("envc_version", &text(env!("CARGO_PKG_VERSION")))?;
    let name = rec.describe(env);
    rec.write_rest(&mut npz, env, auto_reset)?;
    dest.commit(npz.finish()?)?;
    for w in env.warnings() {
        eprintln!("MuJoCo warning: {w}");
    }
    eprintln!("{name}: {n} steps written to {}", out.display());
    Ok(Outcome::Ok)
}

/// A task's trajectory: `obs` [n+1, obs_dim], `info.<key>`, the first reset's `reset_info.<key>`;
/// with `--auto-reset` `reset_obs` and `reset_at` (the first reset included).
#[derive(Default)]
struct TaskTrajectory {
    obs: Vec<f64>,
    step_info: InfoColumns,
    first_reset: InfoColumns,
    reset_obs: Vec<f64>,
    reset_at: Vec<i64>,
}

impl Trajectory for TaskTrajectory {
    type Env = Env;
    fn reset(&mut self, env: &Env, at: Option<usize>) {
        if at.is_none() {
            self.obs.extend_from_slice(env.obs());
            self.first_reset.push(env.reset_info());
        }
        self.reset_obs.extend_from_slice(env.obs());
        self.reset_at.push(at.unwrap_or(0) as i64);
    }
    fn step(&mut self, env: &Env) {
        self.obs.extend_from_slice(env.obs());
        self.step_info.push(env.step_info());
    }
    fn write_obs(
        &mut self,
        npz: &mut NpzWriter<Sticky>,
        env: &Env,
        n: usize,
        _auto_reset: bool,
    ) -> Result<()> {
        let obs = std::mem::take(&mut self.obs);
        npz.add_array("obs", &Array2::from_shape_vec((n + 1, env.obs_dim()), obs)?)?;
        Ok(())
    }
    fn write_rest(self, npz: &mut NpzWriter<Sticky>, env: &Env, auto_reset: bool) -> Result<()> {
        self.step_info.write(npz, "info")?;
        self.first_reset.write_first(npz, "reset_info")?;
        if auto_reset {
            let r = self.reset_at.len();
            npz.add_array(
                "reset_obs",
                &Array2::from_shape_vec((r, env.obs_dim()), self.reset_obs)?,
            )?;
            npz.add_array("reset_at", &Array1::from(self.reset_at))?;
        }
        Ok(())
    }
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
    let as_f64 = || Matrix::F64(actions.clone().into_f64());
    let (seed, out, auto) = (args.seed, args.out.as_path(), args.auto_reset);
    match any {
        envc::AnyEnv::Task(mut env) => roll(
            &mut env,
            TaskTrajectory::default(),
            seed,
            &actions,
            out,
            auto,
        ),
        envc::AnyEnv::Maze(mut env) => {
            let rec = crate::kinds::maze::MazeTrajectory::default();
            roll(&mut *env, rec, seed, &as_f64(), out, auto)
        }
        envc::AnyEnv::MultiAgent(mut env) => {
            let rec = crate::kinds::multi_agent::MultiAgentTrajectory::new(&env);
            roll(&mut env, rec, seed, &as_f64(), out, auto)
        }
    }
}
