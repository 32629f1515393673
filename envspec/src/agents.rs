//! Multi-agent factorizations (`[agents]`): one robot split among cooperating agents, as in
//! MaMuJoCo v1. Each agent drives a named set of nodes (one actuated joint each) and observes the
//! nodes within `k` hops of its own in a joint graph, then a list of global nodes.
//!
//! A multi-agent spec is either a file whose `[agents]` table names a `base` single-agent spec
//! (composition: a MaMuJoCo scenario is the Gymnasium spec plus a factorization), or a complete
//! spec with an `[agents]` table of its own. The language is documented in
//! `docs/spec-reference.md` ("Multi-agent factorizations").

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::ir::{Apply, ResolvedSpec, Segment};
use crate::params::{Override, OverrideValue, ParamValue};
use crate::selector::{self, Field, ParamIndex, Selection};
use crate::syntax::Spec;
use crate::value::{Entry, Val, ValKind};

/// Keys of `[agents]`.
pub const AGENTS_KEYS: &[&str] = &[
    "base",
    "id",
    "doc",
    "agent_conf",
    "agent_obsk",
    "local_categories",
    "global_categories",
    "body_clip",
    "edges",
    "confs",
    "nodes",
    "globals",
    "parity",
    "action_bounds",
    "base_params",
];
/// Keys of `[agents.nodes.<name>]` and `[agents.globals.<name>]`.
pub const NODE_KEYS: &[&str] = &[
    "label", "joint", "qpos", "qvel", "actuator", "bodies", "extra", "doc",
];
/// Keys of one extra-observation segment.
pub const EXTRA_KEYS: &[&str] = &["source", "minus", "apply", "clip"];
/// The categories with a built-in meaning (any other name is observed only through `extra`).
pub const BUILTIN_CATEGORIES: &[&str] = &[
    "qpos",
    "qvel",
    "qfrc_actuator",
    "cinert",
    "cvel",
    "cfrc_ext",
];
/// The `agent_conf` of single-agent mode (MaMuJoCo's `agent_conf=None`): one agent, `agent_0`,
/// with every action, observing the single-agent observation (= the state).
pub const SINGLE_AGENT: &str = "none";
/// The parameters of the multi-agent layer (every other override goes to the base spec).
pub const AGENT_PARAMS: &[&str] = &["agent_conf", "agent_obsk"];

/// A resolved multi-agent spec: the base env plus the chosen factorization at depth `k`.
#[derive(Clone, Debug)]
pub struct AgentsSpec {
    /// The single-agent env every agent shares (its observation is the global state).
    pub base: ResolvedSpec,
    pub spec_path: PathBuf,
    /// `id = "..."` (default: the file stem), e.g. `MaMuJoCo-Ant-v1`.
    pub id: String,
    pub doc: String,
    /// Names of every conf the spec declares, in order.
    pub confs: Vec<String>,
    pub conf: String,
    pub k: usize,
    pub agents: Vec<Agent>,
    /// Parity notes written in the spec (`parity = "..."`).
    pub parity: String,
    /// `action_bounds = "first_element"`: every agent's action bounds are the single-agent action
    /// space's element 0 (MaMuJoCo v1); otherwise each local action keeps its actuator's range.
    pub first_element_bounds: bool,
}

impl AgentsSpec {
    pub fn state_dim(&self) -> usize {
        self.base.obs_dim
    }
    pub fn act_dim(&self) -> usize {
        self.base.act_dim()
    }
    /// Every selection some agent observes (`source`s and `minus`es), in agent order.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        self.agents
            .iter()
            .flat_map(|a| a.observation.iter().flat_map(Segment::sources))
    }
    /// Whether any agent observes contact forces (`mj_rnePostConstraint` must run).
    pub fn reads_contact_forces(&self) -> bool {
        self.sources().any(|s| s.field.needs_rne_post_constraint())
    }
}

