//! Resolving a command's SPEC|ID argument and its `--set key=value` overrides through the one
//! door (`envspec::open`, `envc::open`): every command opens every kind of spec the same way.

use anyhow::Result;
use envc::{AnyEnv, Override};
use envspec::{Code, Diagnostic, Kind};

/// Parse `--set key=value` arguments.
pub fn overrides(sets: &[String]) -> Result<Vec<Override>> {
    sets.iter()
        .map(|s| {
            Override::parse(s).map_err(|mut d| {
                d.message = format!("--set {s}: {}", d.message);
                anyhow::anyhow!("{d}")
            })
        })
        .collect()
}

/// The env of an id or path, any kind.
pub fn env(id_or_path: &str, sets: &[String]) -> Result<AnyEnv> {
    let o = overrides(sets)?;
    envc::open(id_or_path, &o).map_err(|e| anyhow::anyhow!("{e}"))
}

/// E0602: `command` does not serve this kind of spec.
pub fn unsupported(command: &str, id: &str, kind: Kind, why: &str, help: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}",
        Diagnostic::new(
            Code::E0602,
            format!("`envc {command}` {why}; `{id}` is a {kind} spec")
        )
        .help(help)
    )
}

/// How a user names a task on the command line: its id when it is bundled, else its file (an id
/// only a file declares does not open).
pub fn runnable_name(id: &str, path: &std::path::Path) -> String {
    if envspec::open::locate(id).is_ok() {
        return id.to_string();
    }
    let cwd = std::env::current_dir().unwrap_or_default();
    path.strip_prefix(&cwd)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// E1401: an env without a time limit, and no `--max-steps`.
pub fn needs_max_steps(command: &str, id: &str, also: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}",
        envspec::Diagnostic::new(
            envspec::Code::E1401,
            format!("`{id}` has no time limit, so `envc {command}` might never end an episode"),
        )
        .help(format!(
            "{also}set max_episode_steps in the spec (--set max_episode_steps=N)"
        ))
    )
}

/// E1101: an action file whose shape is not `[T ≥ 1, act_dim]` of `id` (every command that reads
/// one: rollout, collect, render; every kind: a multi-agent spec's rows are joint actions).
pub fn action_file_shape(
    path: &std::path::Path,
    (rows, cols): (usize, usize),
    id: &str,
    act_dim: usize,
) -> Result<()> {
    if cols == act_dim && rows > 0 {
        return Ok(());
    }
    let message = if cols != act_dim {
        format!(
            "{} has {cols} columns but {id} takes {act_dim} actions",
            path.display()
        )
    } else {
        format!("{} has no rows", path.display())
    };
    Err(anyhow::anyhow!(
        "{}",
        Diagnostic::new(Code::E1101, message).label(
            "expected [T ≥ 1, act_dim]: one column per action (a multi-agent spec: the joint action, every agent's in global order)"
        )
    ))
}
