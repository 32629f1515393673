//! Spec + parameter values + model → the IR. Every problem is collected; nothing stops at the first.

use std::path::{Path, PathBuf};

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, suggest};
use crate::ir::*;
use crate::limits;
use crate::mjcf::{JointKind, ModelInfo};
use crate::params::{Origin, Override, Param, ParamValue, resolve_params};
use crate::selector::{self, Field, ParamIndex, Selection};
use crate::syntax::{Section, Spec};
use crate::value::{Val, ValKind};

mod actions;
mod actuators;
mod added;
mod commands;
mod conditions;
mod derived;
mod edits;
mod events;
mod geom_properties;
mod goal;
mod joint_properties;
mod keyframes;
mod legged;
mod terrain;
pub(crate) use commands::command_selection;
pub use keyframes::ROOT_POSE_KEYS;
mod manipulation;
mod manipulation_reset;
mod noise;
mod pairing;

struct Ctx<'a> {
    spec: &'a Spec,
    params: &'a [Param],
    model: &'a ModelInfo,
    d: Diagnostics,
    /// Length of the env-held goal vector, and where a `desired = "goal"` first fixed it.
    goal_dim: Option<(usize, Location)>,
    /// `[commands.*]`, resolved before anything that may select them (`command[...]`).
    commands: Vec<Command>,
    /// `[derived.*]` resolved so far (`derived[...]` sees the tables above it).
    derived: Vec<crate::derived::Derived>,
    /// `[derived.*]` tables that failed to resolve (their readers report nothing more).
    derived_failed: Vec<String>,
    /// `[init] record`s: name, offset in the flat record vector, length (`around`).
    records: Vec<(String, usize, usize)>,
    /// `timestep × frame_skip` (a segment's `scale = "dt"`).
    dt: f64,
    /// `frame_skip` (`[init] settle_steps` is bounded in physics steps).
    frame_skip: u32,
}

/// Resolve a checked spec with parameter overrides against its model.
pub fn resolve(spec: &Spec, overrides: &[Override]) -> Result<ResolvedSpec, Diagnostics> {
    let params = resolve_params(spec, overrides)?;
    let param = |n: &str| params.iter().find(|p| p.name == n);

    let xml = param("xml_file").expect("checked by syntax");
    let (model_path, mut model) = load_model(spec, xml)?;

    // `[bodies]` ... add elements to the model, which the other model edits may name (a
    // `[joint_properties]` row over an added joint): resolve them first.
    let mut cx = Ctx {
        spec,
        params: &params,
        model: &model,
        d: Diagnostics::default(),
        goal_dim: None,
        commands: vec![],
        derived: vec![],
        derived_failed: vec![],
        records: vec![],
        dt: 0.0,
        frame_skip: 1,
    };
    let added = cx.added_elements();
    let d = cx.d;
    let mut with_added = model.clone();
    added::apply(&added, &mut with_added);
    // `[actuators]` / `[physics]` change the model itself: resolve them first.
    let mut cx = Ctx {
        spec,
        params: &params,
        model: &with_added,
        d,
        goal_dim: None,
        commands: vec![],
        derived: vec![],
        derived_failed: vec![],
        records: vec![],
        dt: 0.0,
        frame_skip: 1,
    };
    let model_edits = cx.model_edits(added);
    let d = cx.d;
    edits::apply(&model_edits, &mut model);
    let mut cx = Ctx {
        spec,
        params: &params,
        model: &model,
        d,
        goal_dim: None,
        commands: vec![],
        derived: vec![],
        derived_failed: vec![],
        records: vec![],
        dt: 0.0,
        frame_skip: 1,
    };

    let frame_skip = match param("frame_skip").map(|p| &p.value) {
        Some(ParamValue::Int(n)) if (1..=limits::MAX_FRAME_SKIP).contains(n) => *n as u32,
        Some(ParamValue::Int(n)) if *n > limits::MAX_FRAME_SKIP => {
            cx.over_limit("frame_skip", *n, limits::MAX_FRAME_SKIP);
            1
        }
        _ => {
            cx.d.push(cx.param_error("frame_skip", "frame_skip must be a positive integer"));
            1
        }
    };
    // 0 means no time limit (the reference's `max_episode_steps=None`).
    let max_episode_steps = match param("max_episode_steps").map(|p| &p.value) {
        Some(ParamValue::Int(n)) if *n > limits::MAX_EPISODE_STEPS => {
            cx.over_limit("max_episode_steps", *n, limits::MAX_EPISODE_STEPS);
            None
        }
        Some(ParamValue::Int(n)) if *n < 0 => {
            cx.d.push(cx.param_error(
                "max_episode_steps",
                "max_episode_steps must be ≥ 0 (0: no time limit)",
            ));
            None
        }
        Some(ParamValue::Int(n)) if *n > 0 => Some(*n as u64),
        _ => None,
    };

    cx.dt = model.timestep * frame_skip as f64;
    cx.frame_skip = frame_skip;
    let commands = cx.commands(model.timestep * frame_skip as f64);
    cx.commands = commands.clone();
    let command_dim = commands.iter().map(Command::len).sum();
    let derived = cx.derived();
    let derived_dim = derived.iter().map(|d| d.len).sum();
    let actions = cx.actions();
    let manipulation = cx.manipulation();

    let observation = cx.observation();
    let corruption = cx.corruption(&observation);
    let obs_dim = observation.iter().map(Segment::len).sum();
    let terms = cx.reward_terms();
    let all_terms: Vec<RewardTerm> = terms.iter().map(|(t, _)| t.clone()).collect();
    // `sum` names every term, switched on or not; switched-off terms are then pruned from it.
    let full_sum = cx.reward_sum(&all_terms);
    let off: Vec<String> = terms
        .iter()
        .filter(|(_, on)| !on)
        .map(|(t, _)| t.name.clone())
        .collect();
    let (reward, reward_sum) = prune_terms(terms, full_sum);
    let terminate_when_unhealthy = match &spec.health_terminate {
        Some(v) => cx.flag(v, "health.terminate").unwrap_or(true),
        None => true,
    };
    let health = cx.health();
    let termination = cx.terminations();
    let reset = cx.reset(model_edits.terrain.as_ref());
    let mut info = cx.info(&reward, &off);
    for (i, t) in reward.iter().enumerate() {
        if let Some(key) = &t.info {
            let loc = spec
                .reward
                .iter()
                .find(|s| s.name == t.name)
                .and_then(|s| s.get("info"))
                .map(|v| v.loc.clone());
            info.push((
                InfoItem {
                    key: key.clone(),
                    doc: t.doc.clone(),
                    kind: InfoKind::Term(i),
                    len: 1,
                    at_reset: false,
                    unweighted: false,
                    float32: false,
                    boolean: false,
                },
                loc,
            ));
        }
    }
    cx.check_info_keys(&info);
    let info: Vec<InfoItem> = info.into_iter().map(|(i, _)| i).collect();

    let events = cx.events();
    let goal_dim = cx.goal_dim.as_ref().map_or(0, |(n, _)| *n);
    let Ctx { d, .. } = cx;
    let mut resolved = ResolvedSpec {
        id: spec.id.clone(),
        description: spec.description.clone(),
        spec_path: spec.path().to_path_buf(),
        inputs: vec![],
        reward_threshold: spec.reward_threshold,
        entry_point: spec.entry_point.clone(),
        params: params.clone(),
        model_path,
        model: model.clone(),
        frame_skip,
        max_episode_steps,
        observation,
        obs_dim,
        reward,
        reward_sum,
        health,
        terminate_when_unhealthy,
        termination,
        goal_dim,
        reset,
        info,
        needs_rne_post_constraint: false,
        model_edits,
        commands,
        command_dim,
        derived,
        derived_dim,
        actions,
        corruption,
        events,
        warnings: vec![],
        manipulation,
    };
    resolved.warnings = pairing::warnings(spec, &resolved);
    resolved.warnings.extend(added::falling(spec, &resolved));
    resolved.warnings.extend(far_draws(spec, &resolved));
    let rne = resolved
        .sources()
        .any(|s| s.field.needs_rne_post_constraint());
    resolved.needs_rne_post_constraint = rne;
    let mut d = d;
    if spec.actions.is_none() && resolved.reads(Field::DefaultPose) {
        d.push(
            Diagnostic::new(
                Code::E0132,
                "`default_pose` is read but the spec has no [actions] table",
            )
            .at(spec.id_loc.clone())
            .label("expected an [actions] table with default_pose, or another selector"),
        );
    }
    let d = blame_overrides(d, &params);
    d.into_result(resolved)
}