/// One agent.
#[derive(Clone, Debug)]
pub struct Agent {
    /// `agent_0`, `agent_1`, ... in conf order.
    pub name: String,
    /// Node names in conf order (the local action order).
    pub nodes: Vec<String>,
    /// Global action index of each local action.
    pub actions: Vec<usize>,
    /// Actuator name of each local action.
    pub actuators: Vec<String>,
    /// Node labels per depth 0..=k (label-sorted).
    pub levels: Vec<Vec<String>>,
    /// Observation segments in order, with offsets.
    pub observation: Vec<Segment>,
    pub obs_dim: usize,
    /// For each observation element, its index in the state (the base observation): the element
    /// reads the same value (same source, minus, function and clip). None when some element is
    /// not in the state (then the state cannot be mapped to this agent's observation).
    pub state_index: Option<Vec<usize>>,
}

impl Agent {
    pub fn obs_names(&self) -> Vec<String> {
        self.observation
            .iter()
            .flat_map(|s| s.element_names())
            .collect()
    }
}

/// One observation piece: source, minus, apply, clip.
type Item = (
    Selection,
    Option<Selection>,
    Option<Apply>,
    Option<(f64, f64)>,
);

#[derive(Clone, Debug)]
struct Extra {
    source: Selection,
    minus: Option<Selection>,
    apply: Option<Apply>,
    clip: Option<(f64, f64)>,
}

#[derive(Clone, Debug)]
struct Node {
    name: String,
    label: String,
    qpos: Option<Selection>,
    qvel: Option<Selection>,
    actuator: Option<usize>,
    bodies: Vec<usize>,
    /// (category, segments); an empty list suppresses the category.
    extra: Vec<(String, Vec<Extra>)>,
}

fn err(code: Code, loc: &Location, msg: impl Into<String>, label: impl Into<String>) -> Diagnostic {
    Diagnostic::new(code, msg).at(loc.clone()).label(label)
}

fn str_list(v: &Val, what: &str, d: &mut Diagnostics) -> Vec<(String, Location)> {
    match &v.kind {
        ValKind::Array(a) => a
            .iter()
            .filter_map(|x| match x.as_str() {
                Some(s) => Some((s.to_string(), x.loc.clone())),
                None => {
                    d.push(x.type_error(what, "a string"));
                    None
                }
            })
            .collect(),
        _ => {
            d.push(v.type_error(what, "an array of strings"));
            vec![]
        }
    }
}

