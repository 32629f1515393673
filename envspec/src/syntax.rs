//! The spec as written: sections and named tables with their locations, checked for unknown keys,
//! missing keys and unknown kinds. Typed interpretation (parameters, selectors, model names) is the
//! resolver's job; this layer needs no model.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Diagnostics, Location, SourceFile};
use crate::value::{Entry, Val, parse_document};

mod keys;
mod read;

pub use keys::{
    ACTION_KEYS, ACTUATOR_KINDS, COMMAND_KEYS, DERIVED_KINDS, EVENT_KINDS, GEOM_PROPERTY_KEYS,
    HEALTH_KINDS, INFO_KINDS, JOINT_PROPERTY_KEYS, KEYFRAME_KEYS, LATENCY_KEYS, NOISE_KEYS,
    PHYSICS_KEYS, RESET_KINDS, REWARD_KINDS, TERMINATION_KINDS, TERRAIN_KEYS, TILE_KINDS,
};
pub use read::{env_id_problem, terrain_tiles};

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
        let spec = read::read_spec(file, root, &mut d);
        d.into_result(spec)
    }
}
