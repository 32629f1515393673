//! `envc diff OLD NEW [--format text|markdown|json|github]`: what a spec change does to trained
//! policies and published returns. OLD and NEW are spec files or git revisions (`REV:path`, path
//! relative to the repository root as in `git show`). Exit status: 0 no change, 1 compatible
//! changes only, 3 breaking changes, 2 errors.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use envspec::diff::Verdict;
use envspec::{ParamValue, Spec};

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// The old spec: a file, a bundled env id, or `REV:path` (a git revision).
    old: String,
    /// The new spec: a file, a bundled env id, or `REV:path`.
    new: String,
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
    /// Do not compile the two models with MuJoCo (skips the dynamics comparison).
    #[arg(long)]
    no_model: bool,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum Format {
    Text,
    Markdown,
    Json,
    /// GitHub Actions annotations (workflow commands).
    Github,
}

fn git(args: &[&str]) -> Result<Vec<u8>> {
    let out = Command::new("git")
        .args(args)
        .output()
        .context("cannot run git")?;
    if !out.status.success() {
        bail!(
            "git {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    Ok(out.stdout)
}

/// Files of a spec at a git revision, materialised under a temporary directory with the same
/// relative layout (so the spec's relative model path, and MJCF includes, resolve at that revision).
fn checkout(rev: &str, path: &str, tmp: &Path) -> Result<PathBuf> {
    let root = String::from_utf8(git(&["rev-parse", "--show-toplevel"])?)?
        .trim()
        .to_string();
    let rel = match path.strip_prefix("./") {
        Some(p) => {
            let prefix = String::from_utf8(git(&["rev-parse", "--show-prefix"])?)?
                .trim()
                .to_string();
            format!("{prefix}{p}")
        }
        None => path.to_string(),
    };
    let fetch = |rel: &str| -> Result<PathBuf> {
        let bytes = git(&["-C", &root, "show", &format!("{rev}:{rel}")])?;
        let dest = tmp.join(rel);
        std::fs::create_dir_all(dest.parent().unwrap_or(tmp))?;
        std::fs::write(&dest, bytes)?;
        Ok(dest)
    };
    let spec_file = fetch(&rel)?;
    // The model named by the spec's default xml_file, and the files it includes.
    if let Ok(spec) = Spec::load(&spec_file)
        && let Some(xml) = spec
            .param("xml_file")
            .and_then(|p| p.default.as_str().map(str::to_string))
    {
        let spec_dir = Path::new(&rel).parent().unwrap_or(Path::new(""));
        let mut queue = vec![envspec::path::normalize(&spec_dir.join(&xml))];
        while let Some(m) = queue.pop() {
            let Some(m_rel) = m.to_str() else { continue };
            let Ok(dest) = fetch(m_rel) else { continue };
            let text = std::fs::read_to_string(&dest).unwrap_or_default();
            if let Ok(doc) = roxmltree::Document::parse(&text) {
                for inc in doc.descendants().filter(|n| n.has_tag_name("include")) {
                    if let Some(f) = inc.attribute("file") {
                        queue.push(envspec::path::normalize(
                            &m.parent().unwrap_or(Path::new("")).join(f),
                        ));
                    }
                }
            }
        }
    }
    Ok(spec_file)
}

/// A spec argument as a local file (checked out from git when it is `REV:path`).
fn materialise(arg: &str, tmp: &Path, side: &str) -> Result<PathBuf> {
    if Path::new(arg).exists() {
        return Ok(PathBuf::from(arg));
    }
    if let Some((rev, path)) = arg.split_once(':')
        && !rev.is_empty()
        && !path.is_empty()
    {
        return checkout(rev, path, &tmp.join(side));
    }
    crate::target::spec_path(arg)
}

pub fn run(args: Args) -> Result<Outcome> {
    let tmp = std::env::temp_dir().join(format!("envc-diff-{}", std::process::id()));
    let result = diff(&args, &tmp);
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

fn load(path: &Path) -> Result<(Spec, envspec::ResolvedSpec)> {
    let spec = Spec::load(path).map_err(|d| anyhow::anyhow!("{d}"))?;
    let resolved = envspec::resolve(&spec, &[]).map_err(|d| anyhow::anyhow!("{d}"))?;
    Ok((spec, resolved))
}

fn diff(args: &Args, tmp: &Path) -> Result<Outcome> {
    let old_path = materialise(&args.old, tmp, "old")?;
    let new_path = materialise(&args.new, tmp, "new")?;
    if envspec::agents::is_multi_agent(&old_path) && envspec::agents::is_multi_agent(&new_path) {
        // Multi-agent specs: the base envs, then every conf's agents (envspec::agents::diff).
        let report =
            envspec::agents::diff(&old_path, &new_path).map_err(|d| anyhow::anyhow!("{d}"))?;
        return Ok(print(&report, args.format));
    }
    let (old, old_r) = load(&old_path).with_context(|| format!("old spec {}", args.old))?;
    let (new, new_r) = load(&new_path).with_context(|| format!("new spec {}", args.new))?;
    let mut report = envspec::diff::diff(&old, &old_r, &new, &new_r);
    // Show git revisions as the user wrote them, not the temporary checkout.
    for (arg, path, side) in [(&args.old, &old_path, 0), (&args.new, &new_path, 1)] {
        if !Path::new(arg.as_str()).exists() && arg.contains(':') {
            let shown = arg.clone();
            let real = path.display().to_string();
            if side == 0 {
                report.old_file = shown.clone();
            } else {
                report.new_file = shown.clone();
            }
            for c in &mut report.changes {
                for p in [&mut c.old_at, &mut c.new_at].into_iter().flatten() {
                    if p.file == real {
                        p.file = shown.clone();
                    }
                }
            }
        }
    }
    if !args.no_model {
        let old_m = envc::env::compile(&old_r).map_err(|e| anyhow::anyhow!("old model: {e}"))?;
        let new_m = envc::env::compile(&new_r).map_err(|e| anyhow::anyhow!("new model: {e}"))?;
        let mut model_changes = envc::model_diff::diff_models(&old_m, &new_m);
        let same_file = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => a == b,
        };
        if !same_file(&old_r.model_path, &new_r.model_path) {
            let show = |r: &envspec::ResolvedSpec| match r.param("xml_file") {
                Some(ParamValue::Str(s)) => s.clone(),
                _ => r.model_path.display().to_string(),
            };
            let identical = model_changes.is_empty();
            for c in &mut model_changes {
                c.witness.get_or_insert_with(|| {
                    format!("model file {} → {}", show(&old_r), show(&new_r))
                });
            }
            if identical {
                model_changes.push(envspec::diff::Change {
                    category: envspec::diff::Category::Documentation,
                    subject: "model".into(),
                    aspect: "file".into(),
                    was: Some(show(&old_r)),
                    now: Some(show(&new_r)),
                    old_at: None,
                    new_at: None,
                    witness: Some("the two files compile to identical models".into()),
                    breaking: false,
                });
            }
        }
        report.extend(model_changes);
    }
    // Paths relative to the working directory read better in reviews and CI annotations.
    if let Ok(cwd) = std::env::current_dir() {
        let rel = |f: &mut String| {
            if let Ok(p) = Path::new(f.as_str()).strip_prefix(&cwd) {
                *f = p.display().to_string();
            }
        };
        rel(&mut report.old_file);
        rel(&mut report.new_file);
        for c in &mut report.changes {
            for p in [&mut c.old_at, &mut c.new_at].into_iter().flatten() {
                rel(&mut p.file);
            }
        }
    }
    Ok(print(&report, args.format))
}

fn print(report: &envspec::diff::Report, format: Format) -> Outcome {
    let text = match format {
        Format::Text => report.to_text(),
        Format::Markdown => report.to_markdown(),
        Format::Json => report.to_json(),
        Format::Github => report.to_github(),
    };
    print!("{text}");
    match report.verdict() {
        Verdict::NoChange => Outcome::Ok,
        Verdict::Compatible => Outcome::Problems,
        Verdict::Breaking => Outcome::Breaking,
    }
}
