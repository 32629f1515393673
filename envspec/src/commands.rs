//! Commands (`[commands.*]`), PD position actions (`[actions]`) and the legged-locomotion reward
//! terms, as resolved into the IR (docs/spec-reference.md, "Commands, PD actions and legged
//! terms"). The resolvers are `resolve/commands.rs`, `resolve/actions.rs` and `resolve/legged.rs`;
//! the runtime `runtime/src/commands.rs`.

use crate::selector::Selection;

/// `[commands.<name>]`: a vector drawn from per-component ranges at reset and every
/// `resample_steps` steps; with probability `standing_probability` every component is 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Command {
    /// The table's name; observations select it as `command[NAME]`.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// Component names, in declared order (the draw order).
    pub components: Vec<String>,
    /// Lower end of each component's uniform range.
    pub low: Vec<f64>,
    /// Upper end of each component's uniform range.
    pub high: Vec<f64>,
    /// `resample_seconds` as written (None: drawn at reset only).
    pub resample_seconds: Option<f64>,
    /// `round(resample_seconds / dt)` env steps, at least 1 (0: drawn at reset only).
    pub resample_steps: u64,
    /// Probability that a draw is all zeros (a standing command); 0: never.
    pub standing_probability: f64,
    /// Where the command's components start in the env's command buffer.
    pub offset: usize,
}

impl Command {
    /// Number of components.
    pub fn len(&self) -> usize {
        self.components.len()
    }
    /// Whether it has no components.
    pub fn is_empty(&self) -> bool {
        self.components.is_empty()
    }
}

/// Where the PD default pose comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum DefaultPose {
    /// A keyframe's `qpos` at each actuator's joint (`qposadr`, one per actuator), read from the
    /// compiled model; an actuator that drives no joint (a tendon) takes the keyframe's `ctrl`.
    Keyframe {
        /// The keyframe's name.
        name: String,
        /// The `qpos` address of each actuator's joint (None: the keyframe's `ctrl`).
        qposadr: Vec<Option<usize>>,
    },
    /// One value per actuator, as written.
    Values(Vec<f64>),
    /// The centre of each actuator's control range, read from the compiled model
    /// (`kind = "ctrlrange"`).
    CtrlRangeCentre,
}

/// How `[actions]` turns an action into `ctrl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActionKind {
    /// `ctrl = default_pose + scale × action`, written as given.
    PdPosition,
    /// The action, clipped to [−1, 1], spans each actuator's control range:
    /// `ctrl = clip(centre + action × half_width, ctrlrange)` (Gymnasium-Robotics' hands).
    CtrlRange,
    /// The action, clipped to [−1, 1], is a velocity integrated from the position the agent
    /// last observed: `ctrl = clip(observed + clip(scale × action, velocity) × dt, position)`
    /// (Gymnasium-Robotics' Franka Kitchen, after D4RL).
    PositionDelta,
}

/// `kind = "position_delta"`: where the observed position comes from and the bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct PositionDelta {
    /// The `[observation.*]` segment read (noise and delay included), one value per actuator.
    pub from: String,
    /// Its index in `ResolvedSpec::observation`.
    pub segment: usize,
    /// Per actuator: the velocity bounds.
    pub velocity: Vec<(f64, f64)>,
    /// Per actuator: the position bounds.
    pub position: Vec<(f64, f64)>,
}

impl ActionKind {
    /// The spec's name of the kind.
    pub fn name(self) -> &'static str {
        match self {
            ActionKind::PdPosition => "pd_position",
            ActionKind::CtrlRange => "ctrlrange",
            ActionKind::PositionDelta => "position_delta",
        }
    }
}

/// `[actions]`: an action is a joint target, `ctrl = default_pose + scale × action`.
#[derive(Clone, Debug, PartialEq)]
pub struct PdActions {
    /// How an action becomes `ctrl`.
    pub kind: ActionKind,
    /// Action scale of each actuator: radians (or metres) of target per unit of action (empty
    /// for `ctrlrange`: each actuator's half-width, read from the compiled model).
    pub scale: Vec<f64>,
    /// The target of action 0.
    pub default_pose: DefaultPose,
    /// The action space (every actuator), not the control range.
    pub range: (f64, f64),
    /// Position gain: `gainprm[0] = kp`, `biasprm[1] = −kp` on every actuator.
    pub kp: Option<f64>,
    /// Velocity gain of the servo: `biasprm[2] = −kd`.
    pub kd: Option<f64>,
    /// Joint damping (`dof_damping`) of every actuated joint (Playground's "Kd").
    pub damping: Option<f64>,
    /// `kind = "position_delta"` only: the observed position and the bounds.
    pub delta: Option<PositionDelta>,
}

