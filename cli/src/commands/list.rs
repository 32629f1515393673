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

pub fn run(args: Args) -> Result<Outcome> {
    let root = envc::registry::specs_dir();
    let mut rows = vec![];
    for (id, path) in envc::registry::bundled() {
        let spec =
            envspec::load(&path, &[]).map_err(|d| anyhow::anyhow!("{}: {d}", path.display()))?;
        let rel = path
            .strip_prefix(&root)
            .unwrap_or(&path)
            .display()
            .to_string();
        rows.push((
            id,
            spec.obs_dim,
            spec.act_dim(),
            spec.dt(),
            spec.max_episode_steps,
            format!("specs/{rel}"),
        ));
    }
    rows.extend(crate::commands::maze::list_rows()?);
    match args.format {
        Format::Json => {
            let v: Vec<_> = rows
                .iter()
                .map(|(id, o, a, dt, m, p)| {
                    serde_json::json!({"id": id, "obs_dim": o, "act_dim": a, "dt": dt, "max_episode_steps": m, "spec": p})
                })
                .collect();
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
        Format::Text => {
            println!(
                "{:<34} {:>7} {:>7} {:>8} {:>9}  spec",
                "id", "obs", "act", "dt", "max steps"
            );
            for (id, o, a, dt, m, p) in rows {
                let m = m.map(|m| m.to_string()).unwrap_or_else(|| "none".into());
                println!("{id:<34} {o:>7} {a:>7} {dt:>8} {m:>9}  {p}");
            }
        }
    }
    Ok(Outcome::Ok)
}
