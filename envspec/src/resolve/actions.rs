//! `[actions]`: how the policy's action becomes the model's controls (PD position targets, or
//! the control ranges); IR in `crate::commands`.

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::*;
use crate::limits;
use crate::mjcf::JointKind;
use crate::syntax::Section;
use crate::value::{Val, ValKind};

/// E0132 at `v`.
fn e0132(v: &Val, msg: String, label: &str) -> Diagnostic {
    Diagnostic::new(Code::E0132, msg)
        .at(v.loc.clone())
        .label(label.to_string())
}

impl Ctx<'_> {
    /// `[actions] scale` as a table `joint pattern = scale` over the actuators' joints (mjlab's
    /// per-actuator action scale); later rows win, each row matches a joint, and every actuator
    /// gets a scale.
    fn action_scales(&mut self, v: &Val) -> Option<Vec<f64>> {
        let rows = v.as_table()?;
        let joints: Vec<Option<String>> = self
            .model
            .actuators
            .iter()
            .map(|a| a.target.clone())
            .collect();
        let mut scale: Vec<Option<f64>> = vec![None; joints.len()];
        for e in rows {
            let x = self.num(&e.value, "[actions] scale")?;
            let x = self.within(&e.value, x, "[actions] scale", limits::MAX_MAGNITUDE)?;
            // Actuators without a joint take the empty name, which no pattern matches.
            let hit = self.glob_hits(
                &e.key,
                joints.iter().map(|j| j.as_deref().unwrap_or("")),
                &e.key_loc,
                &format!("the joints of the model's {} actuators", joints.len()),
                "a glob pattern over the actuators' joint names (`*`: any run of characters, `?`: one)",
            )?;
            for k in hit {
                scale[k] = Some(x);
            }
        }
        if let Some(k) = scale.iter().position(Option::is_none) {
            self.d.push(
                Diagnostic::new(
                    Code::E0132,
                    format!(
                        "[actions] scale covers {} of the model's {} actuators: no row matches actuator `{}`",
                        scale.iter().filter(|x| x.is_some()).count(),
                        scale.len(),
                        self.model.actuators[k].name
                    ),
                )
                .at(v.loc.clone())
                .label("expected a row matching every actuator's joint (e.g. \"*\" = 0.25 first)"),
            );
            return None;
        }
        Some(scale.into_iter().flatten().collect())
    }

    /// `[actions]`: PD position targets over every actuator of the model.
    pub(super) fn actions(&mut self) -> Option<PdActions> {
        let s = self.spec.actions.as_ref()?;
        let nu = self.model.nu();
        let kind = match s.get("kind").map(|v| (v, v.as_str())) {
            None | Some((_, Some("pd_position"))) => ActionKind::PdPosition,
            Some((_, Some("ctrlrange"))) => ActionKind::CtrlRange,
            Some((_, Some("position_delta"))) => ActionKind::PositionDelta,
            Some((v, _)) => {
                self.d.push(
                    Diagnostic::new(Code::E0104, "unknown [actions] kind")
                        .at(v.loc.clone())
                        .label("expected \"pd_position\", \"ctrlrange\" or \"position_delta\""),
                );
                ActionKind::PdPosition
            }
        };
        if kind == ActionKind::CtrlRange {
            return self.ctrlrange_actions(s);
        }
        if kind == ActionKind::PositionDelta {
            return self.position_delta_actions(s);
        }
        for key in ["from", "velocity", "position"] {
            if let Some(v) = s.get(key) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("`{key}` applies to [actions] kind = \"position_delta\" only"),
                    )
                    .at(v.loc.clone())
                    .label("PD targets are default_pose + scale × action"),
                );
            }
        }
        let max = limits::MAX_MAGNITUDE;
        let scale = match s.get("scale") {
            Some(v) if v.as_table().is_some() => self.action_scales(v)?,
            Some(v) => {
                let x = self.num(v, "[actions] scale")?;
                vec![self.within(v, x, "[actions] scale", max)?; nu]
            }
            None => vec![1.0; nu],
        };
        let range = self.action_range(s)?;
        let kp = self.action_gain(s, "kp");
        let kd = self.action_gain(s, "kd");
        let damping = self.action_gain(s, "damping");
        let default_pose = self.default_pose(s, nu)?;
        Some(PdActions {
            kind,
            scale,
            default_pose,
            range,
            kp,
            kd,
            damping,
            delta: None,
        })
    }

    /// `[actions] range`: the action space, finite ([-1, 1] by default).
    fn action_range(&mut self, s: &Section) -> Option<(f64, f64)> {
        let max = limits::MAX_MAGNITUDE;
        Some(match s.get("range") {
            Some(v) => {
                let r = self.range(v, "range")?;
                if !(r.0.is_finite() && r.1.is_finite()) {
                    self.d.push(e0132(
                        v,
                        format!("[actions] range [{}, {}] is not finite", r.0, r.1),
                        "expected a finite action space, e.g. [-1.0, 1.0]",
                    ));
                } else {
                    self.within(v, r.0, "[actions] range", max)?;
                    self.within(v, r.1, "[actions] range", max)?;
                }
                r
            }
            None => (-1.0, 1.0),
        })
    }

    /// `[actions] kp`, `kd` or `damping`, when given: a gain ≥ 0.
    fn action_gain(&mut self, s: &Section, key: &str) -> Option<f64> {
        let max = limits::MAX_MAGNITUDE;
        let v = s.get(key)?;
        let x = self.num(v, key)?;
        let x = self.within(v, x, &format!("[actions] {key}"), max)?;
        if x < 0.0 {
            self.d.push(e0132(
                v,
                format!("[actions] {key} is {x}"),
                "expected a gain >= 0",
            ));
        }
        Some(x)
    }

    /// `[actions] default_pose`: a keyframe of the model, or one number per actuator (`nu`).
    fn default_pose(&mut self, s: &Section, nu: usize) -> Option<DefaultPose> {
        let Some(pose) = s.get("default_pose") else {
            self.d.push(
                Diagnostic::new(Code::E0103, "missing `default_pose` in [actions]")
                    .at(s.name_loc.clone())
                    .label("expected a keyframe name (e.g. \"home\") or one number per actuator"),
            );
            return None;
        };
        Some(match &pose.kind {
            ValKind::Str(name) => self.keyframe_pose(name, pose)?,
            ValKind::Array(a) if a.len() == nu => DefaultPose::Values(
                a.iter()
                    .map(|x| {
                        let n = self.num(x, "default_pose")?;
                        self.within(x, n, "a default_pose value", limits::MAX_COORDINATE)
                    })
                    .collect::<Option<_>>()?,
            ),
            other => {
                let given = match other {
                    ValKind::Array(a) => format!("{} numbers were given", a.len()),
                    _ => "a single value was given".to_string(),
                };
                self.d.push(e0132(
                    pose,
                    format!(
                        "[actions] default_pose does not fit the model's {nu} actuators: {given}"
                    ),
                    &format!("expected a keyframe name or an array of {nu} numbers"),
                ));
                return None;
            }
        })
    }

    /// A `default_pose` named by keyframe: the qpos address of each actuator's joint (None for a
    /// tendon or site actuator, whose default is the keyframe's `ctrl`).
    fn keyframe_pose(&mut self, name: &str, pose: &Val) -> Option<DefaultPose> {
        if !self.model.keyframes.iter().any(|k| k == name) {
            self.d.push(
                Diagnostic::new(
                    Code::E0133,
                    format!(
                        "the model {} has no keyframe named `{name}`",
                        self.model.path.display()
                    ),
                )
                .at(pose.loc.clone())
                .label(format!(
                    "expected one of the model's keyframes ({} named)",
                    self.model
                        .keyframes
                        .iter()
                        .filter(|k| !k.is_empty())
                        .count()
                ))
                .help_opt(suggest(
                    name,
                    self.model.keyframes.iter().map(String::as_str),
                )),
            );
            return None;
        }
        let mut qposadr = vec![];
        for a in &self.model.actuators {
            let joint = a.target.as_deref().and_then(|t| self.model.joint(t));
            match joint {
                Some(j) if matches!(j.kind, JointKind::Hinge | JointKind::Slide) => {
                    qposadr.push(Some(j.qposadr))
                }
                // A tendon's (or site's) target is its control: the keyframe's `ctrl`.
                None => qposadr.push(None),
                Some(_) => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0133,
                            format!(
                                "actuator `{}` drives a ball or free joint, so keyframe `{name}` gives it no default position",
                                a.name
                            ),
                        )
                        .at(pose.loc.clone())
                        .label("expected actuators on hinge or slide joints, or tendons")
                        .help("give default_pose as one number per actuator instead"),
                    );
                    return None;
                }
            }
        }
        Some(DefaultPose::Keyframe {
            name: name.to_string(),
            qposadr,
        })
    }

    /// `kind = "ctrlrange"`: the control ranges give the mapping, so no other key is taken.
    fn ctrlrange_actions(&mut self, s: &Section) -> Option<PdActions> {
        for key in ["scale", "default_pose", "range", "kp", "kd", "damping"] {
            if let Some(v) = s.get(key) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("`{key}` does not apply to [actions] kind = \"ctrlrange\""),
                    )
                    .at(v.loc.clone())
                    .label("the control ranges give the centre, the scale and the action space")
                    .help("remove it, or use kind = \"pd_position\""),
                );
            }
        }
        Some(PdActions {
            kind: ActionKind::CtrlRange,
            scale: vec![],
            default_pose: DefaultPose::CtrlRangeCentre,
            range: (-1.0, 1.0),
            kp: None,
            kd: None,
            damping: None,
            delta: None,
        })
    }

    /// `kind = "position_delta"`: `from` (an observation segment, linked once the observation
    /// is resolved), `scale`, and `velocity` / `position` bounds: one `[low, high]` for every
    /// actuator, or a list of one per actuator.
    fn position_delta_actions(&mut self, s: &Section) -> Option<PdActions> {
        for key in ["default_pose", "range", "kp", "kd", "damping"] {
            if let Some(v) = s.get(key) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("`{key}` does not apply to [actions] kind = \"position_delta\""),
                    )
                    .at(v.loc.clone())
                    .label("the action is a velocity from the observed position, in [-1, 1]")
                    .help("remove it, or use kind = \"pd_position\""),
                );
            }
        }
        let nu = self.model.nu();
        let from = match s.get("from").map(|v| (v, v.as_str())) {
            Some((_, Some(name))) => name.to_string(),
            Some((v, None)) => {
                self.d
                    .push(v.type_error("[actions] from", "an [observation.*] segment's name"));
                return None;
            }
            None => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0103,
                        "missing `from` in [actions] kind = \"position_delta\"",
                    )
                    .at(s.name_loc.clone())
                    .label("expected from = the observation segment holding the positions"),
                );
                return None;
            }
        };
        let scale = match s.get("scale") {
            Some(v) => vec![self.num_within(v, "[actions] scale", limits::MAX_MAGNITUDE)?; nu],
            None => vec![1.0; nu],
        };
        let velocity = self.bounds_per_actuator(s, "velocity", nu)?;
        let position = self.bounds_per_actuator(s, "position", nu)?;
        Some(PdActions {
            kind: ActionKind::PositionDelta,
            scale,
            default_pose: DefaultPose::Values(vec![0.0; nu]),
            range: (-1.0, 1.0),
            kp: None,
            kd: None,
            damping: None,
            delta: Some(PositionDelta {
                from,
                segment: usize::MAX,
                velocity,
                position,
            }),
        })
    }

    /// `[low, high]` for every actuator, or one such pair per actuator (unbounded if absent).
    fn bounds_per_actuator(
        &mut self,
        s: &Section,
        key: &str,
        nu: usize,
    ) -> Option<Vec<(f64, f64)>> {
        let Some(v) = s.get(key) else {
            return Some(vec![(f64::NEG_INFINITY, f64::INFINITY); nu]);
        };
        let what = format!("[actions] {key}");
        match v.as_array() {
            Some(rows) if rows.first().is_some_and(|r| r.as_array().is_some()) => {
                if rows.len() != nu {
                    self.d.push(e0132(
                        v,
                        format!(
                            "{what} has {} pairs for the model's {nu} actuators",
                            rows.len()
                        ),
                        "expected one [low, high] per actuator",
                    ));
                    return None;
                }
                rows.iter().map(|r| self.range(r, &what)).collect()
            }
            _ => Some(vec![self.range(v, &what)?; nu]),
        }
    }

    /// Link a `position_delta` action's `from` to its observation segment (after the
    /// observation is resolved): the segment must exist and hold one value per actuator.
    pub(super) fn link_action_source(
        &mut self,
        actions: &mut Option<PdActions>,
        observation: &[Segment],
    ) {
        let Some(d) = actions.as_mut().and_then(|a| a.delta.as_mut()) else {
            return;
        };
        let loc = self
            .spec
            .actions
            .as_ref()
            .and_then(|s| s.get("from"))
            .map(|v| v.loc.clone());
        let nu = self.model.nu();
        match observation.iter().position(|o| o.name == d.from) {
            Some(i) if observation[i].len() == nu => d.segment = i,
            found => {
                let msg = match found {
                    Some(i) => format!(
                        "[actions] from = \"{}\": the segment has {} values, the model {nu} actuators",
                        d.from,
                        observation[i].len()
                    ),
                    None => format!(
                        "[actions] from = \"{}\" is not an [observation.*] segment",
                        d.from
                    ),
                };
                self.d.push(
                    Diagnostic::new(Code::E0132, msg)
                        .at_opt(loc)
                        .label("expected a segment with one position per actuator")
                        .help_opt(suggest(
                            &d.from,
                            observation.iter().map(|o| o.name.as_str()),
                        )),
                );
                *actions = None;
            }
        }
    }
}
