//! Resolving `[agents]` against the base env: the base spec (a file named by `base`, or this
//! file's own task), node and global selectors, actuators and bodies in the base model,
//! hyperedges and confs by node name, each conf checked to drive every actuator exactly once.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::syntax::{err, get, range, str_list};
use super::{EXTRA_KEYS, NODE_KEYS};
use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::ir::{Apply, ResolvedSpec};
use crate::params::Override;
use crate::selector::{self, ParamIndex, Selection};
use crate::syntax::Spec;
use crate::value::{Entry, Val, ValKind};

/// A node or a global of `[agents]`, resolved against the model.
#[derive(Clone, Debug)]
pub(super) struct Extra {
    pub source: Selection,
    pub minus: Option<Selection>,
    pub apply: Option<Apply>,
    pub clip: Option<(f64, f64)>,
}

#[derive(Clone, Debug)]
pub(super) struct Node {
    pub name: String,
    pub label: String,
    pub qpos: Option<Selection>,
    pub qvel: Option<Selection>,
    pub actuator: Option<usize>,
    pub bodies: Vec<usize>,
    /// (category, segments); an empty list suppresses the category.
    pub extra: Vec<(String, Vec<Extra>)>,
}

/// Whether a document is a multi-agent spec without a task of its own (its `[agents] base`
/// holds the task), and that base.
fn delegates(root: &Val) -> Option<Option<&Val>> {
    let top = root.as_table()?;
    let agents = top.iter().find(|e| e.key == "agents")?.value.as_table()?;
    if top.iter().any(|e| e.key == "env") {
        return None;
    }
    Some(agents.iter().find(|e| e.key == "base").map(|e| &e.value))
}

/// Follow `base` from `this` (whose `base` at `at` names `first`) through multi-agent specs
/// that only compose: a chain that returns to a file already on it is E0120, a chain that ends
/// at another multi-agent spec is E0121 (a base must be a task spec). Files that cannot be read
/// are left for the base's own load to report.
fn base_chain(this: &Path, first: &Path, at: &Location) -> Result<(), Diagnostic> {
    // Two spellings of one file (`./a.toml`, `../x/a.toml`) are the same link.
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    let show = |chain: &[PathBuf]| {
        chain
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" → ")
    };
    let mut chain = vec![this.to_path_buf()];
    let mut next = first.to_path_buf();
    loop {
        if chain.iter().any(|p| same(p, &next)) {
            chain.push(next);
            let msg = if chain.len() == 2 {
                "`base` names this file itself".to_string()
            } else {
                format!(
                    "`base` leads back to a spec already on its chain: {}",
                    show(&chain)
                )
            };
            return Err(err(Code::E0120, at, msg, "expected the path of a task spec")
                .help(format!(
                    "a cycle of bases has no task to split: {}; point `base` at a task spec (one with `[env]`)",
                    show(&chain)
                )));
        }
        let task = match crate::value::read_document(&next, None, "spec") {
            Ok((_, root)) => match delegates(&root) {
                Some(base) => {
                    chain.push(next.clone());
                    match base.and_then(Val::as_str) {
                        Some(s) if chain.len() <= 64 => {
                            let dir = next.parent().unwrap_or(Path::new(""));
                            next = crate::path::normalize(&dir.join(s));
                            continue;
                        }
                        _ => None,
                    }
                }
                None => Some(next),
            },
            Err(_) => None,
        };
        if chain.len() == 1 {
            // `first` itself is a task spec (or unreadable: its load says why).
            return Ok(());
        }
        let help = match task {
            Some(t) => format!("point `base` at the task spec it splits, {}", t.display()),
            None => "point `base` at a task spec (one with `[env]`)".to_string(),
        };
        return Err(err(
            Code::E0121,
            at,
            format!(
                "`base` names a multi-agent spec, not a task spec: {}",
                show(&chain)
            ),
            "expected the path of a task spec (one with `[env]`)",
        )
        .help(help));
    }
}

