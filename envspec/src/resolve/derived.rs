//! `[derived.<name>]` and the `derived[...]` selector (IR in `envspec::derived`;
//! docs/spec-reference.md §23). A table may read the ones above it, never itself or later ones.

use super::Ctx;
use crate::derived::{CONTACT_VALUES, ContactSide, ContactValue, Derived, DerivedKind};
use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::ValKind;

impl Ctx<'_> {
    /// Every `[derived.*]` table, in document order; each is visible to the ones after it.
    pub(super) fn derived(&mut self) -> Vec<Derived> {
        let mut offset = 0;
        for s in &self.spec.derived {
            let Some(d) = self.one_derived(s, offset) else {
                self.derived_failed.push(s.name.clone());
                continue;
            };
            offset += d.len;
            self.derived.push(d);
        }
        self.derived.clone()
    }

    fn one_derived(&mut self, s: &Section, offset: usize) -> Option<Derived> {
        let what = format!("[derived.{}]", s.name);
        let at_reset = match s.get("at") {
            None => false,
            Some(v) => match v.as_str() {
                Some("step") => false,
                Some("reset") => true,
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, format!("unknown `at` in {what}"))
                            .at(v.loc.clone())
                            .label("expected \"step\" (after every step) or \"reset\" (once per episode)")
                            .help_opt(v.as_str().and_then(|x| suggest(x, ["step", "reset"]))),
                    );
                    return None;
                }
            },
        };
        if s.kind("difference") == "contact" {
            return self.contact_derived(s, &what, at_reset, offset);
        }
        let source = self.sel_key(s, "source")?;
        let source_loc = s.get("source").map(|v| v.loc.clone())?;
        let paired = |cx: &mut Self, key: &str| -> Option<Option<Selection>> {
            let Some(v) = s.get(key) else {
                return Some(None);
            };
            let m = cx.selection(v, key)?;
            cx.same_len(&source, &m, &v.loc).then_some(Some(m))
        };
        let kind = match s.kind("difference") {
            "norm" => DerivedKind::Norm {
                minus: paired(self, "minus")?,
                source,
            },
            "dot" => {
                let Some(with) = paired(self, "with")? else {
                    self.d.push(
                        Diagnostic::new(Code::E0103, format!("missing `with` in {what}"))
                            .at(s.name_loc.clone())
                            .label("expected with = \"<selector>\", the second vector"),
                    );
                    return None;
                };
                DerivedKind::Dot { source, with }
            }
            _ => {
                let minus = paired(self, "minus")?;
                let divide_by = match s.get("divide_by") {
                    None => None,
                    Some(v) => {
                        let d = self.selection(v, "divide_by")?;
                        if !self.scalar(&d, &v.loc, "divide_by") {
                            return None;
                        }
                        Some(d)
                    }
                };
                DerivedKind::Difference {
                    source,
                    minus,
                    divide_by,
                }
            }
        };
        let len = match &kind {
            DerivedKind::Difference { source, .. } => source.len(),
            _ => 1,
        };
        if len == 0 {
            self.d.push(
                Diagnostic::new(
                    Code::E0403,
                    format!("`source` of {what} selects no element"),
                )
                .at(source_loc)
                .label("expected a selector of at least one element"),
            );
            return None;
        }
        Some(Derived {
            name: s.name.clone(),
            doc: s.doc(),
            kind,
            at_reset,
            offset,
            len,
        })
    }

    /// `kind = "contact"`: `between = ["a", "b"]` (or `["a"]`: a and anything), geoms or bodies.
    fn contact_derived(
        &mut self,
        s: &Section,
        what: &str,
        at_reset: bool,
        offset: usize,
    ) -> Option<Derived> {
        let v = self.need_key(
            s,
            "between",
            "expected between = [\"geom or body\", \"geom or body\"] (or one name: it and anything)",
        )?;
        let names = match &v.kind {
            ValKind::Array(a) if (1..=2).contains(&a.len()) => a.clone(),
            _ => {
                self.d
                    .push(v.type_error("between", "an array of one or two geom or body names"));
                return None;
            }
        };
        let mut sides = Vec::new();
        for n in &names {
            let (name, body) = self.geom_name(n, "between")?;
            sides.push(ContactSide { name, body });
        }
        let value = match s.get("value") {
            None => ContactValue::Touching,
            Some(v) => {
                match CONTACT_VALUES.iter().find(|(n, _)| Some(*n) == v.as_str()) {
                    Some((_, c)) => *c,
                    None => {
                        self.d.push(
                        Diagnostic::new(Code::E0104, format!("unknown `value` in {what}"))
                            .at(v.loc.clone())
                            .label("expected \"touching\", \"count\", \"normal_force\" or \"force\"")
                            .help_opt(v.as_str().and_then(|x| {
                                suggest(x, CONTACT_VALUES.iter().map(|(n, _)| *n))
                            })),
                    );
                        return None;
                    }
                }
            }
        };
        let mut sides = sides.into_iter();
        let a = sides.next()?;
        let len = if value == ContactValue::Force { 3 } else { 1 };
        Some(Derived {
            name: s.name.clone(),
            doc: s.doc(),
            kind: DerivedKind::Contact {
                a,
                b: sides.next(),
                value,
            },
            at_reset,
            offset,
            len,
        })
    }

    /// `derived[NAME]` (every value) or `derived[NAME][k]` (one), over the tables resolved so far.
    pub(super) fn derived_selection(&mut self, text: &str, loc: &Location) -> Option<Selection> {
        let err = |msg: String, label: String, help: Option<String>| {
            Diagnostic::new(Code::E0181, msg)
                .at(loc.clone())
                .label(label)
                .help_opt(help)
        };
        let parsed = text
            .trim()
            .strip_prefix("derived")
            .and_then(|r| r.trim().strip_prefix('['))
            .and_then(|r| r.split_once(']'))
            .map(|(n, t)| (n.trim(), t.trim()));
        let Some((name, tail)) = parsed else {
            self.d.push(err(
                format!("cannot read derived selector `{text}`"),
                "expected derived[NAME] or derived[NAME][k]".into(),
                None,
            ));
            return None;
        };
        let Some(d) = self.derived.iter().find(|d| d.name == name).cloned() else {
            if self.derived_failed.iter().any(|f| f == name) {
                // Its own error is reported where it is declared.
                return None;
            }
            let declared = self.spec.derived.iter().any(|s| s.name == name);
            let label = if declared {
                "expected a [derived.*] table above the one that reads it".to_string()
            } else {
                "expected the name of a [derived.<name>] table".to_string()
            };
            self.d.push(err(
                format!("no derived value `{name}` here"),
                label,
                suggest(
                    name,
                    self.spec
                        .derived
                        .iter()
                        .map(|s| s.name.as_str())
                        .filter(|s| *s != name),
                ),
            ));
            return None;
        };
        let picked: Vec<usize> = if tail.is_empty() {
            (0..d.len).collect()
        } else {
            match tail
                .strip_prefix('[')
                .and_then(|t| t.strip_suffix(']'))
                .and_then(|k| k.trim().parse::<usize>().ok())
            {
                Some(k) if k < d.len => vec![k],
                _ => {
                    self.d.push(err(
                        format!("cannot read derived selector `{text}`"),
                        format!(
                            "expected derived[{name}] or derived[{name}][k] with k < {}",
                            d.len
                        ),
                        None,
                    ));
                    return None;
                }
            }
        };
        let names = picked
            .iter()
            .map(|&k| {
                if d.len == 1 {
                    format!("derived[{name}]")
                } else {
                    format!("derived[{name}][{k}]")
                }
            })
            .collect();
        Some(Selection {
            field: Field::Derived,
            indices: picked.iter().map(|k| d.offset + k).collect(),
            names,
            text: text.to_string(),
        })
    }
}

/// Whether `text` is a `derived[...]` selector.
pub(super) fn is_derived(text: &str) -> bool {
    let t = text.trim();
    t.strip_prefix("derived")
        .is_some_and(|r| !r.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
}
