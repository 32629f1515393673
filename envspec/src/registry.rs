//! The ids envc knows: every task, maze and multi-agent spec under the bundled `specs/`
//! ([`crate::bundle`]), scanned once per process, and the user's own spec files and directories
//! (`ENVC_SPEC_PATH`, [`register`]). The kind of each file comes from its top-level tables (see
//! [`Kind::of_document`]); maze registry files (`[[family]]`) expand into their ids. A user's id
//! never takes over a bundled one, nor one registered from another file (E0603).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use crate::diagnostic::{Code, Diagnostic, SourceFile, suggest};
use crate::params::Override;
use crate::value::parse_document;

pub use crate::kind::Kind;

/// One bundled id.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The env id, e.g. `Ant-v5`.
    pub id: String,
    /// What kind of spec it opens as.
    pub kind: Kind,
    /// The spec file.
    pub path: PathBuf,
    /// Overrides the id implies (a maze family's map, reward type and time limit).
    pub overrides: Vec<Override>,
    /// In `specs/examples/`: listed apart from the suites (`envc list` leaves them out); some
    /// name models that are not shipped (the Go1 from MuJoCo Menagerie).
    pub example: bool,
    /// The id opens as a single-agent env (`envc::Env`): a task, including a complete task spec
    /// that also declares agents, under its `[env]` id (e.g. `CoupledHalfCheetah-v0`).
    pub task: bool,
    /// A user's spec (`ENVC_SPEC_PATH` or [`register`]), not a bundled one.
    pub user: bool,
}

/// The directory holding the bundled specs (see [`crate::bundle`] for where it is).
pub fn specs_dir() -> PathBuf {
    crate::bundle::specs_dir()
}

/// `specs/examples/`: example specs (some name models that are not shipped with envc).
pub fn examples_dir() -> PathBuf {
    specs_dir().join("examples")
}

/// Every bundled id, examples included, sorted by id.
pub fn entries() -> &'static [Entry] {
    static ALL: OnceLock<Vec<Entry>> = OnceLock::new();
    ALL.get_or_init(|| scan(&specs_dir()))
}

/// The bundled ids whose models ship with envc (no examples), sorted by id.
pub fn bundled() -> impl Iterator<Item = &'static Entry> {
    entries().iter().filter(|e| !e.example)
}

/// The user's ids: those of `ENVC_SPEC_PATH` (read at first use), then those [`register`]ed, in
/// that order. Entries live for the rest of the process (registration is rare and small).
fn user_table() -> &'static Mutex<Vec<&'static Entry>> {
    static USER: OnceLock<Mutex<Vec<&'static Entry>>> = OnceLock::new();
    USER.get_or_init(|| {
        let mut table: Vec<&'static Entry> = vec![];
        // Ids already taken, for a walk linear in the number of files.
        let mut by_id = std::collections::HashMap::<String, usize>::new();
        let mut problems = vec![];
        for dir in std::env::var_os("ENVC_SPEC_PATH")
            .map(|v| std::env::split_paths(&v).collect::<Vec<_>>())
            .unwrap_or_default()
        {
            // A conflicting, unreadable or unparsable entry of the variable is left out here;
            // `envc` commands and `import envc` name it (`spec_path_problems`).
            match user_entries_of(&dir) {
                Ok((found, p)) => {
                    problems.extend(p);
                    for e in found {
                        match by_id.get(&e.id) {
                            Some(&i) if same_file(&table[i].path, &e.path) => {}
                            Some(&i) => problems.push(taken(&e, &table[i].path, "registered")),
                            None => match claim(&[], &e) {
                                Ok(()) => {
                                    by_id.insert(e.id.clone(), table.len());
                                    table.push(Box::leak(Box::new(e)));
                                }
                                Err(d) => problems.push(d),
                            },
                        }
                    }
                }
                Err(d) => problems.push(d),
            }
        }
        let _ = SPEC_PATH_PROBLEMS.set(problems);
        Mutex::new(table)
    })
}

/// What the first walk of `ENVC_SPEC_PATH` left out, and why.
static SPEC_PATH_PROBLEMS: OnceLock<Vec<Diagnostic>> = OnceLock::new();

/// The user's registered ids, sorted by id.
pub fn user_entries() -> Vec<&'static Entry> {
    let mut v = user_table().lock().map(|t| t.clone()).unwrap_or_default();
    v.sort_by(|a, b| a.id.cmp(&b.id));
    v
}

