//! `envc diff OLD NEW [--format text|markdown|json|github]`: what a spec change does to trained
//! policies and published returns. OLD and NEW are spec files, bundled ids or git revisions
//! (`REV:path`, path relative to the repository root as in `git show`; every file of that side is
//! read at the revision through `envspec::source`, as on disk), both task specs, both
//! multi-agent specs or both maze specs (E0905 otherwise). Every change names its rule
//! (docs/diff-rules.md). Exit status: 0 no change, 1 compatible changes only, 3 breaking changes,
//! 2 errors.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use envspec::diff::{Change, Report, RuleId, Verdict};
use envspec::{Kind, Override, ParamValue, Spec};

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

/// A `REV:path` argument: the revision and the path relative to the repository root.
fn git_side(arg: &str) -> Option<(&str, &str)> {
    if Path::new(arg).exists() {
        return None;
    }
    arg.split_once(':')
        .filter(|(rev, path)| !rev.is_empty() && !path.is_empty())
}

/// The repository root and the path of `path` in it (`./p` is relative to the working
/// directory, as in `git show`).
fn in_repository(path: &str) -> Result<(PathBuf, String)> {
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
    Ok((PathBuf::from(root), rel))
}

/// The reader of both sides: each `REV:path` side's revision mounted under `tmp/<side>`, so its
/// spec, maps, base and robot specs, model, includes and meshes are read by envspec's readers
/// (the same limits and errors as on disk) and written there for MuJoCo to compile.
fn reader(args: &Args, tmp: &Path) -> Result<envspec::source::Reader> {
    let mut reader = envspec::source::Reader::disk();
    for (arg, side) in [(&args.old, "old"), (&args.new, "new")] {
        let Some((rev, path)) = git_side(arg) else {
            continue;
        };
        let (repo, _) = in_repository(path).map_err(|e| cannot_take(rev, path, &e))?;
        let source = envspec::source::Source::GitRev {
            repo,
            rev: rev.to_string(),
        };
        reader = reader.mount(tmp.join(side), source);
    }
    Ok(reader)
}

fn cannot_take(rev: &str, path: &str, e: &dyn std::fmt::Display) -> anyhow::Error {
    anyhow::anyhow!("error[E0906]: cannot take `{path}` at git revision `{rev}`: {e:#}")
}

/// One side of the diff: a local file and, for a registered maze id, the overrides it stands for.
struct Side {
    path: PathBuf,
    overrides: Vec<Override>,
    /// The registered id, which the spec file's own id does not name.
    id: Option<String>,
}

/// A spec argument as a local file (under its mount when it is `REV:path`).
fn materialise(arg: &str, tmp: &Path, side: &str) -> Result<Side> {
    let file = |path| Side {
        path,
        overrides: vec![],
        id: None,
    };
    if Path::new(arg).exists() {
        return Ok(file(PathBuf::from(arg)));
    }
    if let Some((rev, path)) = git_side(arg) {
        // Read through the mounted revision (`reader`); a spec git cannot give is E0906.
        let (_, rel) = in_repository(path).map_err(|e| cannot_take(rev, path, &e))?;
        let spec = tmp.join(side).join(rel);
        envspec::source::read_bytes(&spec, envspec::limits::MAX_SPEC_BYTES)
            .map_err(|e| cannot_take(rev, path, &e))?;
        return Ok(file(spec));
    }
    // A bundled id of any kind, through the one door.
    let t = envspec::open::locate(arg).map_err(|d| anyhow::anyhow!("{d}"))?;
    Ok(Side {
        path: t.path,
        overrides: t.overrides,
        id: t.id.filter(|_| t.kind == Some(Kind::Maze)),
    })
}

/// The kind of a spec file (its top-level tables), as the one door decides it; an unreadable
/// file is a task, whose reader then reports it.
fn kind_of(path: &Path) -> Kind {
    envspec::open::Document::read(path).map_or(Kind::Task, |d| d.kind)
}

