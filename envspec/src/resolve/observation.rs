//! `[observation.*]`: the segments of the observation vector, in declared order.

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::{Apply, Segment};
use crate::limits;
use crate::value::{Val, ValKind};

use super::Ctx;

impl Ctx<'_> {
    pub(super) fn observation(&mut self) -> Vec<Segment> {
        let mut out = vec![];
        let mut offset = 0;
        for s in &self.spec.observation {
            // A segment switched off by `when` is still checked: an override must not reveal errors.
            let enabled = match s.get("when") {
                Some(w) => self.flag(w, "when").unwrap_or(true),
                None => true,
            };
            let Some(mut source) = self.sel_key(s, "source") else {
                continue;
            };
            let mut minus = self.sel_key(s, "minus");
            if let Some(m) = &minus
                && !self.same_len(
                    &source,
                    m,
                    &s.get("minus").expect("`minus` was read just above").loc,
                )
            {
                minus = None;
            }
            if let Some(df) = s.get("drop_first")
                && let Some(n) = self.drop_first(df)
            {
                source.drop_first(n);
                if let Some(m) = &mut minus {
                    m.drop_first(n);
                }
            }
            let apply = match s.get("apply") {
                None => None,
                Some(v) => match v.as_str() {
                    Some("sin") => Some(Apply::Sin),
                    Some("cos") => Some(Apply::Cos),
                    Some("positive") => Some(Apply::Positive),
                    _ => {
                        self.d.push(
                            Diagnostic::new(Code::E0104, "unknown function in `apply`")
                                .at(v.loc.clone())
                                .label("expected \"sin\", \"cos\" or \"positive\""),
                        );
                        None
                    }
                },
            };
            let clip = s.get("clip").and_then(|v| self.range(v, "clip"));
            let scale = s.get("scale").and_then(|v| match v.as_str() {
                Some("dt") => Some(self.dt),
                _ => {
                    let x = self.num(v, "scale")?;
                    self.within(v, x, "scale", limits::MAX_MAGNITUDE)
                }
            });
            let indicator = s.get("indicator").and_then(|v| self.indicator(v));
            let seg = Segment {
                name: s.name.clone(),
                doc: s.doc(),
                source,
                minus,
                apply,
                clip,
                scale,
                indicator,
                offset,
            };
            if !enabled {
                continue;
            }
            offset += seg.len();
            out.push(seg);
        }
        out
    }

    /// `drop_first = 2` or `drop_first = { count = 2, when = "flag" }`.
    fn drop_first(&mut self, v: &Val) -> Option<usize> {
        match &v.kind {
            ValKind::Int(n) if *n >= 0 => Some(*n as usize),
            ValKind::Table(t) => {
                for e in t {
                    if e.key != "count" && e.key != "when" {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0101,
                                format!("unknown key `{}` in drop_first", e.key),
                            )
                            .at(e.key_loc.clone())
                            .label("expected count, when")
                            .help_opt(suggest(&e.key, ["count", "when"])),
                        );
                    }
                }
                let count = t.iter().find(|e| e.key == "count");
                let Some(count) = count else {
                    self.d.push(
                        Diagnostic::new(Code::E0103, "missing `count` in drop_first")
                            .at(v.loc.clone())
                            .label("expected count = N"),
                    );
                    return None;
                };
                let n = match count.value.kind {
                    ValKind::Int(n) if n >= 0 => n as usize,
                    _ => {
                        self.d.push(
                            count
                                .value
                                .type_error("drop_first.count", "a non-negative integer"),
                        );
                        return None;
                    }
                };
                let on = match t.iter().find(|e| e.key == "when") {
                    Some(w) => self.flag(&w.value, "drop_first.when")?,
                    None => true,
                };
                Some(if on { n } else { 0 })
            }
            _ => {
                self.d
                    .push(v.type_error("drop_first", "a count or { count, when }"));
                None
            }
        }
    }
}
