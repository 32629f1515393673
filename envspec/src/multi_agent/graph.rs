//! The agent graph: each agent of the chosen conf observes the nodes within `k` hops of its own
//! (MaMuJoCo's `get_joints_at_kdist`), category by category, then the globals; its observation
//! elements are matched with the state's (the base env's observation).

use super::Agent;
use super::resolve::{Graph, Node, actuator_name};
use super::syntax::Categories;
use crate::ir::{Apply, ResolvedSpec, Segment};
use crate::selector::{Field, Selection};

/// One observation piece: source, minus, apply, clip.
type Item = (
    Selection,
    Option<Selection>,
    Option<Apply>,
    Option<(f64, f64)>,
);

/// MaMuJoCo's `agent_conf=None`: one agent with every action, observing the state.
pub(super) fn single_agent(base: &ResolvedSpec) -> Agent {
    let model = &base.model;
    Agent {
        name: "agent_0".into(),
        nodes: (0..model.nu()).map(|a| format!("action{a}")).collect(),
        actions: (0..model.nu()).collect(),
        actuators: (0..model.nu()).map(|a| actuator_name(model, a)).collect(),
        levels: vec![],
        obs_dim: base.obs_dim,
        observation: base.observation.clone(),
        state_index: Some((0..base.obs_dim).collect()),
    }
}

/// The agents of a conf (`parts`: each agent's nodes), observing at depth `k`.
pub(super) fn agents(
    parts: &[Vec<usize>],
    graph: &Graph,
    categories: &Categories,
    body_clip: Option<(f64, f64)>,
    k: usize,
    base: &ResolvedSpec,
) -> Vec<Agent> {
    let mut agents: Vec<Agent> = parts
        .iter()
        .enumerate()
        .map(|(i, part)| {
            build_agent(
                format!("agent_{i}"),
                part,
                graph,
                categories,
                body_clip,
                k,
                &base.model,
            )
        })
        .collect();
    for a in &mut agents {
        a.state_index = state_index(&a.observation, &base.observation);
    }
    agents
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

/// One agent of a conf: its nodes' actions, its `k` levels and its observation segments.
fn build_agent(
    name: String,
    part: &[usize],
    graph: &Graph,
    categories: &Categories,
    body_clip: Option<(f64, f64)>,
    k: usize,
    model: &crate::mjcf::ModelInfo,
) -> Agent {
    let Graph {
        nodes,
        edges,
        globals,
    } = graph;
    let (local_categories, global_categories) = (&categories.local, &categories.global);
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
                scale: None,
                indicator: None,
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
