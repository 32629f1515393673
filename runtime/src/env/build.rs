//! Building an env: compiling the spec's model, checking it against the numbering the spec was
//! resolved with, and laying out every buffer the env steps in (nothing allocates afterwards).

use std::path::Path;
use std::sync::Arc;

use envspec::ir::*;
use envspec::{Field, Override, ResolvedSpec, Selection};
use mujoco_rs::prelude::{MjData, MjModel};

use super::info::{layout, total};
use super::sim::Sim;
use super::{BoxSpace, Env};
use crate::error::EnvError;
use crate::mj;
use crate::mj::Call;
use crate::mj::log as mujoco_log;
use crate::numerics::default_profile;

impl Env {
    /// Load a spec file with parameter overrides and build the env.
    pub fn from_spec_file(path: impl AsRef<Path>, overrides: &[Override]) -> Result<Env, EnvError> {
        let spec = envspec::load(path.as_ref(), overrides)?;
        Env::new(Arc::new(spec))
    }

    /// A bundled env by id (e.g. `"Ant-v5"`) or a spec file path, with overrides.
    pub fn make(id_or_path: &str, overrides: &[Override]) -> Result<Env, EnvError> {
        Env::from_spec_file(crate::registry::find(id_or_path)?, overrides)
    }

    /// Build an env from a resolved spec (compiles the model).
    pub fn new(spec: Arc<ResolvedSpec>) -> Result<Env, EnvError> {
        let model = Arc::new(compile(&spec)?);
        Env::with_model(spec, model)
    }

    /// Build an env sharing an already compiled model (vectorized envs share one).
    pub fn with_model(spec: Arc<ResolvedSpec>, model: Arc<MjModel>) -> Result<Env, EnvError> {
        Env::with_world_model(spec, model, 0)
    }

    /// `with_model` for a model that adds `world_sites` sites to the world body of the spec's
    /// model (a maze's goal marker); everything else must match the spec's model.
    pub(crate) fn with_world_model(
        spec: Arc<ResolvedSpec>,
        model: Arc<MjModel>,
        world_sites: usize,
    ) -> Result<Env, EnvError> {
        mujoco_log::install();
        check_model(&spec, &model, world_sites)?;
        crate::model_values::check(&spec.model_path, &model)?;
        // Randomized model fields are written in the env's own copy; envs sharing the compiled
        // model are unaffected.
        let model = if spec.events.iter().any(envspec::events::Event::writes_model) {
            Arc::new(MjModel::clone(&model))
        } else {
            model
        };
        let events = if spec.events.is_empty() {
            None
        } else {
            Some(crate::events::Events::new(
                &spec.id,
                &spec.events,
                model.ffi(),
            )?)
        };
        // mj_makeData raises mju_error when the allocation fails: guarded, it is an error too.
        let data = crate::mj::log::guard(|| MjData::try_new(Arc::clone(&model)))
            .map_err(|e| e.to_string())
            .and_then(|d| d.map_err(|e| e.to_string()))
            .map_err(|e| EnvError::Compile {
                path: spec.model_path.clone(),
                message: format!("cannot allocate mjData: {e}"),
            })?;
        let numerics = default_profile()?;
        let m = model.ffi();
        let render = crate::render::EnvRender::new(&spec.params, m)?;
        let mut sim = Sim::new(&spec, &model, data, numerics)?;
        let mut warnings = vec![];
        let (qpos_init, qvel_init) = start_state(&spec, &mut sim, &mut warnings)?;
        let timestep = m.opt.timestep;
        let dt = timestep * spec.frame_skip as f64;

        let (velocity_sources, term_slot, info_slot) = velocity_slots(&spec);
        let uses_mass_center = spec.reads(Field::MassCenter);
        let uses_subtree = spec.reads(Field::SubtreeLinvel) || spec.reads(Field::SubtreeAngmom);

        let step_info = layout(&mut spec.info.iter());
        let reset_info = layout(&mut spec.reset_info());

        let action_space = action_space(&spec, &model, sim.nu);
        let observation_space = BoxSpace {
            low: vec![f64::NEG_INFINITY; spec.obs_dim],
            high: vec![f64::INFINITY; spec.obs_dim],
        };
        let max_draw = spec.reset.iter().map(|r| r.target.len()).max().unwrap_or(0);

        let latency =
            crate::latency::ActionLatency::new(spec.corruption.action_latency, spec.act_dim());
        mujoco_log::drain_into(&mut warnings);
        Ok(Env {
            before: vec![0.0; velocity_sources.len()],
            velocity_sources,
            term_slot,
            info_slot,
            term_values: vec![0.0; 2 * spec.reward.len()],
            unweighted_terms: unweighted_terms(&spec),
            obs: vec![0.0; spec.obs_dim],
            step_info_values: vec![0.0; total(&step_info)],
            reset_info_values: vec![0.0; total(&reset_info)],
            step_info,
            reset_info,
            qvel_init,
            qpos_init,
            draw: vec![0.0; max_draw],
            terrain_origins: terrain_origins(&model),
            sim,
            rng: None,
            dt,
            timestep,
            uses_mass_center,
            uses_subtree,
            elapsed: 0,
            has_reset: false,
            reset_failure: None,
            action_f32: false,
            warnings,
            observation_space,
            action_space,
            obs_noise: crate::obs_noise::ObsNoise::new(&spec),
            latency,
            spec,
            render,
            events,
        })
    }
}

