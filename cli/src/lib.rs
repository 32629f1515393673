//! `envc`: work with environment specs from a terminal and in pull requests. A library so that
//! the same command runs as its own binary (`src/main.rs`) and inside the Python extension (the
//! wheel's `envc` console script, one native build per MuJoCo version instead of two).
//!
//! Exit status: 0 success; 1 the command ran and found problems (invalid spec, breaking diff, ...);
//! 2 bad arguments, unknown ids or unreadable files.

use std::ffi::OsString;

use clap::{Parser, Subcommand};

mod commands;
mod kinds;
mod output;
mod target;
mod trajectory;

#[derive(Parser)]
#[command(
    name = "envc",
    version,
    about = "Compile, inspect, run and diff robot RL environment specs"
)]
struct Cli {
    /// Numerics profile for every env the command builds: `auto` (as numpy would compute on this
    /// machine) or a named profile such as `openblas-skylakex+svml` (`envc info` lists them).
    /// Default: $ENVC_NUMERICS, else `auto`.
    #[arg(long, global = true, value_name = "PROFILE")]
    numerics: Option<String>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Every bundled env: id, obs dim, action dim, dt, max steps, source spec.
    List(commands::list::Args),
    /// Validate specs and the models they name.
    Check(commands::check::Args),
    /// Step rates against the physics ceiling: single env and vectorized.
    Bench(commands::bench::Args),
    /// The fully resolved spec: parameters, observation layout, actions, reward, health, reset, info.
    Show(commands::show::Args),
    /// Run one action sequence from a .npy file and save the trajectory as .npz.
    Rollout(commands::rollout::Args),
    /// Run episodes with a zero or random policy and summarise returns, lengths and speed.
    Run(commands::run::Args),
    /// Semantic diff of two specs (files or git `REV:path`): what breaks trained policies, what
    /// changes returns. Exit status 0 no change, 1 compatible, 3 breaking.
    Diff(commands::diff::Args),
    /// Record a Minari dataset (arrow or hdf5) from episodes of an env.
    Collect(commands::collect::Args),
    /// Inspect Minari datasets (envc's or Python's).
    Dataset(commands::dataset::Args),
    /// A crate of your own with a typed env of a spec: builds and runs with `cargo run`.
    New(commands::new::Args),
    /// This machine's CPU features, the numerics profile `auto` picks and why, and the versions
    /// envc matches.
    Info(commands::info::Args),
    /// Render episodes headless to a video (.mp4, .gif) or PNG frames, as Gymnasium renders them.
    Render(commands::render::Args),
}

/// `1 episode`, `2 episodes`.
pub fn plural(n: impl Into<u64>, one: &str, many: &str) -> String {
    let n = n.into();
    format!("{n} {}", if n == 1 { one } else { many })
}

/// How a command ended, mapped to the exit status.
pub enum Outcome {
    Ok,
    /// The command ran and found problems (status 1).
    Problems,
    /// `diff` found breaking changes (status 3).
    Breaking,
}

/// A collection stops at its next step on SIGINT, SIGTERM or SIGHUP, and the error that follows
/// removes its staging directory (the default action would end the process with it in place).
/// A second signal has the default action: the process ends at once.
pub(crate) fn stop_collections_on_signals() {
    envc::os::stop_on_signals(&envc_datasets::STOP);
}

/// Run the `envc` command line `args` (the program name first) and return its exit status.
/// Help, `--version` and malformed arguments end the process as clap does.
pub fn main_with(args: Vec<OsString>) -> u8 {
    envc::os::default_sigpipe();
    let cli = Cli::parse_from(args);
    if let Some(p) = &cli.numerics {
        match envc::numerics::Profile::resolve(p, "--numerics") {
            Ok(p) => envc::numerics::set_default_profile(p),
            Err(e) => {
                eprintln!("envc: {e}");
                return 2;
            }
        }
    }
    // A spec of one's own (ENVC_SPEC_PATH) that is unreadable or claims a taken id stops every
    // command, rather than being left out of the registry unseen.
    let problems = envspec::registry::spec_path_problems();
    if !problems.is_empty() {
        for d in &problems {
            eprint!("{d}");
        }
        eprintln!("envc: ENVC_SPEC_PATH names specs envc cannot register (above)");
        return 2;
    }
    let result = match cli.command {
        Command::List(a) => commands::list::run(a),
        Command::Check(a) => commands::check::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Show(a) => commands::show::run(a),
        Command::Rollout(a) => commands::rollout::run(a),
        Command::Run(a) => commands::run::run(a),
        Command::Diff(a) => commands::diff::run(a),
        Command::Collect(a) => commands::collect::run(a),
        Command::Dataset(a) => commands::dataset::run(a),
        Command::Info(a) => commands::info::run(a),
        Command::New(a) => commands::new::run(a),
        Command::Render(a) => commands::render::run(a),
    };
    match result {
        Ok(Outcome::Ok) => 0,
        Ok(Outcome::Problems) => 1,
        Ok(Outcome::Breaking) => 3,
        Err(e) => {
            // One line naming the problem; spec diagnostics keep their multi-line rendering.
            eprintln!("envc: {e:#}");
            2
        }
    }
}