/// Every id: bundled (examples included), then the user's.
pub fn all_entries() -> Vec<&'static Entry> {
    entries().iter().chain(user_entries()).collect()
}

/// What Gymnasium's registration needs of an id — its time limit (None: none) and reward
/// threshold — read from the spec's own text and parameters, without its model: registering
/// thousands of specs stays cheap. `None` when the id is not a task spec whose text checks out
/// (the caller opens it fully then).
pub fn task_registration(e: &Entry) -> Option<(Option<u64>, Option<f64>)> {
    if e.kind != Kind::Task {
        return None;
    }
    let (file, root) = crate::value::read_document(&e.path, None, "spec").ok()?;
    let spec = crate::syntax::Spec::from_document(&file, &root).ok()?;
    let params = crate::params::resolve_params(&spec, &e.overrides).ok()?;
    let max = match params
        .iter()
        .find(|p| p.name == "max_episode_steps")
        .map(|p| &p.value)
    {
        Some(crate::params::ParamValue::Int(n)) if *n > 0 => Some(*n as u64),
        Some(crate::params::ParamValue::Int(_)) => None,
        _ => return None,
    };
    Some((max, spec.reward_threshold))
}

/// Registers every id of a spec file, or of every spec file under a directory, so that it opens
/// by id (`envc run MyBot-v0`, `gymnasium.make("envc/MyBot-v0")`). Registering the same file
/// again is a no-op; an id that is bundled, or registered from another file, is E0603 and
/// nothing is registered.
pub fn register(path: &Path) -> Result<Vec<String>, Diagnostic> {
    let (found, problems) = user_entries_of(path)?;
    if let Some(first) = problems.into_iter().next() {
        return Err(first);
    }
    let mut table = user_table()
        .lock()
        .map_err(|_| Diagnostic::new(Code::E0603, "the registry is unusable after a panic"))?;
    for e in &found {
        claim(&table, e)?;
    }
    let mut ids = vec![];
    for e in found {
        ids.push(e.id.clone());
        if !table.iter().any(|t| t.id == e.id) {
            table.push(Box::leak(Box::new(e)));
        }
    }
    Ok(ids)
}

/// The problems of `ENVC_SPEC_PATH`: entries that are unreadable, do not parse, declare an id
/// Gymnasium refuses or one that is taken (read once, with the registry).
pub fn spec_path_problems() -> Vec<Diagnostic> {
    user_table();
    SPEC_PATH_PROBLEMS.get().cloned().unwrap_or_default()
}

