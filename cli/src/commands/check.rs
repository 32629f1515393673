//! `envc check SPEC...`: validate specs and the models they name; every error at once.

use anyhow::Result;
use envspec::Diagnostic;

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Spec files or bundled env ids.
    #[arg(required = true)]
    specs: Vec<String>,
    /// Parameter overrides applied to every spec (`key=value`, TOML literal values).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Also compile each model with MuJoCo (catches what only the compiler sees).
    #[arg(long)]
    compile: bool,
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
}

#[derive(clap::ValueEnum, Clone, Copy, PartialEq)]
enum Format {
    Text,
    Json,
}

fn json(d: &Diagnostic) -> serde_json::Value {
    let (file, line, column) = match &d.location {
        Some(l) => {
            let (line, col) = l.file.line_col(l.span.start);
            (
                Some(l.file.path.display().to_string()),
                Some(line),
                Some(col),
            )
        }
        None => (None, None, None),
    };
    serde_json::json!({
        "code": d.code.to_string(), "message": d.message, "file": file, "line": line, "column": column,
        "expected": d.label, "help": d.help,
    })
}

pub fn run(args: Args) -> Result<Outcome> {
    let overrides = crate::target::overrides(&args.set)?;
    let mut report = vec![];
    let mut failed = 0;
    for s in &args.specs {
        if crate::commands::maze::is_maze(s) {
            // A maze spec or a registered maze id: the maze file, its robot spec and the world.
            let (ok, diags, extra) = crate::commands::maze::check(s, &overrides);
            if !ok {
                failed += 1;
            }
            match args.format {
                Format::Text if ok => println!("ok {s}"),
                Format::Text => {
                    for d in &diags {
                        println!("{d}");
                    }
                    if let Some(e) = &extra {
                        println!("{e}");
                    }
                    println!("FAILED {s} ({} errors)", diags.len().max(1));
                }
                Format::Json => report.push(serde_json::json!({
                    "spec": s, "ok": ok,
                    "errors": diags.iter().map(json).collect::<Vec<_>>(), "compile_error": extra,
                })),
            }
            continue;
        }
        let path = crate::target::spec_path(s)?;
        if envspec::agents::is_multi_agent(&path) {
            // A multi-agent spec: the factorization and its base spec (envspec::agents).
            let r = crate::commands::multi_agent::check(&path, &overrides, args.compile);
            let (ok, diags, extra) = r;
            if !ok {
                failed += 1;
            }
            match args.format {
                Format::Text if ok => println!("ok {}", path.display()),
                Format::Text => {
                    for d in &diags {
                        println!("{d}");
                    }
                    if let Some(e) = &extra {
                        println!("{e}");
                    }
                    println!("FAILED {} ({} errors)", path.display(), diags.len().max(1));
                }
                Format::Json => report.push(serde_json::json!({
                    "spec": path.display().to_string(), "ok": ok,
                    "errors": diags.iter().map(json).collect::<Vec<_>>(), "compile_error": extra,
                })),
            }
            continue;
        }
        let (ok, diags, extra) = match envspec::load(&path, &overrides) {
            Ok(spec) => {
                if args.compile {
                    match envc::Env::new(std::sync::Arc::new(spec)) {
                        Ok(_) => (true, vec![], None),
                        Err(e) => (false, vec![], Some(e.to_string())),
                    }
                } else {
                    (true, vec![], None)
                }
            }
            Err(d) => (false, d.0, None),
        };
        if !ok {
            failed += 1;
        }
        match args.format {
            Format::Text => {
                if ok {
                    println!("ok {}", path.display());
                } else {
                    for d in &diags {
                        println!("{d}");
                    }
                    if let Some(e) = &extra {
                        println!("{e}");
                    }
                    println!(
                        "FAILED {} ({} error{})",
                        path.display(),
                        diags.len().max(1),
                        if diags.len() > 1 { "s" } else { "" }
                    );
                }
            }
            Format::Json => report.push(serde_json::json!({
                "spec": path.display().to_string(), "ok": ok,
                "errors": diags.iter().map(json).collect::<Vec<_>>(), "compile_error": extra,
            })),
        }
    }
    if args.format == Format::Json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(if failed > 0 {
        Outcome::Problems
    } else {
        Outcome::Ok
    })
}
