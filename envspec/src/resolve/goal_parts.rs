//! `[goal.parts]`: a goal made of named parts, kept as a checklist (docs/spec-reference.md §22).
//! Each part selects what the env achieves and fixes what it should be; `in_play` (a `names`
//! parameter, or a list) says which parts an episode has, in order. The goal vector is the
//! parts' desired values end to end, and `achieved` their selections.

use super::Ctx;
use super::manipulation::misfit;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::GoalNorm;
use crate::manipulation::{GOAL_PART_KEYS, GoalPart, GoalParts};
use crate::params::ParamValue;
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

/// One declared part: its name, selection and desired value.
struct Declared {
    name: String,
    achieved: Selection,
    desired: Vec<f64>,
}

impl Ctx<'_> {
    /// The parts of `[goal]` in play, and the achieved selection they make together.
    pub(super) fn goal_parts(
        &mut self,
        s: &Section,
        table: &Val,
    ) -> Option<(Selection, GoalParts)> {
        let Some(rows) = table.as_table() else {
            self.d.push(table.type_error(
                "[goal] parts",
                "a table of parts, e.g. parts.door = { achieved = \"qpos[door]\", desired = [1.2] }",
            ));
            return None;
        };
        let mut declared: Vec<Declared> = vec![];
        for row in rows {
            if let Some(p) = self.goal_part(&row.key, &row.value) {
                declared.push(p);
            }
        }
        if declared.len() != rows.len() {
            return None;
        }
        if declared.is_empty() {
            self.d.push(misfit(
                &table.loc,
                "[goal] parts is empty".into(),
                "expected at least one part",
            ));
            return None;
        }
        let in_play = self.parts_in_play(s, &declared)?;
        let field = declared[in_play[0]].achieved.field;
        if let Some(p) = in_play
            .iter()
            .map(|&i| &declared[i])
            .find(|p| p.achieved.field != field)
        {
            self.d.push(misfit(
                &table.loc,
                format!(
                    "[goal] part `{}` selects another field than part `{}`",
                    p.name, declared[in_play[0]].name
                ),
                "expected every part to select the same field (e.g. qpos), so the achieved goal is one selection",
            ));
            return None;
        }
        let threshold = match s.get("threshold") {
            Some(v) => self.num(v, "[goal] threshold")?,
            None => {
                self.d.push(
                    Diagnostic::new(Code::E0103, "missing `threshold` in [goal] with parts")
                        .at(s.name_loc.clone())
                        .label("expected the distance below which a part counts as reached"),
                );
                return None;
            }
        };
        let norm = match s.get("norm") {
            None => GoalNorm::Blas,
            Some(v) => match v.as_str().and_then(GoalNorm::parse) {
                Some(n @ (GoalNorm::Blas | GoalNorm::Pairwise)) => n,
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown [goal] norm for parts")
                            .at(v.loc.clone())
                            .label("expected \"blas\" (the default) or \"pairwise\""),
                    );
                    return None;
                }
            },
        };
        let flag = |ctx: &mut Self, key: &str| match s.get(key) {
            None => Some(true),
            Some(v) => ctx.flag(v, &format!("[goal] {key}")),
        };
        let remove_done = flag(self, "remove_done")?;
        let terminate_when_done = flag(self, "terminate_when_done")?;
        let mut achieved = Selection {
            field,
            names: vec![],
            indices: vec![],
            text: String::new(),
        };
        let mut parts = vec![];
        for &i in &in_play {
            let p = &declared[i];
            parts.push(GoalPart {
                name: p.name.clone(),
                offset: achieved.indices.len(),
                desired: p.desired.clone(),
            });
            achieved.names.extend(p.achieved.names.iter().cloned());
            achieved.indices.extend(p.achieved.indices.iter().copied());
            if !achieved.text.is_empty() {
                achieved.text.push_str(" + ");
            }
            achieved.text.push_str(&p.achieved.text);
        }
        let parts = GoalParts {
            parts,
            threshold,
            norm,
            remove_done,
            terminate_when_done,
        };
        Some((achieved, parts))
    }

    /// One `name = { achieved, desired }` row.
    fn goal_part(&mut self, name: &str, v: &Val) -> Option<Declared> {
        let what = format!("[goal] parts.{name}");
        let Some(entries) = v.as_table() else {
            self.d.push(v.type_error(
                &what,
                "a table { achieved = \"selector\", desired = [numbers] }",
            ));
            return None;
        };
        for e in entries {
            if !GOAL_PART_KEYS.contains(&e.key.as_str()) {
                self.d.push(
                    Diagnostic::new(Code::E0101, format!("unknown key `{}` in {what}", e.key))
                        .at(e.key_loc.clone())
                        .label("expected `achieved` or `desired`")
                        .help_opt(suggest(&e.key, GOAL_PART_KEYS.iter().copied())),
                );
            }
        }
        let get = |k: &str| entries.iter().find(|e| e.key == k).map(|e| &e.value);
        let (Some(a), Some(d)) = (get("achieved"), get("desired")) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("{what} needs `achieved` and `desired`"),
                )
                .at(v.loc.clone())
                .label("expected { achieved = \"selector\", desired = [numbers] }"),
            );
            return None;
        };
        let achieved = self.selection(a, "achieved")?;
        if achieved.is_empty() || achieved.field == Field::Goal {
            self.d.push(misfit(
                &a.loc,
                format!("{what}: `{}` selects no simulation element", achieved.text),
                "expected a selector of the simulation, e.g. \"qpos[door]\"",
            ));
            return None;
        }
        let desired = match d.as_array() {
            Some(xs) => xs
                .iter()
                .map(|x| self.num(x, &format!("{what} desired")))
                .collect::<Option<Vec<f64>>>()?,
            None => vec![self.num(d, &format!("{what} desired"))?],
        };
        if desired.len() != achieved.len() {
            self.d.push(misfit(
                &d.loc,
                format!(
                    "{what}: `desired` has {} numbers, `{}` selects {}",
                    desired.len(),
                    achieved.text,
                    achieved.len()
                ),
                "expected one desired number per selected element",
            ));
            return None;
        }
        Some(Declared {
            name: name.to_string(),
            achieved,
            desired,
        })
    }

    /// `in_play`: indices into `declared`, in the order given (every part, in table order, by
    /// default). A name that is no part, or given twice, is refused.
    fn parts_in_play(&mut self, s: &Section, declared: &[Declared]) -> Option<Vec<usize>> {
        let Some(v) = s.get("in_play") else {
            return Some((0..declared.len()).collect());
        };
        let (names, param) = match &v.kind {
            ValKind::Array(xs) => {
                let names = xs.iter().map(|x| x.as_str().map(str::to_string)).collect();
                let Some(names) = names else {
                    self.d
                        .push(v.type_error("[goal] in_play", "a list of part names"));
                    return None;
                };
                (names, None)
            }
            ValKind::Str(p) => match self.lookup(p, &v.loc, "a list of part names")? {
                ParamValue::Names(n) => (n, Some(p.clone())),
                other => {
                    self.wrong_param_type(p, &v.loc, "a list of names", &other);
                    return None;
                }
            },
            _ => {
                self.d.push(
                    v.type_error("[goal] in_play", "a list of part names or a parameter name"),
                );
                return None;
            }
        };
        let names: Vec<String> = names;
        let known = || declared.iter().map(|p| p.name.as_str());
        let mut out: Vec<usize> = vec![];
        for n in &names {
            let found = declared.iter().position(|p| &p.name == n);
            let problem = match found {
                None => Some(format!("`{n}` is not a part of [goal] parts")),
                Some(i) if out.contains(&i) => Some(format!("part `{n}` is in play twice")),
                Some(i) => {
                    out.push(i);
                    None
                }
            };
            if let Some(msg) = problem {
                let list = known().collect::<Vec<_>>().join("\", \"");
                let e = match &param {
                    Some(p) => self.param_error(p, &msg),
                    None => Diagnostic::new(Code::E0105, msg).at(v.loc.clone()),
                };
                self.d.push(
                    e.label(format!("expected names among \"{list}\""))
                        .help_opt(suggest(n, known())),
                );
                return None;
            }
        }
        if out.is_empty() {
            self.d.push(
                Diagnostic::new(Code::E0105, "[goal] in_play names no part")
                    .at(v.loc.clone())
                    .label("expected at least one part in play"),
            );
            return None;
        }
        Some(out)
    }
}
