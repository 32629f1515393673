//! The resolved IR of a task spec as data, for executors outside Rust (`envc.gpu`): a JSON
//! description of what the CPU core executes, and the compiled model as MuJoCo's binary format,
//! so a batched executor runs exactly the model envc compiles (spec additions included).
//!
//! The JSON describes every part the plain term kinds need. Parts it does not describe (legged
//! kernels, commands, PD actions, events, observation noise and delay, goal terms) are listed
//! under `not_exported`, so an executor refuses them instead of dropping them.

use envspec::Field;
use envspec::ir::{
    Apply, CheckKind, CmpOp, Distribution, Divisor, HealthCheck, InfoItem, InfoKind, ResetStep,
    ResolvedSpec, RewardTerm, Segment, SumNode, TermKind, Until,
};
use envspec::selector::Selection;
use pyo3::prelude::*;
use serde_json::{Value, json};

use crate::convert;
use crate::errors;

fn sel(s: &Selection) -> Value {
    json!({ "field": s.field.name(), "indices": s.indices, "text": s.text })
}

fn opt_sel(s: Option<&Selection>) -> Value {
    s.map(sel).unwrap_or(Value::Null)
}

/// A number; ±inf and NaN (which JSON lacks) as `{"f64": "inf"}` (Rust's spelling, which
/// Python's `float` reads).
fn num(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        json!({ "f64": x.to_string() })
    }
}

fn nums(x: &[f64]) -> Value {
    Value::Array(x.iter().copied().map(num).collect())
}

fn range(r: Option<(f64, f64)>) -> Value {
    r.map(|(a, b)| json!([num(a), num(b)]))
        .unwrap_or(Value::Null)
}

fn sum_node(n: &SumNode) -> Value {
    match n {
        SumNode::Term(i) => json!(i),
        SumNode::Sum(c) => Value::Array(c.iter().map(sum_node).collect()),
    }
}

fn op(o: CmpOp) -> &'static str {
    match o {
        CmpOp::Lt => "lt",
        CmpOp::Le => "le",
        CmpOp::Gt => "gt",
        CmpOp::Ge => "ge",
    }
}

/// Sizes of the compiled model that selections index into.
struct Sizes {
    nq: usize,
    nv: usize,
    nu: usize,
    nbody: usize,
    nsite: usize,
    ntendon: usize,
}

/// The JSON plan, in the order the GPU executor reads it. `not_exported` gathers, in this order,
/// what the plan leaves out: tables and fields, reward terms, termination, reset steps, info
/// items, then the parts run on the CPU core alone.
fn plan(spec: &ResolvedSpec, z: &Sizes, act: &envc::BoxSpace) -> Value {
    let mut not_exported = cpu_only_tables(spec);
    let observation: Vec<Value> = spec.observation.iter().map(segment).collect();
    let reward: Vec<Value> = spec
        .reward
        .iter()
        .map(|t| reward_term(t, &mut not_exported))
        .collect();
    let health: Vec<Value> = spec.health.iter().map(health_check).collect();
    for t in &spec.termination {
        not_exported.push(format!("[termination.{}] kind = \"goal_reached\"", t.name));
    }
    let reset: Vec<Value> = spec
        .reset
        .iter()
        .map(|r| reset_step(r, &mut not_exported))
        .collect();
    let info: Vec<Value> = spec
        .info
        .iter()
        .map(|i| info_item(i, &mut not_exported))
        .collect();
    cpu_only_parts(spec, &mut not_exported);
    json!({
        "id": spec.id,
        "frame_skip": spec.frame_skip,
        "max_episode_steps": spec.max_episode_steps,
        "timestep": spec.model.timestep,
        "dt": spec.dt(),
        "sizes": {
            "nq": z.nq, "nv": z.nv, "nu": z.nu, "nbody": z.nbody, "nsite": z.nsite,
            "ntendon": z.ntendon,
        },
        "obs_dim": spec.obs_dim,
        "act_low": nums(&act.low),
        "act_high": nums(&act.high),
        "observation": observation,
        "reward": reward,
        "reward_sum": sum_node(&spec.reward_sum),
        "health": health,
        "terminate_when_unhealthy": spec.terminate_when_unhealthy,
        "reset": reset,
        "info": info,
        "needs_rne_post_constraint": spec.needs_rne_post_constraint,
        "reads_mass_center": spec.reads(Field::MassCenter),
        "not_exported": not_exported,
    })
}

