//! `envc bench ID...|all`: step rates against the physics ceiling (the measuring is in
//! `envc::bench`).

use anyhow::Result;
use envc::bench::{BenchConfig, BenchResult};

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Bundled ids or spec files of any kind; `all` for every bundled id. Mazes and multi-agent
    /// specs are measured single-env (vector envs run tasks; their vector columns show `-`).
    #[arg(required = true)]
    envs_or_all: Vec<String>,
    /// Envs in the vectorized measurement.
    #[arg(long = "envs", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=4096))]
    num_envs: u32,
    /// Threads of the vectorized measurement (the caller counts as one).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=256))]
    threads: u32,
    /// Measuring time per env, split over the rounds and the three measurements.
    #[arg(long, default_value_t = 6.0, value_parser = seconds)]
    seconds: f64,
    /// Interleaved rounds (medians are reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    rounds: u32,
    /// Parameter overrides applied to every env (`key=value`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
}

#[derive(clap::ValueEnum, Clone, Copy, PartialEq)]
enum Format {
    Text,
    Json,
}

fn json(r: &BenchResult) -> serde_json::Value {
    serde_json::json!({
        "id": r.id, "frame_skip": r.frame_skip, "rne_post_constraint": r.rne_post_constraint,
        "envs": r.envs, "threads": r.threads, "rounds": r.rounds,
        "ceiling_steps_per_s": r.ceiling, "single_steps_per_s": r.single,
        "vector_steps_per_s": r.vector, "single_over_ceiling": r.single_ratio,
        "vector_over_threads_x_ceiling": r.vector_ratio,
        "parallel_ceiling_steps_per_s": r.parallel_ceiling, "vector_over_parallel_ceiling": r.vector_parallel_ratio, "mean_episode_len": r.episode_len,
    })
}

/// `--seconds`: a positive, finite duration of at most a day (an argument error otherwise).
fn seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x <= 86_400.0 => Ok(x),
        _ => Err("expected a positive number of seconds, at most a day (86400)".into()),
    }
}

pub fn run(args: Args) -> Result<Outcome> {
    let overrides = crate::target::overrides(&args.set)?;
    let ids: Vec<String> = if args.envs_or_all.iter().any(|a| a == "all") {
        envspec::registry::bundled().map(|e| e.id.clone()).collect()
    } else {
        args.envs_or_all.clone()
    };
    let cfg = BenchConfig {
        envs: args.num_envs as usize,
        threads: args.threads as usize,
        seconds: args.seconds,
        rounds: args.rounds as usize,
    };
    if args.format == Format::Text {
        println!(
            "{:<26} {:>3} {:>3} {:>11} {:>11} {:>6} {:>11} {:>7} {:>11} {:>6}",
            "env",
            "fs",
            "rne",
            "ceiling/s",
            "single/s",
            "÷ceil",
            "vector/s",
            "÷M·ceil",
            "par.ceil/s",
            "÷par"
        );
    }
    let mut out = vec![];
    for id in &ids {
        let r =
            envc::bench::bench(id, &overrides, &cfg).map_err(|e| anyhow::anyhow!("{id}: {e}"))?;
        match args.format {
            Format::Text => {
                // A measurement that does not apply (vector envs of a maze) prints as `-`.
                let f = |x: f64, prec: usize| {
                    if x.is_nan() {
                        "-".to_string()
                    } else {
                        format!("{x:.prec$}")
                    }
                };
                println!(
                    "{:<26} {:>3} {:>3} {:>11} {:>11} {:>6} {:>11} {:>7} {:>11} {:>6}",
                    r.id,
                    r.frame_skip,
                    if r.rne_post_constraint { "yes" } else { "no" },
                    f(r.ceiling, 0),
                    f(r.single, 0),
                    f(r.single_ratio, 3),
                    f(r.vector, 0),
                    f(r.vector_ratio, 3),
                    f(r.parallel_ceiling, 0),
                    f(r.vector_parallel_ratio, 3)
                )
            }
            Format::Json => out.push(json(&r)),
        }
    }
    match args.format {
        Format::Text => println!(
            "medians of {} interleaved rounds; vector: {} envs on {} threads and par.ceil: that many raw loops at once (wall time); others thread CPU time",
            cfg.rounds, cfg.envs, cfg.threads
        ),
        Format::Json => println!("{}", serde_json::to_string_pretty(&out)?),
    }
    Ok(Outcome::Ok)
}
