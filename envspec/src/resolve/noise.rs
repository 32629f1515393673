//! `noise` and `delay` of `[observation.*]` segments and `[latency] action`: resolved into
//! [`Corruption`] (`envspec::noise`). Segments switched off by `when` are still checked.

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::Segment;
use crate::limits::{MAX_DELAY_STEPS, MAX_NOISE};
use crate::noise::{Corruption, Noise, NoiseKind, SegmentCorruption};
use crate::params::ParamValue;
use crate::syntax::NOISE_KEYS;
use crate::value::{Val, ValKind};

use super::Ctx;

impl Ctx<'_> {
    /// Noise and delay of the resolved segments `observation`, and the action latency.
    pub(super) fn corruption(&mut self, observation: &[Segment]) -> Corruption {
        let mut out = Corruption::default();
        let spec = self.spec;
        for s in &spec.observation {
            let what = |k: &str| format!("observation.{}.{k}", s.name);
            let noise = s.get("noise").and_then(|v| self.noise(v, &what("noise")));
            let delay = s
                .get("delay")
                .and_then(|v| self.steps(v, &what("delay")))
                .unwrap_or(0);
            if noise.is_none() && delay == 0 {
                continue;
            }
            // Switched off by `when`: not in the observation, nothing to corrupt.
            if let Some(segment) = observation.iter().position(|o| o.name == s.name) {
                out.segments.push(SegmentCorruption {
                    name: s.name.clone(),
                    segment,
                    noise,
                    delay,
                });
            }
        }
        if let Some(l) = &spec.latency
            && let Some(v) = l.get("action")
        {
            out.action_latency = self.steps(v, "latency.action").unwrap_or(0);
        }
        out
    }

    /// `{ kind, scale, level = 1, when = true }`; None when switched off or wrong.
    fn noise(&mut self, v: &Val, what: &str) -> Option<Noise> {
        let ValKind::Table(t) = &v.kind else {
            self.d
                .push(v.type_error(what, "a table such as { kind = \"uniform\", scale = 0.05 }"));
            return None;
        };
        for e in t {
            if !NOISE_KEYS.contains(&e.key.as_str()) {
                self.d.push(
                    Diagnostic::new(Code::E0101, format!("unknown key `{}` in {what}", e.key))
                        .at(e.key_loc.clone())
                        .label(format!("expected one of: {}", NOISE_KEYS.join(", ")))
                        .help_opt(suggest(&e.key, NOISE_KEYS.iter().copied())),
                );
            }
        }
        let get = |k: &str| t.iter().find(|e| e.key == k).map(|e| &e.value);
        let missing = |k: &str| {
            Diagnostic::new(Code::E0103, format!("missing `{k}` in {what}"))
                .at(v.loc.clone())
                .label(format!(
                    "expected `{k} = ...` (e.g. {{ kind = \"uniform\", scale = 0.05 }})"
                ))
        };
        let kind = match get("kind") {
            None => {
                self.d.push(missing("kind"));
                None
            }
            Some(k) => match k.as_str() {
                Some(name) => {
                    let kind = NoiseKind::parse(name);
                    if kind.is_none() {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0104,
                                format!("unknown noise kind `{name}` in {what}"),
                            )
                            .at(k.loc.clone())
                            .label(format!("expected one of: {}", NoiseKind::NAMES.join(", ")))
                            .help_opt(suggest(name, NoiseKind::NAMES.iter().copied())),
                        );
                    }
                    kind
                }
                None => {
                    self.d
                        .push(k.type_error(&format!("{what}.kind"), "a string"));
                    None
                }
            },
        };
        let scale = match get("scale") {
            None => {
                self.d.push(missing("scale"));
                None
            }
            Some(x) => self.amplitude(x, &format!("{what}.scale")),
        };
        let level = match get("level") {
            None => Some(1.0),
            Some(x) => self.amplitude(x, &format!("{what}.level")),
        };
        let scale_first = match get("order") {
            None => Some(false),
            Some(o) => match o.as_str() {
                Some("draw_level_scale") => Some(false),
                Some("level_scale_draw") => Some(true),
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, format!("unknown {what}.order"))
                            .at(o.loc.clone())
                            .label("expected \"draw_level_scale\" (the default) or \"level_scale_draw\""),
                    );
                    None
                }
            },
        };
        let on = match get("when") {
            None => true,
            Some(w) => self.flag(w, &format!("{what}.when")).unwrap_or(true),
        };
        let (kind, scale, level, scale_first) = (kind?, scale?, level?, scale_first?);
        if level * scale > MAX_NOISE {
            self.d.push(
                Diagnostic::new(
                    Code::E0140,
                    format!(
                        "{what}: level × scale = {} is beyond envc's limit of {MAX_NOISE}",
                        level * scale
                    ),
                )
                .at(v.loc.clone())
                .label(format!("expected an amplitude of at most {MAX_NOISE}"))
                .help("see docs/limits.md"),
            );
            return None;
        }
        on.then_some(Noise {
            kind,
            scale,
            level,
            scale_first,
        })
    }

    /// A finite number ≥ 0 (or a parameter holding one).
    fn amplitude(&mut self, v: &Val, what: &str) -> Option<f64> {
        let x = self.num(v, what)?;
        if x < 0.0 {
            self.d.push(
                Diagnostic::new(
                    Code::E0140,
                    format!("{what} is {x}; noise cannot be negative"),
                )
                .at(v.loc.clone())
                .label("expected a number ≥ 0 (a standard deviation or half-width)"),
            );
            return None;
        }
        Some(x)
    }

    /// A number of env steps in `0..=MAX_DELAY_STEPS`, or an int parameter holding one.
    fn steps(&mut self, v: &Val, what: &str) -> Option<usize> {
        let n = match &v.kind {
            ValKind::Int(n) => *n,
            ValKind::Str(name) => match self.lookup(name, &v.loc, "a step count")? {
                ParamValue::Int(n) => n,
                other => {
                    self.wrong_param_type(name, &v.loc, "an integer", &other);
                    return None;
                }
            },
            _ => {
                self.d
                    .push(v.type_error(what, "a number of env steps or an integer parameter name"));
                return None;
            }
        };
        if !(0..=MAX_DELAY_STEPS).contains(&n) {
            let via = match &v.kind {
                ValKind::Str(name) => format!(" (the value of parameter `{name}`)"),
                _ => String::new(),
            };
            self.d.push(
                Diagnostic::new(
                    Code::E0141,
                    format!("{what} is {n} steps{via}; expected 0 … {MAX_DELAY_STEPS}"),
                )
                .at(v.loc.clone())
                .label(format!(
                    "expected a number of env steps from 0 to {MAX_DELAY_STEPS}"
                ))
                .help("each env keeps that many past values; see docs/limits.md"),
            );
            return None;
        }
        Some(n as usize)
    }
}
