//! Reading a value of the spec: a number, range or flag written in place, or the name of the
//! parameter that holds it. Each problem is reported where the value is written.

use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::params::{Origin, Param, ParamValue};
use crate::value::{Val, ValKind};

use super::Ctx;

impl Ctx<'_> {
    pub(super) fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }

    pub(super) fn param_error(&self, name: &str, msg: &str) -> Diagnostic {
        let loc = self.param(name).and_then(|p| match &p.origin {
            Origin::Default(l) => Some(l.clone()),
            Origin::Override(_) => None,
        });
        let help = self.param(name).and_then(|p| match &p.origin {
            Origin::Override(_) => Some(format!(
                "the value {} comes from an override of `{name}`",
                p.value
            )),
            Origin::Default(_) => None,
        });
        Diagnostic::new(Code::E0105, msg.to_string())
            .at_opt(loc)
            .label("invalid value")
            .help_opt(help)
    }

    /// E0110: an integer parameter above its limit in `envspec::limits`.
    pub(super) fn over_limit(&mut self, name: &str, n: i64, limit: i64) {
        let mut e = self.param_error(
            name,
            &format!("{name} {n} is beyond envc's limit of {limit}"),
        );
        e.code = Code::E0110;
        self.d.push(e);
    }

    /// E0110 when `x` (read from `v`) is beyond `limit` in magnitude; `Some(x)` otherwise.
    pub(super) fn within(&mut self, v: &Val, x: f64, what: &str, limit: f64) -> Option<f64> {
        if x.abs() <= limit {
            return Some(x);
        }
        self.d.push(
            Diagnostic::new(
                Code::E0110,
                format!("{what} of {x:e} is beyond envc's limit of ±{limit:e}"),
            )
            .at(v.loc.clone())
            .label(format!("expected a value within ±{limit:e}"))
            .help("beyond it the simulation diverges or overflows; see docs/limits.md"),
        );
        None
    }

    /// A finite number within `±limit` (E0105 / E0110 otherwise), as `[actions]` bounds its own.
    pub(super) fn num_within(&mut self, v: &Val, what: &str, limit: f64) -> Option<f64> {
        let x = self.num(v, what)?;
        self.within(v, x, what, limit)
    }

    pub(super) fn unknown_param(&self, name: &str, loc: &Location, expected: &str) -> Diagnostic {
        Diagnostic::new(
            Code::E0201,
            format!("`{name}` is not a parameter of this spec"),
        )
        .at(loc.clone())
        .label(format!(
            "expected {expected} or the name of a parameter in [params]"
        ))
        .help_opt(suggest(name, self.params.iter().map(|p| p.name.as_str())))
    }

    /// A parameter looked up by a reference in the spec.
    pub(super) fn lookup(
        &mut self,
        name: &str,
        loc: &Location,
        expected: &str,
    ) -> Option<ParamValue> {
        match self.param(name) {
            Some(p) => Some(p.value.clone()),
            None => {
                let e = self.unknown_param(name, loc, expected);
                self.d.push(e);
                None
            }
        }
    }

    pub(super) fn wrong_param_type(
        &mut self,
        name: &str,
        loc: &Location,
        expected: &str,
        got: &ParamValue,
    ) {
        self.d.push(
            Diagnostic::new(
                Code::E0102,
                format!("parameter `{name}` is {got}, not {expected}"),
            )
            .at(loc.clone())
            .label(format!("expected {expected}")),
        );
    }

    /// A finite number, or the name of a numeric parameter holding one. NaN and ±inf are refused
    /// here (a weight, gain, scale or size of `inf` makes every reward or state non-finite);
    /// range bounds, which may be infinite, go through [`Ctx::range`].
    pub(super) fn num(&mut self, v: &Val, what: &str) -> Option<f64> {
        let x = self.num_or_inf(v, what)?;
        if x.is_finite() {
            return Some(x);
        }
        let via = match &v.kind {
            ValKind::Str(name) => format!(" (the value of parameter `{name}`)"),
            _ => String::new(),
        };
        self.d.push(
            Diagnostic::new(
                Code::E0105,
                format!(
                    "{what} is {}{via}; it must be a finite number",
                    crate::value::format_float(x)
                ),
            )
            .at(v.loc.clone())
            .label("expected a finite number"),
        );
        None
    }

    /// A number, or the name of a numeric parameter; ±inf allowed, NaN refused.
    pub(super) fn num_or_inf(&mut self, v: &Val, what: &str) -> Option<f64> {
        let x = self.any_num(v, what)?;
        if x.is_nan() {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{what} is NaN"))
                    .at(v.loc.clone())
                    .label("expected a number (NaN compares false with everything)"),
            );
            return None;
        }
        Some(x)
    }

    fn any_num(&mut self, v: &Val, what: &str) -> Option<f64> {
        match &v.kind {
            ValKind::Int(i) => Some(*i as f64),
            ValKind::Float(x) => Some(*x),
            // `"-name"`: the parameter's value, negated (exactly).
            ValKind::Str(text) => {
                let (sign, name) = match text.strip_prefix('-') {
                    Some(n) if self.param(n.trim()).is_some() => (-1.0, n.trim()),
                    _ => (1.0, text.as_str()),
                };
                match self.lookup(name, &v.loc, "a number")? {
                    ParamValue::Float(x) => Some(sign * x),
                    ParamValue::Int(i) => Some(sign * i as f64),
                    other => {
                        self.wrong_param_type(name, &v.loc, "a number", &other);
                        None
                    }
                }
            }
            _ => {
                self.d
                    .push(v.type_error(what, "a number or a parameter name"));
                None
            }
        }
    }

    /// `[low, high]`, or the name of a range parameter.
    pub(super) fn range(&mut self, v: &Val, what: &str) -> Option<(f64, f64)> {
        let r = match &v.kind {
            ValKind::Array(a) if a.len() == 2 => {
                Some((self.num_or_inf(&a[0], what)?, self.num_or_inf(&a[1], what)?))
            }
            ValKind::Str(name) => match self.lookup(name, &v.loc, "a range")? {
                ParamValue::Range(a, b) => Some((a, b)),
                other => {
                    self.wrong_param_type(name, &v.loc, "a range [low, high]", &other);
                    None
                }
            },
            _ => {
                self.d
                    .push(v.type_error(what, "[low, high] or a parameter name"));
                None
            }
        }?;
        if r.0 > r.1 {
            self.d.push(
                Diagnostic::new(
                    Code::E0105,
                    format!("{what}: low {} is above high {}", r.0, r.1),
                )
                .at(v.loc.clone())
                .label("expected low <= high"),
            );
        }
        Some(r)
    }

    /// `true`/`false`, or a bool parameter's name, optionally negated with `!`.
    pub(super) fn flag(&mut self, v: &Val, what: &str) -> Option<bool> {
        match &v.kind {
            ValKind::Bool(b) => Some(*b),
            // `a and b`: every part holds (each part is one of the forms below).
            ValKind::Str(s) if s.contains(" and ") => {
                let mut all = Some(true);
                for part in s.split(" and ") {
                    let part = Val {
                        kind: ValKind::Str(part.trim().to_string()),
                        loc: v.loc.clone(),
                    };
                    all = match (all, self.flag(&part, what)) {
                        (Some(a), Some(b)) => Some(a && b),
                        _ => None,
                    };
                }
                all
            }
            // `name == "value"` / `name != "value"`: a string parameter compared with a literal
            // (`when = "reward_type == 'dense'"`).
            ValKind::Str(s) if s.contains("==") || s.contains("!=") => {
                let (name, lit, eq) = match s.split_once("==") {
                    Some((n, l)) => (n, l, true),
                    None => {
                        let (n, l) = s.split_once("!=").unwrap_or((s, ""));
                        (n, l, false)
                    }
                };
                let lit = lit.trim().trim_matches(|c| c == '\'' || c == '"');
                match self.lookup(name.trim(), &v.loc, "a string parameter")? {
                    ParamValue::Str(x) => Some((x == lit) == eq),
                    other => {
                        self.wrong_param_type(name.trim(), &v.loc, "a string", &other);
                        None
                    }
                }
            }
            ValKind::Str(s) => {
                let (neg, name) = match s.strip_prefix('!') {
                    Some(n) => (true, n.trim()),
                    None => (false, s.as_str()),
                };
                match self.lookup(name, &v.loc, "true, false")? {
                    ParamValue::Bool(b) => Some(b != neg),
                    other => {
                        self.wrong_param_type(name, &v.loc, "a bool", &other);
                        None
                    }
                }
            }
            _ => {
                self.d
                    .push(v.type_error(what, "true, false or a bool parameter name"));
                None
            }
        }
    }
}
