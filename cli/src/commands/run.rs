//! `envc run SPEC|ID [--episodes N] [--policy zero|random] [--seed S] [--set k=v ...]`: episodes with
//! a progress bar, then a summary of returns, lengths and throughput. Any kind of spec: a maze's
//! reward is its goal reward, a multi-agent spec's the shared team reward of the joint action.

use std::time::Instant;

use anyhow::Result;
use envc::rng::NumpyRng;
use indicatif::{ProgressBar, ProgressStyle};

use crate::Outcome;
use envc::{JointAction, JointEnv};

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id.
    spec: String,
    /// Episodes to run (at most 10,000,000: each keeps its return and length for the summary).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(0..=10_000_000))]
    episodes: u64,
    #[arg(long, value_enum, default_value = "random")]
    policy: Policy,
    /// Seed of the first reset (later episodes continue the stream) and of the random policy.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Parameter overrides (`key=value`, TOML literal values).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Episode length cap. Required for envs without a time limit (a continuing maze, a spec
    /// with `max_episode_steps = 0`), which might otherwise never end; for others it caps
    /// episodes below their own limit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    max_steps: Option<u64>,
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum Policy {
    /// All-zero actions.
    Zero,
    /// Uniform in the action space's bounds.
    Random,
}

#[derive(clap::ValueEnum, Clone, Copy, PartialEq)]
enum Format {
    Text,
    Json,
}

/// mean, population std, min, max
fn stats(x: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len().max(1) as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    let min = x.iter().copied().fold(f64::INFINITY, f64::min);
    let max = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean, var.sqrt(), min, max)
}

pub fn run(args: Args) -> Result<Outcome> {
    let mut env = crate::target::env(&args.spec, &args.set)?;
    let limit = env.max_episode_steps();
    let Some(cap) = args.max_steps.or(limit) else {
        return Err(crate::target::needs_max_steps(
            "run",
            env.id(),
            "give --max-steps N (steps per episode), or ",
        ));
    };
    let tally = run_episodes(&args, &mut env, cap)?;
    if tally.returns.is_empty() {
        // No episode, no statistics: min/max of nothing would print as inf / -inf.
        match args.format {
            Format::Json => println!(
                "{}",
                serde_json::to_string_pretty(&serde_json::json!({
                    "env": env.id(), "episodes": 0, "steps": 0, "terminations": 0,
                    "return": null, "length": null, "steps_per_second": null,
                    "warnings": env.warnings(), "terminated_by": [], "reset_state_fails": null,
                }))?
            ),
            Format::Text => println!("{}: no episodes run (--episodes 0)", env.id()),
        }
        return Ok(Outcome::Ok);
    }
    match args.format {
        Format::Json => print_json(&args, &env, &tally)?,
        Format::Text => print_text(&args, &env, &tally),
    }
    Ok(Outcome::Ok)
}

/// What the episodes of a run came to.
struct Tally {
    returns: Vec<f64>,
    lengths: Vec<f64>,
    steps: u64,
    terminations: u64,
    /// Whether the spec reports `is_success` (goal tasks, as HER evaluates them).
    tracks_success: bool,
    /// Episodes whose last step reported `is_success` = 1.
    successes: u64,
    /// Why episodes ended: reason → (count, an example).
    endings: std::collections::BTreeMap<String, (u64, String)>,
    /// A health check the reset state already fails.
    bad_start: Option<envc::Unhealthy>,
    /// Wall time of the episodes.
    secs: f64,
}

/// `args.episodes` episodes of at most `cap` steps, with a progress bar in text mode.
fn run_episodes(args: &Args, env: &mut envc::AnyEnv, cap: u64) -> Result<Tally> {
    let space = env.action_space().clone();
    // The policy's own stream, separate from the env's (as Gymnasium's action_space.seed).
    let mut policy_rng = NumpyRng::from_seed(args.seed);
    let mut action = vec![0.0; env.act_dim()];
    let bar = if args.format == Format::Text {
        ProgressBar::new(args.episodes)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} episodes ({elapsed})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(env.id().to_string());
    let mut tally = Tally {
        returns: vec![],
        lengths: vec![],
        steps: 0,
        terminations: 0,
        tracks_success: env
            .physics_env()
            .spec()
            .info
            .iter()
            .any(|i| i.key == "is_success"),
        successes: 0,
        endings: Default::default(),
        bad_start: None,
        secs: 0.0,
    };
    let start = Instant::now();
    for ep in 0..args.episodes {
        env.try_reset(if ep == 0 { Some(args.seed) } else { None })?;
        if tally.bad_start.is_none() && env.kind() != envspec::Kind::Maze {
            tally.bad_start = env.physics_env().unhealthy();
        }
        let (mut ret, mut len) = (0.0, 0u64);
        loop {
            if let Policy::Random = args.policy {
                for (i, a) in action.iter_mut().enumerate() {
                    *a = policy_rng.uniform(space.low[i], space.high[i]);
                }
            }
            let s = env.step_joint(JointAction::F64(&action))?;
            ret += s.reward;
            len += 1;
            if s.terminated || s.truncated || len >= cap {
                tally.terminations += s.terminated as u64;
                let info = env.physics_env().step_info();
                tally.successes += u64::from(info.scalar("is_success") == Some(1.0));
                if s.terminated {
                    let (reason, example) = ending(env);
                    let e = tally.endings.entry(reason).or_insert((0, example));
                    e.0 += 1;
                }
                break;
            }
        }
        tally.steps += len;
        tally.returns.push(ret);
        tally.lengths.push(len as f64);
        bar.inc(1);
    }
    bar.finish_and_clear();
    tally.secs = start.elapsed().as_secs_f64();
    Ok(tally)
}

