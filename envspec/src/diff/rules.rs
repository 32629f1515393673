//! The table of diff rules: every change `envc diff` reports is an instance of one rule, with a
//! stable id, the category it belongs to (who it hurts), whether it alters behaviour by default,
//! and a one-line description. `docs/diff-rules.md` lists the same table (a test keeps them equal).
//!
//! Ids are kebab-case, prefixed by the part of the spec they concern; they are never renamed or
//! reused (a retired rule keeps its id out of use). A rule that alters behaviour "by default" may
//! be reported as compatible in one instance when the resolved spec shows no effect; its
//! description says when.

use serde::Serialize;

/// Who a change hurts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    /// The observation's layout (length, order, meaning).
    Observation,
    /// The action's layout.
    Action,
    /// The reward's terms and weights.
    Reward,
    /// Health, termination and the time limit.
    Termination,
    /// The initial-state distribution.
    Reset,
    /// Commands, observation noise and delay, action latency, domain randomization: what the
    /// policy is trained on.
    Randomization,
    /// The compiled model's physics.
    Dynamics,
    /// The constructor's parameters and defaults.
    Parameters,
    /// The `info` entries.
    Info,
    /// Text only: no behaviour changes.
    Documentation,
}

impl Category {
    /// Every category, in report order.
    pub const ALL: &'static [Category] = &[
        Category::Observation,
        Category::Action,
        Category::Reward,
        Category::Termination,
        Category::Reset,
        Category::Randomization,
        Category::Dynamics,
        Category::Parameters,
        Category::Info,
        Category::Documentation,
    ];
    /// The name used in JSON and in docs/diff-rules.md.
    pub fn key(self) -> &'static str {
        match self {
            Category::Observation => "observation",
            Category::Action => "action",
            Category::Reward => "reward",
            Category::Termination => "termination",
            Category::Reset => "reset",
            Category::Randomization => "randomization",
            Category::Dynamics => "dynamics",
            Category::Parameters => "parameters",
            Category::Info => "info",
            Category::Documentation => "documentation",
        }
    }
    /// The section heading in text and Markdown reports.
    pub fn title(self) -> &'static str {
        match self {
            Category::Observation => "observation layout",
            Category::Action => "action layout",
            Category::Reward => "reward",
            Category::Termination => "termination / episode",
            Category::Reset => "reset distribution",
            Category::Randomization => "randomization / training distribution",
            Category::Dynamics => "dynamics",
            Category::Parameters => "parameters",
            Category::Info => "info",
            Category::Documentation => "documentation only",
        }
    }
    /// Who it hurts when the change alters behaviour.
    pub fn impact(self) -> &'static str {
        match self {
            Category::Observation | Category::Action => "breaks trained policies",
            Category::Reward => "returns are no longer comparable",
            Category::Termination => "episode lengths and returns change",
            Category::Reset => "initial states change; returns are not comparable",
            Category::Randomization => {
                "the training distribution changes: policies may not transfer; returns are not comparable"
            }
            Category::Dynamics => "the physics changes; trained policies and returns are affected",
            Category::Parameters => "constructor arguments change",
            Category::Info => "logged info changes",
            Category::Documentation => "no behaviour change",
        }
    }
}

/// One rule of the table.
#[derive(Clone, Copy, Debug)]
pub struct Rule {
    /// The variant naming it in code.
    pub rule: RuleId,
    /// The stable id printed in reports, e.g. `reward-term-key-changed`.
    pub id: &'static str,
    /// The category its changes are reported under.
    pub category: Category,
    /// Whether a change of this rule alters behaviour unless its description says otherwise.
    pub breaking: bool,
    /// What the rule covers (docs/diff-rules.md's table).
    pub description: &'static str,
}

