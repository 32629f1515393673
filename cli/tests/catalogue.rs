//! The error catalogue (docs/errors.md, "Triggered by"): every case under `tests/catalogue/` is a
//! bad input run through the built `envc`, which must answer with the case's error code (and no
//! panic); every code of docs/errors.md's table has a case or a listed exception; and the
//! "Triggered by" lines of docs/errors.md are generated from the cases, so they cannot go stale
//! (`ENVC_BLESS=1 cargo test --workspace --test cli catalogue::` rewrites them).
//!
//! A case is one file `tests/catalogue/<name>.toml`, or a directory `tests/catalogue/<name>/`
//! holding `case.toml` and the files it needs (copied next to the command). Keys of a case:
//! - `code`, `about` (the bad input in a few words, shown in docs/errors.md), `args` (the `envc`
//!   command line);
//! - `spec_from` + `edits`: a repository spec copied with each `[old, new]` applied once (every
//!   `old` must occur), as `{spec}`; its relative paths still resolve (the repository is mirrored
//!   around it with symbolic links);
//! - `files` (name → text), `npy` (name → rows of float64 written as `.npy`), `env` (variables),
//!   `before` (command lines run first, e.g. to create a dataset), `status` (default 1 or 2),
//!   `memory_kb` (an address-space cap, `ulimit -v`, for the case's command: a model that needs
//!   more memory than a process may have).
//!
//! Placeholders in `args`, `files` and `before`: `{spec}`, `{tmp}` (the case's scratch directory,
//! also the working directory), `{root}` (the repository). Inputs the API tests already pin with
//! positions and messages (envspec/tests/bad_input.rs, maze_errors.rs, agents_typos.rs,
//! cli/tests/exit_status.rs) are not repeated there; the catalogue checks that each code reaches
//! a user through the command line.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    code: String,
    about: String,
    args: Vec<String>,
    #[serde(default)]
    spec_from: Option<String>,
    #[serde(default)]
    edits: Vec<[String; 2]>,
    #[serde(default)]
    files: BTreeMap<String, String>,
    #[serde(default)]
    npy: BTreeMap<String, Vec<Vec<f64>>>,
    #[serde(default)]
    env: BTreeMap<String, String>,
    #[serde(default)]
    before: Vec<Vec<String>>,
    #[serde(default)]
    status: Option<i32>,
    #[serde(default)]
    memory_kb: Option<u64>,
}

#[derive(serde::Deserialize)]
struct Exception {
    code: String,
    why: String,
}

#[derive(serde::Deserialize)]
struct Exceptions {
    exception: Vec<Exception>,
}

fn root() -> PathBuf {
    Path::new(ROOT).canonicalize().unwrap()
}

