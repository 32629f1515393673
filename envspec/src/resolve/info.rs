use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::ir::*;
use crate::syntax::Section;

use super::Ctx;

impl Ctx<'_> {
    /// The info entries: the `[info.*]` entries that are switched on, then the reward terms'
    /// `info` keys (E0106 for a key used twice). `off`: the names of the reward terms switched
    /// off by `when`.
    pub(super) fn info_items(&mut self, reward: &[RewardTerm], off: &[String]) -> Vec<InfoItem> {
        let mut info = self.info(reward, off);
        for (i, t) in reward.iter().enumerate() {
            if let Some(key) = &t.info {
                let loc = self
                    .spec
                    .reward
                    .iter()
                    .find(|s| s.name == t.name)
                    .and_then(|s| s.get("info"))
                    .map(|v| v.loc.clone());
                info.push((
                    InfoItem {
                        key: key.clone(),
                        doc: t.doc.clone(),
                        kind: InfoKind::Term(i),
                        len: 1,
                        at_reset: false,
                        unweighted: false,
                        float32: false,
                        boolean: false,
                    },
                    loc,
                ));
            }
        }
        self.check_info_keys(&info);
        info.into_iter().map(|(i, _)| i).collect()
    }

    /// The `[info.*]` entries that are switched on, each with the location of its key.
    /// `off`: the names of the reward terms switched off by `when`.
    fn info(&mut self, terms: &[RewardTerm], off: &[String]) -> Vec<(InfoItem, Option<Location>)> {
        let mut out = vec![];
        for s in &self.spec.info {
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let key = match s.get("key") {
                None => s.name.clone(),
                Some(v) => match v.as_str() {
                    Some(k) => k.to_string(),
                    None => {
                        self.d.push(v.type_error("key", "an info key (a string)"));
                        continue;
                    }
                },
            };
            let key_loc = s
                .get("key")
                .map(|v| v.loc.clone())
                .unwrap_or(s.name_loc.clone());
            let in_reset = match s.get("in_reset") {
                Some(v) => self.flag(v, "in_reset").unwrap_or(true),
                None => true,
            };
            let unweighted = match s.get("unweighted") {
                Some(v) => self.flag(v, "unweighted").unwrap_or(false),
                None => false,
            };
            let Some((kind, len, at_reset)) = self.info_kind(s, terms, off, enabled, in_reset)
            else {
                continue;
            };
            if !enabled {
                continue;
            }
            let (float32, boolean) = self.info_dtype(s);
            out.push((
                InfoItem {
                    key,
                    doc: s.doc(),
                    kind,
                    len,
                    at_reset,
                    unweighted,
                    float32,
                    boolean,
                },
                Some(key_loc),
            ));
        }
        out
    }

    /// What an entry reports, its length, and whether the reset's info has it too (None: an
    /// error, reported here or by the syntax check).
    fn info_kind(
        &mut self,
        s: &Section,
        terms: &[RewardTerm],
        off: &[String],
        enabled: bool,
        in_reset: bool,
    ) -> Option<(InfoKind, usize, bool)> {
        Some(match s.kind("value") {
            "term" => (self.term_info(s, terms, off, enabled)?, 1, false),
            "goal_reached" => {
                let what = format!("[info.{}]", s.name);
                let c = self.goal_check(s, &what, GoalNorm::Blas)?;
                (InfoKind::GoalReached(c), 1, in_reset)
            }
            "goals_reached" => {
                let what = format!("[info.{}]", s.name);
                let cs = self.goal_checks(s, &what, GoalNorm::Blas)?;
                (InfoKind::GoalsReached(cs), 1, in_reset)
            }
            "condition" => {
                let what = format!("[info.{}] condition", s.name);
                // A missing `condition` is reported by the syntax check.
                let v = s.get("condition")?;
                let cs = self.conditions(v, &what)?;
                (InfoKind::Condition(cs), 1, in_reset)
            }
            "goal_parts" => {
                let which = s.get("which").and_then(|v| {
                    let set = v.as_str().and_then(PartSet::parse);
                    if set.is_none() {
                        self.d.push(
                            Diagnostic::new(Code::E0104, "unknown goal_parts `which`")
                                .at(v.loc.clone())
                                .label("expected \"remaining\", \"reached\" or \"completed\""),
                        );
                    }
                    set
                });
                if self.goal_parts == 0 {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0170,
                            format!("[info.{}] kind = \"goal_parts\" needs [goal] parts", s.name),
                        )
                        .at(s.name_loc.clone())
                        .label("expected a [goal] table with `parts`"),
                    );
                    return None;
                }
                let Some(which) = which else {
                    if s.get("which").is_none() {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0103,
                                format!("missing `which` in [info.{}]", s.name),
                            )
                            .at(s.name_loc.clone())
                            .label("expected which = \"remaining\", \"reached\" or \"completed\""),
                        );
                    }
                    return None;
                };
                (InfoKind::GoalParts(which), self.goal_parts, in_reset)
            }
            kind => return self.source_info(s, kind, in_reset),
        })
    }

    /// `kind = "term"`: a reward term by name, which must be switched on whenever the entry is.
    fn term_info(
        &mut self,
        s: &Section,
        terms: &[RewardTerm],
        off: &[String],
        enabled: bool,
    ) -> Option<InfoKind> {
        let v = s.get("term")?;
        let Some(name) = v.as_str() else {
            self.d
                .push(v.type_error("term", "the name of a reward term"));
            return None;
        };
        match terms.iter().position(|t| t.name == name) {
            Some(i) => Some(InfoKind::Term(i)),
            None => {
                let declared = self.spec.reward.iter().any(|r| r.name == name);
                if !declared {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0502,
                            format!(
                                "[info.{}] reports `{name}`, which is not a reward term",
                                s.name
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected the name of a [reward.<name>] table")
                        .help_opt(suggest(
                            name,
                            self.spec.reward.iter().map(|r| r.name.as_str()),
                        )),
                    );
                } else if enabled && off.iter().any(|o| o == name) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0502,
                            format!(
                                "[info.{}] reports reward term `{name}`, which its `when` switches off",
                                s.name
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected a term that is switched on whenever this entry is (give the entry the same `when`)"),
                    );
                }
                // A declared term that failed to resolve was reported where it failed.
                None
            }
        }
    }

    /// An entry that reads a selection: `value` (optionally `minus` another), `norm`, `velocity`.
    fn source_info(
        &mut self,
        s: &Section,
        kind: &str,
        in_reset: bool,
    ) -> Option<(InfoKind, usize, bool)> {
        let source = self.sel_key(s, "source")?;
        let len = source.len();
        Some(match kind {
            "value" => {
                let minus = self.sel_key(s, "minus").filter(|m| {
                    self.same_len(
                        &source,
                        m,
                        &s.get("minus").expect("`minus` was read just above").loc,
                    )
                });
                (InfoKind::Value { source, minus }, len, in_reset)
            }
            "norm" => (InfoKind::Norm { source }, 1, in_reset),
            "velocity" => {
                if !self.scalar(
                    &source,
                    &s.get("source").expect("`source` was read just above").loc,
                    "a velocity",
                ) {
                    return None;
                }
                (InfoKind::Velocity { source }, 1, false)
            }
            _ => return None,
        })
    }

    /// An entry's `dtype` as (float32, bool): "float64" (the default), "float32" or "bool".
    fn info_dtype(&mut self, s: &Section) -> (bool, bool) {
        match s.get("dtype") {
            None => (false, false),
            Some(v) => match v.as_str() {
                Some("float32") => (true, false),
                Some("float64") => (false, false),
                Some("bool") => (false, true),
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown info `dtype`")
                            .at(v.loc.clone())
                            .label("expected \"float64\" (the default), \"float32\" or \"bool\""),
                    );
                    (false, false)
                }
            },
        }
    }

    fn check_info_keys(&mut self, info: &[(InfoItem, Option<Location>)]) {
        for (i, (item, loc)) in info.iter().enumerate() {
            if info[..i].iter().any(|(o, _)| o.key == item.key) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0106,
                        format!("info key `{}` is defined twice", item.key),
                    )
                    .at_opt(loc.clone())
                    .label("expected unique info keys (among the entries switched on)"),
                );
            }
        }
    }
}
