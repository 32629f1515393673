//! Spec + parameter values + model → the IR. Every problem is collected; nothing stops at the first.

use std::path::{Path, PathBuf};

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location};
use crate::ir::*;
use crate::limits;
use crate::mjcf::ModelInfo;
use crate::params::{Origin, Override, Param, ParamValue, resolve_params};
use crate::selector::Field;
use crate::syntax::Spec;

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
mod goal_parts;
mod health;
mod info;
mod joint_properties;
mod keyframes;
mod legged;
mod manipulation;
mod manipulation_reset;
mod noise;
mod observation;
mod pairing;
mod reset;
mod reward;
mod selection;
mod terrain;
mod values;

pub(crate) use commands::command_selection;
pub use keyframes::ROOT_POSE_KEYS;

struct Ctx<'a> {
    spec: &'a Spec,
    params: &'a [Param],
    model: &'a ModelInfo,
    d: Diagnostics,
    /// Length of the env-held goal vector, and where a `desired = "goal"` first fixed it.
    goal_dim: Option<(usize, Location)>,
    /// The number of `[goal]` parts in play (0: the goal is not made of parts).
    goal_parts: usize,
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

impl<'a> Ctx<'a> {
    /// A context with nothing resolved yet; `d` holds the problems found before it.
    fn new(spec: &'a Spec, params: &'a [Param], model: &'a ModelInfo, d: Diagnostics) -> Self {
        Ctx {
            spec,
            params,
            model,
            d,
            goal_dim: None,
            goal_parts: 0,
            commands: vec![],
            derived: vec![],
            derived_failed: vec![],
            records: vec![],
            dt: 0.0,
            frame_skip: 1,
        }
    }
}