/// The model `xml_file` names (`${NAME}` expanded; a relative default against the spec's
/// directory), read for its names and numbering.
fn load_model(spec: &Spec, xml: &Param) -> Result<(PathBuf, ModelInfo), Diagnostics> {
    // `${NAME}`: an environment variable (a model inside an installed package, say).
    let expanded = match &xml.value {
        ParamValue::Str(s) => crate::path::expand_env(s).map_err(|name| {
            let at = match &xml.origin {
                Origin::Default(loc) => Some(loc.clone()),
                Origin::Override(_) => None,
            };
            Diagnostics::from(
                Diagnostic::new(
                    Code::E0301,
                    format!("xml_file names ${{{name}}}, an environment variable that is not set"),
                )
                .at_opt(at)
                .label("expected a path; ${NAME} reads the variable NAME")
                .help(format!("set it, e.g. `export {name}=/path/to/models`")),
            )
        })?,
        _ => unreachable!("xml_file is a path parameter"),
    };
    let model_path = match &xml.origin {
        Origin::Default(_) => crate::path::normalize(&spec.dir().join(&expanded)),
        Origin::Override(_) => PathBuf::from(&expanded),
    };
    let model = ModelInfo::from_file(&model_path).map_err(|e| {
        let at = match &xml.origin {
            Origin::Default(loc) => Some(loc.clone()),
            Origin::Override(_) => None,
        };
        let help = format!("xml_file resolved to {}", model_path.display());
        // A problem inside the model keeps its own location; else point at `xml_file`.
        let e = if e.location.is_some() {
            e
        } else {
            e.at_opt(at)
        };
        Diagnostics::from(e.help(help))
    })?;
    Ok((model_path, model))
}

/// W0171: a reset step that puts a position (a slide joint, a free joint's x, y, z, the goal
/// vector) further than `limits::PLAUSIBLE_DISTANCE` from where it is drawn: centimetres written
/// for metres, most likely.
fn far_draws(spec: &Spec, r: &ResolvedSpec) -> Vec<Diagnostic> {
    let positional = |s: &Selection, k: usize| -> bool {
        match s.field {
            Field::Goal => true,
            Field::Qpos => r.model.joints.iter().any(|j| {
                let i = s.indices[k];
                match j.kind {
                    JointKind::Slide => j.qposadr == i,
                    JointKind::Free => (j.qposadr..j.qposadr + 3).contains(&i),
                    _ => false,
                }
            }),
            _ => false,
        }
    };
    let mut out = vec![];
    for step in &r.reset {
        let widest = (0..step.target.len())
            .filter(|&k| positional(&step.target, k))
            .map(|k| match &step.dist {
                Distribution::Uniform { low, high } => low[k].abs().max(high[k].abs()),
                Distribution::Values { values } => values[k].abs(),
                Distribution::Constant { value } if step.around.is_some() || !step.set => {
                    value.abs()
                }
                _ => 0.0,
            })
            .fold(0.0, f64::max);
        if widest > limits::PLAUSIBLE_DISTANCE {
            let at = spec
                .reset
                .iter()
                .find(|s| s.name == step.name)
                .map(|s| s.name_loc.clone());
            out.push(
                Diagnostic::new(
                    Code::W0171,
                    format!(
                        "[reset.{}] moves a position by up to {widest} m (more than {} m)",
                        step.name,
                        limits::PLAUSIBLE_DISTANCE
                    ),
                )
                .at_opt(at)
                .label("a draw this far puts the body (or goal) far outside a robot's workspace")
                .help("MuJoCo lengths are metres: 15 cm is 0.15"),
            );
        }
    }
    out
}

/// An error about a value that came from an override is the override's: its message names the
/// override first (`--set name=value` on the command line, the keyword `name=value` in Python),
/// and the spec line that uses the parameter stays as context.
fn blame_overrides(d: Diagnostics, params: &[Param]) -> Diagnostics {
    let mut out = Diagnostics::default();
    for mut e in d.0 {
        let used = e.location.as_ref().map(|l| {
            l.file.text[l.span.clone()]
                .trim()
                .trim_matches('"')
                .trim_start_matches(['-', '+'])
                .to_string()
        });
        let over = used.and_then(|u| {
            params
                .iter()
                .find(|p| matches!(p.origin, Origin::Override(_)) && p.name == u)
        });
        if let Some(p) = over
            && !e.message.starts_with("override ")
        {
            e.message = format!(
                "override `{}={}` (`--set {0}=…`, or the keyword `{0}=…` in Python): {}",
                p.name, p.value, e.message
            );
            let context = "the spec uses the parameter here; its value comes from the override";
            e.label = Some(match e.label.take() {
                Some(l) => format!("{l} ({context})"),
                None => context.to_string(),
            });
        }
        out.push(e);
    }
    out
}

/// Drop the terms switched off by `when`: from the term list (renumbering the rest) and from the
/// sum, where a list left empty disappears from its parent (the top level stays, summing to 0).
/// Why no draw of `dist` (n values) can meet `until`, if that is certain: a norm below a bound ≤ 0,
/// a uniform box whose nearest point is not below the bound, or whose farthest is not above it.
fn unmet(dist: &Distribution, n: usize, until: Until) -> Option<String> {
    let norm = |f: &dyn Fn(usize) -> f64| (0..n).map(|i| f(i) * f(i)).sum::<f64>().sqrt();
    // The smallest and largest norm a draw can have.
    let (lo, hi) = match dist {
        Distribution::Uniform { low, high } => (
            norm(&|i| {
                if low[i] <= 0.0 && 0.0 <= high[i] {
                    0.0
                } else {
                    low[i].abs().min(high[i].abs())
                }
            }),
            norm(&|i| low[i].abs().max(high[i].abs())),
        ),
        Distribution::Normal { scale } if *scale == 0.0 => (0.0, 0.0),
        Distribution::Normal { .. } => (0.0, f64::INFINITY),
        Distribution::Constant { value } => {
            let v = norm(&|_| *value);
            (v, v)
        }
        Distribution::Values { values } => {
            let v = norm(&|i| values[i]);
            (v, v)
        }
        // (no `resample_until` on these kinds)
        Distribution::Keyframe { .. }
        | Distribution::RootPose { .. }
        | Distribution::Meet(_)
        | Distribution::Rotation(_)
        | Distribution::UnitQuaternion
        | Distribution::Settle(_)
        | Distribution::TerrainOrigin { .. } => (0.0, f64::INFINITY),
    };
    match until {
        Until::NormBelow(x) if x <= 0.0 => Some(format!("a norm is never below {x}")),
        Until::NormBelow(x) if lo >= x => Some(format!(
            "the smallest norm a draw can have is {lo}, not below {x}"
        )),
        Until::NormAbove(x) if hi <= x => Some(format!(
            "the largest norm a draw can have is {hi}, not above {x}"
        )),
        Until::MinDistance(x) if hi < x => Some(format!(
            "the largest distance a draw can have is {hi}, not {x} or more"
        )),
        _ => None,
    }
}

