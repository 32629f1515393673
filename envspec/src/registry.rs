//! The ids envc knows: every task, maze and multi-agent spec under the bundled `specs/`
//! ([`crate::bundle`]), scanned once per process, and the user's own spec files and directories
//! (`ENVC_SPEC_PATH`, [`register`]). The kind of each file comes from its top-level tables (see
//! [`Kind::of_document`]); maze registry files (`[[family]]`) expand into their ids. A user's id
//! never takes over a bundled one, nor one registered from another file (E0603).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use crate::diagnostic::{Code, Diagnostic, SourceFile, suggest};
use crate::params::Override;
use crate::value::{Val, parse_document};

/// The three kinds of spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A single-agent task (`[env]`, observation, reward, ...).
    Task,
    /// A maze world around a robot task (`[maze]`).
    Maze,
    /// A factorization of a task among agents (`[agents]`).
    Agents,
}

impl Kind {
    /// The kind a parsed spec document declares: `[maze]` → maze, `[agents]` → multi-agent,
    /// anything else a task (whose own checks then say what is missing).
    pub fn of_document(root: &Val) -> Kind {
        let top = root.as_table().unwrap_or(&[]);
        let has = |k: &str| top.iter().any(|e| e.key == k);
        if has("maze") {
            Kind::Maze
        } else if has("agents") {
            Kind::Agents
        } else {
            Kind::Task
        }
    }

    /// The kind's name in messages, e.g. `multi-agent`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Task => "task",
            Kind::Maze => "maze",
            Kind::Agents => "multi-agent",
        }
    }
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

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
        let mut table = vec![];
        for dir in std::env::var_os("ENVC_SPEC_PATH")
            .map(|v| std::env::split_paths(&v).collect::<Vec<_>>())
            .unwrap_or_default()
        {
            // A conflicting or unreadable entry of the variable is left out here; `envc list`
            // and `envc info` name it (`spec_path_problems`).
            if let Ok(found) = user_entries_of(&dir) {
                for e in found {
                    if claim(&table, &e).is_ok() && !table.iter().any(|t: &&Entry| t.id == e.id) {
                        table.push(&*Box::leak(Box::new(e)));
                    }
                }
            }
        }
        Mutex::new(table)
    })
}

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

/// Registers every id of a spec file, or of every spec file under a directory, so that it opens
/// by id (`envc run MyBot-v0`, `gymnasium.make("envc/MyBot-v0")`). Registering the same file
/// again is a no-op; an id that is bundled, or registered from another file, is E0603 and
/// nothing is registered.
pub fn register(path: &Path) -> Result<Vec<String>, Diagnostic> {
    let found = user_entries_of(path)?;
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

/// The problems of `ENVC_SPEC_PATH`: entries that are unreadable or claim a taken id.
pub fn spec_path_problems() -> Vec<Diagnostic> {
    let mut out = vec![];
    let mut seen: Vec<&'static Entry> = vec![];
    for dir in std::env::var_os("ENVC_SPEC_PATH")
        .map(|v| std::env::split_paths(&v).collect::<Vec<_>>())
        .unwrap_or_default()
    {
        match user_entries_of(&dir) {
            Ok(found) => {
                for e in found {
                    match claim(&seen, &e) {
                        Ok(()) => seen.push(Box::leak(Box::new(e))),
                        Err(d) => out.push(d),
                    }
                }
            }
            Err(d) => out.push(d),
        }
    }
    out
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

/// The entries of a user's spec file, or of every spec file under a directory.
fn user_entries_of(path: &Path) -> Result<Vec<Entry>, Diagnostic> {
    let abs = path.canonicalize().map_err(|e| {
        Diagnostic::new(
            Code::E0600,
            format!("cannot read spec path {}: {e}", path.display()),
        )
    })?;
    let mut found = if abs.is_dir() {
        scan(&abs)
    } else {
        entries_of(&abs, false)
    };
    if found.is_empty() {
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
    Ok(found)
}

/// The entry of an id, bundled or the user's; E0601 with the closest id when there is none.
pub fn lookup(id: &str) -> Result<&'static Entry, Diagnostic> {
    if let Some(e) = entries().iter().find(|e| e.id == id) {
        return Ok(e);
    }
    let user = user_entries();
    if let Some(e) = user.iter().find(|e| e.id == id) {
        return Ok(e);
    }
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
        Kind::Agents => {
            // A complete task that also declares agents: its task id opens the task.
            let agents = id_in("agents")
                .or_else(|| id_in("env"))
                .unwrap_or_else(stem);
            let mut v = vec![Entry {
                task: false,
                ..entry(agents.clone(), Kind::Agents)
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
