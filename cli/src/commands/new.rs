//! `envc new DIR [--spec SPEC|ID]`: a crate of your own, outside this repository, with a typed env
//! of a spec. It builds and runs with plain `cargo run`: no environment variables, nothing to copy.
//!
//! What it writes, and why each file is needed outside the repository:
//! - `spec.toml`: the spec, its model path made absolute (the copy lives elsewhere);
//! - `Cargo.toml`: `envc` by path, and MuJoCo-facing dependencies optimized in debug builds (as
//!   envc's workspace does: debug physics is ~10× slower);
//! - `.cargo/config.toml`: where mujoco-rs finds MuJoCo 3.17.0 (the repository's own config does
//!   not apply to other crates);
//! - `build.rs`: an rpath to that library (a dependency's link arguments do not reach your binary);
//! - `Cargo.lock`: this repository's, so the crate builds with the versions envc is tested with;
//! - `src/main.rs`: the typed env (`envc::env!`) run for one episode.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// The new crate's directory (created; must not exist or be empty).
    dir: PathBuf,
    /// The task spec to start from: a bundled id or a spec file.
    #[arg(long, default_value = "Hopper-v5")]
    spec: String,
}

/// The repository envc was built from (its runtime crate, MuJoCo, lock file).
fn repo() -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    p.canonicalize().unwrap_or(p)
}

/// A crate name from a directory name: lowercase, `-` for anything else.
fn crate_name(dir: &Path) -> String {
    let base = dir
        .file_name()
        .map(|s| s.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let name: String = base
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    match name.trim_matches('-') {
        "" => "my-robot".into(),
        n if n.starts_with(|c: char| c.is_ascii_digit()) => format!("robot-{n}"),
        n => n.to_string(),
    }
}

pub fn run(args: Args) -> Result<Outcome> {
    let spec = match envspec::open(&args.spec, &[]).map_err(|d| anyhow::anyhow!("{d}"))? {
        envc::AnySpec::Task(s) => s,
        other => {
            return Err(crate::target::unsupported(
                "new",
                other.id(),
                other.kind(),
                "makes a typed task env (envc::env!)",
                "start from a task spec; mazes and factorizations open with envc::open",
            ));
        }
    };
    let dir = &args.dir;
    if dir.exists()
        && dir
            .read_dir()
            .map(|mut d| d.next().is_some())
            .unwrap_or(true)
    {
        bail!(
            "error[E1412]: {} exists and is not empty; `envc new` never writes into an existing crate",
            dir.display()
        );
    }
    let repo = repo();
    let mujoco = repo.join("third_party").join("mujoco");
    if !mujoco.join("lib").is_dir() {
        bail!(
            "MuJoCo is not provisioned in {}: run scripts/setup.sh first",
            mujoco.display()
        );
    }
    // The spec with its model path absolute (relative to the spec file it came from).
    let text = std::fs::read_to_string(&spec.spec_path)
        .with_context(|| format!("cannot read {}", spec.spec_path.display()))?;
    let model = spec
        .model_path
        .canonicalize()
        .unwrap_or(spec.model_path.clone());
    let text = with_model(&text, &model.display().to_string())
        .with_context(|| format!("cannot edit {}", spec.spec_path.display()))?;
    let name = crate_name(dir);
    let files: Vec<(&str, String)> = vec![
        ("spec.toml", text),
        ("Cargo.toml", cargo_toml(&name, &repo)),
        (".cargo/config.toml", config_toml(&mujoco)),
        ("build.rs", BUILD_RS.into()),
        ("src/main.rs", MAIN_RS.into()),
        (
            "Cargo.lock",
            std::fs::read_to_string(repo.join("Cargo.lock")).unwrap_or_default(),
        ),
    ];
    write_whole(dir, &files)?;
    println!(
        "created {} ({} from {}): cd {} && cargo run",
        dir.display(),
        name,
        spec.id,
        dir.display()
    );
    Ok(Outcome::Ok)
}

/// The spec's text with its `[params] xml_file` (the value, or its `default`) set to `model`;
/// every other byte (comments, layout, key order) as it was. A spec without one is unchanged.
fn with_model(text: &str, model: &str) -> Result<String> {
    let mut doc: toml_edit::DocumentMut = text.parse()?;
    let Some(item) = doc
        .get_mut("params")
        .and_then(|p| p.as_table_like_mut())
        .and_then(|p| p.get_mut("xml_file"))
    else {
        return Ok(text.to_string());
    };
    if let Some(t) = item
        .as_table_like_mut()
        .filter(|t| t.contains_key("default"))
    {
        t.insert("default", toml_edit::value(model));
    } else {
        let decor = item.as_value().map(|v| v.decor().clone());
        *item = toml_edit::value(model);
        if let (Some(decor), Some(v)) = (decor, item.as_value_mut()) {
            *v.decor_mut() = decor;
        }
    }
    Ok(doc.to_string())
}

/// Write the crate into a hidden sibling directory and rename it to `dir` only when every file is
/// written, so a full disk or a kill leaves no half-made crate under the user's name (E1410).
fn write_whole(dir: &Path, files: &[(&str, String)]) -> Result<()> {
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let cannot = |what: &Path, e: std::io::Error| {
        anyhow::anyhow!(
            "error[E1410]: cannot write {}: {e}; nothing was written",
            what.display()
        )
    };
    let tmp = parent.join(format!(".{name}.envc-new-{}", std::process::id()));
    let write = || -> Result<()> {
        for (rel, body) in files {
            let path = tmp.join(rel);
            if let Some(p) = path.parent() {
                std::fs::create_dir_all(p).map_err(|e| cannot(dir, e))?;
            }
            std::fs::write(&path, body).map_err(|e| cannot(dir, e))?;
        }
        // An empty directory may stand where the crate goes: rename replaces only that.
        if dir.is_dir() {
            std::fs::remove_dir(dir).map_err(|e| cannot(dir, e))?;
        }
        std::fs::rename(&tmp, dir).map_err(|e| cannot(dir, e))
    };
    let written = write();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    written
}

fn cargo_toml(name: &str, repo: &Path) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "[package]\nname = \"{name}\"\nversion = \"0.1.0\"\nedition = \"2024\"\n"
    );
    let _ = writeln!(
        o,
        "[dependencies]\nenvc = {{ path = {:?} }}\n",
        repo.join("runtime").display().to_string()
    );
    let _ = writeln!(
        o,
        "# MuJoCo-facing dependencies optimized in debug builds too (debug physics is ~10x slower);\n# line tables only: backtraces keep files and lines, and the first build is faster.\n[profile.dev.package.\"*\"]\nopt-level = 2\ndebug = \"line-tables-only\""
    );
    o
}