pub fn run(args: Args) -> Result<Outcome> {
    let tmp = std::env::temp_dir().join(format!("envc-diff-{}", std::process::id()));
    let result = reader(&args, &tmp).and_then(|mut r| r.run(|| diff(&args, &tmp)));
    let _ = std::fs::remove_dir_all(&tmp);
    // An error in a file of a `REV:path` side names it `REV:file`, not its temporary copy.
    result.map_err(|e| {
        let mut text = format!("{e:#}");
        for (arg, side) in [(&args.old, "old"), (&args.new, "new")] {
            if let Some((rev, _)) = git_side(arg) {
                let copy = format!("{}/", tmp.join(side).display());
                text = text.replace(&copy, &format!("{rev}:"));
            }
        }
        anyhow::anyhow!(text)
    })
}

fn load(path: &Path) -> Result<(Spec, envspec::ResolvedSpec)> {
    let spec = Spec::load(path).map_err(|d| anyhow::anyhow!("{d}"))?;
    let resolved = envspec::resolve(&spec, &[]).map_err(|d| anyhow::anyhow!("{d}"))?;
    Ok((spec, resolved))
}

fn diff(args: &Args, tmp: &Path) -> Result<Outcome> {
    let old = materialise(&args.old, tmp, "old")?;
    let new = materialise(&args.new, tmp, "new")?;
    let (old_path, new_path) = (&old.path, &new.path);
    let kind = kind_of(old_path);
    if kind_of(new_path) != kind {
        let d = envspec::diff::kind_mismatch(
            kind.name(),
            Path::new(&args.old),
            kind_of(new_path).name(),
            Path::new(&args.new),
        );
        bail!("{d}");
    }
    let mut report = match kind {
        // Multi-agent specs: the base envs, then every conf's agents.
        Kind::MultiAgent => envspec::diff::diff_multi_agent(old_path, new_path)
            .map_err(|d| anyhow::anyhow!("{d}"))?,
        Kind::Maze => diff_mazes(args, &old, &new)?,
        Kind::Task => diff_tasks(args, old_path, new_path)?,
    };
    name_revisions(args, &mut report, old_path, new_path, tmp);
    relative_paths(&mut report);
    Ok(print(&report, args.format))
}

/// Two maze specs: the mazes, then the robot models each resolves.
fn diff_mazes(args: &Args, old: &Side, new: &Side) -> Result<Report> {
    let load = |s: &Side, what: &str| {
        envspec::maze::load_maze(&s.path, &s.overrides)
            .map_err(|d| anyhow::anyhow!("{d}"))
            .with_context(|| format!("{what} maze {}", s.path.display()))
    };
    let (o, n) = (load(old, "old")?, load(new, "new")?);
    let mut report = envspec::diff::diff_mazes(&o, &n);
    report.old_id = old.id.clone().unwrap_or(report.old_id);
    report.new_id = new.id.clone().unwrap_or(report.new_id);
    report.extend(vec![]); // the flags name the ids
    // The robot models (compiled as each maze resolves its robot; identical models add
    // nothing). A robot that does not resolve is already reported.
    let resolve = |m: &envspec::maze::MazeSpec| envspec::load(&m.robot, &m.robot_overrides);
    if !args.no_model
        && let (Ok(a), Ok(b)) = (resolve(&o), resolve(&n))
    {
        let mut changes = model_changes(&a, &b)?;
        for c in &mut changes {
            c.subject = format!("robot {}", c.subject);
        }
        report.extend(changes);
    }
    Ok(report)
}

/// Two task specs: the specs, then the compiled models, each model change judged by its effect.
fn diff_tasks(args: &Args, old_path: &Path, new_path: &Path) -> Result<Report> {
    let (old, old_r) = load(old_path).with_context(|| format!("old spec {}", args.old))?;
    let (new, new_r) = load(new_path).with_context(|| format!("new spec {}", args.new))?;
    let mut report = envspec::diff::diff(&old, &old_r, &new, &new_r);
    if !args.no_model {
        let mut changes = model_changes(&old_r, &new_r)?;
        judge_model_changes(&mut report, &mut changes, &old_r, &new_r);
        report.extend(changes);
    }
    Ok(report)
}

