//! The keys and kinds each table of a task spec accepts, which the reader checks a spec against.

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
pub(super) const ENV_KEYS: &[&str] = &["id", "description", "reward_threshold", "entry_point"];

pub(super) const PARAM_KEYS: &[&str] = &["default", "doc", "type", "fixed"];
pub(crate) const PARAM_TYPES: &[&str] = &[
    "bool", "int", "float", "range", "string", "path", "body", "table", "names",
];
pub(super) const SEGMENT_KEYS: &[&str] = &[
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
pub const NOISE_KEYS: &[&str] = &["kind", "scale", "level", "order", "when"];
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
    ("parts_reached", &[]),
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
pub(super) const DERIVED_COMMON: &[&str] = &["kind", "source", "at", "doc"];
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
    "from",
    "velocity",
    "position",
    "doc",
];
/// Keys of a goal-reaching check (`goal_sparse`, `goal_reached`).
pub(super) const GOAL_KEYS: &[&str] = &["achieved", "desired", "threshold", "norm"];
pub(super) const REWARD_COMMON: &[&str] = &[
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
pub(super) const TILE_COMMON: &[&str] = &["kind", "proportion", "doc"];
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
    ("goal_parts", &["which", "in_reset"]),
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
pub(super) const INFO_COMMON: &[&str] = &["kind", "key", "when", "dtype", "doc"];

/// Actuator kinds of `[actuators.*]` with the keys each accepts besides `ACTUATOR_COMMON`.
pub const ACTUATOR_KINDS: &[(&str, &[&str])] = &[
    ("motor", &[]),
    ("position", &["kp", "kv"]),
    ("velocity", &["kv"]),
];
pub(super) const ACTUATOR_COMMON: &[&str] =
    &["joint", "kind", "gear", "ctrlrange", "forcerange", "doc"];
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
pub(super) const EVENT_COMMON: &[&str] = &["kind", "mode", "interval_seconds", "when", "doc"];
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
