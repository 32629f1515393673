//! Manipulation tasks as data: what runs once before the first reset (`[init]`), Cartesian
//! end-effector actions through a mocap body (`[end_effector]`), joints held after every step
//! (`[hold.*]`) and the goal-conditioned task (`[goal]`: dict observations, `compute_reward`).
//! Gymnasium-Robotics' Fetch envs are these tables (`specs/robotics/fetch/`); the language is
//! `docs/spec-reference.md` §22. The resolver is `resolve::manipulation`.

use crate::selector::Selection;

/// Keys of `[init]`.
pub const INIT_KEYS: &[&str] = &[
    "qpos",
    "reset_welds",
    "mocap",
    "settle_steps",
    "record",
    "reset_data",
    "doc",
];
/// Keys of one `[init] mocap` placement.
pub const MOCAP_KEYS: &[&str] = &["body", "site", "offset", "lift", "quat"];
/// Keys of `[end_effector]`.
pub const END_EFFECTOR_KEYS: &[&str] = &[
    "mocap",
    "scale",
    "rotation",
    "gripper",
    "gripper_action",
    "block_gripper",
    "doc",
];
/// Keys of `[goal]`.
pub const GOAL_TABLE_KEYS: &[&str] = &[
    "achieved",
    "marker",
    "marker_site",
    "parts",
    "in_play",
    "threshold",
    "norm",
    "remove_done",
    "terminate_when_done",
    "doc",
];
/// Keys of one `[goal.parts]` row.
pub const GOAL_PART_KEYS: &[&str] = &["achieved", "desired"];
/// Keys of `[hold.<name>]`.
pub const HOLD_KEYS: &[&str] = &["joints", "value", "when", "doc"];

/// The manipulation tables of a spec, resolved (all empty for a spec without them).
#[derive(Clone, Debug, Default)]
pub struct Manipulation {
    /// `[init]`.
    pub init: Option<Init>,
    /// `[end_effector]`.
    pub end_effector: Option<EndEffector>,
    /// `[hold.*]` switched on, in document order.
    pub hold: Vec<Hold>,
    /// `[goal]`.
    pub goal: Option<GoalTable>,
}

impl Manipulation {
    /// Whether the spec declares any of the tables (executors that run none of them refuse such
    /// specs).
    pub fn any(&self) -> bool {
        self.init.is_some()
            || self.end_effector.is_some()
            || !self.hold.is_empty()
            || self.goal.is_some()
    }
    /// The length of the flat vector of `[init] record` values.
    pub fn record_len(&self) -> usize {
        self.init
            .as_ref()
            .map_or(0, |i| i.records.iter().map(|r| r.source.len()).sum())
    }
}

/// `[init]`: run once when the env is made, as Gymnasium-Robotics' `_env_setup`; its end state
/// (qpos, qvel, time) is where every reset starts, instead of the model's `qpos0`.
#[derive(Clone, Debug)]
pub struct Init {
    /// `qpos = { joint = value(s) }`: the joint's qpos address and its values, in table order.
    pub qpos: Vec<(String, usize, Vec<f64>)>,
    /// `reset_welds`: every weld constraint's relative pose becomes the identity (anchor and
    /// offset 0, quaternion w = 1), as `reset_mocap_welds`.
    pub reset_welds: bool,
    /// `mocap`: mocap bodies placed after `mj_forward`, in order.
    pub mocap: Vec<MocapPlacement>,
    /// `settle_steps`: control steps (`frame_skip` × `mj_step` each) run after the placement.
    pub settle_steps: u32,
    /// `record`: values read after settling, which reset draws may start from (`around`).
    pub records: Vec<Record>,
    /// `reset_data` (default true): every reset starts with `mj_resetData`. False: a reset
    /// writes the time, `qpos` and `qvel` alone, so the controls and the solver's warm start
    /// carry over from the last episode (Gymnasium-Robotics' hand manipulation resets so).
    pub reset_data: bool,
}

/// One `[init] mocap` placement: `mocap_pos = site_xpos[site] + offset` (or `offset` alone),
/// `mocap_quat = quat`.
#[derive(Clone, Debug)]
pub struct MocapPlacement {
    /// The mocap body's name (checked against the compiled model).
    pub body: String,
    /// The site the position is relative to.
    pub site: Option<usize>,
    /// Added to the site's position: `offset + [0, 0, lift]`, computed first as the reference
    /// does (`np.array([x, y, z + lift]) + site_xpos`).
    pub offset: [f64; 3],
    /// The mocap quaternion (w, x, y, z), as written (MuJoCo normalizes a copy).
    pub quat: [f64; 4],
}

