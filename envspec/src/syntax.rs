//! The spec as written: sections and named tables with their locations, checked for unknown keys,
//! missing keys and unknown kinds. Typed interpretation (parameters, selectors, model names) is the
//! resolver's job; this layer needs no model.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::value::{Entry, Val, ValKind, parse_document};

/// A named table such as `[reward.ctrl]`.
#[derive(Clone, Debug)]
pub struct Section {
    /// The table's name, e.g. `ctrl` for `[reward.ctrl]`.
    pub name: String,
    /// Where the name is written in the header.
    pub name_loc: Location,
    /// The whole table.
    pub loc: Location,
    /// Its keys, in document order.
    pub entries: Vec<Entry>,
}

impl Section {
    /// The value of `key`, if written.
    pub fn get(&self, key: &str) -> Option<&Val> {
        self.entries.iter().find(|e| e.key == key).map(|e| &e.value)
    }
    /// The value of `key`, if it is a string.
    pub fn str(&self, key: &str) -> Option<&str> {
        self.get(key).and_then(Val::as_str)
    }
    /// The `kind` key (or the section's default kind).
    pub fn kind<'a>(&'a self, default: &'a str) -> &'a str {
        self.str("kind").unwrap_or(default)
    }
    /// The `doc` key, or empty.
    pub fn doc(&self) -> String {
        self.str("doc").unwrap_or("").to_string()
    }
}

/// A declared parameter.
#[derive(Clone, Debug)]
pub struct ParamDecl {
    /// The parameter's name.
    pub name: String,
    /// Where the name is written.
    pub name_loc: Location,
    /// The default value as written (typed by the resolver).
    pub default: Val,
    /// The `doc` text of the long form (empty in the short form).
    pub doc: String,
    /// Explicit `type = "..."` from the long form.
    pub ty: Option<(String, Location)>,
    /// `fixed = true`: part of the spec, but not a constructor argument (overrides are refused).
    pub fixed: bool,
}

/// A parsed, key-checked spec file.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The spec's text, for locations.
    pub file: Arc<SourceFile>,
    /// `[env] id`, e.g. `Ant-v5`.
    pub id: String,
    /// Where the id is written.
    pub id_loc: Location,
    /// `[env] description`.
    pub description: String,
    /// `[env] reward_threshold`: the return at which the task counts as solved (Gymnasium's).
    pub reward_threshold: Option<f64>,
    /// `[env] entry_point`: the Python class that builds the same env (`module.path:Class`),
    /// written into dataset metadata so Python can recover the env.
    pub entry_point: Option<String>,
    /// `[params]`, in document order.
    pub params: Vec<ParamDecl>,
    /// `[observation.<name>]`: the observation's segments, in order.
    pub observation: Vec<Section>,
    /// `[reward] sum`: the order and grouping in which terms are added.
    pub reward_sum: Option<Val>,
    /// `[reward.<name>]`: the reward terms.
    pub reward: Vec<Section>,
    /// `[health] terminate`: whether an unhealthy state ends the episode.
    pub health_terminate: Option<Val>,
    /// `[health.<name>]`: the health checks.
    pub health: Vec<Section>,
    /// `[reset.<name>]`: the reset steps, in order.
    pub reset: Vec<Section>,
    /// `[info.<name>]`: the info entries.
    pub info: Vec<Section>,
    /// `[termination.<name>]`: conditions that end the episode (beside health).
    pub termination: Vec<Section>,
    /// `[actuators.<name>]`: actuators added to the model when it is loaded.
    pub actuators: Vec<Section>,
    /// `[joint_properties."<glob>"]`: joint and actuator properties by joint-name pattern, one
    /// section per row (its name is the pattern), in file order.
    pub joint_properties: Vec<Section>,
    /// `[geom_properties."<glob>"]`: contact properties by geom-name pattern, one section per
    /// row (its name is the pattern), in file order.
    pub geom_properties: Vec<Section>,
    /// `[keyframes.<name>]`: keyframes added to the model, by joint name or pattern.
    pub keyframes: Vec<Section>,
    /// `[physics]`: simulation options set when the model is loaded.
    pub physics: Option<Section>,
    /// `[bodies.<name>]`, `[sites.<name>]`, `[geoms.<name>]`, `[cameras.<name>]`,
    /// `[lights.<name>]`: elements added to the model when it is loaded, in that table order.
    pub added: Vec<(AddedKind, Section)>,
    /// `[commands.<name>]`: command vectors (velocity commands, …), in declared order.
    pub commands: Vec<Section>,
    /// `[derived.<name>]` tables, in document order.
    pub derived: Vec<Section>,
    /// `[actions]`: PD position targets.
    pub actions: Option<Section>,
    /// `[latency]`: action latency (`envspec::noise`).
    pub latency: Option<Section>,
    /// `[events.<name>]`: domain randomization and pushes (`envspec::events`).
    pub events: Vec<Section>,
    /// `[terrain]` with its `[terrain.<tile>]` generators (`envspec::resolve::terrain` checks
    /// the keys).
    pub terrain: Option<Section>,
    /// `[init]`: what runs once before the first reset (`envspec::manipulation`).
    pub init: Option<Section>,
    /// `[end_effector]`: Cartesian actions through a mocap body.
    pub end_effector: Option<Section>,
    /// `[goal]`: a goal-conditioned task (dict observations, `compute_reward`).
    pub goal: Option<Section>,
    /// `[hold.<name>]`: joints held at a value after every step.
    pub hold: Vec<Section>,
}

