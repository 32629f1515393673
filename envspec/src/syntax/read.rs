//! Reading a task spec's document into a [`Spec`]: each top-level table by its reader, in document
//! order (the order of the checks, so of the diagnostics), its keys and kinds checked against `keys`.

use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::value::{Entry, Val, ValKind};

use super::keys::*;
use super::{AddedKind, ParamDecl, Section, Spec};

/// E0111 for an id Gymnasium cannot register under `envc/`: its grammar is
/// `[namespace/]name[-vN]` with `[\w:.-]` characters; envc supplies the namespace, so the id is
/// one name (`envc.make` would fail with Gymnasium's "Malformed environment ID" otherwise).
pub fn env_id_problem(id: &str, at: Location) -> Option<Diagnostic> {
    let bad = id
        .chars()
        .find(|c| !(c.is_alphanumeric() || matches!(c, '_' | ':' | '.' | '-')));
    let why = match bad {
        _ if id.is_empty() => "it is empty".to_string(),
        Some('/') => "it contains `/` (envc registers it as `envc/<id>`)".to_string(),
        Some(c) => format!("it contains {c:?}"),
        None => return None,
    };
    Some(
        Diagnostic::new(
            Code::E0111,
            format!("`{id}` is not an id Gymnasium can register: {why}"),
        )
        .at(at)
        .label("expected letters, digits, `_`, `:`, `.` and `-`, e.g. \"MyRobot-v0\""),
    )
}

/// The `[terrain.<name>]` tables of `[terrain]`'s entries, as sections.
pub fn terrain_tiles(entries: &[Entry]) -> Vec<Section> {
    entries
        .iter()
        .filter_map(|e| {
            Some(Section {
                name: e.key.clone(),
                name_loc: e.key_loc.clone(),
                loc: e.value.loc.clone(),
                entries: e.value.as_table()?.to_vec(),
            })
        })
        .collect()
}

fn unknown_key(entry: &Entry, context: &str, allowed: &[&str]) -> Diagnostic {
    Diagnostic::new(
        Code::E0101,
        format!("unknown key `{}` in {context}", entry.key),
    )
    .at(entry.key_loc.clone())
    .label(format!("expected one of: {}", allowed.join(", ")))
    .help_opt(suggest(&entry.key, allowed.iter().copied()))
}

fn check_keys(entries: &[Entry], allowed: &[&str], context: &str, d: &mut Diagnostics) {
    for e in entries {
        if !allowed.contains(&e.key.as_str()) {
            d.push(unknown_key(e, context, allowed));
        }
    }
}

fn table<'a>(v: &'a Val, what: &str, d: &mut Diagnostics) -> Option<&'a [Entry]> {
    match v.as_table() {
        Some(t) => Some(t),
        None => {
            d.push(v.type_error(what, "a table"));
            None
        }
    }
}

/// `module.path:Class` as Gymnasium's `load_env_creator` splits it: a dotted module path and one
/// attribute, each part a Python identifier.
fn is_entry_point(s: &str) -> bool {
    let ident = |p: &str| {
        p.chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
            && p.chars().all(|c| c.is_alphanumeric() || c == '_')
    };
    s.split_once(':')
        .is_some_and(|(module, class)| module.split('.').all(ident) && ident(class))
}

/// Every top-level table of a task spec, each read by its reader in document order.
pub(super) fn read_spec(file: &Arc<SourceFile>, root: &Val, d: &mut Diagnostics) -> Spec {
    let top = root.as_table().unwrap_or(&[]);
    check_keys(top, TOP_KEYS, "the spec (top level)", d);
    let get = |k: &str| top.iter().find(|e| e.key == k);
    let whole = Location::new(file, 0..0);

    let mut spec = empty_spec(file, &whole);

    if let Some(e) = get("maze") {
        // A `[maze]` file is a maze spec (envspec::maze), run by envc's MazeEnv, not a task spec.
        d.push(
            Diagnostic::new(
                Code::E0108,
                "`[maze]` makes this a maze spec, not a robot task spec",
            )
            .at(e.key_loc.clone())
            .label("a maze spec")
            .help("load it as a maze (`envc::MazeEnv`, or any `envc` command)"),
        );
    }
    // `[agents]` (a multi-agent factorization) is read by envspec::multi_agent; the single-agent env
    // of such a spec ignores it.

    read_env(top, &whole, &mut spec, d);
    read_params(top, &whole, &mut spec, d);
    read_observation(top, &mut spec, d);
    read_reward(top, &mut spec, d);
    read_health(top, &mut spec, d);
    read_reset(top, &mut spec, d);
    read_info(top, &mut spec, d);
    read_termination(top, &mut spec, d);
    read_model_edits(top, &mut spec, d);
    read_derived(top, &mut spec, d);
    read_commands(top, &mut spec, d);
    spec.actions = one_table(top, "actions", ACTION_KEYS, d);
    spec.terrain = read_terrain(top, d);
    read_events(top, &mut spec, d);
    spec.physics = one_table(top, "physics", PHYSICS_KEYS, d);
    spec.latency = one_table(top, "latency", LATENCY_KEYS, d);
    read_manipulation(top, &mut spec, d);
    spec
}