/// The tables, fields and observation options the plan does not describe.
fn cpu_only_tables(spec: &ResolvedSpec) -> Vec<String> {
    let mut not_exported: Vec<String> = vec![];
    if spec.model_edits.forward_before_observation {
        // The executors read the observation where the step leaves the data.
        not_exported.push("[physics] forward_before_observation = true".to_string());
    }
    // The manipulation tables and the fields only they compute run on the CPU core alone.
    let m = &spec.manipulation;
    for (on, table) in [
        (m.init.is_some(), "[init]"),
        (m.end_effector.is_some(), "[end_effector]"),
        (!m.hold.is_empty(), "[hold.*]"),
        (m.goal.is_some(), "[goal]"),
    ] {
        if on {
            not_exported.push(table.to_string());
        }
    }
    for seg in spec.observation.iter().filter(|s| s.scale.is_some()) {
        not_exported.push(format!("[observation.{}] scale", seg.name));
    }
    for f in [
        envspec::Field::Xquat,
        envspec::Field::SiteXmat,
        envspec::Field::SiteEuler,
        envspec::Field::BodyEuler,
        envspec::Field::SiteXvelp,
        envspec::Field::SiteXvelr,
        envspec::Field::Goal,
        envspec::Field::SensorData,
        envspec::Field::MocapPos,
        envspec::Field::MocapQuat,
        envspec::Field::Derived,
    ] {
        if spec.reads(f) {
            not_exported.push(format!("the field `{}`", f.name()));
        }
    }
    for s in spec.observation.iter().filter(|s| s.indicator.is_some()) {
        not_exported.push(format!("[observation.{}] indicator", s.name));
    }
    for t in spec.reward.iter() {
        if !t.only_if.is_empty() || !t.unless.is_empty() {
            not_exported.push(format!("[reward.{}] only_if / unless", t.name));
        }
    }
    not_exported
}

fn segment(s: &Segment) -> Value {
    json!({
        "name": s.name,
        "source": sel(&s.source),
        "minus": opt_sel(s.minus.as_ref()),
        "apply": s.apply.map(|a| match a { Apply::Sin => "sin", Apply::Cos => "cos", Apply::Positive => "positive" }),
        "clip": range(s.clip),
        "offset": s.offset,
        "len": s.len(),
    })
}

/// A reward term; a kind the plan does not describe goes to `not_exported`.
fn reward_term(t: &RewardTerm, not_exported: &mut Vec<String>) -> Value {
    let mut v = json!({
        "name": t.name,
        "kind": t.kind_name(),
        "weight": num(t.weight),
        "cost": t.cost,
        "info": t.info,
        "before": t.before,
        "paid_when_unhealthy": t.paid_when_unhealthy,
    });
    let o = v.as_object_mut().expect("an object");
    match &t.kind {
        TermKind::Velocity { source } => {
            o.insert("source".into(), sel(source));
        }
        TermKind::SumSquares {
            source,
            clip_input,
            clip,
        } => {
            o.insert("source".into(), sel(source));
            o.insert("clip_input".into(), range(*clip_input));
            o.insert("clip".into(), range(*clip));
        }
        TermKind::Norm { source, minus } => {
            o.insert("source".into(), sel(source));
            o.insert("minus".into(), opt_sel(minus.as_ref()));
        }
        TermKind::Quadratic {
            source,
            coefs,
            targets,
        } => {
            o.insert("source".into(), sel(source));
            o.insert("coefs".into(), nums(coefs));
            o.insert("targets".into(), nums(targets));
        }
        TermKind::Value { source, divide_by } => {
            o.insert("source".into(), sel(source));
            let d = divide_by.map(|d| match d {
                Divisor::Timestep => "timestep",
                Divisor::Dt => "dt",
            });
            o.insert("divide_by".into(), json!(d));
        }
        TermKind::Healthy | TermKind::Constant => {}
        TermKind::GoalSparse(_)
        | TermKind::GoalDense(_)
        | TermKind::GoalMissed(_)
        | TermKind::GoalDistance(_)
        | TermKind::GoalsMissed(_)
        | TermKind::PartsReached
        | TermKind::WeightedSquare { .. }
        | TermKind::Legged(_) => {
            not_exported.push(format!("[reward.{}] kind = \"{}\"", t.name, t.kind_name()));
        }
    }
    v
}

