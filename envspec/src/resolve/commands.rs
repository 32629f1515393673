//! Resolving `[commands.*]` and `command[...]` selectors (IR in `crate::commands`; `[actions]` and
//! the legged reward kinds are in `actions` and `legged`).

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::ir::*;
use crate::limits;
use crate::selector::{Field, Selection};
use crate::value::{Val, ValKind};

impl Ctx<'_> {
    /// `[commands.*]` in declared order; `dt` turns `resample_seconds` into steps.
    pub(super) fn commands(&mut self, dt: f64) -> Vec<Command> {
        let mut out: Vec<Command> = vec![];
        let mut offset = 0;
        for s in &self.spec.commands {
            let context = format!("[commands.{}]", s.name);
            let bad = |v: &Val, msg: String, label: &str| {
                Diagnostic::new(Code::E0130, msg)
                    .at(v.loc.clone())
                    .label(label.to_string())
            };
            let mut c = Command {
                name: s.name.clone(),
                doc: s.doc(),
                components: vec![],
                low: vec![],
                high: vec![],
                resample_seconds: None,
                resample_steps: 0,
                standing_probability: 0.0,
                offset,
            };
            if let Some(v) = s.get("components") {
                match &v.kind {
                    ValKind::Table(entries) if !entries.is_empty() => {
                        for e in entries {
                            // Two numbers read here (a reversed pair is E0130, not E0105),
                            // or a range parameter.
                            let r = match &e.value.kind {
                                ValKind::Array(a) if a.len() == 2 => self
                                    .num_or_inf(&a[0], &e.key)
                                    .zip(self.num_or_inf(&a[1], &e.key)),
                                _ => self.range(&e.value, &e.key),
                            };
                            let Some((lo, hi)) = r else {
                                continue;
                            };
                            if !(lo.is_finite() && hi.is_finite()) || lo > hi {
                                self.d.push(bad(
                                    &e.value,
                                    format!(
                                        "command component `{}` of {context} has range [{lo}, {hi}]",
                                        e.key
                                    ),
                                    "expected [low, high] with finite low <= high",
                                ));
                                continue;
                            }
                            let what = format!("command component `{}`", e.key);
                            let max = limits::MAX_MAGNITUDE;
                            if self.within(&e.value, lo, &what, max).is_none()
                                || self.within(&e.value, hi, &what, max).is_none()
                            {
                                continue;
                            }
                            c.components.push(e.key.clone());
                            c.low.push(lo);
                            c.high.push(hi);
                        }
                    }
                    _ => self.d.push(bad(
                        v,
                        format!("{context} has no components"),
                        "expected a table of ranges, e.g. { lin_vel_x = [-1.0, 1.0] }",
                    )),
                }
            }
            if let Some(v) = s.get("resample_seconds")
                && let Some(x) = self.num(v, "resample_seconds")
            {
                if x < 0.0 {
                    self.d.push(bad(
                        v,
                        format!("resample_seconds of {context} is {x}"),
                        "expected seconds >= 0 (0: drawn at reset only)",
                    ));
                } else if x > 0.0 {
                    c.resample_seconds = Some(x);
                    c.resample_steps = ((x / dt).round() as u64).max(1);
                }
            }
            if let Some(v) = s.get("standing_probability")
                && let Some(p) = self.num(v, "standing_probability")
            {
                if (0.0..=1.0).contains(&p) {
                    c.standing_probability = p;
                } else {
                    self.d.push(bad(
                        v,
                        format!("standing_probability of {context} is {p}"),
                        "expected a probability in [0, 1]",
                    ));
                }
            }
            offset += c.len();
            out.push(c);
        }
        out
    }

    /// `command[NAME]`, `command[NAME][i:j]`, `command[NAME][component]`,
    /// `command[NAME].component` (or `command`: every command).
    pub(super) fn command_selection(&mut self, text: &str, loc: &Location) -> Option<Selection> {
        command_selection(text, loc, &self.commands, &mut self.d)
    }
}

/// A `command[...]` selector over `commands` (task specs, and `[agents]` extras over the base
/// env's commands).
pub(crate) fn command_selection(
    text: &str,
    loc: &Location,
    commands: &[Command],
    d: &mut crate::diagnostic::Diagnostics,
) -> Option<Selection> {
    let rest = text.trim().strip_prefix("command")?.trim();
    let err = |msg: String, label: String, help: Option<String>| {
        Diagnostic::new(Code::E0131, msg)
            .at(loc.clone())
            .label(label)
            .help_opt(help)
    };
    let all = |c: &Command| (0..c.len()).map(|k| c.offset + k).collect::<Vec<_>>();
    let names = |c: &Command, idx: &[usize]| {
        idx.iter()
            .map(|&i| format!("command[{}].{}", c.name, c.components[i - c.offset]))
            .collect::<Vec<_>>()
    };
    if rest.is_empty() {
        let indices: Vec<usize> = (0..commands.iter().map(Command::len).sum()).collect();
        let names = commands.iter().flat_map(|c| names(c, &all(c))).collect();
        return Some(Selection {
            field: Field::Command,
            indices,
            names,
            text: text.to_string(),
        });
    }
    let Some((name, tail)) = rest
        .strip_prefix('[')
        .and_then(|r| r.split_once(']'))
        .map(|(n, t)| (n.trim(), t.trim()))
    else {
        d.push(err(
            format!("cannot read command selector `{text}`"),
            "expected command[NAME], command[NAME][i:j] or command[NAME].component".into(),
            None,
        ));
        return None;
    };
    let Some(c) = commands.iter().find(|c| c.name == name).cloned() else {
        d.push(err(
            format!("no command named `{name}`"),
            format!(
                "expected one of the [commands.*] tables: {}",
                commands
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            suggest(name, commands.iter().map(|c| c.name.as_str())),
        ));
        return None;
    };
    let part = tail
        .strip_prefix('.')
        .map(str::trim)
        .or_else(|| tail.strip_prefix('[').and_then(|t| t.strip_suffix(']')))
        .map(str::trim);
    let idx: Vec<usize> = match part {
        None if tail.is_empty() => all(&c),
        None => {
            d.push(err(
                format!("cannot read command selector `{text}`"),
                "expected command[NAME], command[NAME][i:j] or command[NAME].component".into(),
                None,
            ));
            return None;
        }
        Some(p) => {
            let int = |x: &str, d: i64| -> Option<i64> {
                if x.trim().is_empty() {
                    Some(d)
                } else {
                    x.trim().parse().ok()
                }
            };
            let n = c.len() as i64;
            let clamp = |v: i64| if v < 0 { (v + n).max(0) } else { v.min(n) };
            if let Some((a, b)) = p.split_once(':')
                && let (Some(a), Some(b)) = (int(a, 0), int(b, n))
            {
                (clamp(a)..clamp(b).max(clamp(a)))
                    .map(|k| c.offset + k as usize)
                    .collect()
            } else if let Some(k) = c.components.iter().position(|x| x == p) {
                vec![c.offset + k]
            } else if let Ok(k) = p.parse::<i64>()
                && (-n..n).contains(&k)
            {
                vec![c.offset + clamp(if k < 0 { k + n } else { k }) as usize]
            } else {
                d.push(err(
                    format!("command `{}` has no component `{p}`", c.name),
                    format!("expected one of: {}", c.components.join(", ")),
                    suggest(p, c.components.iter().map(String::as_str)),
                ));
                return None;
            }
        }
    };
    Some(Selection {
        field: Field::Command,
        names: names(&c, &idx),
        indices: idx,
        text: text.to_string(),
    })
}
