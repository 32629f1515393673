//! `[reward.*]` terms and `[reward] sum`: how the terms add up to the reward.

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::*;
use crate::selector::Selection;
use crate::syntax::Section;
use crate::value::{Val, ValKind};

use super::Ctx;

/// Drop the terms switched off by `when`: from the term list (renumbering the rest) and from the
/// sum, where a list left empty disappears from its parent (the top level stays, summing to 0).
fn prune_terms(terms: Vec<(RewardTerm, bool)>, sum: SumNode) -> (Vec<RewardTerm>, SumNode) {
    let mut map = Vec::with_capacity(terms.len());
    let mut kept = vec![];
    for (t, on) in terms {
        map.push(on.then_some(kept.len()));
        if on {
            kept.push(t);
        }
    }
    fn prune(n: SumNode, map: &[Option<usize>]) -> Option<SumNode> {
        match n {
            SumNode::Term(i) => map.get(i).copied().flatten().map(SumNode::Term),
            SumNode::Sum(c) => {
                let c: Vec<SumNode> = c.into_iter().filter_map(|x| prune(x, map)).collect();
                (!c.is_empty()).then_some(SumNode::Sum(c))
            }
        }
    }
    let sum = prune(sum, &map).unwrap_or(SumNode::Sum(vec![]));
    (kept, sum)
}