/// A spec with nothing read yet (its id at the start of the file).
fn empty_spec(file: &Arc<SourceFile>, whole: &Location) -> Spec {
    Spec {
        file: Arc::clone(file),
        id: String::new(),
        id_loc: whole.clone(),
        description: String::new(),
        reward_threshold: None,
        entry_point: None,
        params: vec![],
        observation: vec![],
        reward_sum: None,
        reward: vec![],
        health_terminate: None,
        health: vec![],
        termination: vec![],
        reset: vec![],
        info: vec![],
        actuators: vec![],
        joint_properties: vec![],
        geom_properties: vec![],
        keyframes: vec![],
        physics: None,
        added: vec![],
        commands: vec![],
        derived: vec![],
        actions: None,
        latency: None,
        events: vec![],
        terrain: None,
        init: None,
        end_effector: None,
        goal: None,
        hold: vec![],
    }
}

/// A top-level table read as one section (`[actions]`, `[physics]`, `[init]`, …), its keys
/// checked against `keys`.
fn one_table(top: &[Entry], name: &str, keys: &[&str], d: &mut Diagnostics) -> Option<Section> {
    let e = top.iter().find(|e| e.key == name)?;
    let t = table(&e.value, &format!("[{name}]"), d)?;
    check_keys(t, keys, &format!("[{name}]"), d);
    Some(Section {
        name: name.into(),
        name_loc: e.key_loc.clone(),
        loc: e.value.loc.clone(),
        entries: t.to_vec(),
    })
}

/// `[env]`: the id (which Gymnasium must be able to register), description, reward threshold
/// and entry point.
fn read_env(top: &[Entry], whole: &Location, spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    match get("env") {
        None => d.push(
            Diagnostic::new(Code::E0103, "missing `[env]` table")
                .at(whole.clone())
                .label("expected an [env] table with at least `id`"),
        ),
        Some(e) => {
            if let Some(t) = table(&e.value, "[env]", d) {
                check_keys(t, ENV_KEYS, "[env]", d);
                match t.iter().find(|e| e.key == "id") {
                    Some(idv) => match idv.value.as_str() {
                        Some(s) => {
                            spec.id = s.to_string();
                            spec.id_loc = idv.value.loc.clone();
                            if let Some(d_) = env_id_problem(s, idv.value.loc.clone()) {
                                d.push(d_);
                            }
                        }
                        None => d.push(idv.value.type_error("env.id", "a string")),
                    },
                    None => d.push(
                        Diagnostic::new(Code::E0103, "missing `id` in [env]")
                            .at(e.key_loc.clone())
                            .label("expected `id = \"Name-v0\"`"),
                    ),
                }
                if let Some(v) = t.iter().find(|e| e.key == "description") {
                    match v.value.as_str() {
                        Some(s) => spec.description = s.to_string(),
                        None => d.push(v.value.type_error("env.description", "a string")),
                    }
                }
                if let Some(v) = t.iter().find(|e| e.key == "reward_threshold") {
                    match v.value.as_f64() {
                        Some(x) => spec.reward_threshold = Some(x),
                        None => d.push(v.value.type_error("env.reward_threshold", "a number")),
                    }
                }
                if let Some(v) = t.iter().find(|e| e.key == "entry_point") {
                    match v.value.as_str() {
                        Some(s) if is_entry_point(s) => spec.entry_point = Some(s.to_string()),
                        Some(s) => d.push(
                            Diagnostic::new(
                                Code::E0104,
                                format!("`{s}` is not a Python entry point"),
                            )
                            .at(v.value.loc.clone())
                            .label("expected `module.path:Class`")
                            .help("e.g. `entry_point = \"gymnasium.envs.mujoco.ant_v5:AntEnv\"`"),
                        ),
                        None => d.push(v.value.type_error("env.entry_point", "a string")),
                    }
                }
            }
        }
    }
}