/// Where every reset starts, `(qpos, qvel)`: `qpos0` at rest, or the end state of `[init]`. A
/// trial `mj_forward` at qpos0 comes first, so a model MuJoCo cannot run (its arena too small,
/// say) is refused when the env is built (`check --compile`), not at the first reset.
fn start_state(
    spec: &ResolvedSpec,
    sim: &mut Sim,
    warnings: &mut Vec<String>,
) -> Result<(Vec<f64>, Vec<f64>), EnvError> {
    // Every reset starts with `mj_resetData`, so nothing of the trial carries over; its warnings
    // are dropped.
    mujoco_log::drain_into(warnings);
    let trial = sim.call(Call::Forward);
    mujoco_log::drain_into(&mut vec![]);
    if let Err(message) = trial {
        return Err(EnvError::Mujoco {
            env: spec.id.clone(),
            during: "in a trial mj_forward when building the env",
            message,
        });
    }
    // `[init]`: its end state is where every reset starts.
    let mut qpos_init = sim.model.qpos0().to_vec();
    let mut qvel_init = vec![0.0; sim.nv];
    if let Some(init) = &spec.manipulation.init {
        let numerics = sim.numerics;
        if let Err(message) = sim
            .manip
            .run_init(init, &mut sim.data, spec.frame_skip, numerics)
        {
            return Err(EnvError::Mujoco {
                env: spec.id.clone(),
                during: "in [init] when building the env",
                message,
            });
        }
        qpos_init.copy_from_slice(sim.data.qpos());
        qvel_init.copy_from_slice(sim.data.qvel());
        mujoco_log::drain_into(warnings);
    }
    Ok((qpos_init, qvel_init))
}

/// The scalar sources velocity terms and velocity info entries differentiate (terms first, then
/// info entries, in spec order), and each term's and each info entry's index among them.
fn velocity_slots(spec: &ResolvedSpec) -> (Vec<Selection>, Vec<Option<usize>>, Vec<Option<usize>>) {
    let mut velocity_sources = vec![];
    let term_slot = spec
        .reward
        .iter()
        .map(|t| match &t.kind {
            TermKind::Velocity { source } => {
                velocity_sources.push(source.clone());
                Some(velocity_sources.len() - 1)
            }
            _ => None,
        })
        .collect();
    let info_slot = spec
        .info
        .iter()
        .map(|i| match &i.kind {
            InfoKind::Velocity { source } => {
                velocity_sources.push(source.clone());
                Some(velocity_sources.len() - 1)
            }
            _ => None,
        })
        .collect();
    (velocity_sources, term_slot, info_slot)
}

/// Per reward term: whether an `unweighted` info entry reports it (its weight-1 value is needed).
fn unweighted_terms(spec: &ResolvedSpec) -> Vec<bool> {
    (0..spec.reward.len())
        .map(|i| {
            spec.info
                .iter()
                .any(|it| it.unweighted && matches!(it.kind, InfoKind::Term(j) if j == i))
        })
        .collect()
}

/// The action space: the actuators' control ranges, `[actions]`'s range, or an end effector's
/// Box(-1, 1).
fn action_space(spec: &ResolvedSpec, model: &MjModel, nu: usize) -> BoxSpace {
    let ctrlrange = model.actuator_ctrlrange().as_flattened();
    // Gymnasium: Box(ctrlrange.astype(float32)); the bounds are the float32-rounded values.
    let mut action_space = BoxSpace {
        low: (0..nu).map(|i| ctrlrange[2 * i] as f32 as f64).collect(),
        high: (0..nu)
            .map(|i| ctrlrange[2 * i + 1] as f32 as f64)
            .collect(),
    };
    // PD actions: the declared action space, not the control range.
    if let Some(a) = &spec.actions {
        action_space.low.fill(a.range.0 as f32 as f64);
        action_space.high.fill(a.range.1 as f32 as f64);
    }
    // End-effector actions: Box(-1, 1) of their own length.
    if spec.manipulation.end_effector.is_some() {
        action_space = BoxSpace {
            low: vec![-1.0; spec.act_dim()],
            high: vec![1.0; spec.act_dim()],
        };
    }
    action_space
}