fn prune_terms(terms: Vec<(RewardTerm, bool)>, sum: SumNode) -> (Vec<RewardTerm>, SumNode) {
    let mut map = Vec::with_capacity(terms.len());
    let mut kept = vec![];
    for (t, on) in terms {
        map.push(on.then_some(kept.len()));
        if on {
            kept.push(t);
        }
    }
    fn prune(n: SumNode, map: &[Option<usize>]) -> Option<SumNode> {
        match n {
            SumNode::Term(i) => map.get(i).copied().flatten().map(SumNode::Term),
            SumNode::Sum(c) => {
                let c: Vec<SumNode> = c.into_iter().filter_map(|x| prune(x, map)).collect();
                (!c.is_empty()).then_some(SumNode::Sum(c))
            }
        }
    }
    let sum = prune(sum, &map).unwrap_or(SumNode::Sum(vec![]));
    (kept, sum)
}

/// Load, check and resolve a spec file in one call.
pub fn load(path: &Path, overrides: &[Override]) -> Result<ResolvedSpec, Diagnostics> {
    let (spec, inputs) = crate::source::recorded(|| resolve(&Spec::load(path)?, overrides));
    let mut spec = spec?;
    spec.inputs = inputs;
    Ok(spec)
}

impl Ctx<'_> {
    fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }

    fn param_error(&self, name: &str, msg: &str) -> Diagnostic {
        let loc = self.param(name).and_then(|p| match &p.origin {
            Origin::Default(l) => Some(l.clone()),
            Origin::Override(_) => None,
        });
        let help = self.param(name).and_then(|p| match &p.origin {
            Origin::Override(_) => Some(format!(
                "the value {} comes from an override of `{name}`",
                p.value
            )),
            Origin::Default(_) => None,
        });
        Diagnostic::new(Code::E0105, msg.to_string())
            .at_opt(loc)
            .label("invalid value")
            .help_opt(help)
    }

    /// E0110: an integer parameter above its limit in `envspec::limits`.
    fn over_limit(&mut self, name: &str, n: i64, limit: i64) {
        let mut e = self.param_error(
            name,
            &format!("{name} {n} is beyond envc's limit of {limit}"),
        );
        e.code = Code::E0110;
        self.d.push(e);
    }

    /// E0110 when `x` (read from `v`) is beyond `limit` in magnitude; `Some(x)` otherwise.
    fn within(&mut self, v: &Val, x: f64, what: &str, limit: f64) -> Option<f64> {
        if x.abs() <= limit {
            return Some(x);
        }
        self.d.push(
            Diagnostic::new(
                Code::E0110,
                format!("{what} of {x:e} is beyond envc's limit of ±{limit:e}"),
            )
            .at(v.loc.clone())
            .label(format!("expected a value within ±{limit:e}"))
            .help("beyond it the simulation diverges or overflows; see docs/limits.md"),
        );
        None
    }

    /// A finite number within `±limit` (E0105 / E0110 otherwise), as `[actions]` bounds its own.
    fn num_within(&mut self, v: &Val, what: &str, limit: f64) -> Option<f64> {
        let x = self.num(v, what)?;
        self.within(v, x, what, limit)
    }

    fn unknown_param(&self, name: &str, loc: &Location, expected: &str) -> Diagnostic {
        Diagnostic::new(
            Code::E0201,
            format!("`{name}` is not a parameter of this spec"),
        )
        .at(loc.clone())
        .label(format!(
            "expected {expected} or the name of a parameter in [params]"
        ))
        .help_opt(suggest(name, self.params.iter().map(|p| p.name.as_str())))
    }

    /// A parameter looked up by a reference in the spec.
    fn lookup(&mut self, name: &str, loc: &Location, expected: &str) -> Option<ParamValue> {
        match self.param(name) {
            Some(p) => Some(p.value.clone()),
            None => {
                let e = self.unknown_param(name, loc, expected);
                self.d.push(e);
                None
            }
        }
    }

    fn wrong_param_type(&mut self, name: &str, loc: &Location, expected: &str, got: &ParamValue) {
        self.d.push(
            Diagnostic::new(
                Code::E0102,
                format!("parameter `{name}` is {got}, not {expected}"),
            )
            .at(loc.clone())
            .label(format!("expected {expected}")),
        );
    }

    /// A finite number, or the name of a numeric parameter holding one. NaN and ±inf are refused
    /// here (a weight, gain, scale or size of `inf` makes every reward or state non-finite);
    /// range bounds, which may be infinite, go through [`Ctx::range`].
    fn num(&mut self, v: &Val, what: &str) -> Option<f64> {
        let x = self.num_or_inf(v, what)?;
        if x.is_finite() {
            return Some(x);
        }
        let via = match &v.kind {
            ValKind::Str(name) => format!(" (the value of parameter `{name}`)"),
            _ => String::new(),
        };
        self.d.push(
            Diagnostic::new(
                Code::E0105,
                format!(
                    "{what} is {}{via}; it must be a finite number",
                    crate::value::format_float(x)
                ),
            )
            .at(v.loc.clone())
            .label("expected a finite number"),
        );
        None
    }

    /// A number, or the name of a numeric parameter; ±inf allowed, NaN refused.
    fn num_or_inf(&mut self, v: &Val, what: &str) -> Option<f64> {
        let x = self.any_num(v, what)?;
        if x.is_nan() {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{what} is NaN"))
                    .at(v.loc.clone())
                    .label("expected a number (NaN compares false with everything)"),
            );
            return None;
        }
        Some(x)
    }

    fn any_num(&mut self, v: &Val, what: &str) -> Option<f64> {
        match &v.kind {
            ValKind::Int(i) => Some(*i as f64),
            ValKind::Float(x) => Some(*x),
            // `"-name"`: the parameter's value, negated (exactly).
            ValKind::Str(text) => {
                let (sign, name) = match text.strip_prefix('-') {
                    Some(n) if self.param(n.trim()).is_some() => (-1.0, n.trim()),
                    _ => (1.0, text.as_str()),
                };
                match self.lookup(name, &v.loc, "a number")? {
                    ParamValue::Float(x) => Some(sign * x),
                    ParamValue::Int(i) => Some(sign * i as f64),
                    other => {
                        self.wrong_param_type(name, &v.loc, "a number", &other);
                        None
                    }
                }
            }
            _ => {
                self.d
                    .push(v.type_error(what, "a number or a parameter name"));
                None
            }
        }
    }

    /// `[low, high]`, or the name of a range parameter.
    fn range(&mut self, v: &Val, what: &str) -> Option<(f64, f64)> {
        let r = match &v.kind {
            ValKind::Array(a) if a.len() == 2 => {
                Some((self.num_or_inf(&a[0], what)?, self.num_or_inf(&a[1], what)?))
            }
            ValKind::Str(name) => match self.lookup(name, &v.loc, "a range")? {
                ParamValue::Range(a, b) => Some((a, b)),
                other => {
                    self.wrong_param_type(name, &v.loc, "a range [low, high]", &other);
                    None
                }
            },
            _ => {
                self.d
                    .push(v.type_error(what, "[low, high] or a parameter name"));
                None
            }
        }?;
        if r.0 > r.1 {
            self.d.push(
                Diagnostic::new(
                    Code::E0105,
                    format!("{what}: low {} is above high {}", r.0, r.1),
                )
                .at(v.loc.clone())
                .label("expected low <= high"),
            );
        }
        Some(r)
    }

    /// `true`/`false`, or a bool parameter's name, optionally negated with `!`.
    fn flag(&mut self, v: &Val, what: &str) -> Option<bool> {
        match &v.kind {
            ValKind::Bool(b) => Some(*b),
            // `a and b`: every part holds (each part is one of the forms below).
            ValKind::Str(s) if s.contains(" and ") => {
                let mut all = Some(true);
                for part in s.split(" and ") {
                    let part = Val {
                        kind: ValKind::Str(part.trim().to_string()),
                        loc: v.loc.clone(),
                    };
                    all = match (all, self.flag(&part, what)) {
                        (Some(a), Some(b)) => Some(a && b),
                        _ => None,
                    };
                }
                all
            }
            // `name == "value"` / `name != "value"`: a string parameter compared with a literal
            // (`when = "reward_type == 'dense'"`).
            ValKind::Str(s) if s.contains("==") || s.contains("!=") => {
                let (name, lit, eq) = match s.split_once("==") {
                    Some((n, l)) => (n, l, true),
                    None => {
                        let (n, l) = s.split_once("!=").unwrap_or((s, ""));
                        (n, l, false)
                    }
                };
                let lit = lit.trim().trim_matches(|c| c == '\'' || c == '"');
                match self.lookup(name.trim(), &v.loc, "a string parameter")? {
                    ParamValue::Str(x) => Some((x == lit) == eq),
                    other => {
                        self.wrong_param_type(name.trim(), &v.loc, "a string", &other);
                        None
                    }
                }
            }
            ValKind::Str(s) => {
                let (neg, name) = match s.strip_prefix('!') {
                    Some(n) => (true, n.trim()),
                    None => (false, s.as_str()),
                };
                match self.lookup(name, &v.loc, "true, false")? {
                    ParamValue::Bool(b) => Some(b != neg),
                    other => {
                        self.wrong_param_type(name, &v.loc, "a bool", &other);
                        None
                    }
                }
            }
            _ => {
                self.d
                    .push(v.type_error(what, "true, false or a bool parameter name"));
                None
            }
        }
    }

    fn selection(&mut self, v: &Val, what: &str) -> Option<Selection> {
        let Some(text) = v.as_str() else {
            self.d
                .push(v.type_error(what, "a selector string such as \"qpos[2:]\""));
            return None;
        };
        if text.trim().starts_with("goal")
            && !text.trim()["goal".len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
        {
            return self.goal_selection(text, &v.loc);
        }
        if derived::is_derived(text) {
            return self.derived_selection(text, &v.loc);
        }
        if text.trim().starts_with("command")
            && !text.trim()["command".len()..]
                .starts_with(|c: char| c.is_alphanumeric() || c == '_')
        {
            return self.command_selection(text, &v.loc);
        }
        let params = self.params;
        let lookup = |name: &str| -> Result<ParamIndex, Diagnostic> {
            match params.iter().find(|p| p.name == name).map(|p| &p.value) {
                Some(ParamValue::Int(i)) => Ok(ParamIndex::Int(*i)),
                Some(ParamValue::Str(s)) => Ok(ParamIndex::Name(s.clone())),
                Some(other) => Err(Diagnostic::new(
                    Code::E0102,
                    format!("parameter `{name}` is {other}, not an index or name"),
                )
                .at(v.loc.clone())
                .label("expected an integer or string parameter")),
                None => Err(self.unknown_param(name, &v.loc, "an index")),
            }
        };
        match selector::resolve(text, &v.loc, self.model, &lookup) {
            Ok(s) => Some(s),
            Err(e) => {
                self.d.push(e);
                None
            }
        }
    }

    fn sel_key(&mut self, s: &Section, key: &str) -> Option<Selection> {
        let v = s.get(key)?;
        self.selection(v, key)
    }

    fn same_len(&mut self, a: &Selection, b: &Selection, loc: &Location) -> bool {
        if a.len() != b.len() {
            self.d.push(
                Diagnostic::new(
                    Code::E0403,
                    format!(
                        "`{}` has {} elements but `{}` has {}",
                        a.text,
                        a.len(),
                        b.text,
                        b.len()
                    ),
                )
                .at(loc.clone())
                .label("expected selections of equal length"),
            );
            return false;
        }
        true
    }

    fn scalar(&mut self, s: &Selection, loc: &Location, what: &str) -> bool {
        if s.len() != 1 {
            self.d.push(
                Diagnostic::new(
                    Code::E0403,
                    format!("{what} needs one number, `{}` selects {}", s.text, s.len()),
                )
                .at(loc.clone())
                .label("expected a selector of exactly one element, e.g. `qpos[0]`"),
            );
            return false;
        }
        true
    }

    fn observation(&mut self) -> Vec<Segment> {
        let mut out = vec![];
        let mut offset = 0;
        for s in &self.spec.observation {
            // A segment switched off by `when` is still checked: an override must not reveal errors.
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let Some(mut source) = self.sel_key(s, "source") else {
                continue;
            };
            let mut minus = self.sel_key(s, "minus");
            if let Some(m) = &minus
                && !self.same_len(
                    &source,
                    m,
                    &s.get("minus").expect("`minus` was read just above").loc,
                )
            {
                minus = None;
            }
            if let Some(df) = s.get("drop_first")
                && let Some(n) = self.drop_first(df)
            {
                source.drop_first(n);
                if let Some(m) = &mut minus {
                    m.drop_first(n);
                }
            }
            let apply = match s.get("apply") {
                None => None,
                Some(v) => match v.as_str() {
                    Some("sin") => Some(Apply::Sin),
                    Some("cos") => Some(Apply::Cos),
                    Some("positive") => Some(Apply::Positive),
                    _ => {
                        self.d.push(
                            Diagnostic::new(Code::E0104, "unknown function in `apply`")
                                .at(v.loc.clone())
                                .label("expected \"sin\", \"cos\" or \"positive\""),
                        );
                        None
                    }
                },
            };
            let clip = s.get("clip").and_then(|v| self.range(v, "clip"));
            let scale = s.get("scale").and_then(|v| match v.as_str() {
                Some("dt") => Some(self.dt),
                _ => {
                    let x = self.num(v, "scale")?;
                    self.within(v, x, "scale", limits::MAX_MAGNITUDE)
                }
            });
            let indicator = s.get("indicator").and_then(|v| self.indicator(v));
            let seg = Segment {
                name: s.name.clone(),
                doc: s.doc(),
                source,
                minus,
                apply,
                clip,
                scale,
                indicator,
                offset,
            };
            if !enabled {
                continue;
            }
            offset += seg.len();
            out.push(seg);
        }
        out
    }

    /// `drop_first = 2` or `drop_first = { count = 2, when = "flag" }`.
    fn drop_first(&mut self, v: &Val) -> Option<usize> {
        match &v.kind {
            ValKind::Int(n) if *n >= 0 => Some(*n as usize),
            ValKind::Table(t) => {
                for e in t {
                    if e.key != "count" && e.key != "when" {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0101,
                                format!("unknown key `{}` in drop_first", e.key),
                            )
                            .at(e.key_loc.clone())
                            .label("expected count, when")
                            .help_opt(suggest(&e.key, ["count", "when"])),
                        );
                    }
                }
                let count = t.iter().find(|e| e.key == "count");
                let Some(count) = count else {
                    self.d.push(
                        Diagnostic::new(Code::E0103, "missing `count` in drop_first")
                            .at(v.loc.clone())
                            .label("expected count = N"),
                    );
                    return None;
                };
                let n = match count.value.kind {
                    ValKind::Int(n) if n >= 0 => n as usize,
                    _ => {
                        self.d.push(
                            count
                                .value
                                .type_error("drop_first.count", "a non-negative integer"),
                        );
                        return None;
                    }
                };
                let on = match t.iter().find(|e| e.key == "when") {
                    Some(w) => self.flag(&w.value, "drop_first.when")?,
                    None => true,
                };
                Some(if on { n } else { 0 })
            }
            _ => {
                self.d
                    .push(v.type_error("drop_first", "a count or { count, when }"));
                None
            }
        }
    }

    /// Every term that resolves, with whether its `when` switches it on.
    fn reward_terms(&mut self) -> Vec<(RewardTerm, bool)> {
        let mut out = vec![];
        for s in &self.spec.reward {
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let before = match s.get("at") {
                None => false,
                Some(v) => match v.as_str() {
                    Some("after") => false,
                    Some("before")
                        if matches!(
                            s.kind(""),
                            "velocity" | "healthy" | "feet_air_time" | "feet_slip"
                        ) =>
                    {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0104,
                                format!(
                                    "a `{}` term cannot be evaluated before the step",
                                    s.kind("")
                                ),
                            )
                            .at(v.loc.clone())
                            .label("expected \"after\" (velocity, healthy and feet terms need the post-step state)"),
                        );
                        false
                    }
                    Some("before") => true,
                    _ => {
                        self.d.push(
                            Diagnostic::new(Code::E0104, "unknown `at`")
                                .at(v.loc.clone())
                                .label("expected \"after\" (the post-step state) or \"before\" (the state before the action)")
                                .help_opt(v.as_str().and_then(|x| suggest(x, ["after", "before"]))),
                        );
                        false
                    }
                },
            };
            let paid_when_unhealthy = match s.get("paid_when_unhealthy") {
                Some(v) => self.flag(v, "paid_when_unhealthy").unwrap_or(false),
                None => false,
            };
            let weight = match s.get("weight") {
                Some(w) => self.num(w, "weight").unwrap_or(f64::NAN),
                None => 1.0,
            };
            let cost = match s.get("cost") {
                Some(v) => self.flag(v, "cost").unwrap_or(false),
                None => false,
            };
            let info = match s.get("info") {
                Some(v) => match v.as_str() {
                    Some(k) => Some(k.to_string()),
                    None => {
                        self.d.push(v.type_error("info", "a key name"));
                        None
                    }
                },
                None => None,
            };
            let kind = match s.kind("") {
                "velocity" => self.need_sel(s, "source").and_then(|src| {
                    self.scalar(
                        &src,
                        &s.get("source").expect("`source` was read just above").loc,
                        "a velocity",
                    )
                    .then_some(TermKind::Velocity { source: src })
                }),
                "healthy" => Some(TermKind::Healthy),
                "sum_squares" => self
                    .need_sel(s, "source")
                    .map(|source| TermKind::SumSquares {
                        source,
                        clip_input: s
                            .get("clip_input")
                            .and_then(|v| self.range(v, "clip_input")),
                        clip: s.get("clip").and_then(|v| self.range(v, "clip")),
                    }),
                "norm" => self.need_sel(s, "source").map(|source| {
                    let minus = self.sel_key(s, "minus").filter(|m| {
                        self.same_len(
                            &source,
                            m,
                            &s.get("minus").expect("`minus` was read just above").loc,
                        )
                    });
                    TermKind::Norm { source, minus }
                }),
                "quadratic" => self.need_sel(s, "source").and_then(|source| {
                    let n = source.len();
                    let coefs = self.num_list(s, "coefs", n, 1.0)?;
                    let targets = self.num_list(s, "targets", n, 0.0)?;
                    Some(TermKind::Quadratic {
                        source,
                        coefs,
                        targets,
                    })
                }),
                "value" => self.need_sel(s, "source").and_then(|source| {
                    if !self.scalar(
                        &source,
                        &s.get("source").expect("`source` was read just above").loc,
                        "a value term",
                    ) {
                        return None;
                    }
                    let divide_by = match s.get("divide_by") {
                        None => None,
                        Some(v) => match v.as_str() {
                            Some("timestep") => Some(Divisor::Timestep),
                            Some("dt") => Some(Divisor::Dt),
                            _ => {
                                self.d.push(
                                    Diagnostic::new(Code::E0104, "unknown divisor")
                                        .at(v.loc.clone())
                                        .label("expected \"timestep\" or \"dt\""),
                                );
                                None
                            }
                        },
                    };
                    Some(TermKind::Value { source, divide_by })
                }),
                "constant" => Some(TermKind::Constant),
                "weighted_square" => self.need_sel(s, "source").and_then(|source| {
                    let loc = &s.get("source").expect("`source` was read just above").loc;
                    if !self.scalar(&source, loc, "a weighted_square term") {
                        return None;
                    }
                    let target = match s.get("target") {
                        Some(v) => self.num(v, "target")?,
                        None => 0.0,
                    };
                    Some(TermKind::WeightedSquare { source, target })
                }),
                "goal_sparse" => self
                    .goal_check(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                    .map(TermKind::GoalSparse),
                "goal_dense" => self
                    .goal_distance(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                    .map(TermKind::GoalDense),
                "goal_missed" => self
                    .goal_check(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                    .map(TermKind::GoalMissed),
                "goal_distance" => self
                    .goal_distance(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                    .map(TermKind::GoalDistance),
                "goals_missed" => self
                    .goal_checks(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                    .map(TermKind::GoalsMissed),
                k if LeggedTerm::KINDS.contains(&k) => self.legged_term(s),
                _ => None, // reported by the syntax check
            };
            let only_if = match s.get("only_if") {
                Some(v) => self
                    .conditions(v, &format!("[reward.{}] only_if", s.name))
                    .unwrap_or_default(),
                None => vec![],
            };
            let unless = match s.get("unless") {
                Some(v) => self
                    .conditions(v, &format!("[reward.{}] unless", s.name))
                    .unwrap_or_default(),
                None => vec![],
            };
            if let Some(kind) = kind {
                out.push((
                    RewardTerm {
                        name: s.name.clone(),
                        doc: s.doc(),
                        kind,
                        weight,
                        cost,
                        info,
                        before,
                        paid_when_unhealthy,
                        only_if,
                        unless,
                    },
                    enabled,
                ));
            }
        }
        out
    }

    fn need_sel(&mut self, s: &Section, key: &str) -> Option<Selection> {
        self.need_key(s, key, &format!("expected a `{key}` selector"))?;
        self.sel_key(s, key)
    }

    /// The indices of the names a glob pattern (`*`, `?`) matches. A pattern that matches none is
    /// E0160 at `loc`, "`pattern` matches none of {what}", with the nearest name (a row that
    /// selects nothing is almost always a typo).
    fn glob_hits<'n>(
        &mut self,
        pattern: &str,
        names: impl Iterator<Item = &'n str> + Clone,
        loc: &Location,
        what: &str,
        label: &str,
    ) -> Option<Vec<usize>> {
        let hit: Vec<usize> = names
            .clone()
            .enumerate()
            .filter(|(_, n)| selector::glob(pattern, n))
            .map(|(i, _)| i)
            .collect();
        if hit.is_empty() {
            self.d.push(
                Diagnostic::new(Code::E0160, format!("`{pattern}` matches none of {what}"))
                    .at(loc.clone())
                    .label(label.to_string())
                    .help_opt(suggest(pattern, names)),
            );
            return None;
        }
        Some(hit)
    }

    /// A required key of a `[reward.*]` term: its value, or E0103 at the table (`label` says what
    /// belongs there).
    fn need_key<'s>(&mut self, s: &'s Section, key: &str, label: &str) -> Option<&'s Val> {
        let v = s.get(key);
        if v.is_none() {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `{key}` in [reward.{}]", s.name),
                )
                .at(s.name_loc.clone())
                .label(label.to_string()),
            );
        }
        v
    }

    /// A list of `n` numbers (default: all `default`).
    fn num_list(&mut self, s: &Section, key: &str, n: usize, default: f64) -> Option<Vec<f64>> {
        let Some(v) = s.get(key) else {
            return Some(vec![default; n]);
        };
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a.iter().map(|x| self.num(x, key)).collect(),
            _ => {
                self.d.push(v.type_error(
                    key,
                    &format!("an array of {n} numbers (one per selected element)"),
                ));
                None
            }
        }
    }

    fn reward_sum(&mut self, terms: &[RewardTerm]) -> SumNode {
        let Some(v) = self.spec.reward_sum.clone() else {
            return SumNode::Sum((0..terms.len()).map(SumNode::Term).collect());
        };
        let mut used = vec![0usize; terms.len()];
        let node = self
            .sum_node(&v, terms, &mut used)
            .unwrap_or(SumNode::Sum(vec![]));
        // `used` counts only the terms that resolved; a term that failed was reported where it failed.
        for (i, n) in used.iter().enumerate() {
            if *n != 1 {
                let msg = match n {
                    0 => format!("reward term `{}` is missing from `sum`", terms[i].name),
                    _ => format!("reward term `{}` is used {n} times in `sum`", terms[i].name),
                };
                self.d.push(
                    Diagnostic::new(Code::E0501, msg)
                        .at(v.loc.clone())
                        .label("expected every term exactly once"),
                );
            }
        }
        node
    }

    fn sum_node(&mut self, v: &Val, terms: &[RewardTerm], used: &mut [usize]) -> Option<SumNode> {
        match &v.kind {
            ValKind::Str(name) => match terms.iter().position(|t| &t.name == name) {
                Some(i) => {
                    used[i] += 1;
                    Some(SumNode::Term(i))
                }
                None => {
                    if self.spec.reward.iter().all(|s| &s.name != name) {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0501,
                                format!("`{name}` in `sum` is not a reward term"),
                            )
                            .at(v.loc.clone())
                            .label("expected the name of a [reward.<name>] table")
                            .help_opt(suggest(name, terms.iter().map(|t| t.name.as_str()))),
                        );
                    }
                    None
                }
            },
            ValKind::Array(a) if !a.is_empty() => {
                let nodes: Vec<SumNode> = a
                    .iter()
                    .filter_map(|x| self.sum_node(x, terms, used))
                    .collect();
                Some(SumNode::Sum(nodes))
            }
            _ => {
                self.d
                    .push(v.type_error("reward.sum", "a (nested) list of term names"));
                None
            }
        }
    }

    fn health(&mut self) -> Vec<HealthCheck> {
        let mut out = vec![];
        for s in &self.spec.health {
            let Some(src) = s.get("source") else { continue };
            let srcs: Vec<Val> = match &src.kind {
                ValKind::Array(a) => a.clone(),
                _ => vec![src.clone()],
            };
            let sources: Vec<Selection> = srcs
                .iter()
                .filter_map(|v| self.selection(v, "source"))
                .collect();
            if sources.len() != srcs.len() {
                continue;
            }
            let kind = match s.kind("") {
                "finite" => CheckKind::Finite,
                "in_range" => {
                    let Some(r) = s.get("range") else {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0103,
                                format!("missing `range` in [health.{}]", s.name),
                            )
                            .at(s.name_loc.clone())
                            .label("expected range = [low, high] or a parameter name"),
                        );
                        continue;
                    };
                    let Some((lo, hi)) = self.range(r, "range") else {
                        continue;
                    };
                    let closed = match s.get("bounds") {
                        None => false,
                        Some(b) => match b.as_str() {
                            Some("closed") => true,
                            Some("open") => false,
                            _ => {
                                self.d.push(
                                    Diagnostic::new(Code::E0104, "unknown bounds")
                                        .at(b.loc.clone())
                                        .label("expected \"open\" (lo < x < hi) or \"closed\" (lo <= x <= hi)"),
                                );
                                false
                            }
                        },
                    };
                    CheckKind::InRange { lo, hi, closed }
                }
                "fails_if" => {
                    let op = match s.get("op").and_then(Val::as_str) {
                        Some("<") => CmpOp::Lt,
                        Some("<=") => CmpOp::Le,
                        Some(">") => CmpOp::Gt,
                        Some(">=") => CmpOp::Ge,
                        _ => {
                            let ops = "expected op = \"<\", \"<=\", \">\" or \">=\"";
                            let e = match s.get("op") {
                                None => Diagnostic::new(
                                    Code::E0103,
                                    format!("missing `op` in [health.{}]", s.name),
                                )
                                .at(s.name_loc.clone()),
                                Some(v) if v.as_str().is_some() => Diagnostic::new(
                                    Code::E0104,
                                    format!("unknown `op` in [health.{}]", s.name),
                                )
                                .at(v.loc.clone()),
                                Some(v) => v.type_error("op", "a string"),
                            };
                            self.d.push(e.label(ops));
                            continue;
                        }
                    };
                    let Some(value) = s.get("value").and_then(|v| self.num(v, "value")) else {
                        if s.get("value").is_none() {
                            self.d.push(
                                Diagnostic::new(
                                    Code::E0103,
                                    format!("missing `value` in [health.{}]", s.name),
                                )
                                .at(s.name_loc.clone())
                                .label("expected value = a number or parameter name"),
                            );
                        }
                        continue;
                    };
                    CheckKind::FailsIf { op, value }
                }
                _ => continue,
            };
            out.push(HealthCheck {
                name: s.name.clone(),
                doc: s.doc(),
                kind,
                sources,
            });
        }
        out
    }

    fn reset(&mut self, terrain: Option<&crate::ir::Terrain>) -> Vec<ResetStep> {
        let mut out = vec![];
        // One tile per episode: a second spawn would redraw and overwrite the first.
        let mut spawn: Option<&str> = None;
        for s in &self.spec.reset {
            if s.kind("") == "terrain_origin" {
                if let Some(first) = spawn {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0162,
                            format!(
                                "[reset.{}] is a second terrain_origin reset (the first is [reset.{first}])",
                                s.name
                            ),
                        )
                        .at(s.name_loc.clone())
                        .label("expected one terrain_origin reset: each episode spawns on one tile"),
                    );
                    continue;
                }
                spawn = Some(&s.name);
                out.extend(self.terrain_origin(s, terrain));
                continue;
            }
            if let Some(step) = self.keyframe_reset(s) {
                out.extend(step);
                continue;
            }
            if s.kind("") == "settle" {
                out.extend(self.settle(s));
                continue;
            }
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let Some(target) = self.sel_key(s, "target") else {
                continue;
            };
            if !matches!(
                target.field,
                Field::Qpos | Field::Qvel | Field::Goal | Field::MocapPos | Field::MocapQuat
            ) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0107,
                        format!(
                            "reset target `{}` is not qpos, qvel, goal, mocap_pos or mocap_quat",
                            target.text
                        ),
                    )
                    .at(s
                        .get("target")
                        .expect("`target` was read just above")
                        .loc
                        .clone())
                    .label("expected a selection of qpos, qvel, goal, mocap_pos or mocap_quat"),
                );
                continue;
            }
            let n = target.len();
            let kind = s.kind("");
            let Some(dist) = self.reset_dist(s, kind, n) else {
                continue;
            };
            let widest = match &dist {
                Distribution::Uniform { low, high } => {
                    low.iter().chain(high).fold(0.0, |m: f64, x| m.max(x.abs()))
                }
                Distribution::Normal { scale } => scale.abs(),
                Distribution::Constant { value } => value.abs(),
                Distribution::Values { values } => {
                    values.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
                }
                Distribution::Meet(m) => m
                    .offset
                    .iter()
                    .fold(m.scale.abs() + m.gap.abs(), |a, x| a.max(x.abs())),
                Distribution::Keyframe { .. }
                | Distribution::RootPose { .. }
                | Distribution::Rotation(_)
                | Distribution::UnitQuaternion
                | Distribution::Settle(_)
                | Distribution::TerrainOrigin { .. } => 0.0,
            };
            if widest > limits::MAX_COORDINATE {
                let at = ["scale", "low", "high", "value"]
                    .iter()
                    .find_map(|k| s.get(k))
                    .map(|v| v.loc.clone())
                    .unwrap_or(s.name_loc.clone());
                self.d.push(
                    Diagnostic::new(
                        Code::E0110,
                        format!("[reset.{}]: a draw as large as {widest:e} is beyond envc's limit of {:e}", s.name, limits::MAX_COORDINATE),
                    )
                    .at(at)
                    .label("expected a distribution within ±1e6")
                    .help("MuJoCo takes seconds per step from such a state, or resets it; see docs/limits.md"),
                );
                continue;
            }
            if let Distribution::Uniform { low, high } = &dist {
                // numpy refuses these (and so would reset); report them with the spec's location.
                if let Some(i) = (0..n).find(|&i| {
                    low[i].partial_cmp(&high[i]).is_none_or(|o| o.is_gt())
                        || !(high[i] - low[i]).is_finite()
                }) {
                    let at = s
                        .get("scale")
                        .or(s.get("low"))
                        .map(|v| v.loc.clone())
                        .unwrap_or(s.name_loc.clone());
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!(
                                "[reset.{}]: uniform bounds [{}, {}) are empty or infinite",
                                s.name, low[i], high[i]
                            ),
                        )
                        .at(at)
                        .label("expected low <= high with a finite width (scale >= 0)"),
                    );
                    continue;
                }
            }
            let set = match s.get("mode") {
                None => kind == "constant",
                Some(m) => {
                    match m.as_str() {
                        Some("add") => false,
                        Some("set") => true,
                        _ => {
                            self.d.push(
                            Diagnostic::new(Code::E0104, "unknown reset mode")
                                .at(m.loc.clone())
                                .label("expected \"add\" (initial value + draw) or \"set\" (the draw)"),
                        );
                            false
                        }
                    }
                }
            };
            let (around, probability) = self.reset_placement(s, n);
            let resample_until = s.get("resample_until").and_then(|v| {
                let until = self.until(v)?;
                if matches!(until, Until::MinDistance(_)) && s.get("around").is_none() {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0170,
                            format!("[reset.{}]: min_distance needs `around`", s.name),
                        )
                        .at(v.loc.clone())
                        .label("min_distance is measured from the `around` point")
                        .help("add around = \"<record>\" (an `[init] record`)"),
                    );
                    return None;
                }
                match unmet(&dist, n, until) {
                    None => Some(until),
                    Some(why) => {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0110,
                                format!(
                                    "[reset.{}]: resample_until can never be met: {why}",
                                    s.name
                                ),
                            )
                            .at(v.loc.clone())
                            .label("expected a condition some draw of the distribution meets")
                            .help("the reference would redraw for ever at reset"),
                        );
                        None
                    }
                }
            });
            if !enabled {
                continue;
            }
            out.push(ResetStep {
                name: s.name.clone(),
                doc: s.doc(),
                target,
                dist,
                set,
                resample_until,
                around,
                probability,
            });
        }
        out
    }

    /// The distribution of a `uniform`, `normal` or `constant` reset step of `n` elements.
    fn reset_dist(&mut self, s: &Section, kind: &str, n: usize) -> Option<Distribution> {
        Some(match kind {
            "uniform" => {
                if let Some(scale) = s.get("scale") {
                    let sc = self.num(scale, "scale")?;
                    Distribution::Uniform {
                        low: vec![-sc; n],
                        high: vec![sc; n],
                    }
                } else {
                    let low = self.bound(s, "low", n);
                    let high = self.bound(s, "high", n);
                    Distribution::Uniform {
                        low: low?,
                        high: high?,
                    }
                }
            }
            "normal" => {
                let scale = s
                    .get("scale")
                    .map(|v| self.num(v, "scale"))
                    .unwrap_or(Some(1.0))?;
                Distribution::Normal { scale }
            }
            "constant" => match s.get("value") {
                Some(v) if matches!(v.kind, ValKind::Array(_)) => Distribution::Values {
                    values: self.bound(s, "value", n)?,
                },
                v => Distribution::Constant {
                    value: v.map(|v| self.num(v, "value")).unwrap_or(Some(0.0))?,
                },
            },
            "meet" => return self.meet(s, n),
            "rotation" | "unit_quaternion" => return self.rotation(s, kind, n),
            _ => return None,
        })
    }

    /// `low`/`high` of a uniform: one number for all elements, or one per element.
    fn bound(&mut self, s: &Section, key: &str, n: usize) -> Option<Vec<f64>> {
        let Some(v) = s.get(key) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `{key}` in [reset.{}]", s.name),
                )
                .at(s.name_loc.clone())
                .label("expected `scale`, or both `low` and `high`"),
            );
            return None;
        };
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a.iter().map(|x| self.num(x, key)).collect(),
            ValKind::Array(a) => {
                self.d.push(v.type_error(
                    key,
                    &format!(
                        "a number or an array of {n} numbers (one per target element; {} given)",
                        a.len()
                    ),
                ));
                None
            }
            _ => self.num(v, key).map(|x| vec![x; n]),
        }
    }

    fn until(&mut self, v: &Val) -> Option<Until> {
        let t = v.as_table().filter(|t| t.len() == 1);
        let Some(e) = t.map(|t| &t[0]) else {
            self.d.push(v.type_error(
                "resample_until",
                "{ norm_below = x }, { norm_above = x } or { min_distance = x }",
            ));
            return None;
        };
        let x = self.num(&e.value, &e.key)?;
        match e.key.as_str() {
            "norm_below" => Some(Until::NormBelow(x)),
            "norm_above" => Some(Until::NormAbove(x)),
            "min_distance" => Some(Until::MinDistance(x)),
            k => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("unknown condition `{k}` in resample_until"),
                    )
                    .at(e.key_loc.clone())
                    .label("expected norm_below, norm_above or min_distance")
                    .help_opt(suggest(k, ["norm_below", "norm_above", "min_distance"])),
                );
                None
            }
        }
    }

    /// The `[info.*]` entries that are switched on, each with the location of its key.
    /// `off`: the names of the reward terms switched off by `when`.
    fn info(&mut self, terms: &[RewardTerm], off: &[String]) -> Vec<(InfoItem, Option<Location>)> {
        let mut out = vec![];
        for s in &self.spec.info {
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let key = match s.get("key") {
                None => s.name.clone(),
                Some(v) => match v.as_str() {
                    Some(k) => k.to_string(),
                    None => {
                        self.d.push(v.type_error("key", "an info key (a string)"));
                        continue;
                    }
                },
            };
            let key_loc = s
                .get("key")
                .map(|v| v.loc.clone())
                .unwrap_or(s.name_loc.clone());
            let in_reset = match s.get("in_reset") {
                Some(v) => self.flag(v, "in_reset").unwrap_or(true),
                None => true,
            };
            let unweighted = match s.get("unweighted") {
                Some(v) => self.flag(v, "unweighted").unwrap_or(false),
                None => false,
            };
            let (kind, len, at_reset) = match s.kind("value") {
                "term" => {
                    let Some(v) = s.get("term") else { continue };
                    let Some(name) = v.as_str() else {
                        self.d
                            .push(v.type_error("term", "the name of a reward term"));
                        continue;
                    };
                    match terms.iter().position(|t| t.name == name) {
                        Some(i) => (InfoKind::Term(i), 1, false),
                        None => {
                            let declared = self.spec.reward.iter().any(|r| r.name == name);
                            if !declared {
                                self.d.push(
                                    Diagnostic::new(
                                        Code::E0502,
                                        format!("[info.{}] reports `{name}`, which is not a reward term", s.name),
                                    )
                                    .at(v.loc.clone())
                                    .label("expected the name of a [reward.<name>] table")
                                    .help_opt(suggest(
                                        name,
                                        self.spec.reward.iter().map(|r| r.name.as_str()),
                                    )),
                                );
                            } else if enabled && off.iter().any(|o| o == name) {
                                self.d.push(
                                    Diagnostic::new(
                                        Code::E0502,
                                        format!(
                                            "[info.{}] reports reward term `{name}`, which its `when` switches off",
                                            s.name
                                        ),
                                    )
                                    .at(v.loc.clone())
                                    .label("expected a term that is switched on whenever this entry is (give the entry the same `when`)"),
                                );
                            }
                            // A declared term that failed to resolve was reported where it failed.
                            continue;
                        }
                    }
                }
                "goal_reached" => {
                    let what = format!("[info.{}]", s.name);
                    let Some(c) = self.goal_check(s, &what, GoalNorm::Blas) else {
                        continue;
                    };
                    (InfoKind::GoalReached(c), 1, in_reset)
                }
                "goals_reached" => {
                    let what = format!("[info.{}]", s.name);
                    let Some(cs) = self.goal_checks(s, &what, GoalNorm::Blas) else {
                        continue;
                    };
                    (InfoKind::GoalsReached(cs), 1, in_reset)
                }
                "condition" => {
                    let what = format!("[info.{}] condition", s.name);
                    // A missing `condition` is reported by the syntax check.
                    let Some(v) = s.get("condition") else {
                        continue;
                    };
                    let Some(cs) = self.conditions(v, &what) else {
                        continue;
                    };
                    (InfoKind::Condition(cs), 1, in_reset)
                }
                kind => {
                    let Some(source) = self.sel_key(s, "source") else {
                        continue;
                    };
                    let len = source.len();
                    match kind {
                        "value" => {
                            let minus = self.sel_key(s, "minus").filter(|m| {
                                self.same_len(
                                    &source,
                                    m,
                                    &s.get("minus").expect("`minus` was read just above").loc,
                                )
                            });
                            (InfoKind::Value { source, minus }, len, in_reset)
                        }
                        "norm" => (InfoKind::Norm { source }, 1, in_reset),
                        "velocity" => {
                            if !self.scalar(
                                &source,
                                &s.get("source").expect("`source` was read just above").loc,
                                "a velocity",
                            ) {
                                continue;
                            }
                            (InfoKind::Velocity { source }, 1, false)
                        }
                        _ => continue,
                    }
                }
            };
            if !enabled {
                continue;
            }
            let (float32, boolean) = match s.get("dtype") {
                None => (false, false),
                Some(v) => {
                    match v.as_str() {
                        Some("float32") => (true, false),
                        Some("float64") => (false, false),
                        Some("bool") => (false, true),
                        _ => {
                            self.d.push(
                            Diagnostic::new(Code::E0104, "unknown info `dtype`")
                                .at(v.loc.clone())
                                .label("expected \"float64\" (the default), \"float32\" or \"bool\""),
                        );
                            (false, false)
                        }
                    }
                }
            };
            out.push((
                InfoItem {
                    key,
                    doc: s.doc(),
                    kind,
                    len,
                    at_reset,
                    unweighted,
                    float32,
                    boolean,
                },
                Some(key_loc),
            ));
        }
        out
    }

    fn check_info_keys(&mut self, info: &[(InfoItem, Option<Location>)]) {
        for (i, (item, loc)) in info.iter().enumerate() {
            if info[..i].iter().any(|(o, _)| o.key == item.key) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0106,
                        format!("info key `{}` is defined twice", item.key),
                    )
                    .at_opt(loc.clone())
                    .label("expected unique info keys (among the entries switched on)"),
                );
            }
        }
    }
}
