//! Selections in a spec: a selector string resolved against the model (or the goal, a derived
//! value, a command), the checks on their lengths, and glob patterns over names.

use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::params::ParamValue;
use crate::selector::{self, ParamIndex, Selection};
use crate::syntax::Section;
use crate::value::Val;

use super::{Ctx, derived};

impl Ctx<'_> {
    pub(super) fn selection(&mut self, v: &Val, what: &str) -> Option<Selection> {
        let Some(text) = v.as_str() else {
            self.d
                .push(v.type_error(what, "a selector string such as \"qpos[2:]\""));
            return None;
        };
        if text.trim().starts_with("goal")
            && !text.trim()["goal".len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
        {
            return self.goal_selection(text, &v.loc);
        }
        if derived::is_derived(text) {
            return self.derived_selection(text, &v.loc);
        }
        if text.trim().starts_with("command")
            && !text.trim()["command".len()..]
                .starts_with(|c: char| c.is_alphanumeric() || c == '_')
        {
            return self.command_selection(text, &v.loc);
        }
        let params = self.params;
        let lookup = |name: &str| -> Result<ParamIndex, Diagnostic> {
            match params.iter().find(|p| p.name == name).map(|p| &p.value) {
                Some(ParamValue::Int(i)) => Ok(ParamIndex::Int(*i)),
                Some(ParamValue::Str(s)) => Ok(ParamIndex::Name(s.clone())),
                Some(other) => Err(Diagnostic::new(
                    Code::E0102,
                    format!("parameter `{name}` is {other}, not an index or name"),
                )
                .at(v.loc.clone())
                .label("expected an integer or string parameter")),
                None => Err(self.unknown_param(name, &v.loc, "an index")),
            }
        };
        match selector::resolve(text, &v.loc, self.model, &lookup) {
            Ok(s) => Some(s),
            Err(e) => {
                self.d.push(e);
                None
            }
        }
    }

    pub(super) fn sel_key(&mut self, s: &Section, key: &str) -> Option<Selection> {
        let v = s.get(key)?;
        self.selection(v, key)
    }

    pub(super) fn same_len(&mut self, a: &Selection, b: &Selection, loc: &Location) -> bool {
        if a.len() != b.len() {
            self.d.push(
                Diagnostic::new(
                    Code::E0403,
                    format!(
                        "`{}` has {} elements but `{}` has {}",
                        a.text,
                        a.len(),
                        b.text,
                        b.len()
                    ),
                )
                .at(loc.clone())
                .label("expected selections of equal length"),
            );
            return false;
        }
        true
    }

    pub(super) fn scalar(&mut self, s: &Selection, loc: &Location, what: &str) -> bool {
        if s.len() != 1 {
            self.d.push(
                Diagnostic::new(
                    Code::E0403,
                    format!("{what} needs one number, `{}` selects {}", s.text, s.len()),
                )
                .at(loc.clone())
                .label("expected a selector of exactly one element, e.g. `qpos[0]`"),
            );
            return false;
        }
        true
    }

    /// The indices of the names a glob pattern (`*`, `?`) matches. A pattern that matches none is
    /// E0160 at `loc`, "`pattern` matches none of {what}", with the nearest name (a row that
    /// selects nothing is almost always a typo).
    pub(super) fn glob_hits<'n>(
        &mut self,
        pattern: &str,
        names: impl Iterator<Item = &'n str> + Clone,
        loc: &Location,
        what: &str,
        label: &str,
    ) -> Option<Vec<usize>> {
        let hit: Vec<usize> = names
            .clone()
            .enumerate()
            .filter(|(_, n)| selector::glob(pattern, n))
            .map(|(i, _)| i)
            .collect();
        if hit.is_empty() {
            self.d.push(
                Diagnostic::new(Code::E0160, format!("`{pattern}` matches none of {what}"))
                    .at(loc.clone())
                    .label(label.to_string())
                    .help_opt(suggest(pattern, names)),
            );
            return None;
        }
        Some(hit)
    }
}
