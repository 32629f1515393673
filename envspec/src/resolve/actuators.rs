//! `[actuators.<name>]`: actuators a spec adds on hinge and slide joints (a model edit, resolved
//! before anything else).

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{ActuatorKind, AddedActuator};
use crate::mjcf::JointKind;
use crate::syntax::Section;
use crate::value::{Val, ValKind};

use super::Ctx;

impl Ctx<'_> {
    /// One `[actuators.<name>]` table: an actuator per joint it names, appended to `out`.
    pub(super) fn actuator_section(&mut self, s: &Section, out: &mut Vec<AddedActuator>) {
        if s.name.contains('\0') {
            self.d
                .push(super::added::nul_in_name("actuator", s.name_loc.clone()));
            return;
        }
        let Some(jv) = s.get("joint") else { return };
        let targets = self.actuator_targets(s, jv);
        let gears = self.actuator_gears(s, targets.len());
        let ctrlrange = self.actuator_ctrlrange(s);
        let what = |k: &str| format!("actuators.{}.{k}", s.name);
        let forcerange = s.get("forcerange").and_then(|v| {
            let (lo, hi) = self.range(v, &what("forcerange"))?;
            let max = crate::limits::MAX_MAGNITUDE;
            self.within(v, lo, &what("forcerange"), max)?;
            self.within(v, hi, &what("forcerange"), max)?;
            Some((lo, hi))
        });
        let kind = match s.kind("motor") {
            "position" => ActuatorKind::Position {
                kp: self.gain(s, "kp").unwrap_or(1.0),
                kv: self.gain(s, "kv"),
            },
            "velocity" => ActuatorKind::Velocity {
                kv: self.gain(s, "kv").unwrap_or(1.0),
            },
            _ => ActuatorKind::Motor,
        };

        for ((name, joint), gear) in targets.into_iter().zip(gears) {
            let taken = self.model.actuators.iter().any(|a| a.name == name)
                || out.iter().any(|a| a.name == name);
            if taken {
                self.d.push(
                    Diagnostic::new(Code::E0106, format!("actuator `{name}` is defined twice"))
                        .at(s.name_loc.clone())
                        .label("actuator names must be unique (the model's own included)"),
                );
                continue;
            }
            out.push(AddedActuator {
                name,
                section: s.name.clone(),
                joint,
                kind,
                gear,
                ctrlrange,
                forcerange,
            });
        }
    }

    /// The actuators a table adds, as (actuator name, joint name): one named for the table when
    /// `joint` is one name, one named for each joint of a list or of `"*"` (every hinge and slide
    /// joint).
    fn actuator_targets(&mut self, s: &Section, jv: &Val) -> Vec<(String, String)> {
        let what = |k: &str| format!("actuators.{}.{k}", s.name);
        match &jv.kind {
            ValKind::Str(j) if j == "*" => {
                let all: Vec<(String, String)> = self
                    .model
                    .joints
                    .iter()
                    .filter(|j| matches!(j.kind, JointKind::Hinge | JointKind::Slide))
                    .map(|j| (j.name.clone(), j.name.clone()))
                    .collect();
                if all.is_empty() {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0107,
                            "`joint = \"*\"` matches no hinge or slide joint",
                        )
                        .at(jv.loc.clone())
                        .label("the model has no hinge or slide joints"),
                    );
                }
                all
            }
            ValKind::Str(j) => match self.actuated_joint(j, jv) {
                Some(()) => vec![(s.name.clone(), j.clone())],
                None => vec![],
            },
            ValKind::Array(items) => {
                let mut v = vec![];
                for item in items {
                    match item.as_str() {
                        Some(j) => {
                            if self.actuated_joint(j, item).is_some() {
                                v.push((j.to_string(), j.to_string()));
                            }
                        }
                        None => self.d.push(item.type_error(&what("joint"), "a joint name")),
                    }
                }
                v
            }
            _ => {
                self.d.push(jv.type_error(
                    &what("joint"),
                    "a joint name, a list of joint names or \"*\"",
                ));
                vec![]
            }
        }
    }

    /// `gear`: one for every joint, or one per joint in the `joint` list's order.
    fn actuator_gears(&mut self, s: &Section, n: usize) -> Vec<f64> {
        let what = |k: &str| format!("actuators.{}.{k}", s.name);
        match s.get("gear") {
            None => vec![1.0; n],
            Some(v) => match &v.kind {
                ValKind::Array(a) if a.len() == n => a
                    .iter()
                    .map(|x| {
                        self.num_within(x, &what("gear"), crate::limits::MAX_MAGNITUDE)
                            .unwrap_or(1.0)
                    })
                    .collect(),
                ValKind::Array(a) => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0403,
                            format!(
                                "{} gears for {} joints in [actuators.{}]",
                                a.len(),
                                n,
                                s.name
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected one gear, or one per joint"),
                    );
                    vec![1.0; n]
                }
                _ => vec![
                    self.num_within(v, &what("gear"), crate::limits::MAX_MAGNITUDE)
                        .unwrap_or(1.0);
                    n
                ],
            },
        }
    }

    /// `ctrlrange`: finite in float32 ([-1, 1] when absent or not).
    fn actuator_ctrlrange(&mut self, s: &Section) -> (f64, f64) {
        let what = |k: &str| format!("actuators.{}.{k}", s.name);
        match s.get("ctrlrange") {
            Some(v) => match self.range(v, &what("ctrlrange")) {
                // The action space is [low, high] in float32: it must be finite there, and so
                // must its width, or sampling an action is meaningless.
                Some((lo, hi))
                    if !(lo as f32).is_finite()
                        || !(hi as f32).is_finite()
                        || !(hi - lo).is_finite() =>
                {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!(
                                "{}: [{lo}, {hi}] is not a finite control range",
                                what("ctrlrange")
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected finite bounds (within float32, ±3.4e38)"),
                    );
                    (-1.0, 1.0)
                }
                r => r.unwrap_or((-1.0, 1.0)),
            },
            None => (-1.0, 1.0),
        }
    }

    /// A non-negative gain `kp`/`kv`, when given.
    fn gain(&mut self, s: &Section, key: &str) -> Option<f64> {
        let v = s.get(key)?;
        let x = self.num_within(
            v,
            &format!("actuators.{}.{key}", s.name),
            crate::limits::MAX_MAGNITUDE,
        )?;
        if !(x.is_finite() && x >= 0.0) {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{key} {x} is negative"))
                    .at(v.loc.clone())
                    .label("expected a non-negative gain"),
            );
            return None;
        }
        Some(x)
    }

    /// Check that `name` is a hinge or slide joint of the model.
    fn actuated_joint(&mut self, name: &str, v: &Val) -> Option<()> {
        match self.model.joint(name) {
            Some(j) if matches!(j.kind, JointKind::Hinge | JointKind::Slide) => Some(()),
            Some(j) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0107,
                        format!("joint `{name}` is a {:?} joint", j.kind).to_lowercase(),
                    )
                    .at(v.loc.clone())
                    .label("actuators drive hinge and slide joints only"),
                );
                None
            }
            None => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0303,
                        format!(
                            "the model {} has no joint named `{name}`",
                            self.model.path.display()
                        ),
                    )
                    .at(v.loc.clone())
                    .label("expected a joint of the model")
                    .help_opt(suggest(
                        name,
                        self.model.joints.iter().map(|j| j.name.as_str()),
                    )),
                );
                None
            }
        }
    }
}
