//! State conditions (`only_if` of a reward term, the `condition` info kind) and an observation
//! segment's `indicator` (docs/spec-reference.md §7 "Conditions"; IR in `envspec::conditions`).

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{CmpOp, Condition, Indicator, Quantity};
use crate::value::{Entry, Val, ValKind};

const CONDITION_KEYS: &[&str] = &["source", "minus", "norm", "op", "value"];
const INDICATOR_KEYS: &[&str] = &["op", "value", "then", "else"];
const OPS: &[&str] = &["<", "<=", ">", ">="];

impl Ctx<'_> {
    /// One condition table, or an array of them (all must hold).
    pub(super) fn conditions(&mut self, v: &Val, what: &str) -> Option<Vec<Condition>> {
        match &v.kind {
            ValKind::Table(_) => Some(vec![self.condition(v, what)?]),
            ValKind::Array(a) if !a.is_empty() => a
                .iter()
                .map(|c| self.condition(c, what))
                .collect::<Vec<_>>()
                .into_iter()
                .collect(),
            _ => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0180,
                        format!("{what} is not a condition or a list of conditions"),
                    )
                    .at(v.loc.clone())
                    .label("expected { source = \"qpos[0]\", op = \">\", value = 0.2 }, or an array of such tables"),
                );
                None
            }
        }
    }

    fn condition(&mut self, v: &Val, what: &str) -> Option<Condition> {
        let t = self.known_keys(v, what, CONDITION_KEYS)?;
        let get = |k: &str| t.iter().find(|e| e.key == k).map(|e| &e.value);
        let Some(sv) = get("source") else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `source` in a condition of {what}"),
                )
                .at(v.loc.clone())
                .label("expected source = \"<selector>\""),
            );
            return None;
        };
        let source = self.selection(sv, "source")?;
        let minus = match get("minus") {
            Some(m) => {
                let m = self.selection(m, "minus")?;
                Some(self.same_len(&source, &m, &sv.loc).then_some(m)?)
            }
            None => None,
        };
        let norm = match get("norm") {
            Some(n) => self.flag(n, "norm")?,
            None => false,
        };
        if !norm && source.len() != 1 {
            self.d.push(
                Diagnostic::new(
                    Code::E0180,
                    format!(
                        "a condition of {what} compares one number, `{}` selects {}",
                        source.text,
                        source.len()
                    ),
                )
                .at(sv.loc.clone())
                .label("expected one element, or norm = true to compare the vector's length"),
            );
            return None;
        }
        let op = self.cmp_op(get("op"), v, what)?;
        let value = self.condition_value(get("value"), v, what)?;
        let quantity = if norm {
            Quantity::Norm { source, minus }
        } else {
            Quantity::Value { source, minus }
        };
        Some(Condition {
            quantity,
            op,
            value,
        })
    }

    /// `indicator = { op, value, then, else }` of an observation segment.
    pub(super) fn indicator(&mut self, v: &Val) -> Option<Indicator> {
        let what = "indicator";
        let t = self.known_keys(v, what, INDICATOR_KEYS)?;
        let get = |k: &str| t.iter().find(|e| e.key == k).map(|e| &e.value);
        let op = self.cmp_op(get("op"), v, what)?;
        let value = self.condition_value(get("value"), v, what)?;
        let mut num = |k: &str| match get(k) {
            Some(x) => self.num(x, k),
            None => {
                self.d.push(
                    Diagnostic::new(Code::E0103, format!("missing `{k}` in indicator"))
                        .at(v.loc.clone())
                        .label("expected { op, value, then, else }"),
                );
                None
            }
        };
        let (then, otherwise) = (num("then"), num("else"));
        Some(Indicator {
            op,
            value,
            then: then?,
            otherwise: otherwise?,
        })
    }

    /// The entries of an inline table whose keys are all in `allowed` (E0101 otherwise).
    fn known_keys<'v>(&mut self, v: &'v Val, what: &str, allowed: &[&str]) -> Option<&'v [Entry]> {
        let Some(t) = v.as_table() else {
            self.d.push(v.type_error(what, "a table"));
            return None;
        };
        let mut ok = true;
        for e in t.iter().filter(|e| !allowed.contains(&e.key.as_str())) {
            ok = false;
            self.d.push(
                Diagnostic::new(Code::E0101, format!("unknown key `{}` in {what}", e.key))
                    .at(e.key_loc.clone())
                    .label(format!("expected one of: {}", allowed.join(", ")))
                    .help_opt(suggest(&e.key, allowed.iter().copied())),
            );
        }
        ok.then_some(t)
    }

    fn cmp_op(&mut self, op: Option<&Val>, at: &Val, what: &str) -> Option<CmpOp> {
        let text = op.and_then(Val::as_str);
        let parsed = match text {
            Some("<") => Some(CmpOp::Lt),
            Some("<=") => Some(CmpOp::Le),
            Some(">") => Some(CmpOp::Gt),
            Some(">=") => Some(CmpOp::Ge),
            _ => None,
        };
        if parsed.is_none() {
            let (msg, loc) = match op {
                None => (format!("missing `op` in {what}"), at.loc.clone()),
                Some(v) => (format!("unknown `op` in {what}"), v.loc.clone()),
            };
            self.d.push(
                Diagnostic::new(Code::E0180, msg)
                    .at(loc)
                    .label("expected op = \"<\", \"<=\", \">\" or \">=\"")
                    .help_opt(text.and_then(|x| suggest(x, OPS.iter().copied()))),
            );
        }
        parsed
    }

    fn condition_value(&mut self, value: Option<&Val>, at: &Val, what: &str) -> Option<f64> {
        match value {
            Some(x) => self.num(x, "value"),
            None => {
                self.d.push(
                    Diagnostic::new(Code::E0103, format!("missing `value` in {what}"))
                        .at(at.loc.clone())
                        .label("expected value = <number or parameter>"),
                );
                None
            }
        }
    }
}