fn health_check(h: &HealthCheck) -> Value {
    let sources: Vec<Value> = h.sources.iter().map(sel).collect();
    match h.kind {
        CheckKind::Finite => json!({"name": h.name, "kind": "finite", "sources": sources}),
        CheckKind::InRange { lo, hi, closed } => json!({
            "name": h.name, "kind": "in_range", "sources": sources,
            "lo": num(lo), "hi": num(hi), "closed": closed,
        }),
        CheckKind::FailsIf { op: o, value } => json!({
            "name": h.name, "kind": "fails_if", "sources": sources,
            "op": op(o), "value": num(value),
        }),
    }
}

/// A reset step; what the plan does not describe of it goes to `not_exported`.
fn reset_step(r: &ResetStep, not_exported: &mut Vec<String>) -> Value {
    let dist = reset_distribution(r, not_exported);
    let until = r.resample_until.map(|u| match u {
        Until::NormBelow(x) => json!({"norm_below": num(x)}),
        Until::NormAbove(x) => json!({"norm_above": num(x)}),
        Until::MinDistance(x) => json!({"min_distance": num(x)}),
    });
    if r.around.is_some()
        || r.probability.is_some()
        || matches!(
            r.target.field,
            envspec::Field::Goal | envspec::Field::MocapPos | envspec::Field::MocapQuat
        )
    {
        not_exported.push(format!(
            "[reset.{}] around / probability / a goal or mocap target",
            r.name
        ));
    }
    json!({
        "name": r.name, "target": sel(&r.target), "dist": dist, "set": r.set,
        "resample_until": until,
    })
}

/// A reset step's distribution; `{"kind": "unsupported"}` for those the plan does not describe,
/// which go to `not_exported`.
fn reset_distribution(r: &ResetStep, not_exported: &mut Vec<String>) -> Value {
    match &r.dist {
        Distribution::Uniform { low, high } => {
            json!({"kind": "uniform", "low": nums(low), "high": nums(high)})
        }
        Distribution::Normal { scale } => json!({"kind": "normal", "scale": num(*scale)}),
        Distribution::Constant { value } => {
            json!({"kind": "constant", "value": num(*value)})
        }
        Distribution::Values { .. } => {
            not_exported.push(format!("[reset.{}] value = [per element]", r.name));
            json!({"kind": "unsupported"})
        }
        Distribution::Keyframe { name, .. } => {
            not_exported.push(format!("[reset.{}] kind = \"keyframe\" ({name})", r.name));
            json!({"kind": "unsupported"})
        }
        Distribution::RootPose { .. } => {
            not_exported.push(format!("[reset.{}] kind = \"root_pose\"", r.name));
            json!({"kind": "unsupported"})
        }
        Distribution::TerrainOrigin { .. } => {
            not_exported.push(format!("[reset.{}] kind = \"terrain_origin\"", r.name));
            json!({"kind": "unsupported"})
        }
        Distribution::Meet(_)
        | Distribution::Rotation(_)
        | Distribution::UnitQuaternion
        | Distribution::Settle(_) => {
            not_exported.push(format!(
                "[reset.{}] kind = \"{}\"",
                r.name,
                r.dist.kind_name()
            ));
            json!({"kind": "unsupported"})
        }
    }
}

