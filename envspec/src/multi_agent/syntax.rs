//! Reading `[agents]` without the model: the table and its keys, the overrides split between
//! this layer and the base spec, `base_params`, the header (id, doc, parity, action bounds, body
//! clip), the observation categories and the chosen conf and depth. Like the task pipeline's
//! `syntax`, nothing here looks at the model; `resolve` does.

use std::path::Path;
use std::sync::Arc;

use super::{AGENTS_KEYS, SINGLE_AGENT};
use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::params::{Override, OverrideValue, ParamValue};
use crate::value::{Entry, Val, ValKind};

pub(super) fn err(
    code: Code,
    loc: &Location,
    msg: impl Into<String>,
    label: impl Into<String>,
) -> Diagnostic {
    Diagnostic::new(code, msg).at(loc.clone()).label(label)
}

pub(super) fn str_list(v: &Val, what: &str, d: &mut Diagnostics) -> Vec<(String, Location)> {
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

pub(super) fn range(v: &Val, what: &str, d: &mut Diagnostics) -> Option<(f64, f64)> {
    if let ValKind::Array(a) = &v.kind
        && a.len() == 2
        && let (Some(lo), Some(hi)) = (a[0].as_f64(), a[1].as_f64())
    {
        return Some((lo, hi));
    }
    d.push(v.type_error(what, "[low, high]"));
    None
}

/// A key of a table.
pub(super) fn get<'a>(table: &'a [Entry], k: &str) -> Option<&'a Val> {
    table.iter().find(|e| e.key == k).map(|e| &e.value)
}

/// The `[agents]` table of a spec (E0103 without one: not a multi-agent spec).
pub(super) fn agents_table<'a>(
    file: &Arc<SourceFile>,
    root: &'a Val,
) -> Result<&'a [Entry], Diagnostics> {
    let top = root.as_table().unwrap_or(&[]);
    let whole = Location::new(file, 0..0);
    let Some(agents_entry) = top.iter().find(|e| e.key == "agents") else {
        return Err(Diagnostic::new(Code::E0103, "missing `[agents]` table")
            .at(whole)
            .label("expected an [agents] table: this is not a multi-agent spec")
            .into());
    };
    match agents_entry.value.as_table() {
        Some(table) => Ok(table),
        None => Err(agents_entry.value.type_error("[agents]", "a table").into()),
    }
}

/// Every key of `[agents]` is one of `AGENTS_KEYS` (E0101 with the near miss).
pub(super) fn check_keys(table: &[Entry], d: &mut Diagnostics) {
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
}

/// The overrides split between this layer (`agent_conf`, `agent_obsk`) and the base spec.
pub(super) struct LayerOverrides {
    pub conf: Option<String>,
    pub k: Option<usize>,
    /// `agent_obsk=none`: MaMuJoCo's single-agent mode.
    pub single: bool,
    /// Every other override, then `base_params` the user did not override.
    pub base: Vec<Override>,
}

pub(super) fn split_overrides(overrides: &[Override], d: &mut Diagnostics) -> LayerOverrides {
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
    LayerOverrides {
        conf: conf_override,
        k: k_override,
        single: single_override,
        base: base_overrides,
    }
}

/// `base_params = { name = value }`: parameters of the base spec set by this spec (a user's
/// override of the same name wins). Relative paths resolve against this file's directory.
pub(super) fn base_params(
    table: &[Entry],
    path: &Path,
    base_overrides: &mut Vec<Override>,
    d: &mut Diagnostics,
) {
    let get = |k: &str| get(table, k);
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
}

/// What `[agents]` says about the env as a whole.
pub(super) struct Header {
    pub body_clip: Option<(f64, f64)>,
    pub doc: String,
    pub id: String,
    pub parity: String,
    pub first_element_bounds: bool,
}

pub(super) fn header(table: &[Entry], path: &Path, d: &mut Diagnostics) -> Header {
    let get = |k: &str| get(table, k);
    let body_clip = get("body_clip").and_then(|v| range(v, "agents.body_clip", d));
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
    Header {
        body_clip,
        doc,
        id,
        parity,
        first_element_bounds,
    }
}

/// The categories each depth observes (the last entry serves deeper levels too) and the
/// globals' categories.
pub(super) struct Categories {
    pub local: Vec<Vec<String>>,
    pub global: Vec<String>,
}

pub(super) fn categories(table: &[Entry], d: &mut Diagnostics) -> Categories {
    let get = |k: &str| get(table, k);
    let local_categories: Vec<Vec<String>> = match get("local_categories") {
        None => vec![vec!["qpos".into(), "qvel".into()], vec!["qpos".into()]],
        Some(v) => match &v.kind {
            ValKind::Array(a) if !a.is_empty() => a
                .iter()
                .map(|x| {
                    str_list(x, "agents.local_categories[]", d)
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
        Some(v) => str_list(v, "agents.global_categories", d)
            .into_iter()
            .map(|s| s.0)
            .collect(),
    };
    Categories {
        local: local_categories,
        global: global_categories,
    }
}

/// The conf (`SINGLE_AGENT` for single-agent mode) and depth chosen by the overrides or the
/// spec; `confs` names the spec's confs. An unknown conf is reported only when nothing else is
/// wrong (E0203 for an override, E0104 for the spec's key).
pub(super) fn choice(
    table: &[Entry],
    layer: &LayerOverrides,
    confs: &[String],
    d: &mut Diagnostics,
) -> (String, usize) {
    let get = |k: &str| get(table, k);
    let (conf_override, k_override, single_override) = (&layer.conf, layer.k, layer.single);
    let conf_name = match (conf_override, get("agent_conf")) {
        _ if single_override => SINGLE_AGENT.to_string(),
        (Some(c), _) => c.clone(),
        (None, Some(v)) => v.as_str().unwrap_or("").to_string(),
        (None, None) => confs
            .first()
            .cloned()
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
    let chosen = confs.iter().find(|c| **c == conf_name);
    let single = conf_name == SINGLE_AGENT && chosen.is_none();
    if chosen.is_none() && !single && d.is_empty() {
        let mut names: Vec<&str> = confs.iter().map(String::as_str).collect();
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
    (conf_name, k)
}
