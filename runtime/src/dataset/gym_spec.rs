//! The `env_spec` Minari stores: Gymnasium's `EnvSpec.to_json()` of the env the data came from, so
//! that `dataset.recover_environment()` builds the reference env with the same parameters.
//!
//! envc specs don't name a Python entry point; the table below is Gymnasium 1.4.0's registry for
//! the MuJoCo suite (`gymnasium/envs/__init__.py`), checked against `gym.make(id).spec.to_json()`
//! by `tests/reference/check_minari.py`. An env that is not in it (e.g. a third-party robot spec)
//! gets no `env_spec`: the dataset still loads (the spaces are stored), it just can't be recovered
//! in Python.

use envspec::params::Origin;
use envspec::{ParamValue, ResolvedSpec};

use super::json::PyJson;

/// (name without version, module stem, class).
const GYMNASIUM_MUJOCO: &[(&str, &str, &str)] = &[
    ("Ant", "ant", "AntEnv"),
    ("HalfCheetah", "half_cheetah", "HalfCheetahEnv"),
    ("Hopper", "hopper", "HopperEnv"),
    ("Humanoid", "humanoid", "HumanoidEnv"),
    ("HumanoidStandup", "humanoidstandup", "HumanoidStandupEnv"),
    (
        "InvertedDoublePendulum",
        "inverted_double_pendulum",
        "InvertedDoublePendulumEnv",
    ),
    (
        "InvertedPendulum",
        "inverted_pendulum",
        "InvertedPendulumEnv",
    ),
    ("Pusher", "pusher", "PusherEnv"),
    ("Reacher", "reacher", "ReacherEnv"),
    ("Swimmer", "swimmer", "SwimmerEnv"),
    ("Walker2d", "walker2d", "Walker2dEnv"),
];

/// Gymnasium's entry point for a MuJoCo-suite id such as `Ant-v5`.
pub fn entry_point(id: &str) -> Option<String> {
    let (name, version) = id.rsplit_once("-v")?;
    if !matches!(version, "4" | "5") {
        return None;
    }
    let (_, module, class) = GYMNASIUM_MUJOCO.iter().find(|(n, _, _)| *n == name)?;
    Some(format!("gymnasium.envs.mujoco.{module}_v{version}:{class}"))
}

fn param_json(v: &ParamValue) -> Option<PyJson> {
    Some(match v {
        ParamValue::Bool(b) => PyJson::Bool(*b),
        ParamValue::Int(i) => PyJson::Int(*i as i128),
        ParamValue::Float(x) => PyJson::Float(*x),
        ParamValue::Range(a, b) => PyJson::List(vec![PyJson::Float(*a), PyJson::Float(*b)]),
        ParamValue::Str(s) => PyJson::Str(s.clone()),
        ParamValue::Table(_) => return None,
    })
}

/// `EnvSpec.to_json()` text for the env, or `None` (with the reason) when Gymnasium can't rebuild it.
/// Overridden parameters become `kwargs` (`max_episode_steps` is the spec's own field, as in
/// `gym.make(id, max_episode_steps=...)`).
pub fn env_spec_json(spec: &ResolvedSpec) -> Result<String, String> {
    let entry =
        entry_point(&spec.id).ok_or_else(|| format!("{} is not a Gymnasium env id", spec.id))?;
    let mut kwargs = vec![];
    for p in &spec.params {
        if p.name == "max_episode_steps" || !matches!(p.origin, Origin::Override(_)) {
            continue;
        }
        let v = param_json(&p.value)
            .ok_or_else(|| format!("parameter {} (a table) has no Python equivalent", p.name))?;
        kwargs.push((p.name.clone(), v));
    }
    let opt_f = |x: Option<f64>| x.map(PyJson::Float).unwrap_or(PyJson::Null);
    let v = PyJson::Obj(vec![
        ("id".into(), PyJson::Str(spec.id.clone())),
        ("entry_point".into(), PyJson::Str(entry)),
        ("reward_threshold".into(), opt_f(spec.reward_threshold)),
        ("nondeterministic".into(), PyJson::Bool(false)),
        (
            "max_episode_steps".into(),
            spec.max_episode_steps
                .map(|n| PyJson::Int(n as i128))
                .unwrap_or(PyJson::Null),
        ),
        ("order_enforce".into(), PyJson::Bool(true)),
        ("disable_env_checker".into(), PyJson::Bool(false)),
        ("kwargs".into(), PyJson::Obj(kwargs)),
        ("additional_wrappers".into(), PyJson::List(vec![])),
        ("vector_entry_point".into(), PyJson::Null),
    ]);
    Ok(v.dump())
}