/// An info item; a goal or condition kind goes to `not_exported`.
fn info_item(i: &InfoItem, not_exported: &mut Vec<String>) -> Value {
    let mut v = json!({
        "key": i.key, "len": i.len, "at_reset": i.at_reset, "unweighted": i.unweighted,
    });
    let o = v.as_object_mut().expect("an object");
    match &i.kind {
        InfoKind::Value { source, minus } => {
            o.insert("kind".into(), json!("value"));
            o.insert("source".into(), sel(source));
            o.insert("minus".into(), opt_sel(minus.as_ref()));
        }
        InfoKind::Norm { source } => {
            o.insert("kind".into(), json!("norm"));
            o.insert("source".into(), sel(source));
        }
        InfoKind::Velocity { source } => {
            o.insert("kind".into(), json!("velocity"));
            o.insert("source".into(), sel(source));
        }
        InfoKind::Term(t) => {
            o.insert("kind".into(), json!("term"));
            o.insert("term".into(), json!(t));
        }
        InfoKind::GoalReached(_) => {
            o.insert("kind".into(), json!("goal_reached"));
            not_exported.push(format!("[info.{}] kind = \"goal_reached\"", i.key));
        }
        InfoKind::GoalsReached(_) => {
            o.insert("kind".into(), json!("goals_reached"));
            not_exported.push(format!("[info.{}] kind = \"goals_reached\"", i.key));
        }
        InfoKind::Condition(_) => {
            o.insert("kind".into(), json!("condition"));
            not_exported.push(format!("[info.{}] kind = \"condition\"", i.key));
        }
        InfoKind::GoalParts(_) => {
            o.insert("kind".into(), json!("goal_parts"));
            not_exported.push(format!("[info.{}] kind = \"goal_parts\"", i.key));
        }
    }
    v
}

/// Commands, PD actions, observation noise and delay, action latency and events.
fn cpu_only_parts(spec: &ResolvedSpec, not_exported: &mut Vec<String>) {
    for c in &spec.commands {
        not_exported.push(format!("[commands.{}]", c.name));
    }
    if let Some(a) = &spec.actions {
        not_exported.push(format!("[actions] kind = \"{}\"", a.kind.name()));
    }
    for s in &spec.corruption.segments {
        if s.noise.is_some() {
            not_exported.push(format!("[observation.{}] noise", s.name));
        }
        if s.delay > 0 {
            not_exported.push(format!("[observation.{}] delay", s.name));
        }
    }
    if spec.corruption.action_latency > 0 {
        not_exported.push("[latency] action".into());
    }
    for e in &spec.events {
        not_exported.push(format!("[events.{}]", e.name));
    }
}

/// `(plan JSON, compiled model as MJB bytes)` of a task spec under overrides, opened through the
/// one door. Other kinds of spec are refused (E0602).
#[pyfunction]
#[pyo3(signature = (id_or_path, overrides = Vec::new()))]
pub fn gpu_plan(id_or_path: &str, overrides: Vec<(String, String)>) -> PyResult<(String, Vec<u8>)> {
    let o = convert::overrides(&overrides);
    let env = envc::open(id_or_path, &o).map_err(errors::env_error)?;
    let envc::AnyEnv::Task(env) = env else {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "error[E0602]: the GPU executor runs task specs only (not mazes or multi-agent specs)",
        ));
    };
    let m = env.model();
    let f = m.ffi();
    let sizes = Sizes {
        nq: f.nq as usize,
        nv: f.nv as usize,
        nu: f.nu as usize,
        nbody: f.nbody as usize,
        nsite: f.nsite as usize,
        ntendon: f.ntendon as usize,
    };
    let mut mjb = vec![0u8; m.size()];
    m.save_to_buffer(&mut mjb)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok((
        plan(env.spec(), &sizes, env.action_space()).to_string(),
        mjb,
    ))
}