impl Ctx<'_> {
    /// The reward terms that resolve and are switched on, their sum, and the names of the terms
    /// `when` switches off.
    pub(super) fn rewards(&mut self) -> (Vec<RewardTerm>, SumNode, Vec<String>) {
        let terms = self.reward_terms();
        let all_terms: Vec<RewardTerm> = terms.iter().map(|(t, _)| t.clone()).collect();
        // `sum` names every term, switched on or not; switched-off terms are then pruned from it.
        let full_sum = self.reward_sum(&all_terms);
        let off: Vec<String> = terms
            .iter()
            .filter(|(_, on)| !on)
            .map(|(t, _)| t.name.clone())
            .collect();
        let (reward, reward_sum) = prune_terms(terms, full_sum);
        (reward, reward_sum, off)
    }

    /// Every term that resolves, with whether its `when` switches it on.
    fn reward_terms(&mut self) -> Vec<(RewardTerm, bool)> {
        let mut out = vec![];
        for s in &self.spec.reward {
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let before = self.term_at(s);
            let paid_when_unhealthy = match s.get("paid_when_unhealthy") {
                Some(v) => self.flag(v, "paid_when_unhealthy").unwrap_or(false),
                None => false,
            };
            let weight = match s.get("weight") {
                Some(w) => self.num(w, "weight").unwrap_or(f64::NAN),
                None => 1.0,
            };
            let cost = match s.get("cost") {
                Some(v) => self.flag(v, "cost").unwrap_or(false),
                None => false,
            };
            let info = self.term_info_key(s);
            let kind = self.term_kind(s);
            let only_if = match s.get("only_if") {
                Some(v) => self
                    .conditions(v, &format!("[reward.{}] only_if", s.name))
                    .unwrap_or_default(),
                None => vec![],
            };
            let unless = match s.get("unless") {
                Some(v) => self
                    .conditions(v, &format!("[reward.{}] unless", s.name))
                    .unwrap_or_default(),
                None => vec![],
            };
            if let Some(kind) = kind {
                out.push((
                    RewardTerm {
                        name: s.name.clone(),
                        doc: s.doc(),
                        kind,
                        weight,
                        cost,
                        info,
                        before,
                        paid_when_unhealthy,
                        only_if,
                        unless,
                    },
                    enabled,
                ));
            }
        }
        out
    }

    /// A term's `at`: "before" (true: the state before the action) or "after" (the default),
    /// which the kinds that need the post-step state refuse.
    fn term_at(&mut self, s: &Section) -> bool {
        match s.get("at") {
            None => false,
            Some(v) => match v.as_str() {
                Some("after") => false,
                Some("before")
                    if matches!(
                        s.kind(""),
                        "velocity" | "healthy" | "feet_air_time" | "feet_slip"
                    ) =>
                {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0104,
                            format!(
                                "a `{}` term cannot be evaluated before the step",
                                s.kind("")
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected \"after\" (velocity, healthy and feet terms need the post-step state)"),
                    );
                    false
                }
                Some("before") => true,
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown `at`")
                            .at(v.loc.clone())
                            .label("expected \"after\" (the post-step state) or \"before\" (the state before the action)")
                            .help_opt(v.as_str().and_then(|x| suggest(x, ["after", "before"]))),
                    );
                    false
                }
            },
        }
    }

    /// A term's `info`: the info key that reports it.
    fn term_info_key(&mut self, s: &Section) -> Option<String> {
        match s.get("info") {
            Some(v) => match v.as_str() {
                Some(k) => Some(k.to_string()),
                None => {
                    self.d.push(v.type_error("info", "a key name"));
                    None
                }
            },
            None => None,
        }
    }

    /// What a term computes, by its `kind` (None: the term has an error, reported).
    fn term_kind(&mut self, s: &Section) -> Option<TermKind> {
        match s.kind("") {
            "velocity" => self.need_sel(s, "source").and_then(|src| {
                self.scalar(
                    &src,
                    &s.get("source").expect("`source` was read just above").loc,
                    "a velocity",
                )
                .then_some(TermKind::Velocity { source: src })
            }),
            "healthy" => Some(TermKind::Healthy),
            "sum_squares" => self
                .need_sel(s, "source")
                .map(|source| TermKind::SumSquares {
                    source,
                    clip_input: s
                        .get("clip_input")
                        .and_then(|v| self.range(v, "clip_input")),
                    clip: s.get("clip").and_then(|v| self.range(v, "clip")),
                }),
            "norm" => self.need_sel(s, "source").map(|source| {
                let minus = self.sel_key(s, "minus").filter(|m| {
                    self.same_len(
                        &source,
                        m,
                        &s.get("minus").expect("`minus` was read just above").loc,
                    )
                });
                TermKind::Norm { source, minus }
            }),
            "quadratic" => self.need_sel(s, "source").and_then(|source| {
                let n = source.len();
                let coefs = self.num_list(s, "coefs", n, 1.0)?;
                let targets = self.num_list(s, "targets", n, 0.0)?;
                Some(TermKind::Quadratic {
                    source,
                    coefs,
                    targets,
                })
            }),
            "value" => self.value_term(s),
            "constant" => Some(TermKind::Constant),
            "weighted_square" => self.need_sel(s, "source").and_then(|source| {
                let loc = &s.get("source").expect("`source` was read just above").loc;
                if !self.scalar(&source, loc, "a weighted_square term") {
                    return None;
                }
                let target = match s.get("target") {
                    Some(v) => self.num(v, "target")?,
                    None => 0.0,
                };
                Some(TermKind::WeightedSquare { source, target })
            }),
            "goal_sparse" => self
                .goal_check(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                .map(TermKind::GoalSparse),
            "goal_dense" => self
                .goal_distance(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                .map(TermKind::GoalDense),
            "goal_missed" => self
                .goal_check(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                .map(TermKind::GoalMissed),
            "goal_distance" => self
                .goal_distance(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                .map(TermKind::GoalDistance),
            "goals_missed" => self
                .goal_checks(s, &format!("[reward.{}]", s.name), GoalNorm::Pairwise)
                .map(TermKind::GoalsMissed),
            "parts_reached" if self.goal_parts == 0 => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0170,
                        format!(
                            "[reward.{}] kind = \"parts_reached\" needs [goal] parts",
                            s.name
                        ),
                    )
                    .at(s.name_loc.clone())
                    .label("expected a [goal] table with `parts`"),
                );
                None
            }
            "parts_reached" => Some(TermKind::PartsReached),
            k if LeggedTerm::KINDS.contains(&k) => self.legged_term(s),
            _ => None, // reported by the syntax check
        }
    }

    /// `kind = "value"`: one selected number, optionally divided by the timestep or `dt`.
    fn value_term(&mut self, s: &Section) -> Option<TermKind> {
        let source = self.need_sel(s, "source")?;
        if !self.scalar(
            &source,
            &s.get("source").expect("`source` was read just above").loc,
            "a value term",
        ) {
            return None;
        }
        let divide_by = match s.get("divide_by") {
            None => None,
            Some(v) => match v.as_str() {
                Some("timestep") => Some(Divisor::Timestep),
                Some("dt") => Some(Divisor::Dt),
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown divisor")
                            .at(v.loc.clone())
                            .label("expected \"timestep\" or \"dt\""),
                    );
                    None
                }
            },
        };
        Some(TermKind::Value { source, divide_by })
    }

    pub(super) fn need_sel(&mut self, s: &Section, key: &str) -> Option<Selection> {
        self.need_key(s, key, &format!("expected a `{key}` selector"))?;
        self.sel_key(s, key)
    }

    /// A required key of a `[reward.*]` term: its value, or E0103 at the table (`label` says what
    /// belongs there).
    pub(super) fn need_key<'s>(
        &mut self,
        s: &'s Section,
        key: &str,
        label: &str,
    ) -> Option<&'s Val> {
        let v = s.get(key);
        if v.is_none() {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `{key}` in [reward.{}]", s.name),
                )
                .at(s.name_loc.clone())
                .label(label.to_string()),
            );
        }
        v
    }

    /// A list of `n` numbers (default: all `default`).
    pub(super) fn num_list(
        &mut self,
        s: &Section,
        key: &str,
        n: usize,
        default: f64,
    ) -> Option<Vec<f64>> {
        let Some(v) = s.get(key) else {
            return Some(vec![default; n]);
        };
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a.iter().map(|x| self.num(x, key)).collect(),
            _ => {
                self.d.push(v.type_error(
                    key,
                    &format!("an array of {n} numbers (one per selected element)"),
                ));
                None
            }
        }
    }

    fn reward_sum(&mut self, terms: &[RewardTerm]) -> SumNode {
        let Some(v) = self.spec.reward_sum.clone() else {
            return SumNode::Sum((0..terms.len()).map(SumNode::Term).collect());
        };
        let mut used = vec![0usize; terms.len()];
        let node = self
            .sum_node(&v, terms, &mut used)
            .unwrap_or(SumNode::Sum(vec![]));
        // `used` counts only the terms that resolved; a term that failed was reported where it failed.
        for (i, n) in used.iter().enumerate() {
            if *n != 1 {
                let msg = match n {
                    0 => format!("reward term `{}` is missing from `sum`", terms[i].name),
                    _ => format!("reward term `{}` is used {n} times in `sum`", terms[i].name),
                };
                self.d.push(
                    Diagnostic::new(Code::E0501, msg)
                        .at(v.loc.clone())
                        .label("expected every term exactly once"),
                );
            }
        }
        node
    }

    fn sum_node(&mut self, v: &Val, terms: &[RewardTerm], used: &mut [usize]) -> Option<SumNode> {
        match &v.kind {
            ValKind::Str(name) => match terms.iter().position(|t| &t.name == name) {
                Some(i) => {
                    used[i] += 1;
                    Some(SumNode::Term(i))
                }
                None => {
                    if self.spec.reward.iter().all(|s| &s.name != name) {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0501,
                                format!("`{name}` in `sum` is not a reward term"),
                            )
                            .at(v.loc.clone())
                            .label("expected the name of a [reward.<name>] table")
                            .help_opt(suggest(name, terms.iter().map(|t| t.name.as_str()))),
                        );
                    }
                    None
                }
            },
            ValKind::Array(a) if !a.is_empty() => {
                let nodes: Vec<SumNode> = a
                    .iter()
                    .filter_map(|x| self.sum_node(x, terms, used))
                    .collect();
                Some(SumNode::Sum(nodes))
            }
            _ => {
                self.d
                    .push(v.type_error("reward.sum", "a (nested) list of term names"));
                None
            }
        }
    }
}
