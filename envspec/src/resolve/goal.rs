//! Goal-reaching terms: the `goal_sparse` / `goal_dense` reward kinds, the `goal_reached` info kind
//! and `[termination.*]` conditions (docs/spec-reference.md §7, §11, §9).

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{Desired, GoalCheck, GoalDistance, GoalNorm, Termination};
use crate::selector::Selection;
use crate::syntax::Section;

impl Ctx<'_> {
    /// A required selector key of a goal table (`what` names the table, e.g. `[reward.goal]`).
    fn goal_sel(&mut self, s: &Section, key: &str, what: &str) -> Option<Selection> {
        if s.get(key).is_none() {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `{key}` in {what}"))
                    .at(s.name_loc.clone())
                    .label(format!("expected a `{key}` selector")),
            );
            return None;
        }
        self.sel_key(s, key)
    }

    /// `achieved`, `desired` and `norm` of a goal table; `norm` defaults to `default_norm`.
    pub(super) fn goal_distance(
        &mut self,
        s: &Section,
        what: &str,
        default_norm: GoalNorm,
    ) -> Option<GoalDistance> {
        let norm = match s.get("norm") {
            None => Some(default_norm),
            Some(v) => {
                // A norm's name, or a string parameter holding one.
                let named = |s: &str| match self.param(s).map(|p| &p.value) {
                    Some(crate::params::ParamValue::Str(x)) => x.clone(),
                    _ => s.to_string(),
                };
                let n = v.as_str().and_then(|s| GoalNorm::parse(&named(s)));
                if n.is_none() {
                    self.d.push(
                        Diagnostic::new(Code::E0802, format!("unknown `norm` in {what}"))
                            .at(v.loc.clone())
                            .label("expected \"pairwise\" (np.linalg.norm(a - b, axis=-1)), \"blas\" (np.linalg.norm(a - b)), \"angle\" or \"angle_ignoring_z\" (quaternions), or a string parameter naming one")
                            .help_opt(v.as_str().and_then(|x| suggest(x, GoalNorm::NAMES.iter().copied()))),
                    );
                }
                n
            }
        };
        let achieved = self.goal_sel(s, "achieved", what);
        if let Some(a) = &achieved
            && a.is_empty()
        {
            self.d.push(
                Diagnostic::new(
                    Code::E0804,
                    format!("`achieved` of {what} selects no element"),
                )
                .at(s.get("achieved").expect("selected").loc.clone())
                .label("expected a selector of at least one element, e.g. `qpos[0:2]`"),
            );
            return None;
        }
        let Some(v) = s.get("desired") else {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `desired` in {what}"))
                    .at(s.name_loc.clone())
                    .label("expected a `desired` selector, or \"goal\" (the env-held goal vector)"),
            );
            return None;
        };
        let achieved = achieved?;
        let n = achieved.len();
        let desired = if v.as_str() == Some("goal") {
            match &self.goal_dim {
                Some((m, at)) if *m != n => {
                    let first = at.position();
                    self.d.push(
                        Diagnostic::new(
                            Code::E0801,
                            format!(
                                "`achieved` of {what} selects {n} elements but the goal vector has {m} (fixed at {first})"
                            ),
                        )
                        .at(s.get("achieved").expect("selected").loc.clone())
                        .label("expected every goal term with desired = \"goal\" to select the same number of elements"),
                    );
                    return None;
                }
                Some(_) => {}
                None => self.goal_dim = Some((n, v.loc.clone())),
            }
            Desired::Goal
        } else {
            let d = self.selection(v, "desired")?;
            if d.len() != n {
                self.d.push(
                    Diagnostic::new(
                        Code::E0801,
                        format!(
                            "`achieved` `{}` selects {n} elements but `desired` `{}` selects {}",
                            achieved.text,
                            d.text,
                            d.len()
                        ),
                    )
                    .at(v.loc.clone())
                    .label("expected as many elements as `achieved`"),
                );
                return None;
            }
            Desired::Select(d)
        };
        let norm = norm?;
        if matches!(norm, GoalNorm::Angle | GoalNorm::AngleIgnoringZ) && n != 4 {
            self.d.push(
                Diagnostic::new(
                    Code::E0801,
                    format!("{what}: norm = \"{}\" compares quaternions, and `achieved` `{}` selects {n} elements", norm.name(), achieved.text),
                )
                .at(s.get("achieved").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                .label("expected 4 elements (w, x, y, z)"),
            );
            return None;
        }
        Some(GoalDistance {
            achieved,
            desired,
            norm,
        })
    }

    /// A goal distance and its `threshold` (required, a finite number ≥ 0).
    pub(super) fn goal_check(
        &mut self,
        s: &Section,
        what: &str,
        default_norm: GoalNorm,
    ) -> Option<GoalCheck> {
        let distance = self.goal_distance(s, what, default_norm);
        let threshold = match s.get("threshold") {
            None => {
                self.d.push(
                    Diagnostic::new(Code::E0103, format!("missing `threshold` in {what}"))
                        .at(s.name_loc.clone())
                        .label("expected threshold = a distance (number or parameter name)"),
                );
                None
            }
            Some(v) => self.num(v, "threshold").and_then(|t| {
                if t.is_finite() && t >= 0.0 {
                    Some(t)
                } else {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0803,
                            format!("threshold {t} of {what} is not a finite distance ≥ 0"),
                        )
                        .at(v.loc.clone())
                        .label("expected a finite number ≥ 0"),
                    );
                    None
                }
            }),
        };
        let strict = match s.get("strict") {
            Some(v) => self.flag(v, "strict")?,
            None => false,
        };
        Some(GoalCheck {
            distance: distance?,
            threshold: threshold?,
            strict,
        })
    }

    /// `checks = [{ achieved, desired, threshold, norm, strict }, ...]`: goal checks that must
    /// all hold (`goals_missed`, `goals_reached`).
    pub(super) fn goal_checks(
        &mut self,
        s: &Section,
        what: &str,
        default_norm: GoalNorm,
    ) -> Option<Vec<GoalCheck>> {
        const KEYS: &[&str] = &["achieved", "desired", "threshold", "norm", "strict"];
        let Some(v) = s.get("checks") else {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `checks` in {what}"))
                    .at(s.name_loc.clone())
                    .label("expected checks = [{ achieved, desired, threshold }, ...]"),
            );
            return None;
        };
        let items = v.as_array().filter(|a| !a.is_empty());
        let Some(items) = items else {
            self.d.push(v.type_error(
                "checks",
                "a non-empty array of { achieved, desired, threshold, norm } tables",
            ));
            return None;
        };
        let mut out = vec![];
        for (i, item) in items.iter().enumerate() {
            let Some(entries) = item.as_table() else {
                self.d
                    .push(item.type_error("checks", "a { achieved, desired, threshold } table"));
                return None;
            };
            for e in entries.iter().filter(|e| !KEYS.contains(&e.key.as_str())) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("unknown key `{}` in {what} checks", e.key),
                    )
                    .at(e.key_loc.clone())
                    .label(format!("expected one of: {}", KEYS.join(", ")))
                    .help_opt(crate::diagnostic::suggest(&e.key, KEYS.iter().copied())),
                );
            }
            let section = Section {
                name: format!("{}.checks[{i}]", s.name),
                name_loc: item.loc.clone(),
                loc: item.loc.clone(),
                entries: entries.to_vec(),
            };
            out.push(self.goal_check(&section, what, default_norm));
        }
        out.into_iter().collect()
    }

    /// The `[termination.*]` conditions that are switched on.
    pub(super) fn terminations(&mut self) -> Vec<Termination> {
        let mut out = vec![];
        for s in &self.spec.termination {
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let what = format!("[termination.{}]", s.name);
            let reached = match s.kind("") {
                "goal_reached" => self.goal_check(s, &what, GoalNorm::Blas),
                _ => None, // reported by the syntax check
            };
            if let (Some(reached), true) = (reached, enabled) {
                out.push(Termination {
                    name: s.name.clone(),
                    doc: s.doc(),
                    reached,
                });
            }
        }
        out
    }
}