/// `‖command‖ > threshold` (or `<` with `below`) gates a term: the kernel is multiplied by 1 or 0
/// (no air-time reward for a standing command; a stand-still cost only for one). With several
/// selections, their norms are added: `‖cmd_xy‖ + |cmd_wz|` is mjlab's command speed.
#[derive(Clone, Debug, PartialEq)]
pub struct Gate {
    /// The command selections whose norms are added and compared (at least one).
    pub command: Vec<Selection>,
    /// The norm it is compared with.
    pub threshold: f64,
    /// Gate open below the threshold instead of above it.
    pub below: bool,
}

/// Contacts of the feet with the floor: a foot is in contact when any contact of the last forward
/// pass pairs it with the floor. Each is a geom, or a body (any of its geoms: for models whose
/// foot geoms have no names; `world` is every geom of the world body).
#[derive(Clone, Debug, PartialEq)]
pub struct FeetContact {
    /// Geom or body names of the feet.
    pub geoms: Vec<String>,
    /// Per foot: the name is a body's, not a geom's.
    pub bodies: Vec<bool>,
    /// Geom or body name of the floor.
    pub floor: String,
    /// The floor's name is a body's, not a geom's.
    pub floor_is_body: bool,
}

/// Reward kernels of legged locomotion (`TermKind::Legged`).
#[derive(Clone, Debug, PartialEq)]
pub enum LeggedTerm {
    /// `exp(−(Σₖ coefₖ·(targetₖ − xₖ)² + Σⱼ zⱼ²) / σ)`: velocity tracking (`target` a command,
    /// `zero` the velocities commanded to be 0, as mjlab's kernels), a pose kept near a
    /// default (`target = "default_pose"`), or with `zero` alone a quantity kept near 0
    /// (mjlab's `upright`: the projected gravity's x and y).
    Tracking {
        /// The tracked quantities `x` (empty with `zero` alone).
        source: Selection,
        /// Their targets (as long as `source`).
        target: Selection,
        /// One weight per element.
        coefs: Vec<f64>,
        /// Width of the exponential.
        sigma: f64,
        /// Quantities whose target is 0 (`z`), their squares added after the tracked sum.
        zero: Option<Selection>,
    },
    /// `exp(−meanₖ((xₖ − mₖ)² / σₖ²))` with a per-element width chosen by a speed regime:
    /// mjlab's `variable_posture` (tighter standing, looser walking and running).
    Posture {
        /// The joint positions `x` (qpos of hinge or slide joints).
        source: Selection,
        /// Their targets `m` (as long as `source`).
        minus: Selection,
        /// The selections whose norms, added, are the speed (empty: one regime).
        speed: Vec<Selection>,
        /// Ascending speed thresholds: regime `r` holds while `speed < thresholds[r]`; the last
        /// regime from the last threshold up. One fewer than `sigma` has rows.
        thresholds: Vec<f64>,
        /// Per regime, one width σₖ per element of `source`.
        sigma: Vec<Vec<f64>>,
    },
    /// `Σᵢ |hᵢ − target| · ‖vᵢ,xy‖^power`, gated: feet kept at a clearance height while they
    /// move (mjlab's `feet_clearance`, Playground's with `power = 0.5`). `hᵢ` is the site's
    /// height above the plane z = 0, clamped to `[0, max_height]` (a downward ray of that
    /// length, as mjlab's foot height scan on flat ground).
    FeetClearance {
        /// `site_xpos` z of each foot site.
        height: Selection,
        /// `site_linvel` x and y of each foot site (2 per foot).
        velocity: Selection,
        /// The target clearance, metres.
        target: f64,
        /// The ray's length: heights are clamped to `[0, max_height]`.
        max_height: f64,
        /// Exponent of the velocity norm.
        power: f64,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// mjlab's `feet_swing_height`: `Σᵢ (peakᵢ / target − 1)² · landingᵢ`, gated. `peakᵢ` is
    /// the highest `clamp(site zᵢ, 0, max_height)` seen at env steps while foot `i` was off the
    /// floor, cleared at each landing and at reset (mjlab keeps it across resets); `landingᵢ`: the
    /// foot touched down during this env step's physics substeps and is still down.
    FeetSwingHeight {
        /// The feet and the floor.
        feet: FeetContact,
        /// `site_xpos` z of each foot site.
        height: Selection,
        /// The target peak height, metres (> 0).
        target: f64,
        /// The ray's length: heights are clamped to `[0, max_height]`.
        max_height: f64,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// mjlab's `soft_landing`: `Σᵢ ‖Fᵢ‖ · landingᵢ`, gated: the net contact force of each foot
    /// with the floor (world frame, summed over its contacts) when it lands (as
    /// `FeetSwingHeight`).
    SoftLanding {
        /// The feet and the floor.
        feet: FeetContact,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// mjlab's `self_collision_cost`: the number of this env step's physics substeps whose first
    /// contact between two geoms of a body's subtree pushes harder than `threshold` newtons.
    SelfCollisions {
        /// The body whose subtree's geoms collide (the robot's root body: every self contact).
        subtree: String,
        /// Contact force norm (N) above which a substep counts.
        threshold: f64,
    },
    /// `Σₖ |xₖ − mₖ|`, optionally gated.
    SumAbs {
        /// The quantities `x`.
        source: Selection,
        /// What is subtracted (`m`; none: zeros).
        minus: Option<Selection>,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// `Σₖ (aₖ − a_prevₖ)²` of the action and the previous step's action.
    ActionRate,
    /// Playground / legged_gym feet air time: `Σ (air_time − threshold) · first_contact`, gated.
    FeetAirTime {
        /// The feet and the floor.
        feet: FeetContact,
        /// Air time in seconds below which a landing costs.
        threshold: f64,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// `Σ contact · (vx² + vy²)` of the feet sites' world velocities, gated.
    FeetSlip {
        /// The feet and the floor.
        feet: FeetContact,
        /// `site_linvel` rows of the feet sites, x and y of each (2 per foot).
        velocity: Selection,
        /// When the term counts.
        gate: Option<Gate>,
    },
    /// `Σ max(lo′ − q, 0) + max(q − hi′, 0)` over hinge/slide joints, with soft limits
    /// `(lo′, hi′)` the model's range scaled by `factor`: about zero (`f·lo, f·hi`: Playground,
    /// legged_gym) or about its centre (`mid ∓ f·(hi − lo)/2`: mjlab, Isaac Lab); joints without a
    /// range add 0.
    JointLimits {
        /// The joint positions `q`.
        source: Selection,
        /// Joint id of each element.
        joints: Vec<usize>,
        /// Scale of the model's range.
        factor: f64,
        /// Scale about the range's centre instead of about zero.
        centered: bool,
    },
}

impl LeggedTerm {
    /// The `kind` values a spec may write (for suggestions).
    pub const KINDS: &'static [&'static str] = &[
        "tracking",
        "sum_abs",
        "action_rate",
        "feet_air_time",
        "feet_slip",
        "joint_limits",
        "posture",
        "feet_clearance",
        "feet_swing_height",
        "soft_landing",
        "self_collisions",
    ];
    /// The `kind` a spec writes for this term.
    pub fn kind_name(&self) -> &'static str {
        match self {
            LeggedTerm::Tracking { .. } => "tracking",
            LeggedTerm::SumAbs { .. } => "sum_abs",
            LeggedTerm::ActionRate => "action_rate",
            LeggedTerm::FeetAirTime { .. } => "feet_air_time",
            LeggedTerm::FeetSlip { .. } => "feet_slip",
            LeggedTerm::JointLimits { .. } => "joint_limits",
            LeggedTerm::Posture { .. } => "posture",
            LeggedTerm::FeetClearance { .. } => "feet_clearance",
            LeggedTerm::FeetSwingHeight { .. } => "feet_swing_height",
            LeggedTerm::SoftLanding { .. } => "soft_landing",
            LeggedTerm::SelfCollisions { .. } => "self_collisions",
        }
    }
    /// The term's gate, for the kinds that have one.
    pub fn gate(&self) -> Option<&Gate> {
        match self {
            LeggedTerm::SumAbs { gate, .. }
            | LeggedTerm::FeetAirTime { gate, .. }
            | LeggedTerm::FeetSlip { gate, .. }
            | LeggedTerm::FeetClearance { gate, .. }
            | LeggedTerm::FeetSwingHeight { gate, .. }
            | LeggedTerm::SoftLanding { gate, .. } => gate.as_ref(),
            _ => None,
        }
    }
    /// The selections the kernel reads, in order.
    pub fn sources(&self) -> Vec<&Selection> {
        let mut out: Vec<&Selection> = match self {
            LeggedTerm::Tracking {
                source,
                target,
                zero,
                ..
            } => [source, target].into_iter().chain(zero.as_ref()).collect(),
            LeggedTerm::SumAbs { source, minus, .. } => {
                std::iter::once(source).chain(minus.as_ref()).collect()
            }
            LeggedTerm::FeetSlip { velocity, .. } => vec![velocity],
            LeggedTerm::JointLimits { source, .. } => vec![source],
            LeggedTerm::Posture {
                source,
                minus,
                speed,
                ..
            } => [source, minus].into_iter().chain(speed).collect(),
            LeggedTerm::FeetClearance {
                height, velocity, ..
            } => vec![height, velocity],
            LeggedTerm::FeetSwingHeight { height, .. } => vec![height],
            LeggedTerm::ActionRate
            | LeggedTerm::FeetAirTime { .. }
            | LeggedTerm::SoftLanding { .. }
            | LeggedTerm::SelfCollisions { .. } => vec![],
        };
        out.extend(self.gate().into_iter().flat_map(|g| &g.command));
        out
    }
    /// The contact pairs the kernel reads after the env step (Playground's air time, slip).
    pub fn feet(&self) -> Option<&FeetContact> {
        match self {
            LeggedTerm::FeetAirTime { feet, .. } | LeggedTerm::FeetSlip { feet, .. } => Some(feet),
            _ => None,
        }
    }
    /// The contact pairs tracked at every physics substep (mjlab's landings).
    pub fn landing_feet(&self) -> Option<&FeetContact> {
        match self {
            LeggedTerm::FeetSwingHeight { feet, .. } | LeggedTerm::SoftLanding { feet, .. } => {
                Some(feet)
            }
            _ => None,
        }
    }
    /// Whether the kernel needs contacts of every physics substep, not only of the last.
    pub fn per_substep(&self) -> bool {
        self.landing_feet().is_some() || matches!(self, LeggedTerm::SelfCollisions { .. })
    }
    /// The formula, for `envc show` and generated docs.
    pub fn formula(&self) -> String {
        let gate = |g: &Option<Gate>| match g {
            Some(g) => format!(
                " · [{} {} {}]",
                speed_text(&g.command),
                if g.below { "<" } else { ">" },
                g.threshold
            ),
            None => String::new(),
        };
        match self {
            LeggedTerm::Tracking {
                source,
                target,
                sigma,
                zero,
                ..
            } => match zero {
                Some(z) if source.is_empty() => format!("exp(−Σ {}² / {sigma})", z.text),
                Some(z) => format!(
                    "exp(−(Σ c·({} − {})² + Σ {}²) / {sigma})",
                    target.text, source.text, z.text
                ),
                None => format!("exp(−Σ c·({} − {})² / {sigma})", target.text, source.text),
            },
            LeggedTerm::Posture {
                source,
                minus,
                speed,
                thresholds,
                ..
            } => {
                let regimes = if speed.is_empty() {
                    String::new()
                } else {
                    format!(", σ by {} against {thresholds:?}", speed_text(speed))
                };
                format!(
                    "exp(−mean(({} − {})² / σ²)){regimes}",
                    source.text, minus.text
                )
            }
            LeggedTerm::FeetSwingHeight {
                feet,
                target,
                max_height,
                gate: g,
                ..
            } => format!(
                "Σ (peak height in the air, clamped to {max_height} / {target} − 1)² · landing({} on {}){}",
                feet.geoms.join(","),
                feet.floor,
                gate(g)
            ),
            LeggedTerm::SoftLanding { feet, gate: g } => format!(
                "Σ ‖net contact force‖ · landing({} on {}){}",
                feet.geoms.join(","),
                feet.floor,
                gate(g)
            ),
            LeggedTerm::SelfCollisions { subtree, threshold } => format!(
                "substeps whose first contact within the subtree of {subtree} exceeds {threshold} N"
            ),
            LeggedTerm::FeetClearance {
                height,
                target,
                max_height,
                power,
                gate: g,
                ..
            } => format!(
                "Σ |clamp({}, 0, {max_height}) − {target}| · ‖v_xy‖^{power}{}",
                height.text,
                gate(g)
            ),
            LeggedTerm::SumAbs {
                source,
                minus,
                gate: g,
            } => match minus {
                Some(m) => format!("Σ |{} − {}|{}", source.text, m.text, gate(g)),
                None => format!("Σ |{}|{}", source.text, gate(g)),
            },
            LeggedTerm::ActionRate => "Σ (action − last_action)²".into(),
            LeggedTerm::FeetAirTime {
                feet,
                threshold,
                gate: g,
            } => format!(
                "Σ (air_time − {threshold}) · first_contact({} on {}){}",
                feet.geoms.join(","),
                feet.floor,
                gate(g)
            ),
            LeggedTerm::FeetSlip { feet, gate: g, .. } => format!(
                "Σ contact({} on {}) · (vx² + vy²){}",
                feet.geoms.join(","),
                feet.floor,
                gate(g)
            ),
            LeggedTerm::JointLimits {
                source,
                factor,
                centered,
                ..
            } => {
                let about = if *centered { "its centre" } else { "zero" };
                format!(
                    "Σ out of {factor} × range (about {about}) of {}",
                    source.text
                )
            }
        }
    }
}

/// `‖a‖ + ‖b‖ …` for a gate's or a posture's speed.
fn speed_text(parts: &[Selection]) -> String {
    parts
        .iter()
        .map(|s| format!("‖{}‖", s.text))
        .collect::<Vec<_>>()
        .join(" + ")
}

impl Command {
    /// One line for `envc show`: components, ranges, schedule, standing probability.
    pub fn describe(&self) -> String {
        let comps: Vec<String> = self
            .components
            .iter()
            .enumerate()
            .map(|(k, n)| format!("{n} ~ U[{}, {}]", self.low[k], self.high[k]))
            .collect();
        let when = match self.resample_seconds {
            Some(s) => format!("at reset and every {s} s ({} steps)", self.resample_steps),
            None => "at reset".into(),
        };
        format!(
            "{}; drawn {when}; all zero with probability {}",
            comps.join(", "),
            self.standing_probability
        )
    }
}

impl PdActions {
    /// What `envc show` prints under the action table.
    pub fn describe(&self) -> String {
        if self.kind == ActionKind::CtrlRange {
            return "actions span the control ranges: ctrl = clip(centre + half_width × clip(action, -1, 1), ctrlrange)".to_string();
        }
        if let Some(d) = &self.delta {
            return format!(
                "position deltas: ctrl = clip(observation.{} + clip(scale × clip(action, -1, 1), velocity) × dt, position), scale {:?}, velocity {:?}, position {:?}",
                d.from, self.scale, d.velocity, d.position
            );
        }
        let pose = match &self.default_pose {
            DefaultPose::CtrlRangeCentre => "the control ranges' centres".to_string(),
            DefaultPose::Keyframe { name, .. } => format!("keyframe `{name}`"),
            DefaultPose::Values(v) => format!("{v:?}"),
        };
        let gain = |k: &str, v: Option<f64>| v.map(|x| format!(", {k} {x}")).unwrap_or_default();
        let uniform = self.scale.windows(2).all(|w| w[0] == w[1]);
        let scale = match self.scale.first() {
            Some(x) if uniform => x.to_string(),
            _ => "scale".to_string(),
        };
        let per_joint = if uniform {
            ""
        } else {
            " (scale per actuator: the joints table)"
        };
        format!(
            "PD position targets: ctrl = default_pose + {scale} × action{per_joint}, default_pose from {pose}{}{}{}",
            gain("kp", self.kp),
            gain("kd", self.kd),
            gain("joint damping", self.damping)
        )
    }
}