/// `[params]`, each declaration read by `read_param`, and the parameters every spec declares.
fn read_params(top: &[Entry], whole: &Location, spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    if let Some(e) = get("params")
        && let Some(t) = table(&e.value, "[params]", d)
    {
        for p in t {
            spec.params.push(read_param(p, d));
        }
    }
    for required in ["xml_file", "frame_skip", "max_episode_steps"] {
        if spec.param(required).is_none() {
            d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing parameter `{required}` in [params]"),
                )
                .at_opt(
                    get("params")
                        .map(|e| e.key_loc.clone())
                        .or(Some(whole.clone())),
                )
                .label(format!("every spec declares `{required}`")),
            );
        }
    }
}

/// `[observation.*]`: the segments, each with a `source`.
fn read_observation(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.observation = sections(get("observation"), "observation", &[], d);
    for s in &spec.observation {
        check_keys(
            &s.entries,
            SEGMENT_KEYS,
            &format!("[observation.{}]", s.name),
            d,
        );
        require(s, "source", &format!("[observation.{}]", s.name), d);
    }
}

/// `[reward.*]` terms and `[reward] sum`.
fn read_reward(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.reward = sections(get("reward"), "reward", &["sum"], d);
    if let Some(t) = get("reward").and_then(|e| e.value.as_table()) {
        spec.reward_sum = t.iter().find(|e| e.key == "sum").map(|e| e.value.clone());
    }
    for s in &spec.reward {
        check_kinded(s, "reward", None, REWARD_KINDS, REWARD_COMMON, d);
    }
}

/// `[health.*]` checks and `[health] terminate`.
fn read_health(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.health = sections(get("health"), "health", &["terminate"], d);
    if let Some(t) = get("health").and_then(|e| e.value.as_table()) {
        spec.health_terminate = t
            .iter()
            .find(|e| e.key == "terminate")
            .map(|e| e.value.clone());
    }
    for s in &spec.health {
        check_kinded(
            s,
            "health",
            None,
            HEALTH_KINDS,
            &["kind", "source", "doc"],
            d,
        );
        require(s, "source", &format!("[health.{}]", s.name), d);
    }
}

/// `[reset.*]` steps, each with the key its kind needs.
fn read_reset(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.reset = sections(get("reset"), "reset", &[], d);
    for s in &spec.reset {
        check_kinded(
            s,
            "reset",
            None,
            RESET_KINDS,
            &[
                "target",
                "kind",
                "mode",
                "around",
                "probability",
                "when",
                "doc",
            ],
            d,
        );
        // (a keyframe sets every qpos; a root pose draw finds the free joint's)
        match s.kind("") {
            "keyframe" => require(s, "keyframe", &format!("[reset.{}]", s.name), d),
            "root_pose" | "terrain_origin" | "settle" => {}
            _ => require(s, "target", &format!("[reset.{}]", s.name), d),
        }
    }
}

/// `[info.*]` entries, each with the key its kind reads.
fn read_info(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.info = sections(get("info"), "info", &[], d);
    for s in &spec.info {
        check_kinded(s, "info", Some("value"), INFO_KINDS, INFO_COMMON, d);
        let needs = match s.kind("value") {
            "term" => "term",
            "goal_reached" => "achieved",
            "goals_reached" => "checks",
            "goal_parts" => "which",
            "condition" => "condition",
            _ => "source",
        };
        require(s, needs, &format!("[info.{}]", s.name), d);
    }
}

/// `[termination.*]` conditions.
fn read_termination(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.termination = sections(get("termination"), "termination", &[], d);
    for s in &spec.termination {
        check_kinded(
            s,
            "termination",
            None,
            TERMINATION_KINDS,
            &["kind", "when", "doc"],
            d,
        );
    }
}

/// The model edits: `[actuators.*]`, `[joint_properties]`, `[geom_properties]`,
/// `[keyframes.*]`, and the elements a spec adds (`[bodies.*]`, `[sites.*]`, …).
fn read_model_edits(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.actuators = sections(get("actuators"), "actuators", &[], d);
    for s in &spec.actuators {
        check_kinded(
            s,
            "actuators",
            Some("motor"),
            ACTUATOR_KINDS,
            ACTUATOR_COMMON,
            d,
        );
        require(s, "joint", &format!("[actuators.{}]", s.name), d);
    }
    spec.joint_properties = sections(get("joint_properties"), "joint_properties", &[], d);
    for s in &spec.joint_properties {
        check_keys(
            &s.entries,
            JOINT_PROPERTY_KEYS,
            &format!("[joint_properties.\"{}\"]", s.name),
            d,
        );
    }
    spec.geom_properties = sections(get("geom_properties"), "geom_properties", &[], d);
    for s in &spec.geom_properties {
        check_keys(
            &s.entries,
            GEOM_PROPERTY_KEYS,
            &format!("[geom_properties.\"{}\"]", s.name),
            d,
        );
    }
    spec.keyframes = sections(get("keyframes"), "keyframes", &[], d);
    for s in &spec.keyframes {
        check_keys(
            &s.entries,
            KEYFRAME_KEYS,
            &format!("[keyframes.{}]", s.name),
            d,
        );
    }
    for (kind, table_name, keys) in AddedKind::ALL {
        for s in sections(get(table_name), table_name, &[], d) {
            check_keys(&s.entries, keys, &format!("[{table_name}.{}]", s.name), d);
            spec.added.push((kind, s));
        }
    }
}

