//! `[keyframes.<name>]`: keyframes a spec adds to its model, written by joint name or glob
//! pattern; and the reset kinds that read them (`keyframe`) or draw a root pose (`root_pose`).

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{Distribution, ResetStep, SpecKeyframe};
use crate::mjcf::JointKind;
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

use super::Ctx;

/// The order of `root_pose`'s six draws (mjlab's `_SE3_KEYS`).
pub const ROOT_POSE_KEYS: [&str; 6] = ["x", "y", "z", "roll", "pitch", "yaw"];

impl Ctx<'_> {
    fn e0162(&mut self, v: &Val, message: String, label: &str) {
        self.d.push(
            Diagnostic::new(Code::E0162, message)
                .at(v.loc.clone())
                .label(label.to_string()),
        );
    }

    fn numbers(&mut self, v: &Val, what: &str, n: usize) -> Option<Vec<f64>> {
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a
                .iter()
                .map(|x| self.num_within(x, what, crate::limits::MAX_COORDINATE))
                .collect(),
            ValKind::Array(a) => {
                self.e0162(
                    v,
                    format!("{what} has {} numbers; it takes {n}", a.len()),
                    &format!("expected {n} numbers"),
                );
                None
            }
            _ => {
                self.d
                    .push(v.type_error(what, &format!("an array of {n} numbers")));
                None
            }
        }
    }

    /// The free joint a root reset moves: `joint = "…"`, else the model's first.
    pub(super) fn root_joint(&mut self, s: &Section, kind: &str) -> Option<crate::mjcf::Joint> {
        if let Some(v) = s.get("joint") {
            let name = v.as_str().unwrap_or_default();
            return match self.model.joint(name) {
                Some(j) if matches!(j.kind, JointKind::Free) => Some(j.clone()),
                _ => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0162,
                            format!(
                                "[reset.{}]: `{name}` is not a free joint of the model",
                                s.name
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected the name of a free joint (a floating base)"),
                    );
                    None
                }
            };
        }
        let free = self.free_joint().cloned();
        if free.is_none() {
            self.d.push(
                Diagnostic::new(
                    Code::E0162,
                    format!(
                        "[reset.{}]: a {kind} reset needs a free joint; the model has none",
                        s.name
                    ),
                )
                .at(s.name_loc.clone())
                .label(format!("{kind} moves a floating base")),
            );
        }
        free
    }

    /// The first free joint (a floating base), for root values.
    fn free_joint(&self) -> Option<&crate::mjcf::Joint> {
        self.model
            .joints
            .iter()
            .find(|j| matches!(j.kind, JointKind::Free))
    }

    pub(super) fn keyframes(&mut self) -> Vec<SpecKeyframe> {
        let mut out: Vec<SpecKeyframe> = vec![];
        for s in &self.spec.keyframes {
            if s.name.contains('\0') {
                self.d
                    .push(super::added::nul_in_name("keyframe", s.name_loc.clone()));
                continue;
            }
            if self.model.keyframes.iter().any(|k| k == &s.name)
                || out.iter().any(|k| k.name == s.name)
            {
                self.d.push(
                    Diagnostic::new(
                        Code::E0106,
                        format!("keyframe `{}` is defined twice", s.name),
                    )
                    .at(s.name_loc.clone())
                    .label("keyframe names must be unique (the model's own included)"),
                );
                continue;
            }
            if let Some(k) = self.keyframe(s) {
                out.push(k);
            }
        }
        out
    }

    fn keyframe(&mut self, s: &Section) -> Option<SpecKeyframe> {
        let what = |k: &str| format!("keyframes.{}.{k}", s.name);
        let mut k = SpecKeyframe {
            name: s.name.clone(),
            from: None,
            values: vec![],
        };
        if let Some(v) = s.get("from") {
            let name = v.as_str().unwrap_or_default().to_string();
            match self.model.keyframes.iter().position(|x| *x == name) {
                Some(i) => k.from = Some(i),
                None => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0162,
                            format!(
                                "the model {} has no keyframe named `{name}` ({} named)",
                                self.model.path.display(),
                                self.model
                                    .keyframes
                                    .iter()
                                    .filter(|x| !x.is_empty())
                                    .count()
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected one of the model's own keyframes")
                        .help_opt(suggest(
                            &name,
                            self.model.keyframes.iter().map(String::as_str),
                        )),
                    );
                    return None;
                }
            }
        }
        for (key, n, at) in [("root_pos", 3, 0), ("root_quat", 4, 3)] {
            let Some(v) = s.get(key) else { continue };
            let Some(x) = self.numbers(v, &what(key), n) else {
                continue;
            };
            let Some(adr) = self.free_joint().map(|j| j.qposadr) else {
                self.e0162(
                    v,
                    format!("{} needs a free joint; the model has none", what(key)),
                    "root values are the first free joint's qpos",
                );
                continue;
            };
            k.values
                .extend(x.into_iter().enumerate().map(|(i, x)| (adr + at + i, x)));
        }
        if let Some(v) = s.get("joints") {
            let ValKind::Table(rows) = &v.kind else {
                self.d.push(
                    v.type_error(&what("joints"), "a table of joint name or pattern = value"),
                );
                return Some(k);
            };
            let joints: Vec<(String, usize)> = self
                .model
                .joints
                .iter()
                .filter(|j| matches!(j.kind, JointKind::Hinge | JointKind::Slide))
                .map(|j| (j.name.clone(), j.qposadr))
                .collect();
            for row in rows {
                let Some(x) =
                    self.num_within(&row.value, &what("joints"), crate::limits::MAX_COORDINATE)
                else {
                    continue;
                };
                let Some(hit) = self.glob_hits(
                    &row.key,
                    joints.iter().map(|(n, _)| n.as_str()),
                    &row.key_loc,
                    &format!(
                        "the {} hinge and slide joints of {}",
                        joints.len(),
                        self.model.path.display()
                    ),
                    "a joint name or glob pattern (`*`, `?`)",
                ) else {
                    continue;
                };
                let hit: Vec<usize> = hit.into_iter().map(|i| joints[i].1).collect();
                // Later rows win: the runtime writes the values in order.
                k.values.extend(hit.into_iter().map(|a| (a, x)));
            }
        }
        Some(k)
    }

    /// `kind = "keyframe"` and `kind = "root_pose"` reset steps (None for other kinds).
    pub(super) fn keyframe_reset(&mut self, s: &Section) -> Option<Option<ResetStep>> {
        match s.kind("") {
            "keyframe" => Some(self.reset_to_keyframe(s)),
            "root_pose" => Some(self.root_pose(s)),
            _ => None,
        }
    }

    fn reset_to_keyframe(&mut self, s: &Section) -> Option<ResetStep> {
        let v = s.get("keyframe")?;
        let Some(name) = v.as_str() else {
            self.d.push(v.type_error("keyframe", "a keyframe name"));
            return None;
        };
        let Some(index) = self.model.keyframes.iter().position(|k| k == name) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0162,
                    format!(
                        "[reset.{}]: no keyframe named `{name}` in the model or the spec ({} named)",
                        s.name,
                        self.model.keyframes.iter().filter(|k| !k.is_empty()).count()
                    ),
                )
                .at(v.loc.clone())
                .label("expected a keyframe of the model or a [keyframes.*] table")
                .help_opt(suggest(
                    name,
                    self.model.keyframes.iter().map(String::as_str),
                )),
            );
            return None;
        };
        let nq = self.model.nq;
        Some(ResetStep {
            name: s.name.clone(),
            doc: s.doc(),
            target: Selection {
                field: Field::Qpos,
                indices: (0..nq).collect(),
                names: (0..nq).map(|i| format!("qpos[{i}]")).collect(),
                text: "qpos".into(),
            },
            dist: Distribution::Keyframe {
                index,
                name: name.to_string(),
            },
            set: true,
            resample_until: None,
            around: None,
            probability: None,
        })
    }

    fn root_pose(&mut self, s: &Section) -> Option<ResetStep> {
        let joint = self.root_joint(s, "root_pose")?;
        let mut ranges = [(0.0, 0.0); 6];
        for (i, key) in ROOT_POSE_KEYS.iter().enumerate() {
            let Some(v) = s.get(key) else { continue };
            let (lo, hi) = self.range(v, &format!("reset.{}.{key}", s.name))?;
            if !(lo.is_finite() && hi.is_finite() && lo <= hi)
                || lo.abs().max(hi.abs()) > crate::limits::MAX_COORDINATE
            {
                self.e0162(
                    v,
                    format!(
                        "[reset.{}] {key} = [{lo}, {hi}] is not a finite range",
                        s.name
                    ),
                    "expected [low, high] with low ≤ high, within ±1e6",
                );
                return None;
            }
            ranges[i] = (lo, hi);
        }
        Some(root_step(s, &joint, 7, Distribution::RootPose { ranges }))
    }
}

/// A reset step adding `dist`'s draw to the first `n` of a free joint's `qpos` (x, y, z, then
/// the quaternion).
pub(super) fn root_step(
    s: &Section,
    joint: &crate::mjcf::Joint,
    n: usize,
    dist: Distribution,
) -> ResetStep {
    let a = joint.qposadr;
    ResetStep {
        name: s.name.clone(),
        doc: s.doc(),
        target: Selection {
            field: Field::Qpos,
            indices: (a..a + n).collect(),
            names: ["x", "y", "z", "qw", "qx", "qy", "qz"][..n]
                .iter()
                .map(|c| format!("qpos[{}].{c}", joint.name))
                .collect(),
            text: format!("qpos[{}]", joint.name),
        },
        dist,
        set: false,
        resample_until: None,
        around: None,
        probability: None,
    }
}
