//! The `env_spec` Minari stores: Gymnasium's `EnvSpec.to_json()` of the env the data came from, so
//! that `dataset.recover_environment()` builds the reference env with the same parameters.
//!
//! The entry point is the spec's `[env] entry_point` (docs/spec-reference.md); the bundled
//! Gymnasium specs name Gymnasium 1.4.0's classes, checked against `gym.make(id).spec.to_json()`
//! by `tests/reference/check_minari.py`. A spec without one (a third-party robot that has no
//! Python class, e.g. the Go1) and every maze name the envc Python package's own registration
//! (`envc/<id>`, [`envc_env_spec_json`]): `recover_environment()` rebuilds them with `envc`
//! installed.

use envspec::params::Origin;
use envspec::{ParamValue, ResolvedSpec};

use crate::json::PyJson;

fn param_json(v: &ParamValue) -> Option<PyJson> {
    Some(match v {
        ParamValue::Bool(b) => PyJson::Bool(*b),
        ParamValue::Int(i) => PyJson::Int(*i as i128),
        ParamValue::Float(x) => PyJson::Float(*x),
        ParamValue::Range(a, b) => PyJson::List(vec![PyJson::Float(*a), PyJson::Float(*b)]),
        ParamValue::Str(s) => PyJson::Str(s.clone()),
        ParamValue::Names(n) => PyJson::List(n.iter().map(|s| PyJson::Str(s.clone())).collect()),
        ParamValue::Table(_) => return None,
    })
}

/// `EnvSpec.to_json()` of the envc Python package's registration of a spec: id `envc/<id>`, the
/// entry point of the spec's kind, `spec_id` (a bundled id, or the spec file's absolute path) and
/// the overridden parameters as kwargs.
pub fn envc_env_spec_json(
    id: &str,
    entry_point: &str,
    spec_arg: &str,
    max_episode_steps: Option<u64>,
    overrides: Vec<(String, PyJson)>,
) -> String {
    let mut kwargs = vec![("spec_id".to_string(), PyJson::Str(spec_arg.to_string()))];
    kwargs.extend(overrides);
    PyJson::Obj(vec![
        ("id".into(), PyJson::Str(format!("envc/{id}"))),
        ("entry_point".into(), PyJson::Str(entry_point.into())),
        ("reward_threshold".into(), PyJson::Null),
        ("nondeterministic".into(), PyJson::Bool(false)),
        (
            "max_episode_steps".into(),
            max_episode_steps
                .map(|n| PyJson::Int(n as i128))
                .unwrap_or(PyJson::Null),
        ),
        ("order_enforce".into(), PyJson::Bool(true)),
        ("disable_env_checker".into(), PyJson::Bool(false)),
        ("kwargs".into(), PyJson::Obj(kwargs)),
        ("additional_wrappers".into(), PyJson::List(vec![])),
        (
            "vector_entry_point".into(),
            PyJson::Str("envc._vector:EnvcVectorEnv".into()),
        ),
    ])
    .dump()
}

/// How a spec is named to `envc`: its bundled id when the registry has it at this path, else
/// the spec file's absolute path.
pub fn envc_spec_arg(id: &str, path: &std::path::Path) -> String {
    let abs = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    match envspec::registry::lookup(id) {
        Ok(e) if e.path.canonicalize().ok().as_deref() == Some(abs.as_path()) => id.to_string(),
        _ => abs.display().to_string(),
    }
}

/// `env_spec` with `envc_provenance` added to its kwargs when it names one of envc's own env
/// classes (which check it); a reference class (Gymnasium's) would refuse the keyword, so its
/// spec is left as it is. The text is Gymnasium's `to_json()` or ours: its first `"kwargs": {` is
/// the top-level key (string values escape their quotes, and no earlier value is an object).
pub(crate) fn with_provenance(env_spec: &str, provenance: &serde_json::Value) -> String {
    const KWARGS: &str = "\"kwargs\": {";
    let envc = env_spec.contains("\"entry_point\": \"envc.");
    match (envc, env_spec.find(KWARGS)) {
        (true, Some(at)) => {
            let at = at + KWARGS.len();
            let empty = env_spec[at..].starts_with('}');
            let sep = if empty { "" } else { ", " };
            format!(
                "{}\"envc_provenance\": {provenance}{sep}{}",
                &env_spec[..at],
                &env_spec[at..]
            )
        }
        _ => env_spec.to_string(),
    }
}

/// The envc registration of a task spec without `[env] entry_point`.
pub fn envc_task_env_spec_json(spec: &ResolvedSpec) -> Result<String, String> {
    let mut kwargs = vec![];
    for p in &spec.params {
        if p.name == "max_episode_steps" || !matches!(p.origin, Origin::Override(_)) {
            continue;
        }
        let v = param_json(&p.value)
            .ok_or_else(|| format!("parameter {} (a table) has no Python equivalent", p.name))?;
        kwargs.push((p.name.clone(), v));
    }
    Ok(envc_env_spec_json(
        &spec.id,
        "envc._gym:EnvcEnv",
        &envc_spec_arg(&spec.id, &spec.spec_path),
        spec.max_episode_steps,
        kwargs,
    ))
}

/// `EnvSpec.to_json()` text for the env, or `None` (with the reason) when Gymnasium can't rebuild it.
/// Overridden parameters become `kwargs` (`max_episode_steps` is the spec's own field, as in
/// `gym.make(id, max_episode_steps=...)`).
pub fn env_spec_json(spec: &ResolvedSpec) -> Result<String, String> {
    let entry = spec
        .entry_point
        .clone()
        .ok_or_else(|| format!("{} names no `entry_point` in [env]", spec.id))?;
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

#[cfg(test)]
mod tests {
    use super::env_spec_json;
    use envspec::Override;

    fn spec(file: &str, overrides: &[Override]) -> envspec::ResolvedSpec {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        envspec::load(&root.join(file), overrides).unwrap()
    }

    #[test]
    fn matches_gymnasiums_to_json() {
        // Gymnasium 1.4.0: gym.make("Hopper-v5", healthy_reward=2.0, max_episode_steps=200).spec.to_json()
        let want = r#"{"id": "Hopper-v5", "entry_point": "gymnasium.envs.mujoco.hopper_v5:HopperEnv", "reward_threshold": 3800.0, "nondeterministic": false, "max_episode_steps": 200, "order_enforce": true, "disable_env_checker": false, "kwargs": {"healthy_reward": 2.0}, "additional_wrappers": [], "vector_entry_point": null}"#;
        let s = spec(
            "specs/gymnasium/hopper.toml",
            &[
                Override::text("healthy_reward", "2.0"),
                Override::text("max_episode_steps", "200"),
            ],
        );
        assert_eq!(env_spec_json(&s).unwrap(), want);
    }

    #[test]
    fn no_entry_point_no_env_spec() {
        let mut s = spec("specs/gymnasium/hopper.toml", &[]);
        s.entry_point = None;
        assert!(env_spec_json(&s).is_err());
    }
}