/// The kinds of model element a spec can add.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AddedKind {
    /// `[bodies]`.
    Body,
    /// `[sites]`.
    Site,
    /// `[geoms]`.
    Geom,
    /// `[cameras]`.
    Camera,
    /// `[lights]`.
    Light,
}

impl AddedKind {
    /// Each kind with its table name and the keys its entries may have.
    pub const ALL: [(AddedKind, &'static str, &'static [&'static str]); 5] = [
        (
            AddedKind::Body,
            "bodies",
            &[
                "pos", "joints", "geom", "size", "rgba", "mocap", "gravcomp", "mass", "weld", "doc",
            ],
        ),
        (
            AddedKind::Site,
            "sites",
            &["body", "pos", "size", "rgba", "doc"],
        ),
        (
            AddedKind::Geom,
            "geoms",
            &[
                "body", "type", "pos", "size", "rgba", "contact", "mass", "density", "doc",
            ],
        ),
        (
            AddedKind::Camera,
            "cameras",
            &["body", "pos", "xyaxes", "fovy", "doc"],
        ),
        (AddedKind::Light, "lights", &["body", "pos", "dir", "doc"]),
    ];
}

impl Spec {
    /// The spec file.
    pub fn path(&self) -> &Path {
        &self.file.path
    }
    /// The spec's directory (relative model paths resolve against it).
    pub fn dir(&self) -> PathBuf {
        self.file
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }
    /// The declaration of parameter `name`.
    pub fn param(&self, name: &str) -> Option<&ParamDecl> {
        self.params.iter().find(|p| p.name == name)
    }

    /// Read and check a spec file.
    pub fn load(path: &Path) -> Result<Spec, Diagnostics> {
        let (file, root) = crate::value::read_document(path, None, "spec")?;
        Spec::from_document(&file, &root)
    }

    /// Check a spec given as text (`path` is used for messages and relative model paths).
    pub fn parse(path: &Path, text: String) -> Result<Spec, Diagnostics> {
        let file = SourceFile::new(path, text);
        let root = parse_document(&file)?;
        Spec::from_document(&file, &root)
    }

    /// Check a spec file already read and parsed (the one door reads each file once).
    pub fn from_document(file: &Arc<SourceFile>, root: &Val) -> Result<Spec, Diagnostics> {
        let mut d = Diagnostics::default();
        let spec = read_spec(file, root, &mut d);
        d.into_result(spec)
    }
}

pub(crate) const TOP_KEYS: &[&str] = &[
    "env",
    "params",
    "observation",
    "reward",
    "health",
    "reset",
    "info",
    "termination",
    "actuators",
    "joint_properties",
    "geom_properties",
    "keyframes",
    "physics",
    "bodies",
    "sites",
    "geoms",
    "cameras",
    "lights",
    "latency",
    "agents",
    "maze",
    "commands",
    "actions",
    "events",
    "terrain",
    "init",
    "end_effector",
    "goal",
    "hold",
    "derived",
];
const ENV_KEYS: &[&str] = &["id", "description", "reward_threshold", "entry_point"];

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
const PARAM_KEYS: &[&str] = &["default", "doc", "type", "fixed"];
pub(crate) const PARAM_TYPES: &[&str] = &[
    "bool", "int", "float", "range", "string", "path", "body", "table",
];
const SEGMENT_KEYS: &[&str] = &[
    "source",
    "minus",
    "apply",
    "clip",
    "when",
    "drop_first",
    "noise",
    "delay",
    "scale",
    "indicator",
    "doc",
];
/// Keys of an observation segment's `noise` table.
pub const NOISE_KEYS: &[&str] = &["kind", "scale", "level", "when"];
/// Keys of `[latency]`.
pub const LATENCY_KEYS: &[&str] = &["action", "doc"];

/// Term kinds of `[reward.*]` with the keys each accepts besides kind, weight, cost, info, doc.
pub const REWARD_KINDS: &[(&str, &[&str])] = &[
    ("velocity", &["source"]),
    ("healthy", &["paid_when_unhealthy"]),
    ("sum_squares", &["source", "clip_input", "clip"]),
    ("norm", &["source", "minus"]),
    ("quadratic", &["source", "coefs", "targets"]),
    ("value", &["source", "divide_by"]),
    ("constant", &[]),
    ("weighted_square", &["source", "target"]),
    ("goal_sparse", GOAL_KEYS),
    ("goal_dense", &["achieved", "desired", "norm"]),
    ("goal_missed", GOAL_KEYS),
    ("goal_distance", &["achieved", "desired", "norm"]),
    ("goals_missed", &["checks"]),
    ("tracking", &["source", "target", "coefs", "sigma", "zero"]),
    ("sum_abs", &["source", "minus", "gate"]),
    ("action_rate", &[]),
    ("feet_air_time", &["feet", "floor", "threshold", "gate"]),
    ("feet_slip", &["feet", "floor", "sites", "gate"]),
    ("joint_limits", &["source", "factor", "about"]),
    (
        "posture",
        &["source", "minus", "std", "speed", "thresholds"],
    ),
    (
        "feet_clearance",
        &["sites", "target_height", "max_height", "power", "gate"],
    ),
    (
        "feet_swing_height",
        &[
            "feet",
            "floor",
            "sites",
            "target_height",
            "max_height",
            "gate",
        ],
    ),
    ("soft_landing", &["feet", "floor", "gate"]),
    ("self_collisions", &["subtree", "threshold"]),
];
/// Kinds of `[derived.<name>]` with the keys each accepts besides `DERIVED_COMMON`.
pub const DERIVED_KINDS: &[(&str, &[&str])] = &[
    ("difference", &["minus", "divide_by"]),
    ("norm", &["minus"]),
    ("dot", &["with"]),
    ("contact", &["between", "value"]),
];
const DERIVED_COMMON: &[&str] = &["kind", "source", "at", "doc"];
/// Keys of `[commands.<name>]`.
pub const COMMAND_KEYS: &[&str] = &[
    "components",
    "resample_seconds",
    "standing_probability",
    "doc",
];
/// Keys of `[actions]`.
pub const ACTION_KEYS: &[&str] = &[
    "kind",
    "scale",
    "default_pose",
    "range",
    "kp",
    "kd",
    "damping",
    "doc",
];
/// Keys of a goal-reaching check (`goal_sparse`, `goal_reached`).
const GOAL_KEYS: &[&str] = &["achieved", "desired", "threshold", "norm"];
const REWARD_COMMON: &[&str] = &[
    "kind", "weight", "cost", "info", "when", "at", "only_if", "unless", "doc",
];

/// Check kinds of `[health.*]` with the keys each accepts besides kind, source, doc.
pub const HEALTH_KINDS: &[(&str, &[&str])] = &[
    ("finite", &[]),
    ("in_range", &["range", "bounds"]),
    ("fails_if", &["op", "value"]),
];

/// Distributions of `[reset.*]` with the keys each accepts besides target, kind, mode, doc.
pub const RESET_KINDS: &[(&str, &[&str])] = &[
    ("uniform", &["scale", "low", "high", "resample_until"]),
    ("normal", &["scale"]),
    ("constant", &["value"]),
    ("keyframe", &["keyframe"]),
    (
        "root_pose",
        &["joint", "x", "y", "z", "roll", "pitch", "yaw"],
    ),
    ("terrain_origin", &["joint", "rows"]),
    (
        "meet",
        &[
            "center",
            "offset",
            "scale",
            "always",
            "one_of",
            "gap",
            "unchanged",
        ],
    ),
    ("rotation", &["axis", "angle", "parallel"]),
    ("unit_quaternion", &[]),
    ("settle", &["steps", "watch", "above", "record"]),
];
/// Keys of `[terrain]` itself (its tables are the tile generators).
pub const TERRAIN_KEYS: &[&str] = &[
    "tile_size",
    "rows",
    "cols",
    "border_width",
    "border_height",
    "seed",
    "layout",
    "difficulty",
    "doc",
];
/// Tile generators of `[terrain.<name>]` with the keys each accepts besides `TILE_COMMON`.
pub const TILE_KINDS: &[(&str, &[&str])] = &[
    ("flat", &[]),
    (
        "pyramid_stairs",
        &[
            "step_height",
            "step_width",
            "platform_width",
            "border_width",
            "inverted",
        ],
    ),
    (
        "pyramid_slope",
        &[
            "slope",
            "platform_width",
            "border_width",
            "inverted",
            "horizontal_scale",
            "vertical_scale",
        ],
    ),
    (
        "random_uniform",
        &[
            "noise",
            "noise_step",
            "border_width",
            "horizontal_scale",
            "vertical_scale",
            "scale_with_difficulty",
        ],
    ),
];
const TILE_COMMON: &[&str] = &["kind", "proportion", "doc"];

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
/// Keys of `[keyframes.<name>]`.
pub const KEYFRAME_KEYS: &[&str] = &["from", "root_pos", "root_quat", "joints", "doc"];

/// Info kinds of `[info.*]` with the keys each accepts besides the common ones (`INFO_COMMON`).
/// `term` takes `term` (a reward term's name) instead of `source`.
pub const INFO_KINDS: &[(&str, &[&str])] = &[
    ("value", &["source", "minus", "in_reset"]),
    ("norm", &["source", "in_reset"]),
    ("velocity", &["source"]),
    ("term", &["term", "unweighted"]),
    ("condition", &["condition", "in_reset"]),
    (
        "goal_reached",
        &[
            "achieved",
            "desired",
            "threshold",
            "norm",
            "strict",
            "in_reset",
        ],
    ),
    ("goals_reached", &["checks", "in_reset"]),
];

/// Condition kinds of `[termination.*]` with the keys each accepts besides kind, when, doc.
pub const TERMINATION_KINDS: &[(&str, &[&str])] = &[("goal_reached", GOAL_KEYS)];
const INFO_COMMON: &[&str] = &["kind", "key", "when", "dtype", "doc"];

/// Actuator kinds of `[actuators.*]` with the keys each accepts besides `ACTUATOR_COMMON`.
pub const ACTUATOR_KINDS: &[(&str, &[&str])] = &[
    ("motor", &[]),
    ("position", &["kp", "kv"]),
    ("velocity", &["kv"]),
];
const ACTUATOR_COMMON: &[&str] = &["joint", "kind", "gear", "ctrlrange", "forcerange", "doc"];
/// Keys of a `[geom_properties]` row: MJCF's `<geom>` contact attributes of the same names.
pub const GEOM_PROPERTY_KEYS: &[&str] = &[
    "contype",
    "conaffinity",
    "condim",
    "priority",
    "friction",
    "solref",
    "solimp",
    "solmix",
    "margin",
    "gap",
];
/// Keys of a `[joint_properties]` row: joint keys, then keys of the joints' added actuators.
pub const JOINT_PROPERTY_KEYS: &[&str] = &[
    "armature",
    "damping",
    "frictionloss",
    "kp",
    "kv",
    "effort",
    "forcerange",
    "ctrlrange",
    "gear",
    "doc",
];
/// Event kinds of `[events.*]` with the keys each accepts besides `EVENT_COMMON`.
pub const EVENT_KINDS: &[(&str, &[&str])] = &[
    (
        "model",
        &[
            "field",
            "elements",
            "distribution",
            "range",
            "mean",
            "std",
            "operation",
            "shared",
        ],
    ),
    ("push", &["elements", "x", "y"]),
];
const EVENT_COMMON: &[&str] = &["kind", "mode", "interval_seconds", "when", "doc"];
/// Keys of `[physics]`.
pub const PHYSICS_KEYS: &[&str] = &[
    "timestep",
    "integrator",
    "forward_before_observation",
    "cone",
    "iterations",
    "ls_iterations",
    "noslip_iterations",
    "ccd_iterations",
    "tolerance",
    "ls_tolerance",
    "impratio",
];

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

// Every top-level table of a task spec in document order, one flat branch each.
#[allow(clippy::too_many_lines)]
fn read_spec(file: &Arc<SourceFile>, root: &Val, d: &mut Diagnostics) -> Spec {
    let top = root.as_table().unwrap_or(&[]);
    check_keys(top, TOP_KEYS, "the spec (top level)", d);
    let get = |k: &str| top.iter().find(|e| e.key == k);
    let whole = Location::new(file, 0..0);

    let mut spec = Spec {
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
    };

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
    // `[agents]` (a multi-agent factorization) is read by envspec::agents; the single-agent env
    // of such a spec ignores it.

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

    spec.reward = sections(get("reward"), "reward", &["sum"], d);
    if let Some(t) = get("reward").and_then(|e| e.value.as_table()) {
        spec.reward_sum = t.iter().find(|e| e.key == "sum").map(|e| e.value.clone());
    }
    for s in &spec.reward {
        check_kinded(s, "reward", None, REWARD_KINDS, REWARD_COMMON, d);
    }

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

    spec.info = sections(get("info"), "info", &[], d);
    for s in &spec.info {
        check_kinded(s, "info", Some("value"), INFO_KINDS, INFO_COMMON, d);
        let needs = match s.kind("value") {
            "term" => "term",
            "goal_reached" => "achieved",
            "goals_reached" => "checks",
            "condition" => "condition",
            _ => "source",
        };
        require(s, needs, &format!("[info.{}]", s.name), d);
    }

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
    if let Some(e) = get("actions")
        && let Some(t) = table(&e.value, "[actions]", d)
    {
        check_keys(t, ACTION_KEYS, "[actions]", d);
        spec.actions = Some(Section {
            name: "actions".into(),
            name_loc: e.key_loc.clone(),
            loc: e.value.loc.clone(),
            entries: t.to_vec(),
        });
    }
    if let Some(e) = get("terrain")
        && let Some(t) = table(&e.value, "[terrain]", d)
    {
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
        spec.terrain = Some(terrain);
    }
    spec.events = sections(get("events"), "events", &[], d);
    for s in &spec.events {
        check_kinded(s, "events", Some("model"), EVENT_KINDS, EVENT_COMMON, d);
    }
    if let Some(e) = get("physics")
        && let Some(t) = table(&e.value, "[physics]", d)
    {
        check_keys(t, PHYSICS_KEYS, "[physics]", d);
        spec.physics = Some(Section {
            name: "physics".into(),
            name_loc: e.key_loc.clone(),
            loc: e.value.loc.clone(),
            entries: t.to_vec(),
        });
    }
    if let Some(e) = get("latency")
        && let Some(t) = table(&e.value, "[latency]", d)
    {
        check_keys(t, LATENCY_KEYS, "[latency]", d);
        spec.latency = Some(Section {
            name: "latency".into(),
            name_loc: e.key_loc.clone(),
            loc: e.value.loc.clone(),
            entries: t.to_vec(),
        });
    }
    for (name, keys, slot) in [
        ("init", crate::manipulation::INIT_KEYS, &mut spec.init),
        (
            "end_effector",
            crate::manipulation::END_EFFECTOR_KEYS,
            &mut spec.end_effector,
        ),
        ("goal", crate::manipulation::GOAL_TABLE_KEYS, &mut spec.goal),
    ] {
        if let Some(e) = get(name)
            && let Some(t) = table(&e.value, &format!("[{name}]"), d)
        {
            check_keys(t, keys, &format!("[{name}]"), d);
            *slot = Some(Section {
                name: name.into(),
                name_loc: e.key_loc.clone(),
                loc: e.value.loc.clone(),
                entries: t.to_vec(),
            });
        }
    }
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
    spec
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
