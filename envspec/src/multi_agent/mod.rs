//! Multi-agent factorizations (`[agents]`): one robot split among cooperating agents, as in
//! MaMuJoCo v1. Each agent drives a named set of nodes (one actuated joint each) and observes the
//! nodes within `k` hops of its own in a joint graph, then a list of global nodes.
//!
//! A multi-agent spec is either a file whose `[agents]` table names a `base` single-agent spec
//! (composition: a MaMuJoCo scenario is the Gymnasium spec plus a factorization), or a complete
//! spec with an `[agents]` table of its own. The language is documented in
//! `docs/spec-reference.md` ("Multi-agent factorizations").
//!
//! Like the task pipeline, in three steps: `syntax` reads the `[agents]` table (no model),
//! `resolve` resolves the base env and the nodes, edges and confs against its model, `graph`
//! builds each agent's observation at depth `k`.

mod graph;
mod resolve;
mod syntax;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Diagnostics, SourceFile};
use crate::ir::{ResolvedSpec, Segment};
use crate::params::Override;
use crate::selector::Selection;
use crate::value::Val;

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
pub struct MultiAgentSpec {
    /// The single-agent env every agent shares (its observation is the global state).
    pub base: ResolvedSpec,
    /// The multi-agent spec file (its `base` is resolved relative to it).
    pub spec_path: PathBuf,
    /// `id = "..."` (default: the file stem), e.g. `MaMuJoCo-Ant-v1`.
    pub id: String,
    /// The spec's `doc` text, shown by `envc show`.
    pub doc: String,
    /// Names of every conf the spec declares, in order.
    pub confs: Vec<String>,
    /// The chosen `agent_conf` (or `SINGLE_AGENT`).
    pub conf: String,
    /// The chosen `agent_obsk`: how many graph hops an agent observes.
    pub k: usize,
    /// The agents of the chosen conf, in conf order.
    pub agents: Vec<Agent>,
    /// Parity notes written in the spec (`parity = "..."`).
    pub parity: String,
    /// `action_bounds = "first_element"`: every agent's action bounds are the single-agent action
    /// space's element 0 (MaMuJoCo v1); otherwise each local action keeps its actuator's range.
    pub first_element_bounds: bool,
}

impl MultiAgentSpec {
    /// Length of the global state, the base env's observation.
    pub fn state_dim(&self) -> usize {
        self.base.obs_dim
    }
    /// Length of the joint action, the base env's action.
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
    /// Length of this agent's observation.
    pub obs_dim: usize,
    /// For each observation element, its index in the state (the base observation): the element
    /// reads the same value (same source, minus, function and clip). None when some element is
    /// not in the state (then the state cannot be mapped to this agent's observation).
    pub state_index: Option<Vec<usize>>,
}

impl Agent {
    /// One name per observation element, as `envc show` prints them.
    pub fn obs_names(&self) -> Vec<String> {
        self.observation
            .iter()
            .flat_map(|s| s.element_names())
            .collect()
    }
}

/// Load a multi-agent spec with overrides (`agent_conf`, `agent_obsk`, and any base parameter).
pub fn load(path: &Path, overrides: &[Override]) -> Result<MultiAgentSpec, Diagnostics> {
    let (file, root) = crate::value::read_document(path, None, "spec")?;
    from_document(&file, &root, overrides)
}

/// [`load`] on a spec file already read and parsed (the one door reads each file once).
pub fn from_document(
    file: &Arc<SourceFile>,
    root: &Val,
    overrides: &[Override],
) -> Result<MultiAgentSpec, Diagnostics> {
    let path = file.path.as_path();
    // Read: the table, its keys, the overrides and `base_params` (every problem is reported
    // together, in this order, unless the base spec itself fails).
    let table = syntax::agents_table(file, root)?;
    let mut d = Diagnostics::default();
    syntax::check_keys(table, &mut d);
    let mut layer = syntax::split_overrides(overrides, &mut d);
    syntax::base_params(table, path, &mut layer.base, &mut d);
    // Resolve: the base env, then the nodes, edges and confs against its model.
    let base = resolve::base(file, root, table, &layer.base)?;
    let header = syntax::header(table, path, &mut d);
    let graph = resolve::graph(table, &base, &mut d);
    let categories = syntax::categories(table, &mut d);
    let confs = resolve::confs(table, &graph.nodes, &base.model, &mut d);
    let names: Vec<String> = confs.iter().map(|c| c.name.clone()).collect();
    let (conf, k) = syntax::choice(table, &layer, &names, &mut d);
    if !d.is_empty() {
        return Err(d);
    }
    // Graph: each agent's observation; a conf that is not declared is single-agent mode
    // (`syntax::choice` reported any other).
    let (agents, k) = match confs.iter().find(|c| c.name == conf) {
        Some(c) => {
            let agents = graph::agents(&c.parts, &graph, &categories, header.body_clip, k, &base);
            (agents, k)
        }
        None => (vec![graph::single_agent(&base)], 0),
    };
    Ok(MultiAgentSpec {
        base,
        spec_path: path.to_path_buf(),
        id: header.id,
        doc: header.doc,
        confs: names,
        conf,
        k,
        agents,
        parity: header.parity,
        first_element_bounds: header.first_element_bounds,
    })
}

/// A multi-agent spec shared between threads.
pub type SharedMultiAgentSpec = Arc<MultiAgentSpec>;
