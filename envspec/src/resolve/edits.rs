//! Model edits the runtime applies at load time: `[actuators]`, `[joint_properties]`,
//! `[geom_properties]`, `[keyframes]`, `[terrain]` (each in its own module) and `[physics]`
//! (here). They are resolved before anything else and folded into the `ModelInfo`, so selectors
//! (`action`, `ctrl`), the action layout and the timestep already include them.

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::AddedElement;
use crate::ir::{Integrator, ModelEdits, SOLVER_OPTIONS, SolverOption};
use crate::mjcf::{Actuator, ModelInfo};
use crate::syntax::Section;

use super::Ctx;

impl Ctx<'_> {
    /// The model edits; `added`: the `[bodies]` ... elements, resolved first (this context's
    /// model already holds them, so the other tables see the joints and geoms they add).
    pub(super) fn model_edits(&mut self, added: Vec<AddedElement>) -> ModelEdits {
        let mut edits = ModelEdits::default();
        let spec = self.spec;
        edits.added = added;
        for s in &spec.actuators {
            self.actuator_section(s, &mut edits.actuators);
        }
        self.joint_properties(&mut edits);
        self.geom_properties(&mut edits);
        edits.keyframes = self.keyframes();
        edits.terrain = self.terrain();
        if let Some(p) = &spec.physics {
            if let Some(v) = p.get("timestep")
                && let Some(ts) = self.num(v, "physics.timestep")
            {
                if ts > 0.0 && ts <= crate::limits::MAX_TIMESTEP {
                    edits.timestep = Some(ts);
                } else {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!(
                                "timestep {ts} is not in (0, {}] seconds",
                                crate::limits::MAX_TIMESTEP
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected a positive number of seconds, at most 1"),
                    );
                }
            }
            if let Some(v) = p.get("forward_before_observation") {
                edits.forward_before_observation = self
                    .flag(v, "physics.forward_before_observation")
                    .unwrap_or(false);
            }
            self.solver_options(p, &mut edits);
            if let Some(v) = p.get("integrator") {
                match v.as_str() {
                    Some(s) => match Integrator::parse(s) {
                        Some(i) => edits.integrator = Some(i),
                        None => self.d.push(
                            Diagnostic::new(Code::E0104, format!("unknown integrator `{s}`"))
                                .at(v.loc.clone())
                                .label(format!("expected one of: {}", Integrator::NAMES.join(", ")))
                                .help_opt(suggest(s, Integrator::NAMES.iter().copied())),
                        ),
                    },
                    None => self.d.push(v.type_error("physics.integrator", "a string")),
                }
            }
        }
        edits
    }

    /// `[physics]` solver options (`cone`, `iterations`, `impratio`, …): whole numbers where
    /// MuJoCo's field is an integer, each at least its smallest value and at most the limits'.
    fn solver_options(&mut self, p: &Section, edits: &mut ModelEdits) {
        for &(key, option, whole, min) in SOLVER_OPTIONS {
            let Some(v) = p.get(key) else { continue };
            let x = if option == SolverOption::Cone {
                match v.as_str() {
                    Some("pyramidal") => 0.0,
                    Some("elliptic") => 1.0,
                    _ => {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0104,
                                format!("physics.cone is {}", v.to_toml()),
                            )
                            .at(v.loc.clone())
                            .label("expected \"pyramidal\" or \"elliptic\""),
                        );
                        continue;
                    }
                }
            } else {
                let Some(x) = self.num(v, &format!("physics.{key}")) else {
                    continue;
                };
                let max = if whole {
                    crate::limits::MAX_SOLVER_ITERATIONS as f64
                } else {
                    crate::limits::MAX_MAGNITUDE
                };
                if !(x >= min && x <= max) || (whole && x.fract() != 0.0) {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!("physics.{key} is {x}, not in [{min}, {max}]"),
                        )
                        .at(v.loc.clone())
                        .label(if whole {
                            format!("expected a whole number from {min} to {max}")
                        } else {
                            format!("expected a number from {min:e} to {max:e}")
                        }),
                    );
                    continue;
                }
                x
            };
            edits.solver.push((option, x));
        }
    }
}

/// Fold the edits into the model info: added actuators come after the model's own.
pub(super) fn apply(edits: &ModelEdits, model: &mut ModelInfo) {
    super::added::apply(&edits.added, model);
    model
        .actuators
        .extend(edits.actuators.iter().map(|a| Actuator {
            name: a.name.clone(),
            target: Some(a.joint.clone()),
        }));
    if let Some(ts) = edits.timestep {
        model.timestep = ts;
    }
    model
        .keyframes
        .extend(edits.keyframes.iter().map(|k| k.name.clone()));
}