fn config_toml(mujoco: &Path) -> String {
    format!(
        "# Where mujoco-rs finds MuJoCo 3.17.0 (provisioned by envc's scripts/setup.sh).\n[env]\nMUJOCO_DYNAMIC_LINK_DIR = {:?}\nMUJOCO_INCLUDE_DIR = {:?}\n",
        mujoco.join("lib").display().to_string(),
        mujoco.join("include").display().to_string()
    )
}

const BUILD_RS: &str = r#"//! An rpath to MuJoCo, so the binary runs from anywhere without LD_LIBRARY_PATH.
fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    if let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR") {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
"#;

const MAIN_RS: &str = r#"//! A typed env of `spec.toml` (generated by `envc new`). Edit the spec: the build checks it again,
//! and a mistake is a compile error pointing at the line.

envc::env!(pub Robot = "spec.toml");

fn main() -> Result<(), envc::EnvError> {
    let mut env = Robot::make()?;
    env.reset(Some(0));
    let (mut steps, mut ret) = (0u64, 0.0);
    loop {
        let step = env.step(&RobotAction::zeros())?;
        steps += 1;
        ret += step.reward;
        if step.terminated || step.truncated {
            break;
        }
    }
    println!("{}: one episode with zero actions, {steps} steps, return {ret:.3}", Robot::ID);
    Ok(())
}
"#;

#[cfg(test)]
mod tests {
    use super::with_model;

    #[test]
    fn the_model_path_is_set_where_the_spec_declares_it_and_nothing_else_moves() {
        let inline = "# a comment\n[params]\nxml_file = { default = \"../m.xml\", doc = \"MJCF model.\" }\nframe_skip = 4\n";
        assert_eq!(
            with_model(inline, "/abs/m.xml").unwrap(),
            "# a comment\n[params]\nxml_file = { default = \"/abs/m.xml\", doc = \"MJCF model.\" }\nframe_skip = 4\n"
        );
        let plain = "[params]\nxml_file = '../m.xml'  # the model\nframe_skip = 4\n";
        assert_eq!(
            with_model(plain, "/abs/m.xml").unwrap(),
            "[params]\nxml_file = \"/abs/m.xml\"  # the model\nframe_skip = 4\n"
        );
        let table = "[params.xml_file]\ndefault = \"../m.xml\"\ndoc = \"d\"\n";
        assert_eq!(
            with_model(table, "/abs/m.xml").unwrap(),
            "[params.xml_file]\ndefault = \"/abs/m.xml\"\ndoc = \"d\"\n"
        );
        // The same text elsewhere (a comment, another key) is left alone.
        let elsewhere =
            "[params]\n# was \"../m.xml\"\nxml_file = \"../m.xml\"\nother = \"../m.xml\"\n";
        assert_eq!(
            with_model(elsewhere, "/abs/m.xml").unwrap(),
            "[params]\n# was \"../m.xml\"\nxml_file = \"/abs/m.xml\"\nother = \"../m.xml\"\n"
        );
        let none = "[params]\nframe_skip = 4\n";
        assert_eq!(with_model(none, "/abs/m.xml").unwrap(), none);
    }
}