/// Resolve a checked spec with parameter overrides against its model.
pub fn resolve(spec: &Spec, overrides: &[Override]) -> Result<ResolvedSpec, Diagnostics> {
    let params = resolve_params(spec, overrides)?;
    let xml = params
        .iter()
        .find(|p| p.name == "xml_file")
        .expect("checked by syntax");
    let (model_path, mut model) = load_model(spec, xml)?;
    let (model_edits, d) = edit_model(spec, &params, &mut model);
    let mut cx = Ctx::new(spec, &params, &model, d);

    let frame_skip = cx.frame_skip_param();
    let max_episode_steps = cx.max_episode_steps_param();
    cx.dt = model.timestep * frame_skip as f64;
    cx.frame_skip = frame_skip;
    let commands = cx.commands(model.timestep * frame_skip as f64);
    cx.commands = commands.clone();
    let command_dim = commands.iter().map(Command::len).sum();
    let derived = cx.derived();
    let derived_dim = derived.iter().map(|d| d.len).sum();
    let mut actions = cx.actions();
    let manipulation = cx.manipulation();

    let observation = cx.observation();
    cx.link_action_source(&mut actions, &observation);
    let corruption = cx.corruption(&observation);
    let obs_dim = observation.iter().map(Segment::len).sum();
    let (reward, reward_sum, off) = cx.rewards();
    let terminate_when_unhealthy = match &spec.health_terminate {
        Some(v) => cx.flag(v, "health.terminate").unwrap_or(true),
        None => true,
    };
    let health = cx.health();
    let termination = cx.terminations();
    let reset = cx.reset(model_edits.terrain.as_ref());
    let info = cx.info_items(&reward, &off);

    let events = cx.events();
    let goal_dim = cx.goal_dim.as_ref().map_or(0, |(n, _)| *n);
    let Ctx { d, .. } = cx;
    let resolved = ResolvedSpec {
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
    finish(spec, resolved, d, &params)
}

/// Apply the spec's model edits to `model`: the edits, and the problems found so far.
fn edit_model(spec: &Spec, params: &[Param], model: &mut ModelInfo) -> (ModelEdits, Diagnostics) {
    // `[bodies]` ... add elements to the model, which the other model edits may name (a
    // `[joint_properties]` row over an added joint): resolve them first.
    let mut cx = Ctx::new(spec, params, model, Diagnostics::default());
    let added = cx.added_elements();
    let d = cx.d;
    let mut with_added = model.clone();
    added::apply(&added, &mut with_added);
    // `[actuators]` / `[physics]` change the model itself: resolve them first.
    let mut cx = Ctx::new(spec, params, &with_added, d);
    let model_edits = cx.model_edits(added);
    let d = cx.d;
    edits::apply(&model_edits, model);
    (model_edits, d)
}

/// The warnings of a resolved spec, whether it needs `mj_rnePostConstraint`, and the check that
/// a `default_pose` it reads has an `[actions]` table; errors are then blamed on the overrides
/// they come from.
fn finish(
    spec: &Spec,
    mut resolved: ResolvedSpec,
    mut d: Diagnostics,
    params: &[Param],
) -> Result<ResolvedSpec, Diagnostics> {
    resolved.warnings = pairing::warnings(spec, &resolved);
    resolved.warnings.extend(added::falling(spec, &resolved));
    resolved.warnings.extend(reset::far_draws(spec, &resolved));
    let rne = resolved
        .sources()
        .any(|s| s.field.needs_rne_post_constraint());
    resolved.needs_rne_post_constraint = rne;
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
    let d = blame_overrides(d, params);
    d.into_result(resolved)
}

impl Ctx<'_> {
    /// `frame_skip`: physics steps per env step, from 1 to `limits::MAX_FRAME_SKIP` (1 when not).
    fn frame_skip_param(&mut self) -> u32 {
        match self.param("frame_skip").map(|p| &p.value) {
            Some(ParamValue::Int(n)) if (1..=limits::MAX_FRAME_SKIP).contains(n) => *n as u32,
            Some(ParamValue::Int(n)) if *n > limits::MAX_FRAME_SKIP => {
                self.over_limit("frame_skip", *n, limits::MAX_FRAME_SKIP);
                1
            }
            _ => {
                self.d
                    .push(self.param_error("frame_skip", "frame_skip must be a positive integer"));
                1
            }
        }
    }

    /// `max_episode_steps`: the time limit, None for none.
    fn max_episode_steps_param(&mut self) -> Option<u64> {
        // 0 means no time limit (the reference's `max_episode_steps=None`).
        match self.param("max_episode_steps").map(|p| &p.value) {
            Some(ParamValue::Int(n)) if *n > limits::MAX_EPISODE_STEPS => {
                self.over_limit("max_episode_steps", *n, limits::MAX_EPISODE_STEPS);
                None
            }
            Some(ParamValue::Int(n)) if *n < 0 => {
                self.d.push(self.param_error(
                    "max_episode_steps",
                    "max_episode_steps must be ≥ 0 (0: no time limit)",
                ));
                None
            }
            Some(ParamValue::Int(n)) if *n > 0 => Some(*n as u64),
            _ => None,
        }
    }
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
                match name.strip_prefix("python:") {
                    Some(package) => Diagnostic::new(
                        Code::E0301,
                        format!("xml_file names ${{{name}}}, and no Python package `{package}` is installed where envc looks"),
                    )
                    .at_opt(at)
                    .label("expected a path; ${python:PACKAGE} is the installed package's directory")
                    .help(format!("install it (`pip install ...`), or set ENVC_PYTHON_PATH to the directory holding `{package}/`")),
                    None => Diagnostic::new(
                        Code::E0301,
                        format!("xml_file names ${{{name}}}, an environment variable that is not set"),
                    )
                    .at_opt(at)
                    .label("expected a path; ${NAME} reads the variable NAME")
                    .help(format!("set it, e.g. `export {name}=/path/to/models`")),
                },
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

/// Load, check and resolve a spec file in one call.
pub fn load(path: &Path, overrides: &[Override]) -> Result<ResolvedSpec, Diagnostics> {
    let (spec, inputs) = crate::source::recorded(|| resolve(&Spec::load(path)?, overrides));
    let mut spec = spec?;
    spec.inputs = inputs;
    Ok(spec)
}