/// The base env: `base = "path"` (its chain checked, its errors followed by one pointing at
/// `base`), or this file's own task.
pub(super) fn base(
    file: &Arc<SourceFile>,
    root: &Val,
    table: &[Entry],
    base_overrides: &[Override],
) -> Result<ResolvedSpec, Diagnostics> {
    let base = base_spec(file, root, table, base_overrides)?;
    // Agents split the actuators; an end-effector action or a goal dict has no such split.
    let m = &base.manipulation;
    if m.end_effector.is_some() || m.goal.is_some() {
        let at = get(table, "base").map_or_else(
            || crate::diagnostic::Location::new(file, 0..0),
            |v| v.loc.clone(),
        );
        return Err(err(
            Code::E0170,
            &at,
            format!(
                "`{}` has [end_effector] or [goal]: a multi-agent split of its actions and goal dicts is not supported",
                base.id
            ),
            "a task whose actions are its actuators",
        )
        .into());
    }
    Ok(base)
}

fn base_spec(
    file: &Arc<SourceFile>,
    root: &Val,
    table: &[Entry],
    base_overrides: &[Override],
) -> Result<ResolvedSpec, Diagnostics> {
    let path = file.path.as_path();
    Ok(match get(table, "base") {
        Some(v) => match v.as_str() {
            Some(s) => {
                let p = crate::path::normalize(&path.parent().unwrap_or(Path::new("")).join(s));
                base_chain(path, &p, &v.loc)?;
                crate::resolve::load(&p, base_overrides).map_err(|mut e| {
                    e.push(
                        err(
                            Code::E0301,
                            &v.loc,
                            "the base spec has errors",
                            "listed above",
                        )
                        .help(format!("base resolved to {}", p.display())),
                    );
                    e
                })?
            }
            None => return Err(v.type_error("agents.base", "a path").into()),
        },
        None => {
            let spec = Spec::from_document(file, root)?;
            crate::resolve::resolve(&spec, base_overrides)?
        }
    })
}

