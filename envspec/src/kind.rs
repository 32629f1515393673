//! The three kinds of spec — task, maze, multi-agent — and how a document declares its kind:
//! the one place every reader, command and binding dispatches on.

use crate::value::Val;

/// The three kinds of spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A single-agent task (`[env]`, observation, reward, ...).
    Task,
    /// A maze world around a robot task (`[maze]`).
    Maze,
    /// A factorization of a task among agents (`[agents]`); `"agents"` in serialized output, as
    /// the Python package names the kind.
    #[serde(rename = "agents")]
    MultiAgent,
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
            Kind::MultiAgent
        } else {
            Kind::Task
        }
    }

    /// The kind's name in messages, e.g. `multi-agent`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Task => "task",
            Kind::Maze => "maze",
            Kind::MultiAgent => "multi-agent",
        }
    }
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