/// `RuleId` (one variant per rule) and `RULES` (in the same order) from one list.
macro_rules! rules {
    ($($var:ident = $id:literal, $cat:ident, $brk:literal, $desc:literal;)*) => {
        /// A rule, by name; [`RuleId::rule`] gives its row of [`RULES`].
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        /// The id of one diff rule (docs/diff-rules.md); each variant's text is its description.
        pub enum RuleId { $(#[doc = $desc] $var),* }

        /// Every rule, in the order of `docs/diff-rules.md`.
        pub const RULES: &[Rule] = &[
            $(Rule { rule: RuleId::$var, id: $id, category: Category::$cat, breaking: $brk, description: $desc }),*
        ];
    };
}

impl RuleId {
    /// The rule's row in `RULES`.
    pub fn rule(self) -> &'static Rule {
        // The macro lists the variants and the table in the same order.
        &RULES[self as usize]
    }
    /// The rule's stable id.
    pub fn id(self) -> &'static str {
        self.rule().id
    }
    /// The rule's category.
    pub fn category(self) -> Category {
        self.rule().category
    }
}

impl Serialize for RuleId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

rules! {
    // The env as a whole.
    EnvIdChanged = "env-id-changed", Documentation, false,
        "The env id changed (a version bump is how a breaking change is announced).";
    EnvDescriptionChanged = "env-description-changed", Documentation, false,
        "The env's description changed.";
    EnvRewardThresholdChanged = "env-reward-threshold-changed", Documentation, false,
        "`reward_threshold` (the return a run counts as solving the task at) changed; no rollout changes.";
    EnvEntryPointChanged = "env-entry-point-changed", Documentation, false,
        "The Python entry point datasets name for the env changed (recover_environment builds another class).";
    DocChanged = "doc-changed", Documentation, false,
        "The `doc` of a section, an info table or a parameter changed.";
    SelectorRespelled = "selector-respelled", Documentation, false,
        "A selector was written another way that selects the same elements in the same order (`qpos[0:7]` → `qpos[:7]`): shown, but no change (the verdict ignores it).";
    EnvDtChanged = "env-dt-changed", Dynamics, true,
        "The control step `dt = timestep × frame_skip` changed: velocities, costs per step and episode durations change.";

    // Parameters.
    ParamAdded = "param-added", Parameters, false,
        "A parameter was added; callers that do not pass it get its default (its uses are listed).";
    ParamRemoved = "param-removed", Parameters, true,
        "A parameter was removed: callers that pass it fail.";
    ParamNowArgument = "param-now-argument", Parameters, false,
        "A `fixed` parameter became a constructor argument (a new option).";
    ParamNowFixed = "param-now-fixed", Parameters, true,
        "A constructor argument became `fixed`: callers that pass it fail.";
    ParamDefaultUnused = "param-default-unused", Parameters, false,
        "A parameter's default changed, but nothing in the env's behaviour reads it.";
    ParamDefaultObservation = "param-default-observation", Observation, true,
        "A parameter's default changed and an observation segment reads it (its most harmful use decides the category).";
    ParamDefaultReward = "param-default-reward", Reward, true,
        "A parameter's default changed and a reward term or the sum reads it (and no observation segment).";
    ParamDefaultTermination = "param-default-termination", Termination, true,
        "A parameter's default changed and a health check, the termination switch or the time limit reads it.";
    ParamDefaultReset = "param-default-reset", Reset, true,
        "A parameter's default changed and a reset step reads it.";
    ParamDefaultDynamics = "param-default-dynamics", Dynamics, true,
        "The default of `xml_file` or `frame_skip` changed (the compiled models are compared too).";
    ParamDefaultInfo = "param-default-info", Info, true,
        "A parameter's default changed and only info entries read it.";
    ParamDefaultRandomization = "param-default-randomization", Randomization, true,
        "A parameter's default changed and observation noise, an observation delay or the action latency reads it (and nothing more harmful).";

    // Observation.
    ObservationLayoutChanged = "observation-layout-changed", Observation, true,
        "The resolved observation vector differs: elements added, removed, moved, or their values computed differently (witness: indices and element names).";
    ObservationSegmentAdded = "observation-segment-added", Observation, true,
        "An `[observation.*]` segment was added; compatible when the resolved layout is unchanged (e.g. switched off by default).";
    ObservationSegmentRemoved = "observation-segment-removed", Observation, true,
        "An `[observation.*]` segment was removed; compatible when the resolved layout is unchanged.";
    ObservationSegmentRenamed = "observation-segment-renamed", Observation, true,
        "A segment was renamed (same keys, other name); compatible when the resolved layout is unchanged.";
    ObservationSegmentKeyChanged = "observation-segment-key-changed", Observation, true,
        "A key of a segment was added, removed or changed; compatible when the resolved layout is unchanged.";
    ObservationSegmentResolvedChanged = "observation-segment-resolved-changed", Observation, true,
        "A segment's text is unchanged but it resolves differently (a parameter default or the model changed under it).";

    // Observation noise and delay, action latency (the training distribution).
    NoiseAdded = "noise-added", Randomization, true,
        "Observation noise was added to a segment, or switched on under the default parameters: the policy trains on noisy values (witness: the standard deviation).";
    NoiseRemoved = "noise-removed", Randomization, true,
        "Observation noise was removed from a segment, or switched off under the default parameters.";
    NoiseChanged = "noise-changed", Randomization, true,
        "A segment's noise distribution or amplitude changed under the default parameters (witness: the standard deviation before and after, and their ratio).";
    LatencyObservationChanged = "latency-observation-changed", Randomization, true,
        "A segment's observation delay changed (steps and seconds): the policy sees older or newer values.";
    LatencyActionChanged = "latency-action-changed", Randomization, true,
        "The action latency changed (steps and seconds): actions take effect later or sooner.";

    // Reward.
    RewardTermAdded = "reward-term-added", Reward, true,
        "A reward term was added; compatible when switched off under the default parameters.";
    RewardTermRemoved = "reward-term-removed", Reward, true,
        "A reward term was removed; compatible when it was switched off under the default parameters.";
    RewardTermRenamed = "reward-term-renamed", Reward, true,
        "A reward term was renamed (same keys); compatible when the resolved term is unchanged.";
    RewardTermKeyChanged = "reward-term-key-changed", Reward, true,
        "A key of a reward term changed; compatible when the resolved term is unchanged (e.g. a weight spelt as a parameter with the same value).";
    RewardTermResolvedChanged = "reward-term-resolved-changed", Reward, true,
        "A reward term's text is unchanged but it resolves differently under the default parameters.";
    RewardSumChanged = "reward-sum-changed", Reward, true,
        "The terms summed or their grouping changed (the grouping decides the last bit of the reward).";

    // Health and episodes.
    HealthCheckAdded = "health-check-added", Termination, true,
        "A health check was added; compatible when switched off under the default parameters.";
    HealthCheckRemoved = "health-check-removed", Termination, true,
        "A health check was removed; compatible when it was switched off under the default parameters.";
    HealthCheckRenamed = "health-check-renamed", Termination, true,
        "A health check was renamed (same keys); compatible when the resolved check is unchanged.";
    HealthCheckKeyChanged = "health-check-key-changed", Termination, true,
        "A key of a health check changed; compatible when the resolved check is unchanged.";
    HealthCheckResolvedChanged = "health-check-resolved-changed", Termination, true,
        "A health check's text is unchanged but it resolves differently under the default parameters.";
    TerminationAdded = "termination-added", Termination, true,
        "A termination condition was added; compatible when switched off under the default parameters.";
    TerminationRemoved = "termination-removed", Termination, true,
        "A termination condition was removed; compatible when it was switched off under the default parameters.";
    TerminationRenamed = "termination-renamed", Termination, true,
        "A termination condition was renamed (same keys); compatible when the resolved condition is unchanged.";
    TerminationKeyChanged = "termination-key-changed", Termination, true,
        "A key of a termination condition changed; compatible when the resolved condition is unchanged.";
    TerminationResolvedChanged = "termination-resolved-changed", Termination, true,
        "A termination condition's text is unchanged but it resolves differently under the default parameters.";
    HealthTerminateChanged = "health-terminate-changed", Termination, true,
        "Whether an unhealthy state ends the episode changed.";

    // Reset.
    ResetStepAdded = "reset-step-added", Reset, true,
        "A reset step was added; compatible when switched off under the default parameters.";
    ResetStepRemoved = "reset-step-removed", Reset, true,
        "A reset step was removed; compatible when it was switched off under the default parameters.";
    ResetStepRenamed = "reset-step-renamed", Reset, true,
        "A reset step was renamed (same keys); compatible when the resolved step is unchanged.";
    ResetStepKeyChanged = "reset-step-key-changed", Reset, true,
        "A key of a reset step changed; compatible when the resolved step is unchanged.";
    ResetStepResolvedChanged = "reset-step-resolved-changed", Reset, true,
        "A reset step's text is unchanged but it resolves differently under the default parameters.";
    ResetDrawOrderChanged = "reset-draw-order-changed", Reset, true,
        "The order of the reset steps both specs have changed: the RNG draws go to other targets.";

    // Info.
    InfoKeyAdded = "info-key-added", Info, true,
        "An info key was added (loggers and wrappers see a new key).";
    InfoKeyRemoved = "info-key-removed", Info, true,
        "An info key was removed.";
    InfoKeyRenamed = "info-key-renamed", Info, true,
        "An info key was renamed (same definition, or the same reward term, under another key).";
    InfoKeyDefinitionChanged = "info-key-definition-changed", Info, true,
        "An info key is computed differently.";
    InfoKeyReportedAtChanged = "info-key-reported-at-changed", Info, true,
        "An info key moved between the step info only and the reset and step infos.";
    InfoTableInactiveRemoved = "info-table-inactive-removed", Info, false,
        "An `[info.*]` table that applied only under non-default parameters was removed.";

    // Compiled models (compared by the runtime; `envc diff --no-model` skips them).
    ModelSizeChanged = "model-size-changed", Dynamics, true,
        "A compiled model size (nq, nv, nbody, njnt, ngeom, nsite, ntendon) changed.";
    ModelActuatorCountChanged = "model-actuator-count-changed", Action, true,
        "The number of actuators (nu, the action dimension) changed.";
    ModelOptionChanged = "model-option-changed", Dynamics, true,
        "A physics option (timestep, gravity, density, viscosity, integrator, solver, iterations and the other solver options) changed.";
    ModelArrayChanged = "model-array-changed", Dynamics, true,
        "A compiled physics array (body mass, inertia, pose; geom friction, size, contact; joint and dof properties; actuator gear, gains, biases, dynamics, types and force range; equality constraints: type, objects, data, solref, solimp) differs (witness: the rows).";
    ModelActuatorArrayChanged = "model-actuator-array-changed", Action, true,
        "An actuator's control range or transmission target changed: the action space or what an action entry drives.";
    ModelQpos0Changed = "model-qpos0-changed", Reset, true,
        "The model's reference configuration qpos0, or a keyframe's qpos, changed: resets (and poses read from keyframes) start elsewhere.";
    ModelBinaryChanged = "model-binary-changed", Dynamics, true,
        "The compiled models differ only outside the compared arrays (visuals, names, other options); breaking when a rollout shows an effect, compatible when it shows none.";
    ModelFileChanged = "model-file-changed", Documentation, false,
        "The spec names another model file, and the two compile to identical models.";

    // Multi-agent factorizations (the base envs are compared with the rules above, subjects `base ...`).
    AgentsConfAdded = "agents-conf-added", Action, false,
        "A factorization (`agent_conf`) was added; existing ones are untouched.";
    AgentsConfRemoved = "agents-conf-removed", Action, true,
        "A factorization was removed: code that asks for it fails.";
    AgentsCountChanged = "agents-count-changed", Action, true,
        "A factorization has another number of agents.";
    AgentsActionsChanged = "agents-actions-changed", Action, true,
        "An agent drives other actuators, or in another order.";
    AgentsActionBoundsChanged = "agents-action-bounds-changed", Action, false,
        "Agents' action bounds switched between actuator 0's range for all and each actuator's own; the space changes only where the ranges differ.";
    AgentsObservationChanged = "agents-observation-changed", Observation, true,
        "An agent's local observation has other elements (witness: the first differing index).";
    AgentsObservationValuesChanged = "agents-observation-values-changed", Observation, true,
        "An agent's local observation has the same elements, clipped or transformed differently.";
    AgentsDefaultConfChanged = "agents-default-conf-changed", Action, true,
        "The default factorization (`agent_conf`) changed: users who pass none get other agents, other action splits and other observations.";
    AgentsDefaultObskChanged = "agents-default-obsk-changed", Observation, true,
        "The default observation depth (`agent_obsk`) changed: users who pass none get other local observations.";

    // Maze specs.
    MazeIdChanged = "maze-id-changed", Documentation, false,
        "The maze env id changed.";
    MazeGridResized = "maze-grid-resized", Dynamics, true,
        "The map has another number of rows or columns: every wall and cell centre moves (cells are then not compared one by one).";
    MazeWallAdded = "maze-wall-added", Dynamics, true,
        "Wall blocks were added: the world's geometry changes where the robot can go.";
    MazeWallRemoved = "maze-wall-removed", Dynamics, true,
        "Wall blocks were removed: the world's geometry changes where the robot can go.";
    MazeGoalCellAdded = "maze-goal-cell-added", Reward, true,
        "Goal cells (`g`) were added: goals are drawn at reset from other places, so the reward pays for reaching other places.";
    MazeGoalCellRemoved = "maze-goal-cell-removed", Reward, true,
        "Goal cells were removed (with none left, the free cells serve, as in the reference).";
    MazeGoalCellMoved = "maze-goal-cell-moved", Reward, true,
        "A goal cell moved (one removed and one added in row-major order).";
    MazeResetCellAdded = "maze-reset-cell-added", Reset, true,
        "Reset cells (`r`) were added: the robot starts from other places.";
    MazeResetCellRemoved = "maze-reset-cell-removed", Reset, true,
        "Reset cells were removed (with none left, the free cells serve).";
    MazeResetCellMoved = "maze-reset-cell-moved", Reset, true,
        "A reset cell moved.";
    MazeCombinedCellAdded = "maze-combined-cell-added", Reset, true,
        "Combined cells (`c`, both goal and reset) were added: start and goal distributions change.";
    MazeCombinedCellRemoved = "maze-combined-cell-removed", Reset, true,
        "Combined cells were removed.";
    MazeCombinedCellMoved = "maze-combined-cell-moved", Reset, true,
        "A combined cell moved.";
    MazeScalingChanged = "maze-scaling-changed", Dynamics, true,
        "`maze_size_scaling` changed: walls, goals, starts and the position noise all scale.";
    MazeHeightChanged = "maze-height-changed", Dynamics, true,
        "`maze_height` (the wall height) changed.";
    MazeRewardTypeChanged = "maze-reward-type-changed", Reward, true,
        "`reward_type` changed between sparse and dense.";
    MazeContinuingTaskChanged = "maze-continuing-task-changed", Termination, true,
        "`continuing_task` changed: whether reaching the goal ends the episode.";
    MazeResetTargetChanged = "maze-reset-target-changed", Reward, true,
        "`reset_target` changed: whether a reached goal is redrawn in a continuing task (more goals to collect per episode).";
    MazeTimeLimitChanged = "maze-time-limit-changed", Termination, true,
        "`max_episode_steps` of the maze env changed.";
    MazePositionNoiseChanged = "maze-position-noise-changed", Reset, true,
        "`position_noise_range` changed: goals and starts are jittered differently around cell centres.";
    MazeVelocityClipChanged = "maze-velocity-clip-changed", Dynamics, true,
        "`velocity_clip` changed: the robot's velocity is clamped differently before every step.";
    MazeGoalThresholdChanged = "maze-goal-threshold-changed", Reward, true,
        "`goal_threshold` changed: when the goal counts as reached (sparse reward, success, termination).";
    MazeRobotChanged = "maze-robot-changed", Documentation, false,
        "The maze names another robot spec file; the robot's own changes follow (subjects `robot ...`), none if the two behave the same.";
    MazeRobotParamsChanged = "maze-robot-params-changed", Parameters, false,
        "The overrides the maze passes to its robot changed; their effect follows as the robot's own changes.";
    MazeRobotUnresolved = "maze-robot-unresolved", Dynamics, true,
        "A robot spec could not be resolved, so its changes are unknown: counted as breaking until reviewed.";

    // Commands and PD actions.
    CommandsAdded = "commands-added", Randomization, true,
        "A command was added: the policy is asked to follow something new (and its draws shift the RNG stream).";
    CommandsRemoved = "commands-removed", Randomization, true,
        "A command was removed.";
    CommandsComponentsChanged = "commands-components-changed", Randomization, true,
        "A command's components were added, removed or reordered: the command vector (and an observation of it) changes.";
    CommandsRangeChanged = "commands-range-changed", Randomization, true,
        "A command component's range changed: the commands trained on widen or narrow (witness: how the range moved).";
    CommandsScheduleChanged = "commands-schedule-changed", Randomization, true,
        "How often commands are redrawn, or the standing-still probability, changed.";
    ActionsAdded = "actions-added", Action, true,
        "`[actions]` was added: actions become PD position targets instead of raw controls.";
    ActionsRemoved = "actions-removed", Action, true,
        "`[actions]` was removed: actions become raw controls again.";
    ActionsMappingChanged = "actions-mapping-changed", Action, true,
        "The action scale, default pose or action range changed: the same action means another joint target.";
    ActionsGainsChanged = "actions-gains-changed", Action, true,
        "PD gains or joint damping changed: the same target is tracked differently (the dynamics the policy learned changes).";
    // Manipulation (`[init]`, `[end_effector]`, `[hold.*]`, `[goal]`).
    ManipulationInitChanged = "manipulation-init-changed", Reset, true,
        "`[init]` was added, removed or changed: the settled start pose every episode begins from, or the points reset draws are made around, move.";
    EndEffectorChanged = "end-effector-changed", Action, true,
        "`[end_effector]` was added, removed or changed: the same action moves the gripper (or opens the fingers) differently.";
    HoldChanged = "hold-changed", Dynamics, true,
        "A `[hold.*]` table was added, removed or changed: other joints are held after each step, or at another value.";
    GoalChanged = "goal-changed", Observation, true,
        "`[goal]` was added, removed or changed: the observation becomes (or stops being) a goal dict, or `achieved_goal` reads something else.";
    GoalPartsChanged = "goal-parts-changed", Reward, true,
        "A `[goal]` of parts keeps its layout but a part's desired value, the threshold, the norm or the checklist's rules changed: what counts as a part done changes, and with it the reward and the termination.";
    // Derived values (`[derived.*]`).
    DerivedChanged = "derived-changed", Observation, true,
        "A `[derived.*]` table was added, removed or changed: every observation segment, reward term, condition or info entry that reads it sees other values.";
    // Model edits a spec makes (`[actuators.*]`, `[joint_properties]`, `[keyframes.*]`).
    ActuatorsAdded = "actuators-added", Action, true,
        "An `[actuators.*]` table was added: the action gains entries (and the physics a drive).";
    ActuatorsRemoved = "actuators-removed", Action, true,
        "An `[actuators.*]` table was removed: the action loses entries.";
    ActuatorsRenamed = "actuators-renamed", Action, true,
        "An `[actuators.*]` table was renamed (same keys); compatible when the resolved actuators are unchanged.";
    ActuatorsKeyChanged = "actuators-key-changed", Dynamics, true,
        "A key of an `[actuators.*]` table (joints, kind, gains, gear, force or control range) changed; compatible when the resolved actuators are unchanged.";
    ActuatorsResolvedChanged = "actuators-resolved-changed", Dynamics, true,
        "An `[actuators.*]` table's text is unchanged but its actuators resolve differently (a parameter default, or a `[joint_properties]` row, changed under it).";
    JointPropertiesAdded = "joint-properties-added", Dynamics, true,
        "A `[joint_properties]` row was added: armature, damping, friction loss or actuator gains of the joints it matches change.";
    JointPropertiesRemoved = "joint-properties-removed", Dynamics, true,
        "A `[joint_properties]` row was removed: the joints it matched fall back to earlier rows, their actuator tables or the model.";
    JointPropertiesRenamed = "joint-properties-renamed", Dynamics, true,
        "A `[joint_properties]` row's pattern changed (same values); compatible when it matches the same joints with the same result.";
    JointPropertiesKeyChanged = "joint-properties-key-changed", Dynamics, true,
        "A value of a `[joint_properties]` row changed; compatible when the resolved per-joint table is unchanged.";
    JointPropertiesResolvedChanged = "joint-properties-resolved-changed", Dynamics, true,
        "A `[joint_properties]` row's text is unchanged but it resolves differently (the model's joints or a parameter changed).";
    GeomPropertiesAdded = "geom-properties-added", Dynamics, true,
        "A `[geom_properties]` row was added: contact properties (contype, conaffinity, condim, priority, friction, solref, solimp, solmix, margin, gap) of the geoms it matches change.";
    GeomPropertiesRemoved = "geom-properties-removed", Dynamics, true,
        "A `[geom_properties]` row was removed: the geoms it matched fall back to earlier rows or the model.";
    GeomPropertiesRenamed = "geom-properties-renamed", Dynamics, true,
        "A `[geom_properties]` row's pattern changed (same values); compatible when it matches the same geoms with the same result.";
    GeomPropertiesKeyChanged = "geom-properties-key-changed", Dynamics, true,
        "A value of a `[geom_properties]` row changed; compatible when the resolved per-geom table is unchanged.";
    GeomPropertiesResolvedChanged = "geom-properties-resolved-changed", Dynamics, true,
        "A `[geom_properties]` row's text is unchanged but it resolves differently (the model's geoms changed).";
    KeyframesAdded = "keyframes-added", Reset, true,
        "A `[keyframes.*]` keyframe was added; compatible when nothing reads it.";
    KeyframesRemoved = "keyframes-removed", Reset, true,
        "A `[keyframes.*]` keyframe was removed.";
    KeyframesRenamed = "keyframes-renamed", Reset, true,
        "A keyframe was renamed (same values); compatible when what reads it resolves the same.";
    KeyframesKeyChanged = "keyframes-key-changed", Reset, true,
        "A joint value of a keyframe changed: resets from it and default poses read from it move.";
    KeyframesResolvedChanged = "keyframes-resolved-changed", Reset, true,
        "A keyframe's text is unchanged but it resolves to other positions (the model or a pattern's matches changed).";
    // `[physics]` solver options.
    PhysicsOptionChanged = "physics-option-changed", Dynamics, true,
        "A `[physics]` solver option (`cone`, `iterations`, `ls_iterations`, `noslip_iterations`, `ccd_iterations`, `tolerance`, `ls_tolerance`, `impratio`) was set, changed or removed: contacts and constraint forces are solved differently.";
    // When the observation is read (`[physics] forward_before_observation`).
    ObservationRefreshChanged = "observation-refresh-changed", Observation, true,
        "`[physics] forward_before_observation` changed: the observation reads the new state's kinematics (or the last physics substep's), so velocities, positions and contacts in it change.";
    // The ground (`[terrain]`).
    TerrainAdded = "terrain-added", Dynamics, true,
        "`[terrain]` was added: the robot walks on generated tiles (and a `terrain_origin` reset can spawn on them).";
    TerrainRemoved = "terrain-removed", Dynamics, true,
        "`[terrain]` was removed: the generated ground is gone.";
    TerrainChanged = "terrain-changed", Dynamics, true,
        "A `[terrain]` key or generator changed (or resolves differently): the ground's geometry, difficulties or spawn origins change, whatever one seeded rollout happens to walk on.";
    // Domain randomization (`[events.*]`).
    EventsAdded = "events-added", Randomization, true,
        "An `[events.*]` entry was added: the policy trains on randomized models (or is pushed) where it saw one model; returns are not comparable.";
    EventsRemoved = "events-removed", Randomization, true,
        "An `[events.*]` entry was removed: the policy trains on the compiled values where it saw a distribution; returns are not comparable.";
    EventsRangeChanged = "events-range-changed", Randomization, true,
        "A randomization range (uniform or log-uniform bounds, a Gaussian's mean or std, a push's x or y range) changed; the witness says whether the distribution widened, narrowed or shifted.";
    EventsDistributionChanged = "events-distribution-changed", Randomization, true,
        "The distribution (uniform, log_uniform, gaussian) of an event changed: the same range is sampled with other weights.";
    EventsModeChanged = "events-mode-changed", Randomization, true,
        "When an event draws changed (startup: once per seed, reset: every episode, interval: during episodes, or the interval itself).";
    EventsFieldChanged = "events-field-changed", Randomization, true,
        "The model field an event randomizes changed (or an event became a push).";
    EventsElementsChanged = "events-elements-changed", Randomization, true,
        "The elements an event randomizes changed (resolved names; compatible when patterns were rewritten but match the same elements).";
    EventsOperationChanged = "events-operation-changed", Randomization, true,
        "How a draw is applied changed (add, scale, abs): the resulting values differ.";
    EventsSharedChanged = "events-shared-changed", Randomization, true,
        "An event switched between one draw per value and one draw shared by all its values (correlated randomization).";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_kebab_case_and_in_variant_order() {
        let mut seen = std::collections::HashSet::new();
        for (i, r) in RULES.iter().enumerate() {
            assert_eq!(r.rule as usize, i, "{}", r.id);
            assert!(seen.insert(r.id), "duplicate id {}", r.id);
            assert!(
                r.id.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-'),
                "{}",
                r.id
            );
            assert!(!r.description.contains('\n') && r.description.ends_with('.'));
        }
        assert_eq!(RuleId::RewardSumChanged.id(), "reward-sum-changed");
        assert_eq!(RuleId::MazeWallAdded.category(), Category::Dynamics);
    }

    #[test]
    fn rows_as_docs_diff_rules_md_lists_them() {
        // Copied by hand from the tables of docs/diff-rules.md: id | category | breaking.
        let rows = [
            ("env-id-changed", "documentation", false),
            ("selector-respelled", "documentation", false),
            ("env-dt-changed", "dynamics", true),
            ("param-removed", "parameters", true),
            ("param-now-argument", "parameters", false),
            ("param-default-unused", "parameters", false),
            ("param-default-observation", "observation", true),
            ("param-default-randomization", "randomization", true),
            ("noise-added", "randomization", true),
            ("reward-sum-changed", "reward", true),
            ("health-terminate-changed", "termination", true),
            ("reset-draw-order-changed", "reset", true),
            ("info-table-inactive-removed", "info", false),
            ("model-actuator-count-changed", "action", true),
            ("model-file-changed", "documentation", false),
            ("agents-conf-added", "action", false),
            ("agents-action-bounds-changed", "action", false),
            ("maze-wall-added", "dynamics", true),
            ("maze-robot-params-changed", "parameters", false),
            ("goal-changed", "observation", true),
            ("observation-refresh-changed", "observation", true),
            ("terrain-changed", "dynamics", true),
            ("events-shared-changed", "randomization", true),
        ];
        for (id, cat, breaking) in rows {
            let r = RULES.iter().find(|r| r.id == id).expect(id);
            assert_eq!((r.category.key(), r.breaking), (cat, breaking), "{id}");
        }
        // Every documentation rule is compatible: it changes no behaviour.
        for r in RULES
            .iter()
            .filter(|r| r.category == Category::Documentation)
        {
            assert!(!r.breaking, "{}", r.id);
        }
    }

    #[test]
    fn categories_in_report_order() {
        // docs/diff-rules.md: "the report's sections, most harmful first".
        let keys: Vec<&str> = Category::ALL.iter().map(|c| c.key()).collect();
        assert_eq!(
            keys,
            [
                "observation",
                "action",
                "reward",
                "termination",
                "reset",
                "randomization",
                "dynamics",
                "parameters",
                "info",
                "documentation"
            ]
        );
        // The derived order (used to sort reports and pick a default's most harmful use) agrees.
        assert!(Category::ALL.windows(2).all(|w| w[0] < w[1]));
        for c in Category::ALL {
            assert_eq!(
                serde_json::to_string(c).unwrap(),
                format!("\"{}\"", c.key())
            );
        }
        assert_eq!(Category::Observation.impact(), "breaks trained policies");
        assert_eq!(Category::Action.impact(), "breaks trained policies");
        assert_eq!(
            Category::Reward.impact(),
            "returns are no longer comparable"
        );
        assert_eq!(Category::Documentation.impact(), "no behaviour change");
        assert_eq!(
            serde_json::to_string(&RuleId::EnvDtChanged).unwrap(),
            "\"env-dt-changed\""
        );
    }
}