/// A selector of an `[agents]` node or extra segment: model fields, and the task's commands read
/// from the base env's buffer. Parameters are not available here (E0201).
fn select(v: &Val, base: &ResolvedSpec, d: &mut Diagnostics) -> Option<Selection> {
    let no_param = |n: &str| -> Result<ParamIndex, Diagnostic> {
        Err(Diagnostic::new(
            Code::E0201,
            format!("`${n}`: parameters are not available in [agents]"),
        ))
    };
    let Some(s) = v.as_str() else {
        d.push(v.type_error("selector", "a selector string"));
        return None;
    };
    // Commands are the task's, not the model's: read them from the base env's buffer.
    let t = s.trim();
    if t.starts_with("command")
        && !t["command".len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
    {
        return crate::resolve::command_selection(s, &v.loc, &base.commands, d);
    }
    match selector::resolve(s, &v.loc, &base.model, &no_param) {
        Ok(x) => Some(x),
        Err(e) => {
            d.push(e);
            None
        }
    }
}

/// The nodes, the globals and the hyperedges between nodes.
pub(super) struct Graph {
    pub nodes: Vec<Node>,
    pub globals: Vec<Node>,
    pub edges: Vec<Vec<usize>>,
}

/// E0303 for a node name that `[agents.nodes]` does not declare, with the near miss.
fn unknown_node(nodes: &[Node], n: &str, loc: &Location) -> Diagnostic {
    err(
        Code::E0303,
        loc,
        format!("unknown node `{n}`"),
        "expected a name from [agents.nodes]",
    )
    .help_opt(suggest(n, nodes.iter().map(|x| x.name.as_str())))
}

/// `[agents.nodes]`, `[agents.globals]` and `edges`, resolved against the base model.
pub(super) fn graph(table: &[Entry], base: &ResolvedSpec, d: &mut Diagnostics) -> Graph {
    let model = &base.model;
    let sel = |v: &Val, d: &mut Diagnostics| select(v, base, d);
    let read_nodes = |key: &str, is_global: bool, d: &mut Diagnostics| -> Vec<Node> {
        let Some(v) = get(table, key) else {
            return vec![];
        };
        let Some(t) = v.as_table() else {
            d.push(v.type_error(&format!("agents.{key}"), "a table of nodes"));
            return vec![];
        };
        t.iter()
            .filter_map(|e| read_node(e, is_global, model, &sel, d))
            .collect()
    };
    let nodes = read_nodes("nodes", false, d);
    let globals = read_nodes("globals", true, d);
    let node_ix = |n: &str| nodes.iter().position(|x| x.name == n);

    // Hyperedges.
    let mut edges: Vec<Vec<usize>> = vec![];
    if let Some(v) = get(table, "edges") {
        match &v.kind {
            ValKind::Array(a) => {
                for e in a {
                    let mut edge = vec![];
                    for (n, loc) in str_list(e, "agents.edges[]", d) {
                        match node_ix(&n) {
                            Some(i) => edge.push(i),
                            None => d.push(unknown_node(&nodes, &n, &loc)),
                        }
                    }
                    edges.push(edge);
                }
            }
            _ => d.push(v.type_error("agents.edges", "an array of arrays of node names")),
        }
    }
    Graph {
        nodes,
        globals,
        edges,
    }
}

/// One conf: its name and its partition of nodes into agents.
pub(super) struct Conf {
    pub name: String,
    pub parts: Vec<Vec<usize>>,
}

/// `[agents.confs]`: node names to indices, each conf checked to drive every actuator exactly
/// once (E0109) through nodes with an actuator (E0103).
pub(super) fn confs(
    table: &[Entry],
    nodes: &[Node],
    model: &crate::mjcf::ModelInfo,
    d: &mut Diagnostics,
) -> Vec<Conf> {
    let mut confs = vec![];
    match get(table, "confs") {
        // No confs: only single-agent mode (`agent_conf = "none"`).
        None => {}
        Some(v) => match v.as_table() {
            None => d.push(v.type_error("agents.confs", "a table of partitions")),
            Some(t) => {
                for c in t {
                    let (parts, unknown) = conf_parts(c, nodes, d);
                    check_partition(c, &parts, unknown, nodes, model, d);
                    confs.push(Conf {
                        name: c.key.clone(),
                        parts,
                    });
                }
            }
        },
    }
    confs
}

/// A conf's agents as node indices, and whether some name was not a node.
fn conf_parts(c: &Entry, nodes: &[Node], d: &mut Diagnostics) -> (Vec<Vec<usize>>, bool) {
    let node_ix = |n: &str| nodes.iter().position(|x| x.name == n);
    let mut parts = vec![];
    let mut unknown = false;
    match &c.value.kind {
        ValKind::Array(a) if !a.is_empty() => {
            for p in a {
                let mut part = vec![];
                for (n, loc) in str_list(p, "a conf's agent", d) {
                    match node_ix(&n) {
                        Some(i) => part.push(i),
                        None => {
                            unknown = true;
                            d.push(unknown_node(nodes, &n, &loc));
                        }
                    }
                }
                parts.push(part);
            }
        }
        _ => d.push(
            c.value
                .type_error("a conf", "a non-empty array of arrays of node names"),
        ),
    }
    (parts, unknown)
}

/// Every actuator driven exactly once by the conf's nodes. An unknown node is reported once
/// (`unknown`): the check would only repeat it as an undriven actuator.
fn check_partition(
    c: &Entry,
    parts: &[Vec<usize>],
    unknown: bool,
    nodes: &[Node],
    model: &crate::mjcf::ModelInfo,
    d: &mut Diagnostics,
) {
    let mut count = vec![0usize; model.nu()];
    for &i in parts.iter().flatten() {
        match nodes[i].actuator {
            Some(a) => count[a] += 1,
            None => d.push(err(
                Code::E0103,
                &c.key_loc,
                format!(
                    "node `{}` in conf `{}` has no actuator",
                    nodes[i].name, c.key
                ),
                "no actuator drives its joint: add `actuator = \"name\"` to the node",
            )),
        }
    }
    let act_name = |a: usize| actuator_name(model, a);
    for (a, &n) in count.iter().enumerate() {
        if n > 1 {
            d.push(err(
                Code::E0109,
                &c.key_loc,
                format!(
                    "conf `{}` drives actuator `{}` {n} times",
                    c.key,
                    act_name(a)
                ),
                "every actuator must belong to exactly one agent",
            ));
        }
    }
    let missing: Vec<String> = (0..model.nu())
        .filter(|&a| count[a] == 0)
        .map(act_name)
        .collect();
    if !missing.is_empty() && !unknown {
        d.push(err(
            Code::E0109,
            &c.key_loc,
            format!(
                "conf `{}` leaves actuators undriven: {}",
                c.key,
                missing.join(", ")
            ),
            "every actuator must belong to exactly one agent",
        ));
    }
}

/// An actuator's name, or `(joint)` for an unnamed actuator.
pub(super) fn actuator_name(model: &crate::mjcf::ModelInfo, a: usize) -> String {
    let x = &model.actuators[a];
    match (&x.target, x.name.is_empty()) {
        (Some(t), true) => format!("({t})"),
        _ => x.name.clone(),
    }
}

fn read_node(
    e: &Entry,
    is_global: bool,
    model: &crate::mjcf::ModelInfo,
    sel: &dyn Fn(&Val, &mut Diagnostics) -> Option<Selection>,
    d: &mut Diagnostics,
) -> Option<Node> {
    let what = if is_global {
        "agents.globals"
    } else {
        "agents.nodes"
    };
    let Some(t) = e.value.as_table() else {
        d.push(e.value.type_error(&format!("{what}.{}", e.key), "a table"));
        return None;
    };
    let get = |k: &str| t.iter().find(|x| x.key == k).map(|x| &x.value);
    for x in t {
        if !NODE_KEYS.contains(&x.key.as_str()) || (is_global && x.key == "actuator") {
            d.push(
                err(
                    Code::E0101,
                    &x.key_loc,
                    format!("unknown key `{}` in [{what}.{}]", x.key, e.key),
                    format!("expected one of: {}", NODE_KEYS.join(", ")),
                )
                .help_opt(suggest(&x.key, NODE_KEYS.iter().copied())),
            );
        }
    }
    let label = get("label")
        .and_then(Val::as_str)
        .unwrap_or(&e.key)
        .to_string();
    let joint = get("joint").and_then(|v| match v.as_str() {
        Some(j) if model.joint(j).is_some() => Some(j.to_string()),
        Some(j) => {
            d.push(
                err(
                    Code::E0303,
                    &v.loc,
                    format!("the model has no joint `{j}`"),
                    "expected a joint name",
                )
                .help_opt(suggest(j, model.joints.iter().map(|x| x.name.as_str()))),
            );
            None
        }
        None => {
            d.push(v.type_error("joint", "a joint name"));
            None
        }
    });
    let joint_sel = |field: &str| -> Option<Selection> {
        let j = joint.as_ref()?;
        let v = get("joint")?;
        let text = Val {
            kind: ValKind::Str(format!("{field}[{j}]")),
            loc: v.loc.clone(),
        };
        sel(&text, &mut Diagnostics::default())
    };
    let qpos = match get("qpos") {
        Some(v) => sel(v, d),
        None => joint_sel("qpos"),
    };
    let qvel = match get("qvel") {
        Some(v) => sel(v, d),
        None => joint_sel("qvel"),
    };
    let actuator = if is_global {
        None
    } else {
        node_actuator(get("actuator"), joint.as_ref(), model, d)
    };
    let bodies = node_bodies(get("bodies"), model, d);
    let extra = node_extra(get("extra"), sel, d);
    Some(Node {
        name: e.key.clone(),
        label,
        qpos,
        qvel,
        actuator,
        bodies,
        extra,
    })
}

/// A node's actuator: `actuator = "name"` or an index, else the actuator whose target is the
/// node's joint (None when there is none: checked when a conf uses the node, as graph-only nodes
/// need no actuator).
fn node_actuator(
    v: Option<&Val>,
    joint: Option<&String>,
    model: &crate::mjcf::ModelInfo,
    d: &mut Diagnostics,
) -> Option<usize> {
    match v {
        Some(v) => match (&v.kind, v.as_str()) {
            (ValKind::Int(i), _) if (*i as usize) < model.nu() && *i >= 0 => Some(*i as usize),
            (_, Some(a)) => match model.actuators.iter().position(|x| x.name == a) {
                Some(i) => Some(i),
                None => {
                    d.push(
                        err(
                            Code::E0303,
                            &v.loc,
                            format!("the model has no actuator `{a}`"),
                            "expected an actuator name",
                        )
                        .help_opt(suggest(a, model.actuators.iter().map(|x| x.name.as_str()))),
                    );
                    None
                }
            },
            _ => {
                d.push(v.type_error("actuator", "an actuator name or index"));
                None
            }
        },
        None => {
            let found = joint.and_then(|j| {
                model
                    .actuators
                    .iter()
                    .position(|a| a.target.as_deref() == Some(j.as_str()))
            });
            // Checked when a conf uses the node (graph-only nodes need no actuator).
            found
        }
    }
}

/// A node's `bodies`, by name or id.
fn node_bodies(v: Option<&Val>, model: &crate::mjcf::ModelInfo, d: &mut Diagnostics) -> Vec<usize> {
    let mut bodies = vec![];
    match v.map(|v| (v, &v.kind)) {
        None => {}
        Some((_, ValKind::Array(a))) => {
            for b in a {
                match (&b.kind, b.as_str()) {
                    (ValKind::Int(i), _) if *i >= 0 && (*i as usize) < model.nbody() => {
                        bodies.push(*i as usize)
                    }
                    (_, Some(name)) => match model.body_id(name) {
                        Some(i) => bodies.push(i),
                        None => d.push(
                            err(
                                Code::E0303,
                                &b.loc,
                                format!("the model has no body `{name}`"),
                                "expected a body name",
                            )
                            .help_opt(suggest(name, model.bodies.iter().map(String::as_str))),
                        ),
                    },
                    _ => d.push(err(
                        Code::E0304,
                        &b.loc,
                        "not a body of the model",
                        format!("expected a body name or an id below {}", model.nbody()),
                    )),
                }
            }
        }
        Some((v, _)) => d.push(v.type_error("bodies", "an array of body names or ids")),
    }
    bodies
}

/// A node's `extra`: category = segments (an empty list suppresses the category).
fn node_extra(
    v: Option<&Val>,
    sel: &dyn Fn(&Val, &mut Diagnostics) -> Option<Selection>,
    d: &mut Diagnostics,
) -> Vec<(String, Vec<Extra>)> {
    let mut extra = vec![];
    if let Some(v) = v {
        match v.as_table() {
            None => d.push(v.type_error("extra", "a table: category = segments")),
            Some(t) => {
                for c in t {
                    let items: Vec<&Val> = match &c.value.kind {
                        ValKind::Array(a) => a.iter().collect(),
                        _ => vec![&c.value],
                    };
                    let segs = items
                        .into_iter()
                        .filter_map(|it| read_extra(it, sel, d))
                        .collect();
                    extra.push((c.key.clone(), segs));
                }
            }
        }
    }
    extra
}

fn read_extra(
    v: &Val,
    sel: &dyn Fn(&Val, &mut Diagnostics) -> Option<Selection>,
    d: &mut Diagnostics,
) -> Option<Extra> {
    if v.as_str().is_some() {
        return Some(Extra {
            source: sel(v, d)?,
            minus: None,
            apply: None,
            clip: None,
        });
    }
    let Some(t) = v.as_table() else {
        d.push(v.type_error(
            "an extra segment",
            "a selector or { source, minus, apply, clip }",
        ));
        return None;
    };
    let get = |k: &str| t.iter().find(|x| x.key == k).map(|x| &x.value);
    for x in t {
        if !EXTRA_KEYS.contains(&x.key.as_str()) {
            d.push(
                err(
                    Code::E0101,
                    &x.key_loc,
                    format!("unknown key `{}` in an extra segment", x.key),
                    format!("expected one of: {}", EXTRA_KEYS.join(", ")),
                )
                .help_opt(suggest(&x.key, EXTRA_KEYS.iter().copied())),
            );
        }
    }
    let Some(src) = get("source") else {
        d.push(err(
            Code::E0103,
            &v.loc,
            "missing `source` in an extra segment",
            "expected source = \"selector\"",
        ));
        return None;
    };
    let source = sel(src, d)?;
    let minus = match get("minus") {
        Some(m) => {
            let m = sel(m, d)?;
            if m.len() != source.len() {
                d.push(err(
                    Code::E0403,
                    &v.loc,
                    format!(
                        "`minus` has {} elements, `source` {}",
                        m.len(),
                        source.len()
                    ),
                    "expected equal lengths",
                ));
                return None;
            }
            Some(m)
        }
        None => None,
    };
    let apply = match get("apply") {
        None => None,
        Some(a) => match a.as_str() {
            Some("sin") => Some(Apply::Sin),
            Some("cos") => Some(Apply::Cos),
            Some("positive") => Some(Apply::Positive),
            _ => {
                d.push(err(
                    Code::E0104,
                    &a.loc,
                    "unknown function in `apply`",
                    "expected \"sin\", \"cos\" or \"positive\"",
                ));
                None
            }
        },
    };
    let clip = get("clip").and_then(|c| range(c, "clip", d));
    Some(Extra {
        source,
        minus,
        apply,
        clip,
    })
}
