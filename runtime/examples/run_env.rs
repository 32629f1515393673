//! Run a few episodes of an env with a uniformly random policy and print what happened.
//!
//! ```text
//! cargo run --release -p envc --example run_env -- Ant-v5 [--episodes N] [--seed S] [--set key=value ...]
//! ```
//! The env is a bundled id (see `specs/`) or a path to a spec file.

use std::process::ExitCode;
use std::time::Instant;

use envc::rng::NumpyRng;
use envc::{Env, Override};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let mut env_id = None;
    let (mut episodes, mut seed, mut overrides) = (3usize, 0u64, vec![]);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--episodes" => {
                episodes = value("--episodes")?
                    .parse()
                    .map_err(|e| format!("--episodes: {e}"))?
            }
            "--seed" => {
                seed = value("--seed")?
                    .parse()
                    .map_err(|e| format!("--seed: {e}"))?
            }
            "--set" => {
                overrides.push(Override::parse(&value("--set")?).map_err(|d| d.to_string())?)
            }
            _ if env_id.is_none() => env_id = Some(a),
            _ => return Err(format!("unexpected argument `{a}`")),
        }
    }
    let env_id = env_id
        .ok_or("usage: run_env ENV_ID|SPEC [--episodes N] [--seed S] [--set key=value ...]")?;
    let mut env = Env::make(&env_id, &overrides).map_err(|e| e.to_string())?;
    let spec = env.spec().clone();
    println!(
        "{}: obs dim {}, action dim {}, dt {}, max steps {:?}",
        spec.id,
        env.obs_dim(),
        env.act_dim(),
        env.dt(),
        spec.max_episode_steps
    );
    let (low, high) = (
        env.action_space().low.clone(),
        env.action_space().high.clone(),
    );
    let mut policy = NumpyRng::from_seed(seed ^ 0x5eed);
    let mut action = vec![0.0; env.act_dim()];
    let start = Instant::now();
    let mut total_steps = 0u64;
    for ep in 0..episodes {
        env.reset(if ep == 0 { Some(seed) } else { None });
        let (mut ret, mut len) = (0.0, 0u64);
        loop {
            for (i, a) in action.iter_mut().enumerate() {
                *a = policy.uniform(low[i], high[i]);
            }
            let s = env.step(&action).map_err(|e| e.to_string())?;
            ret += s.reward;
            len += 1;
            if s.terminated || s.truncated {
                let how = if s.terminated {
                    "terminated"
                } else {
                    "truncated"
                };
                println!("episode {ep}: return {ret:.3}, length {len} ({how})");
                break;
            }
        }
        total_steps += len;
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{total_steps} steps in {secs:.2} s ({:.0} steps/s)",
        total_steps as f64 / secs
    );
    for w in env.warnings() {
        println!("MuJoCo warning: {w}");
    }
    Ok(())
}