/// `[derived.*]` values, each with a `source` (a contact value names its geoms or bodies instead).
fn read_derived(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.derived = sections(get("derived"), "derived", &[], d);
    for s in &spec.derived {
        check_kinded(
            s,
            "derived",
            Some("difference"),
            DERIVED_KINDS,
            DERIVED_COMMON,
            d,
        );
        if s.kind("difference") != "contact" {
            require(s, "source", &format!("[derived.{}]", s.name), d);
        }
    }
}

/// `[commands.*]`, each with its `components`.
fn read_commands(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.commands = sections(get("commands"), "commands", &[], d);
    for s in &spec.commands {
        check_keys(
            &s.entries,
            COMMAND_KEYS,
            &format!("[commands.{}]", s.name),
            d,
        );
        require(s, "components", &format!("[commands.{}]", s.name), d);
    }
}

/// `[terrain]`: its own keys, and its `[terrain.<name>]` tile generators by kind.
fn read_terrain(top: &[Entry], d: &mut Diagnostics) -> Option<Section> {
    let e = top.iter().find(|e| e.key == "terrain")?;
    let t = table(&e.value, "[terrain]", d)?;
    let terrain = Section {
        name: "terrain".into(),
        name_loc: e.key_loc.clone(),
        loc: e.value.loc.clone(),
        entries: t.to_vec(),
    };
    let (tiles, keys): (Vec<Entry>, Vec<Entry>) = terrain
        .entries
        .iter()
        .cloned()
        .partition(|e| e.value.as_table().is_some());
    check_keys(&keys, TERRAIN_KEYS, "[terrain]", d);
    for tile in terrain_tiles(&tiles) {
        check_kinded(&tile, "terrain", None, TILE_KINDS, TILE_COMMON, d);
    }
    Some(terrain)
}

/// `[events.*]`, each by kind (`model` by default).
fn read_events(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.events = sections(get("events"), "events", &[], d);
    for s in &spec.events {
        check_kinded(s, "events", Some("model"), EVENT_KINDS, EVENT_COMMON, d);
    }
}

/// The manipulation tables: `[init]`, `[end_effector]`, `[goal]` and `[hold.*]`.
fn read_manipulation(top: &[Entry], spec: &mut Spec, d: &mut Diagnostics) {
    let get = |k: &str| top.iter().find(|e| e.key == k);
    spec.init = one_table(top, "init", crate::manipulation::INIT_KEYS, d);
    spec.end_effector = one_table(
        top,
        "end_effector",
        crate::manipulation::END_EFFECTOR_KEYS,
        d,
    );
    spec.goal = one_table(top, "goal", crate::manipulation::GOAL_TABLE_KEYS, d);
    spec.hold = sections(get("hold"), "hold", &[], d);
    for s in &spec.hold {
        check_keys(
            &s.entries,
            crate::manipulation::HOLD_KEYS,
            &format!("[hold.{}]", s.name),
            d,
        );
        require(s, "joints", &format!("[hold.{}]", s.name), d);
    }
}