/// A model change the spec's own changes do not already break: does it reach a rollout at all?
/// (A friction that MuJoCo's max rule overrides at every contact does not.) Then it is
/// compatible, and the witness says how that was checked. (Pointing `xml_file` at another file
/// is judged by what the models do.)
fn judge_model_changes(
    report: &mut Report,
    changes: &mut [Change],
    old_r: &envspec::ResolvedSpec,
    new_r: &envspec::ResolvedSpec,
) {
    let model_file = |c: &Change| c.subject == "param xml_file";
    let spec_breaks = report.changes.iter().any(|c| c.breaking && !model_file(c));
    // Every model difference, the unclassified residual included, is judged by its
    // effect when the spec's own changes do not already break: a gain MuJoCo stores
    // outside the compared arrays must not pass as "no behaviour change".
    let model_differs = !changes.is_empty() || report.changes.iter().any(&model_file);
    if spec_breaks || !model_differs {
        return;
    }
    let effect = rollout_difference(old_r, new_r);
    let file_changes = report.changes.iter_mut().filter(|c| model_file(c));
    for c in changes.iter_mut().chain(file_changes) {
        let (breaking, said) = match &effect {
            None => (
                false,
                format!(
                    "no effect on a rollout: {ROLLOUT_STEPS} steps of seeded random actions (seed 0, resets included) are bit-identical"
                ),
            ),
            Some(w) => (true, w.clone()),
        };
        // (a file named differently that compiles to the same model stays as it was)
        if c.rule == envspec::diff::RuleId::ModelFileChanged {
            continue;
        }
        c.breaking = breaking;
        c.witness = Some(format!(
            "{said}{}",
            c.witness
                .as_deref()
                .map(|w| format!("; {w}"))
                .unwrap_or_default()
        ));
    }
}

/// Show git revisions as the user wrote them (`REV:path`), not the temporary checkout.
fn name_revisions(args: &Args, report: &mut Report, old_path: &Path, new_path: &Path, tmp: &Path) {
    for (arg, path, side) in [(&args.old, old_path, "old"), (&args.new, new_path, "new")] {
        let Some((rev, _)) = arg.split_once(':') else {
            continue;
        };
        if Path::new(arg.as_str()).exists() {
            continue;
        }
        let real = path.display().to_string();
        let checkout = format!("{}/", tmp.join(side).display());
        if side == "old" {
            report.old_file = arg.clone();
        } else {
            report.new_file = arg.clone();
        }
        for c in &mut report.changes {
            for p in [&mut c.old_at, &mut c.new_at].into_iter().flatten() {
                if p.file == real {
                    p.file = arg.clone();
                } else if let Some(rest) = p.file.strip_prefix(&checkout) {
                    // Another file of the checkout, e.g. a maze's robot spec.
                    p.file = format!("{rev}:{rest}");
                }
            }
        }
    }
}

/// Paths relative to the working directory read better in reviews and CI annotations.
fn relative_paths(report: &mut Report) {
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
}

/// Steps of the rollout that decides whether a model change reaches the task.
const ROLLOUT_STEPS: usize = 300;