/// The summary as JSON (`--format json`).
fn print_json(args: &Args, env: &envc::AnyEnv, t: &Tally) -> Result<()> {
    let (rm, rs, rmin, rmax) = stats(&t.returns);
    let (lm, ls, lmin, lmax) = stats(&t.lengths);
    let sps = t.steps as f64 / t.secs.max(1e-9);
    println!(
        "{}",
        serde_json::to_string_pretty(&serde_json::json!({
            "env": env.id(), "episodes": args.episodes, "steps": t.steps, "terminations": t.terminations,
            "return": {"mean": rm, "std": rs, "min": rmin, "max": rmax},
            "length": {"mean": lm, "std": ls, "min": lmin, "max": lmax},
            "steps_per_second": sps, "warnings": env.warnings(),
            "terminated_by": t.endings.iter().map(|(r, (n, e))| serde_json::json!({"reason": r, "count": n, "example": e})).collect::<Vec<_>>(),
            "reset_state_fails": t.bad_start.as_ref().map(|u| u.check.clone()),
            "success_rate": t.tracks_success.then(|| t.successes as f64 / args.episodes as f64),
        }))?
    );
    Ok(())
}

/// The summary as text, with warnings about episodes that end at once.
fn print_text(args: &Args, env: &envc::AnyEnv, t: &Tally) {
    use crate::plural;
    let (rm, rs, rmin, rmax) = stats(&t.returns);
    let (lm, ls, lmin, lmax) = stats(&t.lengths);
    let sps = t.steps as f64 / t.secs.max(1e-9);
    let (terminations, successes) = (t.terminations, t.successes);
    println!(
        "{}: {}, {} ({terminations} terminated)",
        env.id(),
        plural(args.episodes, "episode", "episodes"),
        plural(t.steps, "step", "steps"),
    );
    println!("  return  mean {rm:.3}  std {rs:.3}  min {rmin:.3}  max {rmax:.3}");
    println!("  length  mean {lm:.1}  std {ls:.1}  min {lmin}  max {lmax}");
    if t.tracks_success {
        println!(
            "  success {:.1} % ({successes} of {} episodes end with is_success = 1)",
            100.0 * successes as f64 / args.episodes as f64,
            args.episodes
        );
    }
    println!("  {sps:.0} steps/s");
    for (reason, (n, example)) in &t.endings {
        println!("  terminated {n}× by {reason}: {example}");
    }
    if let Some(u) = &t.bad_start {
        println!(
            "  warning: the reset state already fails health check `{}`: {} = {} ({}); check the spec's reset and the model's initial pose",
            u.check,
            u.element,
            u.value,
            rule(&u.rule)
        );
    } else if terminations == args.episodes && lm <= 3.0 {
        println!(
            "  warning: every episode ended within {}: the initial state may already be close to failing a check",
            plural(lmax as u64, "step", "steps")
        );
    }
    for w in env.warnings() {
        println!("  MuJoCo warning: {w}");
    }
}

/// A check's rule as a clause: the range and finite kinds say when the state is healthy,
/// `fails_if` already says when it is not (`describe::check`).
fn rule(rule: &str) -> String {
    if rule.starts_with("unhealthy") {
        rule.to_string()
    } else {
        format!("healthy when {rule}")
    }
}

/// Why the last step terminated: a health check with the failing element and its value, a goal
/// reached, or another termination condition.
fn ending(env: &envc::AnyEnv) -> (String, String) {
    if env.kind() == envspec::Kind::Maze {
        return ("the goal".into(), "the robot reached the goal".into());
    }
    match env.physics_env().unhealthy() {
        Some(u) => (
            format!("health check `{}`", u.check),
            format!("{} = {} ({})", u.element, u.value, rule(&u.rule)),
        ),
        None => (
            "a termination condition".into(),
            "the state is healthy: a [termination] condition held".into(),
        ),
    }
}