fn range(v: &Val, what: &str, d: &mut Diagnostics) -> Option<(f64, f64)> {
    if let ValKind::Array(a) = &v.kind
        && a.len() == 2
        && let (Some(lo), Some(hi)) = (a[0].as_f64(), a[1].as_f64())
    {
        return Some((lo, hi));
    }
    d.push(v.type_error(what, "[low, high]"));
    None
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

/// Load a multi-agent spec with overrides (`agent_conf`, `agent_obsk`, and any base parameter).
pub fn load(path: &Path, overrides: &[Override]) -> Result<AgentsSpec, Diagnostics> {
    let (file, root) = crate::value::read_document(path, None, "spec")?;
    from_document(&file, &root, overrides)
}

/// [`load`] on a spec file already read and parsed (the one door reads each file once).
// Reads, resolves and builds the agent graph in one pass; to be split in three.
#[allow(clippy::too_many_lines)]
pub fn from_document(
    file: &Arc<SourceFile>,
    root: &Val,
    overrides: &[Override],
) -> Result<AgentsSpec, Diagnostics> {
    let path = file.path.as_path();
    let top = root.as_table().unwrap_or(&[]);
    let whole = Location::new(file, 0..0);
    let Some(agents_entry) = top.iter().find(|e| e.key == "agents") else {
        return Err(Diagnostic::new(Code::E0103, "missing `[agents]` table")
            .at(whole)
            .label("expected an [agents] table: this is not a multi-agent spec")
            .into());
    };
    let Some(table) = agents_entry.value.as_table() else {
        return Err(agents_entry.value.type_error("[agents]", "a table").into());
    };
    let get = |k: &str| table.iter().find(|e| e.key == k).map(|e| &e.value);
    let mut d = Diagnostics::default();
    for e in table {
        if !AGENTS_KEYS.contains(&e.key.as_str()) {
            d.push(
                err(
                    Code::E0101,
                    &e.key_loc,
                    format!("unknown key `{}` in [agents]", e.key),
                    format!("expected one of: {}", AGENTS_KEYS.join(", ")),
                )
                .help_opt(suggest(&e.key, AGENTS_KEYS.iter().copied())),
            );
        }
    }

    // Split the overrides between this layer and the base spec.
    let mut conf_override = None;
    let mut k_override = None;
    let mut single_override = false;
    let mut base_overrides = vec![];
    for o in overrides {
        match o.name.as_str() {
            "agent_conf" => {
                let c = match &o.value {
                    OverrideValue::Text(t) => t.trim().trim_matches('"').to_string(),
                    OverrideValue::Value(ParamValue::Str(s)) => s.clone(),
                    OverrideValue::Value(v) => format!("{v:?}"),
                };
                conf_override = Some(if c.eq_ignore_ascii_case(SINGLE_AGENT) {
                    SINGLE_AGENT.to_string()
                } else {
                    c
                })
            }
            "agent_obsk" => {
                let k = match &o.value {
                    OverrideValue::Text(t) => t.trim().parse::<i64>().ok(),
                    OverrideValue::Value(ParamValue::Int(i)) => Some(*i),
                    _ => None,
                };
                let none = matches!(&o.value, OverrideValue::Text(t)
                    if t.trim().trim_matches('"').eq_ignore_ascii_case(SINGLE_AGENT));
                match k {
                    Some(k) if (0..=64).contains(&k) => k_override = Some(k as usize),
                    // MaMuJoCo's agent_obsk=None: single-agent mode.
                    _ if none => single_override = true,
                    _ => d.push(
                        Diagnostic::new(
                            Code::E0203,
                            "`agent_obsk` must be an integer in 0..=64 or none",
                        )
                        .label("expected e.g. agent_obsk=1"),
                    ),
                }
            }
            _ => base_overrides.push(o.clone()),
        }
    }

    // `base_params = { name = value }`: parameters of the base spec set by this spec (a user's
    // override of the same name wins). Relative paths resolve against this file's directory.
    if let Some(v) = get("base_params") {
        match v.as_table() {
            None => d.push(v.type_error("agents.base_params", "a table of parameter values")),
            Some(t) => {
                for e in t {
                    if base_overrides.iter().any(|o| o.name == e.key) {
                        continue;
                    }
                    let text = match e.value.as_str() {
                        Some(s) if e.key == "xml_file" => {
                            let p = crate::path::normalize(
                                &path.parent().unwrap_or(Path::new("")).join(s),
                            );
                            format!("{:?}", p.display().to_string())
                        }
                        _ => e.value.to_toml(),
                    };
                    base_overrides.push(Override::text(&e.key, &text));
                }
            }
        }
    }
    // The base spec: `base = "path"`, or this file itself.
    let base = match get("base") {
        Some(v) => match v.as_str() {
            Some(s) => {
                let p = crate::path::normalize(&path.parent().unwrap_or(Path::new("")).join(s));
                base_chain(path, &p, &v.loc)?;
                crate::resolve::load(&p, &base_overrides).map_err(|mut e| {
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
            crate::resolve::resolve(&spec, &base_overrides)?
        }
    };
    let model = &base.model;
    let no_param = |n: &str| -> Result<ParamIndex, Diagnostic> {
        Err(Diagnostic::new(
            Code::E0201,
            format!("`${n}`: parameters are not available in [agents]"),
        ))
    };
    let sel = |v: &Val, d: &mut Diagnostics| -> Option<Selection> {
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
        match selector::resolve(s, &v.loc, model, &no_param) {
            Ok(x) => Some(x),
            Err(e) => {
                d.push(e);
                None
            }
        }
    };

    let body_clip = get("body_clip").and_then(|v| range(v, "agents.body_clip", &mut d));
    let doc = get("doc").and_then(Val::as_str).unwrap_or("").to_string();
    let id = get("id")
        .and_then(Val::as_str)
        .map(str::to_string)
        .unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        });
    let parity = get("parity")
        .and_then(Val::as_str)
        .unwrap_or("")
        .to_string();
    let first_element_bounds = match get("action_bounds") {
        None => false,
        Some(v) => match v.as_str() {
            Some("first_element") => true,
            Some("per_actuator") => false,
            _ => {
                d.push(err(
                    Code::E0104,
                    &v.loc,
                    "unknown `action_bounds`",
                    "expected \"per_actuator\" (default) or \"first_element\" (MaMuJoCo v1)",
                ));
                false
            }
        },
    };

    // Nodes and globals.
    let read_nodes = |key: &str, is_global: bool, d: &mut Diagnostics| -> Vec<Node> {
        let Some(v) = get(key) else { return vec![] };
        let Some(t) = v.as_table() else {
            d.push(v.type_error(&format!("agents.{key}"), "a table of nodes"));
            return vec![];
        };
        t.iter()
            .filter_map(|e| read_node(e, is_global, model, &sel, d))
            .collect()
    };
    let nodes = read_nodes("nodes", false, &mut d);
    let globals = read_nodes("globals", true, &mut d);
    let node_ix = |n: &str| nodes.iter().position(|x| x.name == n);
    let unknown_node = |n: &str, loc: &Location| {
        err(
            Code::E0303,
            loc,
            format!("unknown node `{n}`"),
            "expected a name from [agents.nodes]",
        )
        .help_opt(suggest(n, nodes.iter().map(|x| x.name.as_str())))
    };

    // Hyperedges.
    let mut edges: Vec<Vec<usize>> = vec![];
    if let Some(v) = get("edges") {
        match &v.kind {
            ValKind::Array(a) => {
                for e in a {
                    let mut edge = vec![];
                    for (n, loc) in str_list(e, "agents.edges[]", &mut d) {
                        match node_ix(&n) {
                            Some(i) => edge.push(i),
                            None => d.push(unknown_node(&n, &loc)),
                        }
                    }
                    edges.push(edge);
                }
            }
            _ => d.push(v.type_error("agents.edges", "an array of arrays of node names")),
        }
    }

    // Categories.
    let local_categories: Vec<Vec<String>> = match get("local_categories") {
        None => vec![vec!["qpos".into(), "qvel".into()], vec!["qpos".into()]],
        Some(v) => match &v.kind {
            ValKind::Array(a) if !a.is_empty() => a
                .iter()
                .map(|x| {
                    str_list(x, "agents.local_categories[]", &mut d)
                        .into_iter()
                        .map(|s| s.0)
                        .collect()
                })
                .collect(),
            _ => {
                d.push(v.type_error("agents.local_categories", "a non-empty array of arrays"));
                vec![vec![]]
            }
        },
    };
    let global_categories: Vec<String> = match get("global_categories") {
        None => vec!["qpos".into(), "qvel".into()],
        Some(v) => str_list(v, "agents.global_categories", &mut d)
            .into_iter()
            .map(|s| s.0)
            .collect(),
    };

    // Confs.
    let mut confs: Vec<(String, Location, Vec<Vec<usize>>)> = vec![];
    match get("confs") {
        // No confs: only single-agent mode (`agent_conf = "none"`).
        None => {}
        Some(v) => match v.as_table() {
            None => d.push(v.type_error("agents.confs", "a table of partitions")),
            Some(t) => {
                for c in t {
                    let mut parts = vec![];
                    // An unknown node is reported once; the partition check would only repeat it
                    // as an undriven actuator.
                    let mut unknown = false;
                    match &c.value.kind {
                        ValKind::Array(a) if !a.is_empty() => {
                            for p in a {
                                let mut part = vec![];
                                for (n, loc) in str_list(p, "a conf's agent", &mut d) {
                                    match node_ix(&n) {
                                        Some(i) => part.push(i),
                                        None => {
                                            unknown = true;
                                            d.push(unknown_node(&n, &loc));
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
                    // Every actuator exactly once.
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
                    let act_name = |a: usize| {
                        let x = &model.actuators[a];
                        match (&x.target, x.name.is_empty()) {
                            (Some(t), true) => format!("({t})"),
                            _ => x.name.clone(),
                        }
                    };
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
                    confs.push((c.key.clone(), c.key_loc.clone(), parts));
                }
            }
        },
    }

    let conf_name = match (&conf_override, get("agent_conf")) {
        _ if single_override => SINGLE_AGENT.to_string(),
        (Some(c), _) => c.clone(),
        (None, Some(v)) => v.as_str().unwrap_or("").to_string(),
        (None, None) => confs
            .first()
            .map(|c| c.0.clone())
            .unwrap_or_else(|| SINGLE_AGENT.to_string()),
    };
    let k = match (k_override, get("agent_obsk")) {
        (Some(k), _) => k,
        (None, Some(v)) => match &v.kind {
            ValKind::Int(i) if (0..=64).contains(i) => *i as usize,
            _ => {
                d.push(v.type_error("agents.agent_obsk", "an integer in 0..=64"));
                1
            }
        },
        (None, None) => 1,
    };
    let chosen = confs.iter().find(|c| c.0 == conf_name);
    let single = conf_name == SINGLE_AGENT && chosen.is_none();
    if chosen.is_none() && !single && d.is_empty() {
        let mut names: Vec<&str> = confs.iter().map(|c| c.0.as_str()).collect();
        names.push(SINGLE_AGENT);
        // An override is E0203 (it has no place in the file); the spec's own key is E0104.
        let (code, loc) = match conf_override {
            Some(_) => (Code::E0203, None),
            None => (Code::E0104, get("agent_conf").map(|v| v.loc.clone())),
        };
        d.push(
            Diagnostic::new(code, format!("unknown agent_conf `{conf_name}`"))
                .at_opt(loc)
                .label(format!("expected one of: {}", names.join(", ")))
                .help_opt(suggest(&conf_name, names.iter().copied())),
        );
    }
    if !d.is_empty() {
        return Err(d);
    }
    if single {
        // MaMuJoCo's agent_conf=None: one agent with every action, observing the state.
        let base_obs = base.observation.clone();
        let agent = Agent {
            name: "agent_0".into(),
            nodes: (0..model.nu()).map(|a| format!("action{a}")).collect(),
            actions: (0..model.nu()).collect(),
            actuators: (0..model.nu()).map(|a| actuator_name(model, a)).collect(),
            levels: vec![],
            obs_dim: base.obs_dim,
            observation: base_obs,
            state_index: Some((0..base.obs_dim).collect()),
        };
        return Ok(AgentsSpec {
            id,
            doc,
            confs: confs.iter().map(|c| c.0.clone()).collect(),
            conf: conf_name,
            k: 0,
            agents: vec![agent],
            parity,
            first_element_bounds,
            spec_path: path.to_path_buf(),
            base,
        });
    }
    let parts = &chosen.expect("checked").2;

    let mut agents: Vec<Agent> = parts
        .iter()
        .enumerate()
        .map(|(i, part)| {
            build_agent(
                format!("agent_{i}"),
                part,
                &nodes,
                &edges,
                &globals,
                &local_categories,
                &global_categories,
                body_clip,
                k,
                model,
            )
        })
        .collect();
    for a in &mut agents {
        a.state_index = state_index(&a.observation, &base.observation);
    }
    Ok(AgentsSpec {
        base,
        spec_path: path.to_path_buf(),
        id,
        doc,
        confs: confs.iter().map(|c| c.0.clone()).collect(),
        conf: conf_name,
        k,
        agents,
        parity,
        first_element_bounds,
    })
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
        match get("actuator") {
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
                let found = joint.as_ref().and_then(|j| {
                    model
                        .actuators
                        .iter()
                        .position(|a| a.target.as_deref() == Some(j.as_str()))
                });
                // Checked when a conf uses the node (graph-only nodes need no actuator).
                found
            }
        }
    };
    let mut bodies = vec![];
    match get("bodies").map(|v| (v, &v.kind)) {
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
    let mut extra = vec![];
    if let Some(v) = get("extra") {
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
            _ => {
                d.push(err(
                    Code::E0104,
                    &a.loc,
                    "unknown function in `apply`",
                    "expected \"sin\" or \"cos\"",
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

/// `get_joints_at_kdist`: node indices per depth, each level sorted by label (stable: ties keep
/// declaration order).
fn k_levels(part: &[usize], nodes: &[Node], edges: &[Vec<usize>], k: usize) -> Vec<Vec<usize>> {
    let sort = |mut v: Vec<usize>| {
        v.sort_by(|&a, &b| nodes[a].label.cmp(&nodes[b].label).then(a.cmp(&b)));
        v
    };
    let mut explored: Vec<usize> = part.to_vec();
    let mut frontier: Vec<usize> = part.to_vec();
    let mut levels = vec![sort(part.to_vec())];
    for _ in 0..k {
        let mut new = vec![];
        for &x in &frontier {
            for e in edges.iter().filter(|e| e.contains(&x)) {
                for &y in e {
                    if y != x && !explored.contains(&y) && !new.contains(&y) {
                        new.push(y);
                    }
                }
            }
        }
        explored.extend(&new);
        frontier = new.clone();
        levels.push(sort(new));
    }
    levels
}

fn with_field(s: &Selection, field: Field) -> Selection {
    let old = s.field.name();
    Selection {
        field,
        indices: s.indices.clone(),
        names: s
            .names
            .iter()
            .map(|n| n.replacen(old, field.name(), 1))
            .collect(),
        text: s.text.replacen(old, field.name(), 1),
    }
}

/// The segments one node contributes for one category (`emitted` de-duplicates bodies).
fn node_category(
    node: &Node,
    cat: &str,
    body_clip: Option<(f64, f64)>,
    emitted: &mut Vec<(String, usize)>,
    model: &crate::mjcf::ModelInfo,
) -> Vec<Item> {
    if let Some((_, segs)) = node.extra.iter().find(|(c, _)| c == cat) {
        return segs
            .iter()
            .map(|x| (x.source.clone(), x.minus.clone(), x.apply, x.clip))
            .collect();
    }
    match cat {
        "qpos" => node
            .qpos
            .iter()
            .map(|s| (s.clone(), None, None, None))
            .collect(),
        "qvel" => node
            .qvel
            .iter()
            .map(|s| (s.clone(), None, None, None))
            .collect(),
        "qfrc_actuator" => node
            .qvel
            .iter()
            .map(|s| (with_field(s, Field::QfrcActuator), None, None, None))
            .collect(),
        "cinert" | "cvel" | "cfrc_ext" => {
            let (field, cols) = match cat {
                "cinert" => (Field::Cinert, 10),
                "cvel" => (Field::Cvel, 6),
                _ => (Field::CfrcExt, 6),
            };
            let mut out = vec![];
            for &b in &node.bodies {
                if emitted.iter().any(|(c, x)| c == cat && *x == b) {
                    continue;
                }
                emitted.push((cat.to_string(), b));
                let bname = if model.bodies[b].is_empty() {
                    format!("{b}")
                } else {
                    model.bodies[b].clone()
                };
                out.push((
                    Selection {
                        field,
                        indices: (b * cols..b * cols + cols).collect(),
                        names: (0..cols).map(|c| format!("{cat}[{bname}][{c}]")).collect(),
                        text: format!("{cat}[{bname}]"),
                    },
                    None,
                    None,
                    body_clip,
                ));
            }
            out
        }
        _ => vec![],
    }
}

#[allow(clippy::too_many_arguments)]
fn build_agent(
    name: String,
    part: &[usize],
    nodes: &[Node],
    edges: &[Vec<usize>],
    globals: &[Node],
    local_categories: &[Vec<String>],
    global_categories: &[String],
    body_clip: Option<(f64, f64)>,
    k: usize,
    model: &crate::mjcf::ModelInfo,
) -> Agent {
    let levels = k_levels(part, nodes, edges, k);
    let mut segs: Vec<Segment> = vec![];
    let mut offset = 0;
    let mut push = |seg_name: String, items: Vec<Item>, segs: &mut Vec<Segment>| {
        for (i, (source, minus, apply, clip)) in items.into_iter().enumerate() {
            if source.is_empty() {
                continue;
            }
            let len = source.len();
            segs.push(Segment {
                name: if i == 0 {
                    seg_name.clone()
                } else {
                    format!("{seg_name}#{i}")
                },
                doc: String::new(),
                source,
                minus,
                apply,
                clip,
                offset,
            });
            offset += len;
        }
    };
    let mut emitted = vec![];
    for (depth, level) in levels.iter().enumerate() {
        let cats = &local_categories[depth.min(local_categories.len() - 1)];
        for &n in level {
            let node = &nodes[n];
            for cat in cats {
                let items = node_category(node, cat, body_clip, &mut emitted, model);
                push(format!("k{depth}.{}.{cat}", node.name), items, &mut segs);
            }
        }
    }
    let mut emitted = vec![];
    for cat in global_categories {
        for node in globals {
            let items = node_category(node, cat, body_clip, &mut emitted, model);
            push(format!("global.{}.{cat}", node.name), items, &mut segs);
        }
    }
    let obs_dim = segs.iter().map(Segment::len).sum();
    Agent {
        name,
        nodes: part.iter().map(|&i| nodes[i].name.clone()).collect(),
        actions: part
            .iter()
            .map(|&i| nodes[i].actuator.expect("checked"))
            .collect(),
        actuators: part
            .iter()
            .map(|&i| actuator_name(model, nodes[i].actuator.expect("checked")))
            .collect(),
        levels: levels
            .iter()
            .map(|l| l.iter().map(|&i| nodes[i].label.clone()).collect())
            .collect(),
        observation: segs,
        obs_dim,
        state_index: None,
    }
}

/// A multi-agent spec shared between threads.
pub type SharedAgentsSpec = Arc<AgentsSpec>;

/// Semantic diff of two multi-agent specs; see [`crate::diff::diff_agents`].
pub fn diff(old_path: &Path, new_path: &Path) -> Result<crate::diff::Report, Diagnostics> {
    crate::diff::diff_agents(old_path, new_path)
}

/// An actuator's name, or `(joint)` for an unnamed actuator.
fn actuator_name(model: &crate::mjcf::ModelInfo, a: usize) -> String {
    let x = &model.actuators[a];
    match (&x.target, x.name.is_empty()) {
        (Some(t), true) => format!("({t})"),
        _ => x.name.clone(),
    }
}

/// What one observation element reads, for matching local elements with state elements.
type ElemKey = (
    Field,
    usize,
    Option<(Field, usize)>,
    Option<Apply>,
    Option<(u64, u64)>,
);

fn elements(segs: &[Segment]) -> Vec<ElemKey> {
    let mut out = vec![];
    for s in segs {
        for k in 0..s.len() {
            out.push((
                s.source.field,
                s.source.indices[k],
                s.minus.as_ref().map(|m| (m.field, m.indices[k])),
                s.apply,
                s.clip.map(|(lo, hi)| (lo.to_bits(), hi.to_bits())),
            ));
        }
    }
    out
}

fn state_index(local: &[Segment], state: &[Segment]) -> Option<Vec<usize>> {
    let st = elements(state);
    elements(local)
        .iter()
        .map(|e| st.iter().position(|x| x == e))
        .collect()
}