/// How the two specs' rollouts differ (None: bit-identical): same seed (0), the same uniformly
/// random actions, resets included. A check of effect, not of equality: identical models always
/// pass.
fn rollout_difference(
    old_r: &envspec::ResolvedSpec,
    new_r: &envspec::ResolvedSpec,
) -> Option<String> {
    let open = |r: &envspec::ResolvedSpec| envc::Env::new(std::sync::Arc::new(r.clone())).ok();
    let (Some(mut a), Some(mut b)) = (open(old_r), open(new_r)) else {
        return Some("one of the two envs could not be built to compare rollouts".into());
    };
    if a.act_dim() != b.act_dim() || a.obs_dim() != b.obs_dim() {
        return Some(format!(
            "the spaces differ: action {} → {}, observation {} → {}",
            a.act_dim(),
            b.act_dim(),
            a.obs_dim(),
            b.obs_dim()
        ));
    }
    let space = a.action_space().clone();
    let mut rng = envc::rng::NumpyRng::from_seed(0);
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    // The largest observation difference, and where.
    let apart = |x: &[f64], y: &[f64]| {
        x.iter()
            .zip(y)
            .enumerate()
            .map(|(i, (p, q))| (i, (p - q).abs()))
            .fold(
                (0, 0.0f64),
                |m, d| if d.1 > m.1 || d.1.is_nan() { d } else { m },
            )
    };
    let differ = |step: usize, what: &str, x: &[f64], y: &[f64]| {
        let (i, d) = apart(x, y);
        Some(format!(
            "rollouts differ from step {step} of {ROLLOUT_STEPS} (seed 0, seeded random actions): {what}; largest observation difference {d:.3e} at obs[{i}]"
        ))
    };
    let (ra, rb) = (a.reset(Some(0)).0.to_vec(), b.reset(Some(0)).0.to_vec());
    if bits(&ra) != bits(&rb) {
        return differ(0, "the reset observation differs", &ra, &rb);
    }
    let mut action = vec![0.0; space.dim()];
    for t in 1..=ROLLOUT_STEPS {
        for (i, x) in action.iter_mut().enumerate() {
            *x = rng.uniform(space.low[i], space.high[i]);
        }
        let (Ok(sa), Ok(sb)) = (a.step(&action), b.step(&action)) else {
            return Some(format!("a step failed on one side at step {t}"));
        };
        let (oa, ob) = (sa.obs.to_vec(), sb.obs.to_vec());
        if bits(&oa) != bits(&ob) {
            return differ(t, "the observation differs", &oa, &ob);
        }
        if sa.reward.to_bits() != sb.reward.to_bits() {
            return differ(
                t,
                &format!("the reward differs ({} → {})", sa.reward, sb.reward),
                &oa,
                &ob,
            );
        }
        if (sa.terminated, sa.truncated) != (sb.terminated, sb.truncated) {
            return differ(t, "the episode ends on one side only", &oa, &ob);
        }
        if sa.terminated || sa.truncated {
            let (ra, rb) = (a.reset(None).0.to_vec(), b.reset(None).0.to_vec());
            if bits(&ra) != bits(&rb) {
                return differ(t, "the next reset differs", &ra, &rb);
            }
        }
    }
    None
}

/// The compiled models compared (MuJoCo), with the model files named when they differ.
fn model_changes(
    old_r: &envspec::ResolvedSpec,
    new_r: &envspec::ResolvedSpec,
) -> Result<Vec<Change>> {
    let old_m = envc::env::compile(old_r).map_err(|e| anyhow::anyhow!("old model: {e}"))?;
    let new_m = envc::env::compile(new_r).map_err(|e| anyhow::anyhow!("new model: {e}"))?;
    let mut changes = envc::describe::model_diff::diff_models(&old_m, &new_m);
    let same_file = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    };
    let show = |r: &envspec::ResolvedSpec| match r.param("xml_file") {
        Some(ParamValue::Str(s)) => s.clone(),
        _ => r.model_path.display().to_string(),
    };
    // Named differently (the same name at two git revisions is not a change of file).
    if !same_file(&old_r.model_path, &new_r.model_path) && show(old_r) != show(new_r) {
        let identical = changes.is_empty();
        for c in &mut changes {
            c.witness
                .get_or_insert_with(|| format!("model file {} → {}", show(old_r), show(new_r)));
        }
        if identical {
            changes.push(
                Change::new(RuleId::ModelFileChanged, "model", "file")
                    .values(Some(show(old_r)), Some(show(new_r)))
                    .witness("the two files compile to identical models"),
            );
        }
    }
    Ok(changes)
}

fn print(report: &envspec::diff::Report, format: Format) -> Outcome {
    let text = match format {
        Format::Text => report.to_text(),
        Format::Markdown => report.to_markdown(),
        Format::Json => report.to_json(),
        Format::Github => report.to_github(),
    };
    print!("{text}");
    // The one mapping of a verdict to `envc diff`'s exit status (docs/diff-rules.md).
    match report.verdict() {
        Verdict::NoChange => Outcome::Ok,
        Verdict::Compatible => Outcome::Problems,
        Verdict::Breaking => Outcome::Breaking,
    }
}