/// Every case: (name, its directory of extra files if any, the case).
fn cases() -> Vec<(String, Option<PathBuf>, Case)> {
    let dir = root().join("tests/catalogue");
    let mut out = vec![];
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        let p = e.path();
        let name = p.file_stem().unwrap().to_string_lossy().into_owned();
        let (file, extra) = if p.is_dir() {
            (p.join("case.toml"), Some(p.clone()))
        } else if p.extension().is_some_and(|x| x == "toml") && name != "exceptions" {
            (p.clone(), None)
        } else {
            continue;
        };
        let text = std::fs::read_to_string(&file).unwrap();
        let case: Case =
            toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        out.push((name, extra, case));
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

fn exceptions() -> Vec<Exception> {
    let p = root().join("tests/catalogue/exceptions.toml");
    let e: Exceptions = toml::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    e.exception
}

/// Mirror the repository in `to` with symbolic links, except along `rel`'s directories, which are
/// real (so a file written at `to/rel` sits among links to its original siblings).
fn mirror(root: &Path, rel: &Path, to: &Path) {
    let mut from = root.to_path_buf();
    let mut here = to.to_path_buf();
    let parts: Vec<_> = rel.components().collect();
    for (k, part) in parts.iter().enumerate() {
        std::fs::create_dir_all(&here).unwrap();
        for e in std::fs::read_dir(&from).unwrap().flatten() {
            if e.file_name() != part.as_os_str() && !here.join(e.file_name()).exists() {
                std::os::unix::fs::symlink(e.path(), here.join(e.file_name())).unwrap();
            }
        }
        if k + 1 < parts.len() {
            from.push(part);
            here.push(part);
        }
    }
}

fn fill(s: &str, vars: &[(&str, String)]) -> String {
    vars.iter()
        .fold(s.to_string(), |s, (k, v)| s.replace(&format!("{{{k}}}"), v))
}

struct Ran {
    status: Option<i32>,
    text: String,
}

fn run(name: &str, extra: &Option<PathBuf>, case: &Case, scratch: &Path) -> Ran {
    let tmp = scratch.join(name);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    let root = root();
    let mut vars = vec![
        ("tmp", tmp.display().to_string()),
        ("root", root.display().to_string()),
    ];
    if let Some(from) = &case.spec_from {
        let mut text = std::fs::read_to_string(root.join(from))
            .unwrap_or_else(|e| panic!("{name}: spec_from {from}: {e}"));
        for [old, new] in &case.edits {
            assert!(
                text.contains(old.as_str()),
                "{name}: `{old}` does not occur in {from} (update the case)"
            );
            text = text.replacen(old.as_str(), new, 1);
        }
        let repo = tmp.join("repo");
        mirror(&root, Path::new(from), &repo);
        let spec = repo.join(from);
        std::fs::write(&spec, text).unwrap();
        vars.push(("spec", spec.display().to_string()));
    }
    if let Some(dir) = extra {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            if e.file_name() != "case.toml" {
                let text = std::fs::read(e.path()).unwrap();
                let text = match String::from_utf8(text) {
                    Ok(t) => fill(&t, &vars).into_bytes(),
                    Err(e) => e.into_bytes(),
                };
                std::fs::write(tmp.join(e.file_name()), text).unwrap();
            }
        }
    }
    for (f, text) in &case.files {
        let p = tmp.join(f);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, fill(text, &vars)).unwrap();
    }
    for (f, rows) in &case.npy {
        let a = ndarray::Array2::from_shape_fn((rows.len(), rows[0].len()), |(i, j)| rows[i][j]);
        ndarray_npy::write_npy(tmp.join(f), &a).unwrap();
    }
    let envc = |args: &[String], memory_kb: Option<u64>| {
        let mut command = match memory_kb {
            Some(kb) => {
                let mut c = Command::new("sh");
                c.arg("-c")
                    .arg(format!(r#"ulimit -v {kb}; exec "$0" "$@""#))
                    .arg(envc_bin());
                c
            }
            None => Command::new(envc_bin()),
        };
        command
            .args(args.iter().map(|a| fill(a, &vars)))
            .current_dir(&tmp)
            .env("HOME", &tmp)
            .env("MINARI_DATASETS_PATH", tmp.join("datasets"))
            .env_remove("ENVC_NUMERICS")
            .env_remove("NPY_ENABLE_CPU_FEATURES")
            .env_remove("NPY_DISABLE_CPU_FEATURES")
            .envs(&case.env)
            .output()
            .expect("run envc")
    };
    for b in &case.before {
        let o = envc(b, None);
        assert!(
            o.status.success(),
            "{name}: `before` command {b:?} failed: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let o = envc(&case.args, case.memory_kb);
    Ran {
        status: o.status.code(),
        text: format!(
            "{}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ),
    }
}

#[test]
fn every_case_gets_its_code() {
    let scratch = std::env::temp_dir().join(format!("envc-catalogue-{}", std::process::id()));
    let cases = cases();
    let mut failures = vec![];
    let mut inputs = BTreeSet::new();
    for (name, extra, case) in &cases {
        assert!(
            name.starts_with(&case.code),
            "case `{name}`: name it after its code ({}-…)",
            case.code
        );
        let r = run(name, extra, case, &scratch);
        let tagged = r.text.contains(&format!("error[{}]", case.code))
            || r.text.contains(&format!("\"code\": \"{}\"", case.code));
        let status_ok = match case.status {
            Some(s) => r.status == Some(s),
            None => matches!(r.status, Some(1 | 2)),
        };
        if !tagged || !status_ok || r.text.contains("panicked at") {
            failures.push(format!(
                "{name}: expected {} (status {:?}), got status {:?}:\n{}",
                case.code,
                case.status.unwrap_or(2),
                r.status,
                r.text.trim()
            ));
        }
        let dir_files: Vec<Vec<u8>> = extra
            .iter()
            .flat_map(|d| std::fs::read_dir(d).unwrap().flatten())
            .map(|e| std::fs::read(e.path()).unwrap())
            .collect();
        inputs.insert(format!(
            "{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
            case.args, case.spec_from, case.edits, case.files, case.npy, case.env, dir_files
        ));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    assert_eq!(inputs.len(), cases.len(), "two cases are the same input");
    assert!(cases.len() >= 60, "only {} cases", cases.len());
}

/// Codes in docs/errors.md's table, in table order.
fn table_codes(doc: &str) -> Vec<String> {
    doc.lines()
        .filter_map(|l| l.strip_prefix("| [E"))
        .map(|r| format!("E{}", &r[..4]))
        .collect()
}

#[test]
fn every_documented_code_has_a_case_or_a_reason() {
    let doc = std::fs::read_to_string(root().join("docs/errors.md")).unwrap();
    let with_case: BTreeSet<String> = cases().into_iter().map(|c| c.2.code).collect();
    let excepted: BTreeMap<String, String> =
        exceptions().into_iter().map(|e| (e.code, e.why)).collect();
    let table = table_codes(&doc);
    let missing: Vec<_> = table
        .iter()
        .filter(|c| !with_case.contains(*c) && !excepted.contains_key(*c))
        .collect();
    assert!(
        missing.is_empty(),
        "codes of docs/errors.md without a case in tests/catalogue/ nor an entry in \
         tests/catalogue/exceptions.toml: {missing:?}"
    );
    let stale: Vec<_> = excepted.keys().filter(|c| with_case.contains(*c)).collect();
    assert!(
        stale.is_empty(),
        "exceptions that have cases now: {stale:?}"
    );
    let unknown: Vec<_> = with_case.iter().filter(|c| !table.contains(c)).collect();
    assert!(
        unknown.is_empty(),
        "cases of codes not in docs/errors.md: {unknown:?}"
    );
}

/// The command line as a user would type it.
fn shown_args(case: &Case) -> String {
    let spec = case
        .spec_from
        .as_deref()
        .map(|f| {
            Path::new(f)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .unwrap_or_default();
    let args: Vec<String> = case
        .args
        .iter()
        .map(|a| {
            a.replace("{spec}", &spec)
                .replace("{tmp}/", "")
                .replace("{root}/", "")
        })
        .map(|a| if a.contains(' ') { format!("'{a}'") } else { a })
        .collect();
    format!("envc {}", args.join(" "))
}

const BEGIN: &str = "<!-- catalogue: generated from tests/catalogue/ by cli/tests/catalogue.rs -->";
const END: &str = "<!-- /catalogue -->";

/// docs/errors.md with every section's "Triggered by" block regenerated.
fn regenerate(doc: &str) -> String {
    let mut by_code: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (name, _, case) in cases() {
        let env: String = case.env.iter().map(|(k, v)| format!("{k}={v} ")).collect();
        by_code.entry(case.code.clone()).or_default().push(format!(
            "- {} (`{env}{}`, case `{name}`)",
            case.about,
            shown_args(&case)
        ));
    }
    for e in exceptions() {
        by_code
            .entry(e.code)
            .or_default()
            .push(format!("- no command line: {}", e.why));
    }
    // Drop the old blocks, then insert one per section, before its **Fix:** line or at its end.
    let mut lines: Vec<&str> = vec![];
    let (mut skipping, mut after_end) = (false, false);
    for l in doc.lines() {
        if l == BEGIN {
            skipping = true;
        } else if l == END {
            (skipping, after_end) = (false, true);
        } else if !(skipping || after_end && l.is_empty()) {
            lines.push(l);
            after_end = false;
        } else {
            after_end = false;
        }
    }
    let mut out = String::new();
    let mut pending: Option<&Vec<String>> = None;
    let block = |items: &Vec<String>| {
        format!(
            "{BEGIN}\n**Triggered by** (each run by the catalogue test):\n\n{}\n{END}\n\n",
            items.join("\n")
        )
    };
    for (k, l) in lines.iter().enumerate() {
        let next_is_section = lines
            .get(k + 1)
            .is_none_or(|n| n.starts_with("## ") || n.starts_with("Problems in a multi-agent"));
        if let Some(code) = l.strip_prefix("## ") {
            pending = by_code.get(code.trim());
        }
        if l.starts_with("**Fix:**")
            && let Some(items) = pending.take()
        {
            out += &block(items);
        }
        out += l;
        out += "\n";
        if next_is_section && let Some(items) = pending.take() {
            if !out.ends_with("\n\n") {
                out += "\n";
            }
            out += block(items).trim_end();
            out += "\n\n";
        }
    }
    out
}

#[test]
fn docs_triggered_by_matches_the_cases() {
    let path = root().join("docs/errors.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let fresh = regenerate(&doc);
    if std::env::var_os("ENVC_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
        return;
    }
    assert!(
        doc == fresh,
        "docs/errors.md's \"Triggered by\" blocks differ from tests/catalogue/; run \
         `ENVC_BLESS=1 cargo test --workspace --test cli catalogue::` and review the diff"
    );
}

/// The `envc` under test: this build's, or `ENVC_BIN` (scripts/test.sh runs the release binary
/// too, where undefined behaviour the optimizer exposes would show).
fn envc_bin() -> String {
    std::env::var("ENVC_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_envc").to_string())
}