/// Compile the spec's model (MJCF or URDF) with MuJoCo, capturing its messages; `[actuators]` and
/// `[physics]` are applied through mjSpec.
pub fn compile(spec: &ResolvedSpec) -> Result<MjModel, EnvError> {
    mujoco_log::install();
    let path = &spec.model_path;
    let bad = |message: String| EnvError::Compile {
        path: path.clone(),
        message,
    };
    let s = path
        .to_str()
        .ok_or_else(|| bad("the path is not valid UTF-8".into()))?;
    if s.contains('\0') {
        return Err(bad("the path contains a NUL byte".into()));
    }
    // (with no edits, the same parse and compile as `mj_loadXML`)
    let mut model = crate::model_build::compile_edited(path, &spec.model_edits).map_err(bad)?;
    if spec
        .manipulation
        .init
        .as_ref()
        .is_some_and(|i| i.reset_welds)
    {
        mj::manip::reset_welds(&mut model);
    }
    crate::legged::apply_gains(spec, &mut model)?;
    Ok(model)
}

/// The compiled model must have the numbering envspec derived from the MJCF (otherwise names in
/// the spec would point at the wrong elements).
fn check_model(spec: &ResolvedSpec, model: &MjModel, world_sites: usize) -> Result<(), EnvError> {
    let m = model.ffi();
    let info = &spec.model;
    let mismatch = |what: String| EnvError::ModelMismatch {
        path: spec.model_path.clone(),
        what,
    };
    let sizes = [
        ("nq", m.nq as usize, info.nq),
        ("nv", m.nv as usize, info.nv),
        ("nu", m.nu as usize, info.nu()),
        ("nbody", m.nbody as usize, info.nbody()),
        ("njnt", m.njnt as usize, info.joints.len()),
        ("nsite", m.nsite as usize, info.sites.len() + world_sites),
        ("ntendon", m.ntendon as usize, info.tendons.len()),
    ];
    for (name, compiled, read) in sizes {
        if compiled != read {
            return Err(mismatch(format!(
                "{name} is {compiled} compiled but {read} from the MJCF"
            )));
        }
    }
    // njnt entries each, checked equal to the joints read from the MJCF above.
    let (qadr, dadr) = (model.jnt_qposadr(), model.jnt_dofadr());
    for (j, joint) in info.joints.iter().enumerate() {
        if qadr[j] as usize != joint.qposadr || dadr[j] as usize != joint.dofadr {
            return Err(mismatch(format!(
                "joint {j} (`{}`) has different addresses",
                joint.name
            )));
        }
    }
    if m.opt.timestep != info.timestep {
        return Err(mismatch(format!(
            "timestep is {} compiled but {} from the MJCF",
            m.opt.timestep, info.timestep
        )));
    }
    // `sensordata[...]` indices come from the sizes read in the MJCF: each sensor read must sit
    // where MuJoCo put it.
    if spec.reads(Field::SensorData) {
        let (adr, dim) = (model.sensor_adr(), model.sensor_dim());
        let mut at = 0;
        for (s, (name, size)) in info.sensors.iter().enumerate() {
            let Some(size) = size else { break };
            let same = adr.get(s).is_some_and(|&a| a as usize == at)
                && dim.get(s).is_some_and(|&d| d as usize == *size);
            if !same {
                return Err(mismatch(format!(
                    "sensor {s} (`{name}`) has another address or size than the MJCF says"
                )));
            }
            at += size;
        }
    }
    Ok(())
}

/// The terrain origins in the model's numerics (see `Env::terrain_origins`).
fn terrain_origins(model: &MjModel) -> Option<(usize, usize)> {
    let id = model.name_to_id(
        mujoco_rs::prelude::MjtObjBase::mjOBJ_NUMERIC,
        crate::model_build::TERRAIN_ORIGINS,
    )?;
    let adr = *model.numeric_adr().get(id)? as usize;
    let size = *model.numeric_size().get(id)? as usize;
    Some((adr, size / 3))
}