/// Ok when `e` may take its id: not bundled, and not registered from another file.
fn claim(table: &[&'static Entry], e: &Entry) -> Result<(), Diagnostic> {
    let same = |p: &Path| same_file(p, &e.path);
    if let Some(b) = entries().iter().find(|b| b.id == e.id) {
        if same(&b.path) {
            return Ok(());
        }
        return Err(taken(e, &b.path, "bundled with envc"));
    }
    if let Some(t) = table.iter().find(|t| t.id == e.id && !same(&t.path)) {
        return Err(taken(e, &t.path, "registered"));
    }
    Ok(())
}

fn taken(e: &Entry, other: &Path, how: &str) -> Diagnostic {
    Diagnostic::new(
        Code::E0603,
        format!(
            "{} declares the id `{}`, which is {how} ({})",
            e.path.display(),
            e.id,
            other.display()
        ),
    )
    .help("give the spec an id of its own (`[env] id`, `[maze] id` or `[agents] id`); open the file by its path to use it without an id")
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// The entries of a user's spec file, or of every spec file under a directory, and the problems
/// of the files left out: files that do not parse or cannot be read, ids Gymnasium cannot
/// register (E0111), one id declared by two files (E0603, both left out).
fn user_entries_of(path: &Path) -> Result<(Vec<Entry>, Vec<Diagnostic>), Diagnostic> {
    let abs = path.canonicalize().map_err(|e| {
        Diagnostic::new(
            Code::E0600,
            format!("cannot read spec path {}: {e}", path.display()),
        )
    })?;
    let mut problems = vec![];
    let mut found = vec![];
    if abs.is_dir() {
        for file in user_walk(&abs)? {
            match user_file(&file) {
                Ok(v) => found.extend(v),
                Err(d) => problems.push(d),
            }
        }
    } else {
        found = user_file(&abs)?;
    }
    // One id from two files: neither is taken, and both are named.
    found.sort_by(|a, b| {
        (&a.id, a.overrides.is_empty(), &a.path).cmp(&(&b.id, b.overrides.is_empty(), &b.path))
    });
    let mut twice: Vec<String> = vec![];
    for w in found.windows(2) {
        if w[0].id == w[1].id && w[0].path != w[1].path && !twice.contains(&w[0].id) {
            twice.push(w[0].id.clone());
            problems.push(
                Diagnostic::new(
                    Code::E0603,
                    format!(
                        "{} and {} both declare the id `{}`",
                        w[0].path.display(),
                        w[1].path.display(),
                        w[0].id
                    ),
                )
                .help("give each spec an id of its own; neither is registered until then"),
            );
        }
    }
    found.retain(|e| !twice.contains(&e.id));
    // A maze file's own id is also one of its registry's ids: keep the registered one.
    found.dedup_by(|later, first| later.id == first.id);
    if found.is_empty() && problems.is_empty() {
        return Err(Diagnostic::new(
            Code::E0600,
            format!("{} holds no spec with an id", path.display()),
        )
        .help(
            "a task spec declares `[env] id`, a maze `[maze] id`, a factorization `[agents] id`",
        ));
    }
    for e in &mut found {
        e.user = true;
        e.example = false;
    }
    Ok((found, problems))
}

/// The `.toml` files under a user's directory, each once: directories are walked by their
/// canonical paths (a symbolic link back to a parent is a directory already seen), at most
/// `MAX_SPEC_DIR_DEPTH` deep and `MAX_SPEC_DIR_ENTRIES` entries in all (`/proc/self` leads to
/// the whole file system).
fn user_walk(root: &Path) -> Result<Vec<PathBuf>, Diagnostic> {
    use crate::limits::{MAX_SPEC_DIR_DEPTH, MAX_SPEC_DIR_ENTRIES};
    let too_big = |why: String| {
        Diagnostic::new(
            Code::E0110,
            format!("spec directory {}: {why}", root.display()),
        )
        .help("register a directory that holds only specs; see docs/limits.md")
    };
    let mut seen = std::collections::HashSet::new();
    seen.insert(root.to_path_buf());
    let mut dirs = vec![(root.to_path_buf(), 0usize)];
    let mut files = vec![];
    let mut count = 0usize;
    while let Some((dir, depth)) = dirs.pop() {
        let Ok(read) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut names: Vec<PathBuf> = vec![];
        for e in read.flatten() {
            count += 1;
            if count > MAX_SPEC_DIR_ENTRIES {
                return Err(too_big(format!(
                    "more than {MAX_SPEC_DIR_ENTRIES} entries, beyond envc's limit"
                )));
            }
            names.push(e.path());
        }
        names.sort();
        for p in names {
            // `metadata` follows links: a link to a directory is walked once, by its target.
            let Ok(meta) = std::fs::metadata(&p) else {
                continue;
            };
            if meta.is_dir() {
                let Ok(real) = p.canonicalize() else { continue };
                if !seen.insert(real.clone()) {
                    continue;
                }
                if depth + 1 > MAX_SPEC_DIR_DEPTH {
                    return Err(too_big(format!(
                        "{} is nested deeper than envc's limit of {MAX_SPEC_DIR_DEPTH} directories",
                        p.display()
                    )));
                }
                dirs.push((real, depth + 1));
            } else if p.extension().is_some_and(|x| x == "toml") {
                files.push(p);
            }
        }
    }
    Ok(files)
}

/// The entries of one user's file; a file that cannot be read or parsed, or that declares an id
/// Gymnasium cannot register, is its error.
fn user_file(path: &Path) -> Result<Vec<Entry>, Diagnostic> {
    let text = crate::limits::read_text(path, crate::limits::MAX_SPEC_BYTES).map_err(|e| {
        Diagnostic::new(
            e.code(Code::E0600),
            format!("cannot read spec {}: {e}", path.display()),
        )
    })?;
    let file = SourceFile::new(path, text);
    let root = parse_document(&file).map_err(|d| {
        d.0.into_iter().next().unwrap_or_else(|| {
            Diagnostic::new(Code::E0600, format!("{} does not parse", path.display()))
        })
    })?;
    let top = root.as_table().unwrap_or(&[]);
    for k in ["env", "maze", "agents"] {
        let id = top
            .iter()
            .find(|e| e.key == k)
            .and_then(|t| t.value.as_table())
            .and_then(|t| t.iter().find(|e| e.key == "id"));
        if let Some(id) = id
            && let Some(s) = id.value.as_str()
            && let Some(d) = crate::syntax::env_id_problem(s, id.value.loc.clone())
        {
            return Err(d);
        }
    }
    Ok(entries_of(path, false))
}

/// The entry of an id, bundled or the user's; E0601 with the closest id when there is none.
pub fn lookup(id: &str) -> Result<&'static Entry, Diagnostic> {
    if let Some(e) = entries().iter().find(|e| e.id == id) {
        return Ok(e);
    }
    // Found without copying and sorting the table: `envc.registry()` looks up every id.
    let found = user_table()
        .lock()
        .ok()
        .and_then(|t| t.iter().find(|e| e.id == id).copied());
    if let Some(e) = found {
        return Ok(e);
    }
    let user = user_entries();
    let names: Vec<&str> = entries()
        .iter()
        .chain(user.iter().copied())
        .map(|e| e.id.as_str())
        .collect();
    let mut d = Diagnostic::new(
        Code::E0601,
        format!("no bundled env `{id}` and no such spec file"),
    )
    .label("expected a spec path or a bundled id (`envc list` shows them)")
    .help_opt(suggest(id, names));
    if let Err(why) = crate::bundle::root() {
        d = d.help(format!("envc found no bundled specs: {why}"));
    }
    Err(d)
}

fn scan(root: &Path) -> Vec<Entry> {
    let examples = root.join("examples");
    let mut out = vec![];
    let mut dirs = vec![root.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        let Ok(read) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in read.flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                out.extend(entries_of(&p, p.starts_with(&examples)));
            }
        }
    }
    // A maze file's own id is also one of its registry's ids: keep the registered one, which
    // carries the family's map and time limit.
    out.sort_by(|a, b| {
        (&a.id, a.overrides.is_empty(), &a.path).cmp(&(&b.id, b.overrides.is_empty(), &b.path))
    });
    out.dedup_by(|later, first| later.id == first.id);
    out
}

