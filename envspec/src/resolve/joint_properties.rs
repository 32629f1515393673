//! `[joint_properties]`: properties of hinge and slide joints by glob pattern, and of the
//! `[actuators.*]` actuators on them (a model edit, resolved with `[actuators]`).

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{ActuatorKind, JointEdit, ModelEdits};
use crate::mjcf::JointKind;
use crate::syntax::Section;
use crate::value::Val;

use super::Ctx;

/// The keys of a row that set the actuators `[actuators.*]` adds on its joints.
const ACTUATOR_KEYS: [&str; 6] = ["kp", "kv", "effort", "forcerange", "ctrlrange", "gear"];

impl Ctx<'_> {
    /// `[joint_properties]`: each row's glob pattern selects hinge and slide joints; its joint
    /// keys set those joints' properties, its actuator keys those of the `[actuators.*]`
    /// actuators on them. Rows apply in file order, so a later row overrides an earlier one
    /// key by key where both match a joint; a row overrides its `[actuators.*]` table's values.
    pub(super) fn joint_properties(&mut self, edits: &mut ModelEdits) {
        let rows = &self.spec.joint_properties;
        if rows.is_empty() {
            return;
        }
        let joints: Vec<String> = self
            .model
            .joints
            .iter()
            .filter(|j| matches!(j.kind, JointKind::Hinge | JointKind::Slide))
            .map(|j| j.name.clone())
            .collect();
        let mut table: Vec<JointEdit> = joints
            .iter()
            .map(|j| JointEdit {
                joint: j.clone(),
                ..Default::default()
            })
            .collect();
        for row in rows {
            let Some(hit) = self.matched_joints(row, &joints) else {
                continue;
            };
            let mut set: Vec<(String, Vec<f64>)> = vec![];
            self.joint_keys(row, &hit, &mut table, &mut set);
            self.actuator_keys(row, &hit, &joints, &mut table, edits, &mut set);
            edits.joint_rows.push((
                row.name.clone(),
                hit.iter().map(|&i| joints[i].clone()).collect(),
                set,
            ));
        }
        edits.joints = table.into_iter().filter(|e| !e.rows.is_empty()).collect();
    }

    /// The joints (indices into `joints`, the hinge and slide joints) a row's pattern matches;
    /// E0160 when it matches none.
    fn matched_joints(&mut self, row: &Section, joints: &[String]) -> Option<Vec<usize>> {
        let hit: Vec<usize> = (0..joints.len())
            .filter(|&i| crate::selector::glob(&row.name, &joints[i]))
            .collect();
        if hit.is_empty() {
            let named = self
                .model
                .joints
                .iter()
                .filter(|j| j.name == row.name)
                .count();
            self.d.push(
                Diagnostic::new(
                    Code::E0160,
                    format!(
                        "`{}` matches none of the {} hinge and slide joints of {}",
                        row.name,
                        joints.len(),
                        self.model.path.display()
                    ),
                )
                .at(row.name_loc.clone())
                .label(if named > 0 {
                    "this joint is not a hinge or slide joint".to_string()
                } else {
                    "a glob pattern over joint names (`*`: any run of characters, `?`: one)"
                        .to_string()
                })
                .help_opt(suggest(&row.name, joints.iter().map(String::as_str))),
            );
            return None;
        }
        Some(hit)
    }

    /// A row's joint keys (`armature`, `damping`, `frictionloss`), set on the joints it matches.
    fn joint_keys(
        &mut self,
        row: &Section,
        hit: &[usize],
        table: &mut [JointEdit],
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("joint_properties.\"{}\".{k}", row.name);
        for key in ["armature", "damping", "frictionloss"] {
            let Some(v) = row.get(key) else { continue };
            let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                continue;
            };
            set.push((key.to_string(), vec![x]));
            if !(x.is_finite() && x >= 0.0) {
                self.d.push(
                    Diagnostic::new(Code::E0161, format!("{} {x} is negative", what(key)))
                        .at(v.loc.clone())
                        .label("expected a finite number ≥ 0"),
                );
                continue;
            }
            for &i in hit {
                let e = &mut table[i];
                match key {
                    "armature" => e.armature = Some(x),
                    "damping" => e.damping = Some(x),
                    _ => e.frictionloss = Some(x),
                }
                if !e.rows.contains(&row.name) {
                    e.rows.push(row.name.clone());
                }
            }
        }
    }

    /// A row's actuator keys: they set the actuators `[actuators.*]` adds on the joints it
    /// matches (E0161 when there are none).
    fn actuator_keys(
        &mut self,
        row: &Section,
        hit: &[usize],
        joints: &[String],
        table: &mut [JointEdit],
        edits: &mut ModelEdits,
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let on: Vec<usize> = edits
            .actuators
            .iter()
            .enumerate()
            .filter(|(_, a)| hit.iter().any(|&i| joints[i] == a.joint))
            .map(|(k, _)| k)
            .collect();
        if ACTUATOR_KEYS.iter().any(|k| row.get(k).is_some()) {
            for &i in hit {
                let e = &mut table[i];
                if edits.actuators.iter().any(|a| a.joint == e.joint) && !e.rows.contains(&row.name)
                {
                    e.rows.push(row.name.clone());
                }
            }
        }
        for key in ACTUATOR_KEYS {
            let Some(v) = row.get(key) else { continue };
            if on.is_empty() {
                self.d.push(
                    Diagnostic::new(
                        Code::E0161,
                        format!(
                            "`{key}` in [joint_properties.\"{}\"] reaches no actuator: none of the {} joints it matches has one from [actuators.*]",
                            row.name,
                            hit.len()
                        ),
                    )
                    .at(v.loc.clone())
                    .label("actuator keys apply to the actuators [actuators.*] adds on the matched joints")
                    .help("add the joints to an [actuators.<name>] table (its `joint` list fixes the action order)"),
                );
                continue;
            }
            self.actuator_key(row, key, v, &on, edits, set);
        }
    }

    /// One actuator key of a row, set on the actuators `on` (indices into `edits.actuators`).
    fn actuator_key(
        &mut self,
        row: &Section,
        key: &str,
        v: &Val,
        on: &[usize],
        edits: &mut ModelEdits,
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("joint_properties.\"{}\".{k}", row.name);
        match key {
            "kp" | "kv" => self.actuator_gain_key(row, key, v, on, edits, set),
            "effort" => {
                let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                    return;
                };
                if !(x.is_finite() && x > 0.0) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0161,
                            format!("{} {x} is not a positive force", what(key)),
                        )
                        .at(v.loc.clone())
                        .label("expected a finite force limit > 0: forcerange = [-effort, effort]"),
                    );
                    return;
                }
                set.push((key.to_string(), vec![x]));
                for &k in on {
                    edits.actuators[k].forcerange = Some((-x, x));
                }
            }
            "forcerange" | "ctrlrange" => {
                let Some((lo, hi)) = self.range(v, &what(key)) else {
                    return;
                };
                if self
                    .within(v, lo, &what(key), crate::limits::MAX_MAGNITUDE)
                    .is_none()
                    || self
                        .within(v, hi, &what(key), crate::limits::MAX_MAGNITUDE)
                        .is_none()
                {
                    return;
                }
                if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0161,
                            format!("{} [{lo}, {hi}] is not a finite range", what(key)),
                        )
                        .at(v.loc.clone())
                        .label("expected [low, high], finite, low ≤ high"),
                    );
                    return;
                }
                set.push((key.to_string(), vec![lo, hi]));
                for &k in on {
                    if key == "forcerange" {
                        edits.actuators[k].forcerange = Some((lo, hi));
                    } else {
                        edits.actuators[k].ctrlrange = (lo, hi);
                    }
                }
            }
            _ => {
                let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                    return;
                };
                set.push((key.to_string(), vec![x]));
                for &k in on {
                    edits.actuators[k].gear = x;
                }
            }
        }
    }

    /// A row's `kp` or `kv`, set on the actuators `on`: E0161 at the first that is not a position
    /// actuator (or, for `kv`, a velocity actuator).
    fn actuator_gain_key(
        &mut self,
        row: &Section,
        key: &str,
        v: &Val,
        on: &[usize],
        edits: &mut ModelEdits,
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("joint_properties.\"{}\".{k}", row.name);
        let Some(x) = self.gain_value(v, &what(key), key) else {
            return;
        };
        set.push((key.to_string(), vec![x]));
        for &k in on {
            let a = &mut edits.actuators[k];
            let fits = match (&mut a.kind, key) {
                (ActuatorKind::Position { kp, .. }, "kp") => {
                    *kp = x;
                    true
                }
                (ActuatorKind::Position { kv, .. }, _) => {
                    *kv = Some(x);
                    true
                }
                (ActuatorKind::Velocity { kv }, "kv") => {
                    *kv = x;
                    true
                }
                _ => false,
            };
            if !fits {
                self.d.push(
                    Diagnostic::new(
                        Code::E0161,
                        format!(
                            "`{key}` in [joint_properties.\"{}\"] reaches actuator `{}` ([actuators.{}]), which is a {} actuator",
                            row.name,
                            a.name,
                            a.section,
                            match a.kind {
                                ActuatorKind::Motor => "motor",
                                ActuatorKind::Position { .. } => "position",
                                ActuatorKind::Velocity { .. } => "velocity",
                            }
                        ),
                    )
                    .at(v.loc.clone())
                    .label("kp applies to position actuators; kv to position and velocity actuators")
                    .help(format!("set `kind = \"position\"` in [actuators.{}]", a.section)),
                );
                break;
            }
        }
    }

    /// A row's `kp` or `kv`: a gain ≥ 0.
    fn gain_value(&mut self, v: &Val, what: &str, key: &str) -> Option<f64> {
        let x = self.num_within(v, what, crate::limits::MAX_MAGNITUDE)?;
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
}
