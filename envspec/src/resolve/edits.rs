//! `[actuators]` and `[physics]`: model edits the runtime applies at load time. They are resolved
//! before anything else and folded into the `ModelInfo`, so selectors (`action`, `ctrl`), the action
//! layout and the timestep already include them.

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::AddedElement;
use crate::ir::{
    ActuatorKind, AddedActuator, GeomEdit, Integrator, JointEdit, ModelEdits, SOLVER_OPTIONS,
    SolverOption,
};
use crate::mjcf::{Actuator, JointKind, ModelInfo};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

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

    /// `[geom_properties]`: contact properties of the named geoms by glob pattern, rows in file
    /// order (later rows win), each row matching at least one geom.
    fn geom_properties(&mut self, edits: &mut ModelEdits) {
        let rows = &self.spec.geom_properties;
        if rows.is_empty() {
            return;
        }
        let geoms: Vec<String> = self
            .model
            .geoms
            .iter()
            .filter(|g| !g.is_empty())
            .cloned()
            .collect();
        let mut table: Vec<GeomEdit> = geoms
            .iter()
            .map(|g| GeomEdit {
                geom: g.clone(),
                ..Default::default()
            })
            .collect();
        for row in rows {
            let what = |k: &str| format!("geom_properties.\"{}\".{k}", row.name);
            let Some(hit) = self.glob_hits(
                &row.name,
                geoms.iter().map(String::as_str),
                &row.name_loc,
                &format!(
                    "the {} named geoms of {}",
                    geoms.len(),
                    self.model.path.display()
                ),
                "a glob pattern over geom names (`*`: any run of characters, `?`: one)",
            ) else {
                continue;
            };
            let mut set: Vec<(String, Vec<f64>)> = vec![];
            let bad =
                |d: &mut crate::diagnostic::Diagnostics, v: &Val, msg: String, label: &str| {
                    d.push(
                        Diagnostic::new(Code::E0161, msg)
                            .at(v.loc.clone())
                            .label(label.to_string()),
                    );
                };
            for (k, key) in GeomEdit::INTS.iter().enumerate() {
                let Some(v) = row.get(key) else { continue };
                let Some(x) = self.num(v, &what(key)) else {
                    continue;
                };
                let ok = x.fract() == 0.0
                    && x >= 0.0
                    && x <= f64::from(i32::MAX)
                    && (*key != "condim" || [1.0, 3.0, 4.0, 6.0].contains(&x));
                if !ok {
                    let label = if *key == "condim" {
                        "expected 1, 3, 4 or 6"
                    } else {
                        "expected a whole number ≥ 0"
                    };
                    bad(&mut self.d, v, format!("{} is {x}", what(key)), label);
                    continue;
                }
                set.push((key.to_string(), vec![x]));
                for &i in &hit {
                    table[i].ints[k] = Some(x as i32);
                }
            }
            for (k, key) in GeomEdit::REALS.iter().enumerate() {
                let Some(v) = row.get(key) else { continue };
                let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                    continue;
                };
                if !x.is_finite() || (*key == "solmix" && x < 0.0) {
                    bad(
                        &mut self.d,
                        v,
                        format!("{} is {x}", what(key)),
                        "expected a finite number",
                    );
                    continue;
                }
                set.push((key.to_string(), vec![x]));
                for &i in &hit {
                    table[i].reals[k] = Some(x);
                }
            }
            for (key, most) in GeomEdit::ARRAYS {
                let Some(v) = row.get(key) else { continue };
                let values = match &v.kind {
                    ValKind::Array(a) if !a.is_empty() && a.len() <= most => a
                        .iter()
                        .map(|x| self.num_within(x, &what(key), crate::limits::MAX_MAGNITUDE))
                        .collect::<Option<Vec<f64>>>(),
                    ValKind::Array(a) => {
                        bad(
                            &mut self.d,
                            v,
                            format!("{} has {} numbers", what(key), a.len()),
                            &format!("expected 1 to {most} numbers (the leading entries are set)"),
                        );
                        None
                    }
                    _ => {
                        self.d.push(v.type_error(&what(key), "an array of numbers"));
                        None
                    }
                };
                let Some(values) = values else { continue };
                if values.iter().any(|x| !x.is_finite()) {
                    bad(
                        &mut self.d,
                        v,
                        format!("{} is not finite", what(key)),
                        "expected finite numbers",
                    );
                    continue;
                }
                set.push((key.to_string(), values.clone()));
                for &i in &hit {
                    let e = &mut table[i];
                    match key {
                        "friction" => e.friction.clone_from(&values),
                        "solref" => e.solref.clone_from(&values),
                        _ => e.solimp.clone_from(&values),
                    }
                }
            }
            for &i in &hit {
                if !set.is_empty() && !table[i].rows.contains(&row.name) {
                    table[i].rows.push(row.name.clone());
                }
            }
            edits.geom_rows.push((
                row.name.clone(),
                hit.iter().map(|&i| geoms[i].clone()).collect(),
                set,
            ));
        }
        edits.geoms = table.into_iter().filter(|e| !e.rows.is_empty()).collect();
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

    fn actuator_section(&mut self, s: &Section, out: &mut Vec<AddedActuator>) {
        let what = |k: &str| format!("actuators.{}.{k}", s.name);
        if s.name.contains('\0') {
            self.d
                .push(super::added::nul_in_name("actuator", s.name_loc.clone()));
            return;
        }
        let Some(jv) = s.get("joint") else { return };
        // (actuator name, joint name, location to blame)
        let targets: Vec<(String, String)> = match &jv.kind {
            ValKind::Str(j) if j == "*" => {
                let all: Vec<(String, String)> = self
                    .model
                    .joints
                    .iter()
                    .filter(|j| matches!(j.kind, JointKind::Hinge | JointKind::Slide))
                    .map(|j| (j.name.clone(), j.name.clone()))
                    .collect();
                if all.is_empty() {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0107,
                            "`joint = \"*\"` matches no hinge or slide joint",
                        )
                        .at(jv.loc.clone())
                        .label("the model has no hinge or slide joints"),
                    );
                }
                all
            }
            ValKind::Str(j) => match self.actuated_joint(j, jv) {
                Some(()) => vec![(s.name.clone(), j.clone())],
                None => vec![],
            },
            ValKind::Array(items) => {
                let mut v = vec![];
                for item in items {
                    match item.as_str() {
                        Some(j) => {
                            if self.actuated_joint(j, item).is_some() {
                                v.push((j.to_string(), j.to_string()));
                            }
                        }
                        None => self.d.push(item.type_error(&what("joint"), "a joint name")),
                    }
                }
                v
            }
            _ => {
                self.d.push(jv.type_error(
                    &what("joint"),
                    "a joint name, a list of joint names or \"*\"",
                ));
                vec![]
            }
        };

        // One gear for every joint, or one per joint in the `joint` list's order.
        let gears: Vec<f64> = match s.get("gear") {
            None => vec![1.0; targets.len()],
            Some(v) => match &v.kind {
                ValKind::Array(a) if a.len() == targets.len() => a
                    .iter()
                    .map(|x| {
                        self.num_within(x, &what("gear"), crate::limits::MAX_MAGNITUDE)
                            .unwrap_or(1.0)
                    })
                    .collect(),
                ValKind::Array(a) => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0403,
                            format!(
                                "{} gears for {} joints in [actuators.{}]",
                                a.len(),
                                targets.len(),
                                s.name
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected one gear, or one per joint"),
                    );
                    vec![1.0; targets.len()]
                }
                _ => vec![
                    self.num_within(v, &what("gear"), crate::limits::MAX_MAGNITUDE)
                        .unwrap_or(1.0);
                    targets.len()
                ],
            },
        };
        let ctrlrange = match s.get("ctrlrange") {
            Some(v) => match self.range(v, &what("ctrlrange")) {
                // The action space is [low, high] in float32: it must be finite there, and so
                // must its width, or sampling an action is meaningless.
                Some((lo, hi))
                    if !(lo as f32).is_finite()
                        || !(hi as f32).is_finite()
                        || !(hi - lo).is_finite() =>
                {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0105,
                            format!(
                                "{}: [{lo}, {hi}] is not a finite control range",
                                what("ctrlrange")
                            ),
                        )
                        .at(v.loc.clone())
                        .label("expected finite bounds (within float32, ±3.4e38)"),
                    );
                    (-1.0, 1.0)
                }
                r => r.unwrap_or((-1.0, 1.0)),
            },
            None => (-1.0, 1.0),
        };
        let forcerange = s.get("forcerange").and_then(|v| {
            let (lo, hi) = self.range(v, &what("forcerange"))?;
            let max = crate::limits::MAX_MAGNITUDE;
            self.within(v, lo, &what("forcerange"), max)?;
            self.within(v, hi, &what("forcerange"), max)?;
            Some((lo, hi))
        });
        let kind = match s.kind("motor") {
            "position" => ActuatorKind::Position {
                kp: self.gain(s, "kp").unwrap_or(1.0),
                kv: self.gain(s, "kv"),
            },
            "velocity" => ActuatorKind::Velocity {
                kv: self.gain(s, "kv").unwrap_or(1.0),
            },
            _ => ActuatorKind::Motor,
        };

        for ((name, joint), gear) in targets.into_iter().zip(gears) {
            let taken = self.model.actuators.iter().any(|a| a.name == name)
                || out.iter().any(|a| a.name == name);
            if taken {
                self.d.push(
                    Diagnostic::new(Code::E0106, format!("actuator `{name}` is defined twice"))
                        .at(s.name_loc.clone())
                        .label("actuator names must be unique (the model's own included)"),
                );
                continue;
            }
            out.push(AddedActuator {
                name,
                section: s.name.clone(),
                joint,
                kind,
                gear,
                ctrlrange,
                forcerange,
            });
        }
    }

    /// `[joint_properties]`: each row's glob pattern selects hinge and slide joints; its joint
    /// keys set those joints' properties, its actuator keys those of the `[actuators.*]`
    /// actuators on them. Rows apply in file order, so a later row overrides an earlier one
    /// key by key where both match a joint; a row overrides its `[actuators.*]` table's values.
    #[allow(clippy::too_many_lines)] // Rows apply in file order to joints and their actuators together.
    fn joint_properties(&mut self, edits: &mut ModelEdits) {
        let rows = &self.spec.joint_properties;
        if rows.is_empty() {
            return;
        }
        let joints: Vec<String> = self
            .model
            .joints
            .iter()
            .filter(|j| matches!(j.kind, JointKind::Hinge | JointKind::Slide))
            .map(|j| j.name.clone())
            .collect();
        let mut table: Vec<JointEdit> = joints
            .iter()
            .map(|j| JointEdit {
                joint: j.clone(),
                ..Default::default()
            })
            .collect();
        for row in rows {
            let what = |k: &str| format!("joint_properties.\"{}\".{k}", row.name);
            let hit: Vec<usize> = (0..joints.len())
                .filter(|&i| crate::selector::glob(&row.name, &joints[i]))
                .collect();
            if hit.is_empty() {
                let named = self
                    .model
                    .joints
                    .iter()
                    .filter(|j| j.name == row.name)
                    .count();
                self.d.push(
                    Diagnostic::new(
                        Code::E0160,
                        format!(
                            "`{}` matches none of the {} hinge and slide joints of {}",
                            row.name,
                            joints.len(),
                            self.model.path.display()
                        ),
                    )
                    .at(row.name_loc.clone())
                    .label(if named > 0 {
                        "this joint is not a hinge or slide joint".to_string()
                    } else {
                        "a glob pattern over joint names (`*`: any run of characters, `?`: one)"
                            .to_string()
                    })
                    .help_opt(suggest(&row.name, joints.iter().map(String::as_str))),
                );
                continue;
            }
            let mut set: Vec<(String, Vec<f64>)> = vec![];
            // Joint keys.
            for key in ["armature", "damping", "frictionloss"] {
                let Some(v) = row.get(key) else { continue };
                let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                    continue;
                };
                set.push((key.to_string(), vec![x]));
                if !(x.is_finite() && x >= 0.0) {
                    self.d.push(
                        Diagnostic::new(Code::E0161, format!("{} {x} is negative", what(key)))
                            .at(v.loc.clone())
                            .label("expected a finite number ≥ 0"),
                    );
                    continue;
                }
                for &i in &hit {
                    let e = &mut table[i];
                    match key {
                        "armature" => e.armature = Some(x),
                        "damping" => e.damping = Some(x),
                        _ => e.frictionloss = Some(x),
                    }
                    if !e.rows.contains(&row.name) {
                        e.rows.push(row.name.clone());
                    }
                }
            }
            // Actuator keys: the actuators `[actuators.*]` adds on the matched joints.
            let on: Vec<usize> = edits
                .actuators
                .iter()
                .enumerate()
                .filter(|(_, a)| hit.iter().any(|&i| joints[i] == a.joint))
                .map(|(k, _)| k)
                .collect();
            let actuator_keys = ["kp", "kv", "effort", "forcerange", "ctrlrange", "gear"];
            if actuator_keys.iter().any(|k| row.get(k).is_some()) {
                for &i in &hit {
                    let e = &mut table[i];
                    if edits.actuators.iter().any(|a| a.joint == e.joint)
                        && !e.rows.contains(&row.name)
                    {
                        e.rows.push(row.name.clone());
                    }
                }
            }
            for key in actuator_keys {
                let Some(v) = row.get(key) else { continue };
                if on.is_empty() {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0161,
                            format!(
                                "`{key}` in [joint_properties.\"{}\"] reaches no actuator: none of the {} joints it matches has one from [actuators.*]",
                                row.name,
                                hit.len()
                            ),
                        )
                        .at(v.loc.clone())
                        .label("actuator keys apply to the actuators [actuators.*] adds on the matched joints")
                        .help("add the joints to an [actuators.<name>] table (its `joint` list fixes the action order)"),
                    );
                    continue;
                }
                match key {
                    "kp" | "kv" => {
                        let Some(x) = self.gain_value(v, &what(key), key) else {
                            continue;
                        };
                        set.push((key.to_string(), vec![x]));
                        for &k in &on {
                            let a = &mut edits.actuators[k];
                            let fits = match (&mut a.kind, key) {
                                (ActuatorKind::Position { kp, .. }, "kp") => {
                                    *kp = x;
                                    true
                                }
                                (ActuatorKind::Position { kv, .. }, _) => {
                                    *kv = Some(x);
                                    true
                                }
                                (ActuatorKind::Velocity { kv }, "kv") => {
                                    *kv = x;
                                    true
                                }
                                _ => false,
                            };
                            if !fits {
                                self.d.push(
                                    Diagnostic::new(
                                        Code::E0161,
                                        format!(
                                            "`{key}` in [joint_properties.\"{}\"] reaches actuator `{}` ([actuators.{}]), which is a {} actuator",
                                            row.name,
                                            a.name,
                                            a.section,
                                            match a.kind {
                                                ActuatorKind::Motor => "motor",
                                                ActuatorKind::Position { .. } => "position",
                                                ActuatorKind::Velocity { .. } => "velocity",
                                            }
                                        ),
                                    )
                                    .at(v.loc.clone())
                                    .label("kp applies to position actuators; kv to position and velocity actuators")
                                    .help(format!("set `kind = \"position\"` in [actuators.{}]", a.section)),
                                );
                                break;
                            }
                        }
                    }
                    "effort" => {
                        let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE)
                        else {
                            continue;
                        };
                        if !(x.is_finite() && x > 0.0) {
                            self.d.push(
                                Diagnostic::new(
                                    Code::E0161,
                                    format!("{} {x} is not a positive force", what(key)),
                                )
                                .at(v.loc.clone())
                                .label("expected a finite force limit > 0: forcerange = [-effort, effort]"),
                            );
                            continue;
                        }
                        set.push((key.to_string(), vec![x]));
                        for &k in &on {
                            edits.actuators[k].forcerange = Some((-x, x));
                        }
                    }
                    "forcerange" | "ctrlrange" => {
                        let Some((lo, hi)) = self.range(v, &what(key)) else {
                            continue;
                        };
                        if self
                            .within(v, lo, &what(key), crate::limits::MAX_MAGNITUDE)
                            .is_none()
                            || self
                                .within(v, hi, &what(key), crate::limits::MAX_MAGNITUDE)
                                .is_none()
                        {
                            continue;
                        }
                        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                            self.d.push(
                                Diagnostic::new(
                                    Code::E0161,
                                    format!("{} [{lo}, {hi}] is not a finite range", what(key)),
                                )
                                .at(v.loc.clone())
                                .label("expected [low, high], finite, low ≤ high"),
                            );
                            continue;
                        }
                        set.push((key.to_string(), vec![lo, hi]));
                        for &k in &on {
                            if key == "forcerange" {
                                edits.actuators[k].forcerange = Some((lo, hi));
                            } else {
                                edits.actuators[k].ctrlrange = (lo, hi);
                            }
                        }
                    }
                    _ => {
                        let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE)
                        else {
                            continue;
                        };
                        set.push((key.to_string(), vec![x]));
                        for &k in &on {
                            edits.actuators[k].gear = x;
                        }
                    }
                }
            }
            edits.joint_rows.push((
                row.name.clone(),
                hit.iter().map(|&i| joints[i].clone()).collect(),
                set,
            ));
        }
        edits.joints = table.into_iter().filter(|e| !e.rows.is_empty()).collect();
    }

    fn gain_value(&mut self, v: &Val, what: &str, key: &str) -> Option<f64> {
        let x = self.num_within(v, what, crate::limits::MAX_MAGNITUDE)?;
        if !(x.is_finite() && x >= 0.0) {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{key} {x} is negative"))
                    .at(v.loc.clone())
                    .label("expected a non-negative gain"),
            );
            return None;
        }
        Some(x)
    }

    /// A non-negative gain `kp`/`kv`, when given.
    fn gain(&mut self, s: &Section, key: &str) -> Option<f64> {
        let v = s.get(key)?;
        let x = self.num_within(
            v,
            &format!("actuators.{}.{key}", s.name),
            crate::limits::MAX_MAGNITUDE,
        )?;
        if !(x.is_finite() && x >= 0.0) {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{key} {x} is negative"))
                    .at(v.loc.clone())
                    .label("expected a non-negative gain"),
            );
            return None;
        }
        Some(x)
    }

    /// Check that `name` is a hinge or slide joint of the model.
    fn actuated_joint(&mut self, name: &str, v: &Val) -> Option<()> {
        match self.model.joint(name) {
            Some(j) if matches!(j.kind, JointKind::Hinge | JointKind::Slide) => Some(()),
            Some(j) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0107,
                        format!("joint `{name}` is a {:?} joint", j.kind).to_lowercase(),
                    )
                    .at(v.loc.clone())
                    .label("actuators drive hinge and slide joints only"),
                );
                None
            }
            None => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0303,
                        format!(
                            "the model {} has no joint named `{name}`",
                            self.model.path.display()
                        ),
                    )
                    .at(v.loc.clone())
                    .label("expected a joint of the model")
                    .help_opt(suggest(
                        name,
                        self.model.joints.iter().map(|j| j.name.as_str()),
                    )),
                );
                None
            }
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