/// The ids one file declares (none for map files and files that do not parse).
fn entries_of(path: &Path, example: bool) -> Vec<Entry> {
    let Ok(text) = crate::limits::read_text(path, crate::limits::MAX_SPEC_BYTES) else {
        return vec![];
    };
    let file = SourceFile::new(path, text);
    let Ok(root) = parse_document(&file) else {
        return vec![];
    };
    let top = root.as_table().unwrap_or(&[]);
    let table = |k: &str| top.iter().find(|e| e.key == k).map(|e| &e.value);
    let id_in = |k: &str| {
        table(k)
            .and_then(|t| t.as_table())
            .and_then(|t| t.iter().find(|e| e.key == "id"))
            .and_then(|e| e.value.as_str().map(str::to_string))
    };
    let entry = |id: String, kind| Entry {
        id,
        kind,
        path: path.to_path_buf(),
        overrides: vec![],
        example,
        task: table("env").is_some(),
        user: false,
    };
    let stem = || {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    if table("family").is_some() {
        // A maze registry: each family × map × reward type is an id.
        return crate::maze::registry(path)
            .unwrap_or_default()
            .into_iter()
            .map(|r| {
                // A family of task specs (Fetch's sparse and dense ids) opens as tasks.
                let kind = crate::value::read_document(&r.spec, None, "spec")
                    .map_or(Kind::Maze, |(_, root)| Kind::of_document(&root));
                Entry {
                    id: r.id,
                    kind,
                    path: r.spec,
                    overrides: r.overrides,
                    example,
                    task: kind == Kind::Task,
                    user: false,
                }
            })
            .collect();
    }
    match Kind::of_document(&root) {
        Kind::Maze => id_in("maze").map(|id| vec![entry(id, Kind::Maze)]),
        Kind::MultiAgent => {
            // A complete task that also declares agents: its task id opens the task.
            let agents = id_in("agents")
                .or_else(|| id_in("env"))
                .unwrap_or_else(stem);
            let mut v = vec![Entry {
                task: false,
                ..entry(agents.clone(), Kind::MultiAgent)
            }];
            if let Some(task) = id_in("env").filter(|t| *t != agents) {
                v.push(entry(task, Kind::Task));
            }
            Some(v)
        }
        Kind::Task if table("env").is_some() => id_in("env").map(|id| vec![entry(id, Kind::Task)]),
        Kind::Task => None,
    }
    .unwrap_or_default()
}
