//! `[events.<name>]`: domain randomization and pushes resolved against the model (IR in
//! `envspec::events`). Elements are names or glob patterns (`*`, `?`) over the model's named
//! elements of the field's kind.

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::events::*;
use crate::limits;
use crate::mjcf::JointKind;
use crate::selector::glob;
use crate::syntax::Section;
use crate::value::{Val, ValKind};

const DISTRIBUTIONS: &[&str] = &["uniform", "log_uniform", "gaussian"];
const MODES: &[&str] = &["startup", "reset", "interval"];

impl Ctx<'_> {
    pub(super) fn events(&mut self) -> Vec<Event> {
        let spec = self.spec;
        spec.events.iter().filter_map(|s| self.event(s)).collect()
    }

    fn event(&mut self, s: &Section) -> Option<Event> {
        let ctx = format!("[events.{}]", s.name);
        // An event switched off by `when` is still checked (an override must not reveal errors),
        // then left out: it draws nothing.
        let enabled = match s.get("when") {
            Some(w) => self.flag(w, "when").unwrap_or(true),
            None => true,
        };
        let push = s.kind("model") == "push";
        let mode = self.event_mode(s, &ctx)?;
        let elements_text = match s.get("elements") {
            Some(v) => self.strings(v, "elements")?,
            None => vec![],
        };
        let kind = if push {
            self.push_event(s, &ctx, mode, &elements_text)?
        } else {
            self.model_event(s, &ctx, mode, &elements_text)?
        };
        enabled.then(|| Event {
            name: s.name.clone(),
            doc: s.doc(),
            mode,
            kind,
            elements_text,
        })
    }

    /// A `push`: an interval kick of the free joint of each body `elements` names, by a velocity
    /// drawn from the `x` and `y` ranges.
    fn push_event(
        &mut self,
        s: &Section,
        ctx: &str,
        mode: EventMode,
        elements_text: &[String],
    ) -> Option<EventKind> {
        if !matches!(mode, EventMode::Interval { .. }) {
            self.d.push(
                Diagnostic::new(Code::E0152, format!("{ctx}: a push is an interval event"))
                    .at(s.get("mode").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                    .label("expected mode = \"interval\" with interval_seconds"),
            );
            return None;
        }
        let loc = s.get("elements").map_or(&s.name_loc, |v| &v.loc).clone();
        let mut joints = vec![];
        for (b, name) in self.matches(elements_text, ElementKind::Body, s, ctx)? {
            let free = self
                .model
                .joints
                .iter()
                .position(|j| j.body == b && j.kind == JointKind::Free);
            let Some(j) = free else {
                self.d.push(
                    Diagnostic::new(
                        Code::E0152,
                        format!("{ctx}: a push kicks a body's free joint; `{name}` has none"),
                    )
                    .at(loc.clone())
                    .label("expected bodies with a free joint (a floating base)"),
                );
                return None;
            };
            joints.push(Element {
                dofs: (self.model.joints[j].dofadr, 6),
                name,
                index: b,
            });
        }
        let mut axis = |key: &str| match s.get(key) {
            Some(v) => {
                let r = self.range(v, key)?;
                self.finite_range(r, v, key)
            }
            None => Some((0.0, 0.0)),
        };
        let (x, y) = (axis("x")?, axis("y")?);
        Some(EventKind::Push { joints, x, y })
    }

    /// A model event: a `field` of the model, drawn for the elements it names.
    fn model_event(
        &mut self,
        s: &Section,
        ctx: &str,
        mode: EventMode,
        elements_text: &[String],
    ) -> Option<EventKind> {
        let fv = self.need(s, "field", ctx)?;
        let fname = self.string(fv, "field")?;
        let Some(field) = EventField::parse(&fname) else {
            let names: Vec<&str> = FIELDS.iter().map(|(n, _)| *n).collect();
            self.d.push(
                Diagnostic::new(
                    Code::E0104,
                    format!("unknown event field `{fname}` in {ctx}"),
                )
                .at(fv.loc.clone())
                .label(format!("expected one of: {}", names.join(", ")))
                .help_opt(suggest(&fname, names.iter().copied())),
            );
            return None;
        };
        let ek = field.elements();
        let elements = if ek == ElementKind::Model {
            if let Some(v) = s.get("elements") {
                self.d.push(
                    Diagnostic::new(
                        Code::E0152,
                        format!("{ctx}: `{fname}` is model-wide and takes no elements"),
                    )
                    .at(v.loc.clone())
                    .label("remove `elements`"),
                );
                return None;
            }
            vec![]
        } else {
            self.matches(elements_text, ek, s, ctx)?
                .into_iter()
                .map(|(i, n)| self.element(ek, i, n))
                .collect()
        };
        let dist = self.distribution(s, ctx)?;
        let operation = self.operation(s, ctx)?;
        let shared = match s.get("shared") {
            Some(v) => self.flag(v, "shared")?,
            None => false,
        };
        if matches!(mode, EventMode::Interval { .. }) && field.needs_set_const() {
            // mj_setConst recomputes from qpos0 in the env's data: not within an episode.
            self.d.push(
                Diagnostic::new(
                    Code::E0152,
                    format!(
                        "{ctx}: `{fname}` changes MuJoCo's derived constants and can only be \
                         randomized at startup or reset, not at an interval"
                    ),
                )
                .at(s.get("mode").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                .label("expected mode = \"startup\" or \"reset\""),
            );
            return None;
        }
        if matches!(field, EventField::BodyQuatEuler(_))
            && (mode != EventMode::Reset || operation != Operation::Abs)
        {
            // The angles make a whole new orientation at each reset; there is no base.
            self.d.push(
                Diagnostic::new(
                    Code::E0152,
                    format!(
                        "{ctx}: `{fname}` sets the orientation anew at every reset: it needs \
                         mode = \"reset\" and operation = \"abs\""
                    ),
                )
                .at(s.get("mode").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                .label("expected mode = \"reset\", operation = \"abs\" (the default)"),
            );
            return None;
        }
        self.check_limits(s, ctx, field, dist, operation)?;
        Some(EventKind::Model {
            field,
            elements,
            dist,
            operation,
            shared,
        })
    }

    /// `operation`: how a draw meets the model's value (`abs`, the default: the draw replaces it).
    fn operation(&mut self, s: &Section, ctx: &str) -> Option<Operation> {
        Some(match s.get("operation") {
            None => Operation::Abs,
            Some(v) => {
                let o = self.string(v, "operation")?;
                match Operation::parse(&o) {
                    Some(op) => op,
                    None => {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0104,
                                format!("unknown operation `{o}` in {ctx}"),
                            )
                            .at(v.loc.clone())
                            .label(format!("expected one of: {}", Operation::NAMES.join(", ")))
                            .help_opt(suggest(&o, Operation::NAMES.iter().copied())),
                        );
                        return None;
                    }
                }
            }
        })
    }

    fn element(&self, kind: ElementKind, index: usize, name: String) -> Element {
        let dofs = match kind {
            ElementKind::Joint => {
                let j = &self.model.joints[index];
                (j.dofadr, j.kind.nv())
            }
            _ => (0, 0),
        };
        Element { name, index, dofs }
    }

    fn event_mode(&mut self, s: &Section, ctx: &str) -> Option<EventMode> {
        let mv = self.need(s, "mode", ctx)?;
        let m = self.string(mv, "mode")?;
        let interval = s.get("interval_seconds");
        match (m.as_str(), interval) {
            ("startup", None) => Some(EventMode::Startup),
            ("reset", None) => Some(EventMode::Reset),
            ("startup" | "reset", Some(v)) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0152,
                        format!("{ctx}: interval_seconds is for mode = \"interval\", not \"{m}\""),
                    )
                    .at(v.loc.clone())
                    .label("remove it, or make the event an interval event"),
                );
                None
            }
            ("interval", None) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0152,
                        format!("{ctx}: an interval event needs `interval_seconds`"),
                    )
                    .at(mv.loc.clone())
                    .label("expected interval_seconds = 4.0 or a range [4.0, 6.0]"),
                );
                None
            }
            ("interval", Some(v)) => {
                let (low, high) = match &v.kind {
                    ValKind::Array(_) => self.range(v, "interval_seconds")?,
                    _ => {
                        let x = self.num(v, "interval_seconds")?;
                        (x, x)
                    }
                };
                if !(low > 0.0 && high.is_finite() && low <= high) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0152,
                            format!("{ctx}: interval_seconds must be finite and > 0"),
                        )
                        .at(v.loc.clone())
                        .label("expected a number of seconds > 0, or a range of them"),
                    );
                    return None;
                }
                Some(EventMode::Interval { low, high })
            }
            (other, _) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0104,
                        format!("unknown event mode `{other}` in {ctx}"),
                    )
                    .at(mv.loc.clone())
                    .label(format!("expected one of: {}", MODES.join(", ")))
                    .help_opt(suggest(other, MODES.iter().copied())),
                );
                None
            }
        }
    }

    fn distribution(&mut self, s: &Section, ctx: &str) -> Option<EventDist> {
        let dv = self.need(s, "distribution", ctx)?;
        let name = self.string(dv, "distribution")?;
        let bad = |this: &mut Self, v: &Val, msg: String, label: &str| {
            this.d.push(
                Diagnostic::new(Code::E0151, format!("{ctx}: {msg}"))
                    .at(v.loc.clone())
                    .label(label.to_string()),
            );
        };
        match name.as_str() {
            "uniform" | "log_uniform" => {
                let rv = self.need(s, "range", ctx)?;
                let (low, high) = self.range(rv, "range")?;
                let (low, high) = self.finite_range((low, high), rv, "range")?;
                if name == "uniform" {
                    return Some(EventDist::Uniform { low, high });
                }
                if low <= 0.0 {
                    bad(
                        self,
                        rv,
                        format!("a log_uniform range must be positive; low is {low}"),
                        "expected 0 < low <= high",
                    );
                    return None;
                }
                Some(EventDist::LogUniform { low, high })
            }
            "gaussian" => {
                let mv = self.need(s, "mean", ctx)?;
                let sv = self.need(s, "std", ctx)?;
                let (mean, std) = (self.num(mv, "mean")?, self.num(sv, "std")?);
                let max = crate::limits::MAX_MAGNITUDE;
                let (mean, std) = (
                    self.within(mv, mean, "mean", max)?,
                    self.within(sv, std, "std", max)?,
                );
                if std < 0.0 {
                    bad(
                        self,
                        sv,
                        format!("std is {std}; a standard deviation is >= 0"),
                        "expected std >= 0",
                    );
                    return None;
                }
                Some(EventDist::Gaussian { mean, std })
            }
            other => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0104,
                        format!("unknown distribution `{other}` in {ctx}"),
                    )
                    .at(dv.loc.clone())
                    .label(format!("expected one of: {}", DISTRIBUTIONS.join(", ")))
                    .help_opt(suggest(other, DISTRIBUTIONS.iter().copied())),
                );
                None
            }
        }
    }

    /// What the spec can check without the compiled values: absolute values and scale factors
    /// against the field's bounds, and the timestep (whose compiled value the MJCF gives).
    fn check_limits(
        &mut self,
        s: &Section,
        ctx: &str,
        field: EventField,
        dist: EventDist,
        op: Operation,
    ) -> Option<()> {
        let (EventDist::Uniform { .. } | EventDist::LogUniform { .. }) = dist else {
            // Gaussian draws are unbounded: results are clamped to the field's bounds.
            return Some(());
        };
        let loc = s.get("range").map_or(&s.name_loc, |v| &v.loc).clone();
        let (lo, hi) = dist.support();
        let result = match (field, op) {
            (EventField::Timestep, _) => {
                let base = self.spec_timestep();
                Some(op.apply_range(base, (lo, hi)))
            }
            (_, Operation::Abs) => Some((lo, hi)),
            // Scaling a value ≥ 0 by a factor ≥ 0 keeps it ≥ 0.
            (_, Operation::Scale) => Some((lo.min(0.0), 0.0)),
            (_, Operation::Add) => None,
        };
        let Some((rlo, rhi)) = result else {
            return Some(());
        };
        let lower = field.lower_bound();
        let below = match (field, lower) {
            (EventField::Timestep, _) => rlo <= 0.0,
            (_, Some(b)) => rlo < b,
            _ => false,
        };
        let above = field.upper_bound().is_some_and(|u| rhi > u);
        if below || above {
            let expected = if field == EventField::Timestep {
                format!(
                    "a timestep in (0, {}] seconds for every draw (compiled: {})",
                    limits::MAX_TIMESTEP,
                    self.spec_timestep()
                )
            } else {
                format!("values >= 0 for `{}`", field.name())
            };
            self.d.push(
                Diagnostic::new(
                    Code::E0153,
                    format!(
                        "{ctx}: `{}` {} by {} can leave the field's limits",
                        field.name(),
                        op.name(),
                        dist.describe()
                    ),
                )
                .at(loc)
                .label(format!("expected {expected}")),
            );
            return None;
        }
        Some(())
    }

    /// The timestep the model will have (`[physics] timestep` wins over the MJCF's).
    fn spec_timestep(&self) -> f64 {
        self.model.timestep
    }

    /// Elements of `kind` matched by the names and patterns, each once, in model order.
    fn matches(
        &mut self,
        patterns: &[String],
        kind: ElementKind,
        s: &Section,
        ctx: &str,
    ) -> Option<Vec<(usize, String)>> {
        let loc = s.get("elements").map_or(&s.name_loc, |v| &v.loc).clone();
        let names: Vec<&str> = match kind {
            ElementKind::Geom => self.model.geoms.iter().map(String::as_str).collect(),
            ElementKind::Body => self.model.bodies.iter().map(String::as_str).collect(),
            ElementKind::Site => self.model.sites.iter().map(String::as_str).collect(),
            ElementKind::Joint => self.model.joints.iter().map(|j| j.name.as_str()).collect(),
            ElementKind::Actuator => self
                .model
                .actuators
                .iter()
                .map(|a| a.name.as_str())
                .collect(),
            ElementKind::Model => vec![],
        };
        if patterns.is_empty() {
            self.d.push(
                Diagnostic::new(
                    Code::E0152,
                    format!(
                        "{ctx}: missing `elements` (the {} to act on)",
                        kind.plural()
                    ),
                )
                .at(loc)
                .label(format!(
                    "expected elements = [\"name\", \"pattern*\"] naming {}",
                    kind.plural()
                )),
            );
            return None;
        }
        let mut hit = vec![false; names.len()];
        for p in patterns {
            let mut any = false;
            for (i, n) in names.iter().enumerate() {
                if !n.is_empty() && glob(p, n) {
                    hit[i] = true;
                    any = true;
                }
            }
            if !any {
                let named: Vec<&str> = names.iter().copied().filter(|n| !n.is_empty()).collect();
                self.d.push(
                    Diagnostic::new(
                        Code::E0150,
                        format!(
                            "{ctx}: the model {} has no {} matching `{p}`",
                            self.model.path.display(),
                            kind.name()
                        ),
                    )
                    .at(loc.clone())
                    .label(format!(
                        "expected names or patterns of {} ({} named)",
                        kind.plural(),
                        named.len()
                    ))
                    .help_opt(suggest(p, named.iter().copied())),
                );
                return None;
            }
        }
        Some(
            names
                .iter()
                .enumerate()
                .filter(|(i, _)| hit[*i])
                .map(|(i, n)| (i, n.to_string()))
                .collect(),
        )
    }

    fn need<'s>(&mut self, s: &'s Section, key: &str, ctx: &str) -> Option<&'s Val> {
        let v = s.get(key);
        if v.is_none() {
            self.d.push(
                Diagnostic::new(Code::E0103, format!("missing `{key}` in {ctx}"))
                    .at(s.name_loc.clone())
                    .label(format!("expected a `{key}` key")),
            );
        }
        v
    }

    fn string(&mut self, v: &Val, what: &str) -> Option<String> {
        match v.as_str() {
            Some(s) => Some(s.to_string()),
            None => {
                self.d.push(v.type_error(what, "a string"));
                None
            }
        }
    }

    /// A string or an array of strings.
    fn strings(&mut self, v: &Val, what: &str) -> Option<Vec<String>> {
        match &v.kind {
            ValKind::Str(s) => Some(vec![s.clone()]),
            ValKind::Array(a) => a.iter().map(|x| self.string(x, what)).collect(),
            _ => {
                self.d
                    .push(v.type_error(what, "a name or a list of names and patterns"));
                None
            }
        }
    }

    fn finite_range(&mut self, r: (f64, f64), v: &Val, what: &str) -> Option<(f64, f64)> {
        if r.0.is_finite() && r.1.is_finite() && r.0 <= r.1 {
            let max = crate::limits::MAX_MAGNITUDE;
            self.within(v, r.0, what, max)?;
            self.within(v, r.1, what, max)?;
            return Some(r);
        }
        if r.0 > r.1 {
            return None; // reported by `range` (E0105)
        }
        self.d.push(
            Diagnostic::new(
                Code::E0151,
                format!("{what} [{}, {}] is not a finite range", r.0, r.1),
            )
            .at(v.loc.clone())
            .label("expected finite [low, high] with low <= high"),
        );
        None
    }
}
