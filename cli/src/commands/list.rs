//! `envc list`

use anyhow::Result;

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Output format.
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum Format {
    Text,
    Json,
}

/// One row: id, kind, observation dim, joint action dim, dt, max steps, spec file.
type Row = (
    String,
    envspec::Kind,
    String,
    usize,
    f64,
    Option<u64>,
    String,
);

/// A row from the resolved spec (no MuJoCo): a maze's observation is its robot's plus the two
/// 2-D goals; a multi-agent spec lists each agent's observation size.
fn row(e: &envspec::registry::Entry) -> Result<Row> {
    let spec = envspec::open(&e.id, &[]).map_err(|d| anyhow::anyhow!("{}: {d}", e.id))?;
    let (obs, act, dt, max) = match &spec {
        envc::AnySpec::Task(s) => (
            s.obs_dim.to_string(),
            s.act_dim(),
            s.dt(),
            s.max_episode_steps,
        ),
        envc::AnySpec::Maze(m) => {
            let r = envspec::load(&m.robot, &m.robot_overrides)
                .map_err(|d| anyhow::anyhow!("{}: {d}", e.id))?;
            (
                format!("{}+2+2", r.obs_dim),
                r.act_dim(),
                r.dt(),
                m.max_episode_steps,
            )
        }
        envc::AnySpec::MultiAgent(a) => (
            {
                // `agents × obs`, or `agents × min..max` when they differ.
                let dims = a.agents.iter().map(|x| x.obs_dim);
                let (lo, hi) = (dims.clone().min().unwrap_or(0), dims.max().unwrap_or(0));
                let n = a.agents.len();
                if lo == hi {
                    format!("{n}×{lo}")
                } else {
                    format!("{n}×{lo}..{hi}")
                }
            },
            a.act_dim(),
            a.base.dt(),
            a.base.max_episode_steps,
        ),
    };
    let root = envspec::registry::specs_dir();
    // Bundled specs by their place in the bundle; the user's by their path.
    let spec = match e.path.strip_prefix(&root) {
        Ok(rel) if !e.user => format!("specs/{}", rel.display()),
        _ => e.path.display().to_string(),
    };
    Ok((e.id.clone(), e.kind, obs, act, dt, max, spec))
}

pub fn run(args: Args) -> Result<Outcome> {
    // The user's specs (ENVC_SPEC_PATH) follow the bundled ones; one that does not open is
    // named on stderr and left out, so a broken file of one's own never hides the rest.
    let mut rows: Vec<Row> = envspec::registry::bundled()
        .map(row)
        .collect::<Result<_>>()?;
    for e in envspec::registry::user_entries() {
        match row(e) {
            Ok(r) => rows.push(r),
            Err(err) => eprintln!("warning: {err}"),
        }
    }
    match args.format {
        Format::Json => {
            let v: Vec<_> = rows
                .iter()
                .map(|(id, k, o, a, dt, m, p)| {
                    serde_json::json!({"id": id, "kind": k, "obs_dim": o, "act_dim": a, "dt": dt, "max_episode_steps": m, "spec": p})
                })
                .collect();
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
        Format::Text => {
            println!(
                "{:<34} {:<11} {:>10} {:>5} {:>8} {:>9}  spec",
                "id", "kind", "obs", "act", "dt", "max steps"
            );
            for (id, k, o, a, dt, m, p) in rows {
                let m = m.map(|m| m.to_string()).unwrap_or_else(|| "none".into());
                println!(
                    "{id:<34} {:<11} {o:>10} {a:>5} {dt:>8} {m:>9}  {p}",
                    k.name()
                );
            }
        }
    }
    Ok(Outcome::Ok)
}
