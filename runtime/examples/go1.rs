//! A third-party robot from a spec alone: builds the Go1 task of `specs/examples/go1.toml` with the
//! model given on the command line, prints its observation layout, and runs a few episodes with a
//! simple policy (a sinusoid around the middle of each control range) and with a random one.
//!
//! ```text
//! cargo run --release -p envc --example go1 -- [MODEL.xml] [--episodes N] [--spec SPEC.toml]
//! ```
//! MODEL defaults to `../shared/models/unitree_go1/scene.xml`; a MuJoCo Menagerie checkout's
//! `unitree_go1/scene.xml` works the same way. Nothing here knows about the Go1: any spec works.

use std::process::ExitCode;

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
    let mut model = "../shared/models/unitree_go1/scene.xml".to_string();
    let mut spec = concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/examples/go1.toml").to_string();
    let mut episodes = 3usize;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--episodes" => {
                episodes = args
                    .next()
                    .and_then(|v| v.parse().ok())
                    .ok_or("--episodes needs a number")?
            }
            "--spec" => spec = args.next().ok_or("--spec needs a path")?,
            _ => model = a,
        }
    }
    let overrides = [Override::text("xml_file", &model)];
    let mut env = Env::from_spec_file(&spec, &overrides).map_err(|e| e.to_string())?;
    let s = env.spec().clone();
    println!(
        "{}: obs dim {}, action dim {}, dt {} s, model {}",
        s.id,
        s.obs_dim,
        s.act_dim(),
        s.dt(),
        s.model_path.display()
    );
    println!("\nobservation layout:");
    for seg in &s.observation {
        let names = seg.element_names();
        let shown = if names.len() > 4 {
            format!("{}, {}, …, {}", names[0], names[1], names[names.len() - 1])
        } else {
            names.join(", ")
        };
        println!(
            "  {:>3}..{:<3} {:<10} {shown}",
            seg.offset,
            seg.offset + seg.len(),
            seg.name
        );
    }
    let sp = env.action_space().clone();
    println!("\nactions (control ranges from the compiled model):");
    for (i, a) in s.model.actuators.iter().enumerate() {
        println!("  {i:>2} {:<12} [{}, {}]", a.name, sp.low[i], sp.high[i]);
    }

    let mut rng = NumpyRng::from_seed(0);
    for policy in ["sinusoid", "random"] {
        println!("\npolicy: {policy}");
        for ep in 0..episodes {
            env.reset(Some(ep as u64));
            let (mut ret, mut len) = (0.0, 0u64);
            let mut action = vec![0.0; sp.dim()];
            loop {
                for (i, a) in action.iter_mut().enumerate() {
                    let (lo, hi) = (sp.low[i], sp.high[i]);
                    *a = match policy {
                        "random" => rng.uniform(lo, hi),
                        // Middle of the range plus a small, phase-shifted oscillation.
                        _ => {
                            let t = len as f64 * s.dt();
                            0.5 * (lo + hi) + 0.1 * (hi - lo) * (6.0 * t + i as f64).sin()
                        }
                    };
                }
                let st = env.step(&action).map_err(|e| e.to_string())?;
                ret += st.reward;
                len += 1;
                if st.terminated || st.truncated {
                    let how = if st.terminated {
                        "terminated"
                    } else {
                        "truncated"
                    };
                    println!("  episode {ep}: return {ret:9.3}, length {len:4} ({how})");
                    break;
                }
            }
        }
    }
    Ok(())
}
