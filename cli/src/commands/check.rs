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
        // Any kind through the one door; mazes are always compiled (their checks need the world).
        let (kind, diags, extra) = match envspec::open(s, &overrides) {
            Ok(spec) => {
                let kind = Some(spec.kind());
                // A factorization is checked at every conf and depth, not only the one it opened.
                if let envc::AnySpec::MultiAgent(a) = &spec {
                    let d = crate::kinds::multi_agent::check_confs(a, &overrides);
                    if !d.is_empty() {
                        report_one(&args, &mut report, &mut failed, s, kind, d, None, &[]);
                        continue;
                    }
                }
                let extra = (args.compile || spec.kind() == envspec::Kind::Maze)
                    .then(|| envc::AnyEnv::new(spec).err())
                    .flatten();
                match extra {
                    Some(envc::EnvError::Spec(d)) => (kind, d.0, None),
                    Some(e) => (kind, vec![], Some(e.to_string())),
                    None => (kind, vec![], None),
                }
            }
            Err(d) => (None, d.0, None),
        };
        let warnings = match envspec::open(s, &overrides) {
            Ok(envc::AnySpec::Task(r)) => r.warnings.clone(),
            _ => vec![],
        };
        report_one(
            &args,
            &mut report,
            &mut failed,
            s,
            kind,
            diags,
            extra,
            &warnings,
        );
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

/// Print (text) or collect (JSON) one spec's result.
#[allow(clippy::too_many_arguments)]
fn report_one(
    args: &Args,
    report: &mut Vec<serde_json::Value>,
    failed: &mut usize,
    s: &str,
    kind: Option<envspec::Kind>,
    diags: Vec<Diagnostic>,
    extra: Option<String>,
    warnings: &[Diagnostic],
) {
    let ok = diags.is_empty() && extra.is_none();
    *failed += usize::from(!ok);
    if args.format == Format::Text {
        for w in warnings {
            eprint!("{}", w.warning_text());
        }
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
            let n = diags.len().max(1);
            println!("FAILED {s} ({n} error{})", if n > 1 { "s" } else { "" });
        }
        Format::Json => report.push(serde_json::json!({
            "spec": s, "kind": kind, "ok": ok,
            "errors": diags.iter().map(json).collect::<Vec<_>>(), "compile_error": extra,
            "warnings": warnings.iter().map(json).collect::<Vec<_>>(),
        })),
    }
}