fn read_param(p: &Entry, d: &mut Diagnostics) -> ParamDecl {
    let mut decl = ParamDecl {
        name: p.key.clone(),
        name_loc: p.key_loc.clone(),
        default: p.value.clone(),
        doc: String::new(),
        ty: None,
        fixed: false,
    };
    // Long form: a table with a `default` key. A table without one is a table-valued parameter
    // only when it says so with `type = "table"`; otherwise it is an error.
    if let ValKind::Table(t) = &p.value.kind {
        if let Some(def) = t.iter().find(|e| e.key == "default") {
            check_keys(t, PARAM_KEYS, &format!("parameter `{}`", p.key), d);
            decl.default = def.value.clone();
            if let Some(fx) = t.iter().find(|e| e.key == "fixed") {
                match fx.value.kind {
                    ValKind::Bool(b) => decl.fixed = b,
                    _ => d.push(fx.value.type_error("fixed", "true or false")),
                }
            }
            if let Some(doc) = t.iter().find(|e| e.key == "doc") {
                match doc.value.as_str() {
                    Some(s) => decl.doc = s.to_string(),
                    None => d.push(doc.value.type_error("doc", "a string")),
                }
            }
            if let Some(ty) = t.iter().find(|e| e.key == "type") {
                match ty.value.as_str() {
                    Some(s) if PARAM_TYPES.contains(&s) => {
                        decl.ty = Some((s.to_string(), ty.value.loc.clone()))
                    }
                    Some(s) => d.push(
                        Diagnostic::new(Code::E0104, format!("unknown parameter type `{s}`"))
                            .at(ty.value.loc.clone())
                            .label(format!("expected one of: {}", PARAM_TYPES.join(", ")))
                            .help_opt(suggest(s, PARAM_TYPES.iter().copied())),
                    ),
                    None => d.push(ty.value.type_error("type", "a string")),
                }
            }
        } else {
            d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("parameter `{}` is a table without `default`", p.key),
                )
                .at(p.key_loc.clone())
                .label("expected `name = value` or `name = { default = value, doc = \"...\" }`"),
            );
        }
    }
    decl
}

fn sections(
    entry: Option<&Entry>,
    kind: &str,
    reserved: &[&str],
    d: &mut Diagnostics,
) -> Vec<Section> {
    let Some(entry) = entry else { return vec![] };
    let Some(t) = table(&entry.value, &format!("[{kind}]"), d) else {
        return vec![];
    };
    let mut out = vec![];
    for e in t {
        if reserved.contains(&e.key.as_str()) {
            continue;
        }
        match &e.value.kind {
            ValKind::Table(entries) => out.push(Section {
                name: e.key.clone(),
                name_loc: e.key_loc.clone(),
                loc: e.value.loc.clone(),
                entries: entries.clone(),
            }),
            _ => d.push(
                Diagnostic::new(Code::E0102, format!("`{kind}.{}` must be a table", e.key))
                    .at(e.key_loc.clone())
                    .label(if reserved.is_empty() {
                        format!("expected [{kind}.{}] with its keys", e.key)
                    } else {
                        format!(
                            "expected [{kind}.{}] or one of: {}",
                            e.key,
                            reserved.join(", ")
                        )
                    })
                    .help_opt(suggest(&e.key, reserved.iter().copied())),
            ),
        }
    }
    out
}

fn require(s: &Section, key: &str, context: &str, d: &mut Diagnostics) {
    if s.get(key).is_none() {
        d.push(
            Diagnostic::new(Code::E0103, format!("missing `{key}` in {context}"))
                .at(s.name_loc.clone())
                .label(format!("expected a `{key}` key")),
        );
    }
}

/// Check `kind` against the known kinds and the keys against that kind's keys.
fn check_kinded(
    s: &Section,
    section: &str,
    default_kind: Option<&str>,
    kinds: &[(&str, &[&str])],
    common: &[&str],
    d: &mut Diagnostics,
) {
    let context = format!("[{section}.{}]", s.name);
    let names: Vec<&str> = kinds.iter().map(|(k, _)| *k).collect();
    let kind = match (s.get("kind"), default_kind) {
        (Some(v), _) => match v.as_str() {
            Some(k) => match kinds.iter().find(|(n, _)| *n == k) {
                Some(found) => Some(found),
                None => {
                    d.push(
                        Diagnostic::new(
                            Code::E0104,
                            format!("unknown {section} kind `{k}` in {context}"),
                        )
                        .at(v.loc.clone())
                        .label(format!("expected one of: {}", names.join(", ")))
                        .help_opt(suggest(k, names.iter().copied())),
                    );
                    None
                }
            },
            None => {
                d.push(v.type_error("kind", "a string"));
                None
            }
        },
        (None, Some(def)) => kinds.iter().find(|(n, _)| *n == def),
        (None, None) => {
            d.push(
                Diagnostic::new(Code::E0103, format!("missing `kind` in {context}"))
                    .at(s.name_loc.clone())
                    .label(format!("expected kind = one of: {}", names.join(", "))),
            );
            None
        }
    };
    if let Some((_, extra)) = kind {
        let allowed: Vec<&str> = common.iter().chain(extra.iter()).copied().collect();
        check_keys(&s.entries, &allowed, &context, d);
    }
}