/// A named value recorded at the end of `[init]`.
#[derive(Clone, Debug)]
pub struct Record {
    /// Its name (`around = "name[...]"`).
    pub name: String,
    /// What is read.
    pub source: Selection,
    /// Where its values start in the flat record vector.
    pub offset: usize,
}

/// `[end_effector]`: the action moves a mocap body welded to the robot, as Gymnasium-Robotics'
/// `mocap_set_action`: `mocap_pos = xpos[welded] + scale · action[0:3]`,
/// `mocap_quat = xquat[welded] + rotation`; `action[3]` (when `gripper_action`) goes to each
/// gripper actuator: `ctrl = action[3]`, or `qpos[joint] + action[3]` for an actuator with a bias
/// (a position servo), as `ctrl_set_action`. The action is clipped to [−1, 1] first.
#[derive(Clone, Debug)]
pub struct EndEffector {
    /// The mocap body's name (its weld partner is found in the compiled model).
    pub mocap: String,
    /// Position scale of `action[0:3]`.
    pub scale: f64,
    /// Added to the welded body's quaternion every step.
    pub rotation: [f64; 4],
    /// Whether the action has a fourth, gripper element.
    pub gripper_action: bool,
    /// The gripper actuators (indices), each given the gripper element.
    pub gripper: Vec<usize>,
    /// Whether the gripper element is replaced by 0 (`block_gripper`).
    pub block_gripper: bool,
}

impl EndEffector {
    /// The action's length.
    pub fn act_dim(&self) -> usize {
        3 + usize::from(self.gripper_action)
    }
}

/// `[hold.<name>]`: after every step's physics, these joints' positions are set to `value`, then
/// `mj_forward` (Gymnasium-Robotics' blocked gripper).
#[derive(Clone, Debug)]
pub struct Hold {
    /// The table's name.
    pub name: String,
    /// qpos addresses of the joints (hinge or slide).
    pub qpos: Vec<usize>,
    /// The value they are held at.
    pub value: f64,
}

/// `[goal]`: a goal-conditioned task. The observation becomes Gymnasium's dict
/// (`observation`, `achieved_goal` = `achieved`, `desired_goal` = the env-held goal vector),
/// and `compute_reward` evaluates the spec's goal reward terms on given goals.
#[derive(Clone, Debug)]
pub struct GoalTable {
    /// What the env has achieved (read after each step, as the observation).
    pub achieved: Selection,
    /// `marker`: a mocap body put at the goal at every reset (a 3-D goal), so the goal is
    /// seen in renders and read as `xpos[marker]`.
    pub marker: Option<String>,
    /// `marker_site`: a site drawn at the 3-D goal in every render (Gymnasium-Robotics' Fetch
    /// `_render_callback`: the site moved to the goal, then `mj_forward`); the site's id.
    pub marker_site: Option<usize>,
    /// `[goal.parts]`: the goal as named parts (observed as dicts of named goals), each with a
    /// fixed desired value, kept as a checklist; `None` for a single goal vector.
    pub parts: Option<GoalParts>,
}

/// A goal made of named parts in play, each done when `‖achieved − desired‖ < threshold`
/// (the norm as `norm` says). The env keeps which parts are still to complete through an
/// episode: `parts_reached` rewards the ones reached, a part reached leaves the list
/// (`remove_done`), and the episode terminates once every part has been reached
/// (`terminate_when_done`): Gymnasium-Robotics' Franka Kitchen.
#[derive(Clone, Debug, PartialEq)]
pub struct GoalParts {
    /// The parts in play, in order; the goal vector is their desired values end to end, and
    /// `achieved` their achieved selections.
    pub parts: Vec<GoalPart>,
    /// The distance below which a part counts as reached (strictly).
    pub threshold: f64,
    /// How a part's distance sums its squares.
    pub norm: crate::goal_norm::GoalNorm,
    /// A part reached leaves the list of parts still to complete.
    pub remove_done: bool,
    /// The episode terminates when every part has been reached at least once.
    pub terminate_when_done: bool,
}

/// One named part of a goal.
#[derive(Clone, Debug, PartialEq)]
pub struct GoalPart {
    /// The name (the key in the observation's goal dicts).
    pub name: String,
    /// Where the part's numbers start in the goal vector.
    pub offset: usize,
    /// Its desired value (the goal vector's numbers from `offset`).
    pub desired: Vec<f64>,
}

impl GoalPart {
    /// The number of goal numbers of the part.
    pub fn len(&self) -> usize {
        self.desired.len()
    }
    /// Whether the part has no numbers (never: the resolver refuses it).
    pub fn is_empty(&self) -> bool {
        self.desired.is_empty()
    }
}
