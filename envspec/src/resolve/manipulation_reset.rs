//! The reset kinds of manipulation tasks (docs/spec-reference.md §22): `meet`, `rotation` /
//! `unit_quaternion` and `settle`.

use super::Ctx;
use super::manipulation::misfit;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{Distribution, Meet, ResetStep, Settle};
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

impl Ctx<'_> {
    /// A `meet` reset step: `n` target numbers are `n / 3` points, which start at `around`.
    pub(super) fn meet(&mut self, s: &Section, n: usize) -> Option<Distribution> {
        let what = format!("[reset.{}]", s.name);
        let Some(around) = s.get("around") else {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `around` in {what}"))
                    .at(s.name_loc.clone())
                    .label("expected the [init] record the points start from"),
            );
            return None;
        };
        let points = n / 3;
        if !n.is_multiple_of(3) || points == 0 {
            self.d.push(misfit(
                &around.loc,
                format!("{what}: a meet target is points of 3 numbers, and it has {n} numbers"),
                "expected a target of 3, 6, 9, … numbers",
            ));
            return None;
        }
        let Some(center) = s.get("center") else {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `center` in {what}"))
                    .at(s.name_loc.clone())
                    .label(
                        "expected the [init] record (3 numbers) the meeting point is drawn around",
                    ),
            );
            return None;
        };
        let center = self.around(center, 3, &what)?;
        let offset = match s.get("offset") {
            Some(v) => self.number_list(v, "offset", 3)?,
            None => vec![0.0; 3],
        };
        let mut number = |key: &str, default: f64, range: (f64, f64)| -> Option<f64> {
            let Some(v) = s.get(key) else {
                return Some(default);
            };
            let x = self.num(v, key)?;
            if !(range.0 <= x && x <= range.1) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0105,
                        format!("{what}: {key} = {x} is outside [{}, {}]", range.0, range.1),
                    )
                    .at(v.loc.clone())
                    .label(format!("expected a number in [{}, {}]", range.0, range.1)),
                );
                return None;
            }
            Some(x)
        };
        let max = crate::limits::MAX_COORDINATE;
        let scale = number("scale", 0.0, (0.0, max))?;
        let gap = number("gap", 0.0, (0.0, max))?;
        let unchanged = number("unchanged", 0.0, (0.0, 1.0))?;
        let mut indices = |key: &str| -> Option<Vec<usize>> {
            let Some(v) = s.get(key) else {
                return Some(vec![]);
            };
            let list = match &v.kind {
                ValKind::Array(a) => a
                    .iter()
                    .map(|x| match x.kind {
                        ValKind::Int(i) => usize::try_from(i).ok().filter(|&i| i < points),
                        _ => None,
                    })
                    .collect::<Option<Vec<usize>>>(),
                _ => None,
            };
            if list.is_none() {
                self.d.push(v.type_error(
                    key,
                    &format!("an array of point indices below {points} (the target's points)"),
                ));
            }
            list
        };
        let always = indices("always")?;
        let one_of = indices("one_of")?;
        if let Some(i) = always.iter().find(|i| one_of.contains(i)) {
            let at = s
                .get("one_of")
                .map_or(s.name_loc.clone(), |v| v.loc.clone());
            self.d.push(misfit(
                &at,
                format!("{what}: point {i} is in both `always` and `one_of`"),
                "expected the drawn point to be another than those that always move",
            ));
            return None;
        }
        Some(Distribution::Meet(Box::new(Meet {
            center: [center[0], center[1], center[2]],
            offset: [offset[0], offset[1], offset[2]],
            scale,
            always,
            one_of,
            gap,
            unchanged,
        })))
    }

    /// A `rotation` or `unit_quaternion` reset step: its target is one quaternion.
    pub(super) fn rotation(&mut self, s: &Section, kind: &str, n: usize) -> Option<Distribution> {
        if n != 4 {
            let at = s
                .get("target")
                .map_or(s.name_loc.clone(), |v| v.loc.clone());
            self.d.push(misfit(
                &at,
                format!(
                    "[reset.{}]: a {kind} target is one quaternion (4 numbers), not {n}",
                    s.name
                ),
                "expected a quaternion, e.g. \"qpos[object:joint][3:7]\" or \"goal[3:7]\"",
            ));
            return None;
        }
        if kind == "unit_quaternion" {
            return Some(Distribution::UnitQuaternion);
        }
        let axis = match s.get("axis") {
            Some(v) => {
                let a = self.number_list(v, "axis", 3)?;
                if a.iter().all(|x| *x == 0.0) {
                    self.d.push(misfit(
                        &v.loc,
                        format!("[reset.{}]: the rotation axis is zero", s.name),
                        "expected a nonzero axis, e.g. [0.0, 0.0, 1.0]",
                    ));
                    return None;
                }
                Some([a[0], a[1], a[2]])
            }
            None => None,
        };
        let angle = match s.get("angle") {
            Some(v) => {
                let r = self.range(v, "angle")?;
                if !(r.0 <= r.1 && (r.1 - r.0).is_finite()) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!(
                                "[reset.{}]: angle range [{}, {}) is empty or infinite",
                                s.name, r.0, r.1
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected [low, high] radians with low <= high"),
                    );
                    return None;
                }
                r
            }
            None => (-std::f64::consts::PI, std::f64::consts::PI),
        };
        let parallel = match s.get("parallel") {
            Some(v) => self.flag(v, "parallel")?,
            None => false,
        };
        Some(Distribution::Rotation(crate::ir::Rotation {
            axis,
            angle,
            parallel,
        }))
    }

    /// A `settle` reset step (no target).
    pub(super) fn settle(&mut self, s: &Section) -> Option<ResetStep> {
        let what = format!("[reset.{}]", s.name);
        let most = crate::limits::MAX_SETTLE_PHYSICS_STEPS / u64::from(self.frame_skip.max(1));
        let steps = match s.get("steps") {
            Some(v) => match v.kind {
                ValKind::Int(i) if i >= 1 && (i as u64) <= most => i as u32,
                _ => {
                    self.d.push(misfit(
                        &v.loc,
                        format!("{what}: steps must be a step count from 1 to {most}"),
                        "expected a whole number of control steps",
                    ));
                    return None;
                }
            },
            None => {
                self.d.push(
                    Diagnostic::new(Code::E0103, format!("missing `steps` in {what}"))
                        .at(s.name_loc.clone())
                        .label("expected steps = the number of control steps"),
                );
                return None;
            }
        };
        let require = match (s.get("watch"), s.get("above")) {
            (None, None) => None,
            (Some(w), Some(a)) => {
                let sel = self.selection(w, "watch")?;
                if sel.len() != 1 {
                    self.d.push(misfit(
                        &w.loc,
                        format!("{what}: `watch` selects {} values", sel.len()),
                        "expected one value, e.g. \"site_xpos[object:center][2]\"",
                    ));
                    return None;
                }
                let x = self.num(a, "above")?;
                Some((sel, x))
            }
            (Some(v), None) | (None, Some(v)) => {
                self.d.push(misfit(
                    &v.loc,
                    format!("{what}: `watch` and `above` go together"),
                    "expected both: the value checked and the bound it must exceed",
                ));
                return None;
            }
        };
        let records = match s.get("record") {
            Some(v) => self.record_names(v, &what)?,
            None => vec![],
        };
        Some(ResetStep {
            name: s.name.clone(),
            doc: s.doc(),
            target: Selection {
                field: Field::Qpos,
                indices: vec![],
                names: vec![],
                text: String::new(),
            },
            dist: Distribution::Settle(Box::new(Settle {
                steps,
                require,
                records,
            })),
            set: true,
            resample_until: None,
            around: None,
            probability: None,
        })
    }

    /// `record = ["name", ...]`: indices of `[init] record`s.
    fn record_names(&mut self, v: &Val, what: &str) -> Option<Vec<usize>> {
        let known: Vec<String> = self.records.iter().map(|r| r.0.clone()).collect();
        let Some(items) = v.as_array() else {
            self.d
                .push(v.type_error("record", "an array of [init] record names"));
            return None;
        };
        let mut out = vec![];
        for item in items {
            let Some(name) = item.as_str() else {
                self.d
                    .push(item.type_error("record", "the name of an [init] record"));
                return None;
            };
            match known.iter().position(|k| k == name) {
                Some(i) => out.push(i),
                None => {
                    self.d.push(
                        misfit(
                            &item.loc,
                            format!("{what}: `{name}` is no [init] record"),
                            "expected the name of an [init] record",
                        )
                        .help_opt(suggest(name, known.iter().map(String::as_str))),
                    );
                    return None;
                }
            }
        }
        Some(out)
    }
}
