//! `[health.*]`: the checks that make a state unhealthy (and, with `[health] terminate`, end the
//! episode).

use crate::diagnostic::{Code, Diagnostic};
use crate::ir::*;
use crate::selector::Selection;
use crate::syntax::Section;
use crate::value::{Val, ValKind};

use super::Ctx;

impl Ctx<'_> {
    pub(super) fn health(&mut self) -> Vec<HealthCheck> {
        let mut out = vec![];
        for s in &self.spec.health {
            let Some(src) = s.get("source") else { continue };
            let srcs: Vec<Val> = match &src.kind {
                ValKind::Array(a) => a.clone(),
                _ => vec![src.clone()],
            };
            let sources: Vec<Selection> = srcs
                .iter()
                .filter_map(|v| self.selection(v, "source"))
                .collect();
            if sources.len() != srcs.len() {
                continue;
            }
            let kind = match s.kind("") {
                "finite" => CheckKind::Finite,
                "in_range" => match self.in_range_check(s) {
                    Some(kind) => kind,
                    None => continue,
                },
                "fails_if" => match self.fails_if_check(s) {
                    Some(kind) => kind,
                    None => continue,
                },
                _ => continue,
            };
            out.push(HealthCheck {
                name: s.name.clone(),
                doc: s.doc(),
                kind,
                sources,
            });
        }
        out
    }

    /// `kind = "in_range"`: the `range` a value must stay in, with open or closed `bounds`.
    fn in_range_check(&mut self, s: &Section) -> Option<CheckKind> {
        let Some(r) = s.get("range") else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `range` in [health.{}]", s.name),
                )
                .at(s.name_loc.clone())
                .label("expected range = [low, high] or a parameter name"),
            );
            return None;
        };
        let (lo, hi) = self.range(r, "range")?;
        let closed = match s.get("bounds") {
            None => false,
            Some(b) => match b.as_str() {
                Some("closed") => true,
                Some("open") => false,
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown bounds")
                            .at(b.loc.clone())
                            .label("expected \"open\" (lo < x < hi) or \"closed\" (lo <= x <= hi)"),
                    );
                    false
                }
            },
        };
        Some(CheckKind::InRange { lo, hi, closed })
    }

    /// `kind = "fails_if"`: the comparison `op value` that makes a value unhealthy.
    fn fails_if_check(&mut self, s: &Section) -> Option<CheckKind> {
        let op = match s.get("op").and_then(Val::as_str) {
            Some("<") => CmpOp::Lt,
            Some("<=") => CmpOp::Le,
            Some(">") => CmpOp::Gt,
            Some(">=") => CmpOp::Ge,
            _ => {
                let ops = "expected op = \"<\", \"<=\", \">\" or \">=\"";
                let e = match s.get("op") {
                    None => {
                        Diagnostic::new(Code::E0103, format!("missing `op` in [health.{}]", s.name))
                            .at(s.name_loc.clone())
                    }
                    Some(v) if v.as_str().is_some() => {
                        Diagnostic::new(Code::E0104, format!("unknown `op` in [health.{}]", s.name))
                            .at(v.loc.clone())
                    }
                    Some(v) => v.type_error("op", "a string"),
                };
                self.d.push(e.label(ops));
                return None;
            }
        };
        let Some(value) = s.get("value").and_then(|v| self.num(v, "value")) else {
            if s.get("value").is_none() {
                self.d.push(
                    Diagnostic::new(
                        Code::E0103,
                        format!("missing `value` in [health.{}]", s.name),
                    )
                    .at(s.name_loc.clone())
                    .label("expected value = a number or parameter name"),
                );
            }
            return None;
        };
        Some(CheckKind::FailsIf { op, value })
    }
}
