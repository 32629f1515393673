//! The one door: open a bundled id or a spec file, of any kind, with overrides.
//!
//! The file is read once with the spanned reader; its top-level tables say its kind
//! ([`Kind::of_document`]); the kind's reader then works on that document. Every command and the
//! runtime's `envc::open` go through [`open`], so a spec opens the same way everywhere.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Diagnostics, SourceFile};
use crate::ir::ResolvedSpec;
use crate::kind::Kind;
use crate::maze::MazeSpec;
use crate::multi_agent::MultiAgentSpec;
use crate::params::Override;
use crate::registry;
use crate::syntax::Spec;
use crate::value::Val;

/// A resolved spec of any kind.
#[derive(Clone, Debug)]
pub enum AnySpec {
    /// A task spec, resolved against its model.
    Task(Box<ResolvedSpec>),
    /// A maze over a robot's task spec.
    Maze(Box<MazeSpec>),
    /// A multi-agent factorization of a task spec.
    MultiAgent(Box<MultiAgentSpec>),
}

impl AnySpec {
    /// Which of the three it is.
    pub fn kind(&self) -> Kind {
        match self {
            AnySpec::Task(_) => Kind::Task,
            AnySpec::Maze(_) => Kind::Maze,
            AnySpec::MultiAgent(_) => Kind::MultiAgent,
        }
    }

    /// Its env id.
    pub fn id(&self) -> &str {
        match self {
            AnySpec::Task(s) => &s.id,
            AnySpec::Maze(s) => &s.id,
            AnySpec::MultiAgent(s) => &s.id,
        }
    }

    /// The spec file (for a maze family id, the family's maze file).
    pub fn path(&self) -> &Path {
        match self {
            AnySpec::Task(s) => &s.spec_path,
            AnySpec::Maze(s) => &s.path,
            AnySpec::MultiAgent(s) => &s.spec_path,
        }
    }
}

/// A spec file read and parsed once, with its kind.
pub struct Document {
    /// The file's text, for locations.
    pub file: Arc<SourceFile>,
    /// The parsed top-level table.
    pub root: Val,
    /// The kind its top-level tables say (`Kind::of_document`).
    pub kind: Kind,
}

impl Document {
    /// Read and parse a spec file (E0600 when it cannot be read, E0100 when it is not TOML).
    pub fn read(path: &Path) -> Result<Document, Diagnostics> {
        let (file, root) = crate::value::read_document(path, None, "spec")?;
        let kind = Kind::of_document(&root);
        Ok(Document { file, root, kind })
    }
}

/// Where an id-or-path argument points: a spec file plus the overrides a bundled id implies.
#[derive(Clone, Debug)]
pub struct Target {
    /// The spec file to read.
    pub path: PathBuf,
    /// The bundled id, when the argument was one (a maze family id renames the spec).
    pub id: Option<String>,
    /// The kind a bundled id opens as (a file's own tables decide otherwise).
    pub kind: Option<Kind>,
    /// Parameters a bundled id sets, before the user's own.
    pub overrides: Vec<Override>,
}

/// Resolve an id-or-path argument without reading the spec: an existing file (or any `*.toml`
/// path, so a missing file is reported as unreadable) or a bundled id (E0601 otherwise).
pub fn locate(id_or_path: &str) -> Result<Target, Diagnostics> {
    let p = Path::new(id_or_path);
    // Devices and FIFOs count as files here, so reading them is refused with a reason (E0600).
    if (p.exists() && !p.is_dir()) || p.extension().is_some_and(|x| x == "toml") {
        return Ok(Target {
            path: p.to_path_buf(),
            id: None,
            kind: None,
            overrides: vec![],
        });
    }
    let e = registry::lookup(id_or_path)?;
    Ok(Target {
        path: e.path.clone(),
        id: Some(e.id.clone()),
        kind: Some(e.kind),
        overrides: e.overrides.clone(),
    })
}

/// Open a bundled id or a spec file of any kind with user overrides.
pub fn open(id_or_path: &str, overrides: &[Override]) -> Result<AnySpec, Diagnostics> {
    let t = locate(id_or_path)?;
    // The user's overrides replace a bundled id's own of the same name (a layer); only a user's
    // own duplicates are E0205.
    let mut all = t.overrides;
    all.retain(|o| !overrides.iter().any(|u| u.name == o.name));
    all.extend(overrides.iter().cloned());
    let mut spec = open_as(&t.path, t.kind, &all)?;
    if let (Some(id), AnySpec::Maze(m)) = (t.id, &mut spec) {
        m.id = id;
    }
    Ok(spec)
}

/// Open a spec file of any kind with overrides.
pub fn open_file(path: &Path, overrides: &[Override]) -> Result<AnySpec, Diagnostics> {
    open_as(path, None, overrides)
}

/// [`open_file`] as a given kind (a complete task spec that also declares agents opens as either).
fn open_as(
    path: &Path,
    kind: Option<Kind>,
    overrides: &[Override],
) -> Result<AnySpec, Diagnostics> {
    let (spec, inputs) = crate::source::recorded(|| read_as(path, kind, overrides));
    let mut spec = spec?;
    match &mut spec {
        AnySpec::Task(s) => s.inputs = inputs,
        AnySpec::Maze(m) => m.inputs = inputs,
        AnySpec::MultiAgent(_) => {}
    }
    Ok(spec)
}

fn read_as(
    path: &Path,
    kind: Option<Kind>,
    overrides: &[Override],
) -> Result<AnySpec, Diagnostics> {
    let doc = Document::read(path)?;
    Ok(match kind.unwrap_or(doc.kind) {
        Kind::Task => {
            let spec = Spec::from_document(&doc.file, &doc.root)?;
            AnySpec::Task(Box::new(crate::resolve(&spec, overrides)?))
        }
        Kind::Maze => AnySpec::Maze(Box::new(crate::maze::from_document(
            &doc.file, &doc.root, overrides,
        )?)),
        Kind::MultiAgent => AnySpec::MultiAgent(Box::new(crate::multi_agent::from_document(
            &doc.file, &doc.root, overrides,
        )?)),
    })
}
