//! The bundled ids: every task, maze and multi-agent spec under `specs/` of the envc source tree,
//! scanned once per process. The kind of each file comes from its top-level tables (see
//! [`Kind::of_document`]); maze registry files (`[[family]]`) expand into their ids.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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
    pub id: String,
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
}

/// The directory holding the bundled specs.
pub fn specs_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("specs");
    dir.canonicalize().unwrap_or(dir)
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

/// The entry of a bundled id; E0601 with the closest id when there is none.
pub fn lookup(id: &str) -> Result<&'static Entry, Diagnostic> {
    let all = entries();
    all.iter().find(|e| e.id == id).ok_or_else(|| {
        Diagnostic::new(
            Code::E0601,
            format!("no bundled env `{id}` and no such spec file"),
        )
        .label("expected a spec path or a bundled id (`envc list` shows them)")
        .help_opt(suggest(id, all.iter().map(|e| e.id.as_str())))
    })
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
            .map(|r| Entry {
                id: r.id,
                kind: Kind::Maze,
                path: r.spec,
                overrides: r.overrides,
                example,
                task: false,
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
