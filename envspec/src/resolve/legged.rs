//! The legged reward kinds of `[reward.*]` (mjlab's locomotion terms: tracking, feet contact and
//! clearance, posture, joint limits, self collisions; IR in `crate::commands`).

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::ir::*;
use crate::mjcf::JointKind;
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

impl Ctx<'_> {
    /// The legged kinds of `[reward.*]` (None: not one of them, or an error was reported).
    pub(super) fn legged_term(&mut self, s: &Section) -> Option<TermKind> {
        let term = match s.kind("") {
            "tracking" => self.tracking_term(s)?,
            "sum_abs" => {
                let source = self.need_sel(s, "source")?;
                let minus = match s.get("minus") {
                    Some(v) => {
                        let m = self.selection(v, "minus")?;
                        if !self.same_len(&source, &m, &v.loc) {
                            return None;
                        }
                        Some(m)
                    }
                    None => None,
                };
                LeggedTerm::SumAbs {
                    source,
                    minus,
                    gate: self.gate(s)?,
                }
            }
            "action_rate" => LeggedTerm::ActionRate,
            "feet_air_time" => {
                let feet = self.feet(s)?;
                let threshold = match s.get("threshold") {
                    Some(v) => self.num(v, "threshold")?,
                    None => 0.0,
                };
                LeggedTerm::FeetAirTime {
                    feet,
                    threshold,
                    gate: self.gate(s)?,
                }
            }
            "feet_slip" => {
                let feet = self.feet(s)?;
                let (_, velocity) = self.feet_sites(s, Some(feet.geoms.len()))?;
                LeggedTerm::FeetSlip {
                    feet,
                    velocity,
                    gate: self.gate(s)?,
                }
            }
            "feet_clearance" => self.feet_clearance_term(s)?,
            "feet_swing_height" => self.feet_swing_height_term(s)?,
            "soft_landing" => LeggedTerm::SoftLanding {
                feet: self.feet(s)?,
                gate: self.gate(s)?,
            },
            "self_collisions" => self.self_collisions_term(s)?,
            "posture" => self.posture_term(s)?,
            "joint_limits" => self.joint_limits_term(s)?,
            _ => return None,
        };
        Some(TermKind::Legged(term))
    }

    /// `kind = "tracking"`.
    fn tracking_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        // With `zero` alone (no source, no target) the kernel keeps a quantity near 0.
        let alone =
            s.get("zero").is_some() && s.get("source").is_none() && s.get("target").is_none();
        let (source, target) = if alone {
            let none = Selection {
                field: Field::Qpos,
                indices: vec![],
                names: vec![],
                text: String::new(),
            };
            (none.clone(), none)
        } else {
            let source = self.need_sel(s, "source")?;
            let target = self.need_sel(s, "target")?;
            if !self.same_len(&source, &target, &s.get("target")?.loc) {
                return None;
            }
            (source, target)
        };
        let coefs = self.num_list(s, "coefs", source.len(), 1.0)?;
        let sigma = match s.get("sigma") {
            Some(v) => {
                let x = self.num(v, "sigma")?;
                if x <= 0.0 {
                    self.d.push(
                        Diagnostic::new(Code::E0135, format!("sigma is {x}"))
                            .at(v.loc.clone())
                            .label("expected a kernel width > 0"),
                    );
                    return None;
                }
                x
            }
            None => 1.0,
        };
        let zero = match s.get("zero") {
            Some(v) => Some(self.selection(v, "zero")?),
            None => None,
        };
        Some(LeggedTerm::Tracking {
            source,
            target,
            coefs,
            sigma,
            zero,
        })
    }

    /// `kind = "feet_swing_height"`.
    fn feet_swing_height_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        let feet = self.feet(s)?;
        let (height, _) = self.feet_sites(s, Some(feet.geoms.len()))?;
        let LeggedTerm::FeetClearance {
            target, max_height, ..
        } = self.feet_clearance_term(s)?
        else {
            return None;
        };
        if target <= 0.0 {
            let v = s.get("target_height")?;
            self.d.push(
                Diagnostic::new(
                    Code::E0135,
                    format!("feet_swing_height target_height is {target}"),
                )
                .at(v.loc.clone())
                .label("expected a height > 0 (the cost divides by it)"),
            );
            return None;
        }
        Some(LeggedTerm::FeetSwingHeight {
            feet,
            height,
            target,
            max_height,
            gate: self.gate(s)?,
        })
    }

    /// `kind = "self_collisions"`.
    fn self_collisions_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        let v = self.need_key(
            s,
            "subtree",
            "expected subtree = \"<the robot's root body>\"",
        )?;
        let (name, is_body) = self.geom_name(v, "subtree")?;
        if !is_body {
            self.d.push(
                Diagnostic::new(Code::E0134, format!("`{name}` is a geom, not a body"))
                    .at(v.loc.clone())
                    .label("expected the body whose subtree's geoms collide"),
            );
            return None;
        }
        let threshold = match s.get("threshold") {
            Some(v) => {
                let x = self.num_within(v, "threshold", crate::limits::MAX_MAGNITUDE)?;
                if x < 0.0 {
                    self.d.push(
                        Diagnostic::new(Code::E0135, format!("self_collisions threshold is {x}"))
                            .at(v.loc.clone())
                            .label("expected a contact force ≥ 0 (newtons)"),
                    );
                    return None;
                }
                x
            }
            None => 10.0,
        };
        Some(LeggedTerm::SelfCollisions {
            subtree: name,
            threshold,
        })
    }

    /// `kind = "joint_limits"`.
    fn joint_limits_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        let source = self.need_sel(s, "source")?;
        let loc = s.get("source")?.loc.clone();
        let joints = self.hinge_joints(&source, &loc, "joint_limits")?;
        let factor = match s.get("factor") {
            Some(v) => self.num(v, "factor")?,
            None => 1.0,
        };
        let centered = match s.get("about") {
            None => false,
            Some(v) => {
                match v.as_str() {
                    Some("zero") => false,
                    Some("center") => true,
                    _ => {
                        self.d.push(
                        Diagnostic::new(
                            Code::E0104,
                            format!("joint_limits `about` is {}", v.to_toml()),
                        )
                        .at(v.loc.clone())
                        .label("expected \"zero\" (f·lo, f·hi) or \"center\" (mid ∓ f·(hi − lo)/2)"),
                    );
                        return None;
                    }
                }
            }
        };
        Some(LeggedTerm::JointLimits {
            source,
            joints,
            factor,
            centered,
        })
    }

    /// A geom name, else a body name (`true`): the element a contact term watches.
    pub(super) fn geom_name(&mut self, v: &Val, what: &str) -> Option<(String, bool)> {
        let Some(name) = v.as_str() else {
            self.d.push(v.type_error(what, "a geom name"));
            return None;
        };
        if !name.is_empty() && self.model.geoms.iter().any(|g| g == name) {
            return Some((name.to_string(), false));
        }
        if self.model.body_id(name).is_some() {
            return Some((name.to_string(), true));
        }
        self.d.push(
            Diagnostic::new(
                Code::E0134,
                format!(
                    "the model {} has no geom named `{name}`",
                    self.model.path.display()
                ),
            )
            .at(v.loc.clone())
            .label(format!(
                "expected a named geom ({} named) or a body of the model",
                self.model.geoms.iter().filter(|g| !g.is_empty()).count()
            ))
            .help_opt(suggest(
                name,
                self.model
                    .geoms
                    .iter()
                    .chain(&self.model.bodies)
                    .map(String::as_str)
                    .filter(|g| !g.is_empty()),
            )),
        );
        None
    }

    fn feet(&mut self, s: &Section) -> Option<FeetContact> {
        let context = format!("[reward.{}]", s.name);
        let (Some(f), Some(fl)) = (s.get("feet"), s.get("floor")) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `feet` or `floor` in {context}"),
                )
                .at(s.name_loc.clone())
                .label("expected feet = [geom names] and floor = \"geom name\""),
            );
            return None;
        };
        let geoms = match &f.kind {
            ValKind::Array(a) if !a.is_empty() => a
                .iter()
                .map(|g| self.geom_name(g, "feet"))
                .collect::<Vec<_>>(),
            _ => {
                self.d.push(f.type_error("feet", "an array of geom names"));
                return None;
            }
        };
        let floor = self.geom_name(fl, "floor");
        let (geoms, bodies) = geoms
            .into_iter()
            .collect::<Option<Vec<_>>>()?
            .into_iter()
            .unzip();
        let (floor, floor_is_body) = floor?;
        Some(FeetContact {
            geoms,
            bodies,
            floor,
            floor_is_body,
        })
    }

    /// The feet sites of a term (`sites = [...]`): their heights (`site_xpos` z) and their
    /// world velocities' x and y (2 per site). `count`: the number of feet they must match.
    fn feet_sites(&mut self, s: &Section, count: Option<usize>) -> Option<(Selection, Selection)> {
        let v = self.need_key(s, "sites", "expected sites = [one site per foot]")?;
        let names: Vec<&Val> = match &v.kind {
            ValKind::Array(a) if !a.is_empty() => a.iter().collect(),
            _ => {
                self.d.push(v.type_error("sites", "an array of site names"));
                return None;
            }
        };
        if let Some(n) = count
            && names.len() != n
        {
            self.d.push(
                Diagnostic::new(Code::E0134, format!("{} sites for {n} feet", names.len()))
                    .at(v.loc.clone())
                    .label("expected one site per foot geom, in the same order"),
            );
            return None;
        }
        let empty = |field| Selection {
            field,
            indices: vec![],
            names: vec![],
            text: String::new(),
        };
        let (mut height, mut velocity) = (empty(Field::SiteXpos), empty(Field::SiteLinvel));
        for n in names {
            let name = n.as_str().unwrap_or("?");
            for (out, text) in [
                (&mut height, format!("site_xpos[{name}][2]")),
                (&mut velocity, format!("site_linvel[{name}][0:2]")),
            ] {
                let sel = self.selection(
                    &Val {
                        kind: ValKind::Str(text),
                        loc: n.loc.clone(),
                    },
                    "sites",
                )?;
                out.indices.extend(sel.indices);
                out.names.extend(sel.names);
            }
        }
        let n = height.len();
        height.text = format!("site_xpos z of {n} sites");
        velocity.text = format!("site_linvel of {n} sites");
        Some((height, velocity))
    }

    fn gate(&mut self, s: &Section) -> Option<Option<Gate>> {
        let Some(v) = s.get("gate") else {
            return Some(None);
        };
        let t = match v.as_table() {
            Some(t) => t,
            None => {
                self.d
                    .push(v.type_error("gate", "{ command = \"command[NAME]\", above = 0.01 }"));
                return None;
            }
        };
        let command = t.iter().find(|e| e.key == "command");
        let bound = t.iter().find(|e| e.key == "above" || e.key == "below");
        let unknown = t
            .iter()
            .find(|e| !["command", "above", "below"].contains(&e.key.as_str()));
        let (Some(c), Some(a), None) = (command, bound, unknown) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    "a gate has `command` and one of `above` / `below`",
                )
                .at(v.loc.clone())
                .label("expected { command = \"command[NAME]\", above = 0.01 }"),
            );
            return None;
        };
        let command = self.selections(&c.value, "gate.command")?;
        let threshold = self.num(&a.value, "gate threshold")?;
        Some(Some(Gate {
            command,
            threshold,
            below: a.key == "below",
        }))
    }

    /// One selector, or a non-empty array of them (whose norms a gate or a posture adds).
    fn selections(&mut self, v: &Val, what: &str) -> Option<Vec<Selection>> {
        match &v.kind {
            ValKind::Array(a) if !a.is_empty() => a
                .iter()
                .map(|x| self.selection(x, what))
                .collect::<Option<Vec<_>>>(),
            ValKind::Array(_) => {
                self.d
                    .push(v.type_error(what, "a selector or a non-empty array of selectors"));
                None
            }
            _ => Some(vec![self.selection(v, what)?]),
        }
    }

    /// The joint of each element of a selection of hinge or slide joint positions (E0135 when
    /// an element is not one), for the kinds that read joint ranges or names.
    fn hinge_joints(
        &mut self,
        source: &Selection,
        loc: &Location,
        kind: &str,
    ) -> Option<Vec<usize>> {
        let mut joints = vec![];
        for &i in &source.indices {
            let j = (source.field == Field::Qpos)
                .then(|| {
                    self.model.joints.iter().position(|j| {
                        j.qposadr == i && matches!(j.kind, JointKind::Hinge | JointKind::Slide)
                    })
                })
                .flatten();
            match j {
                Some(j) => joints.push(j),
                None => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0135,
                            format!(
                                "{kind} reads `{}`, which is not the position of a hinge or slide joint",
                                source.text
                            ),
                        )
                        .at(loc.clone())
                        .label("expected qpos of hinge or slide joints, e.g. \"qpos[7:]\""),
                    );
                    return None;
                }
            }
        }
        Some(joints)
    }

    /// A posture's `std`: a table `joint pattern = width`, or an array of such tables (one per
    /// speed regime). Each joint of `joints` matches exactly one pattern of each table
    /// (mjlab's `resolve_matching_names_values`); every pattern matches a joint.
    fn posture_std(&mut self, v: &Val, joints: &[usize]) -> Option<Vec<Vec<f64>>> {
        let tables: Vec<&Val> = match &v.kind {
            ValKind::Array(a) if !a.is_empty() => a.iter().collect(),
            ValKind::Table(_) => vec![v],
            _ => {
                self.d.push(v.type_error(
                    "std",
                    "a table `joint pattern = width`, or an array of them (one per regime)",
                ));
                return None;
            }
        };
        let names: Vec<String> = joints
            .iter()
            .map(|&j| self.model.joints[j].name.clone())
            .collect();
        let mut out = vec![];
        for t in tables {
            let Some(rows) = t.as_table() else {
                self.d
                    .push(t.type_error("std", "a table `joint pattern = width`"));
                return None;
            };
            let mut width: Vec<Option<(f64, &str)>> = vec![None; names.len()];
            for e in rows {
                let x = self.num(&e.value, "std")?;
                if !(x.is_finite() && x > 0.0) {
                    self.d.push(
                        Diagnostic::new(Code::E0135, format!("std {x} for `{}`", e.key))
                            .at(e.value.loc.clone())
                            .label("expected a finite width > 0"),
                    );
                    return None;
                }
                let hit = self.glob_hits(
                    &e.key,
                    names.iter().map(String::as_str),
                    &e.key_loc,
                    &format!("the {} joints the posture reads", names.len()),
                    "a glob pattern over joint names (`*`: any run of characters, `?`: one)",
                )?;
                for k in hit {
                    if let Some((_, other)) = width[k] {
                        self.d.push(
                            Diagnostic::new(
                                Code::E0135,
                                format!(
                                    "joint `{}` matches both `{other}` and `{}`",
                                    names[k], e.key
                                ),
                            )
                            .at(e.key_loc.clone())
                            .label(
                                "each joint takes its width from exactly one pattern of a table",
                            ),
                        );
                        return None;
                    }
                    width[k] = Some((x, &e.key));
                }
            }
            if let Some(k) = width.iter().position(Option::is_none) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0135,
                        format!(
                            "no pattern of this std table matches joint `{}` ({} of {} joints have a width)",
                            names[k],
                            width.iter().filter(|w| w.is_some()).count(),
                            names.len()
                        ),
                    )
                    .at(t.loc.clone())
                    .label("every joint the posture reads needs a width"),
                );
                return None;
            }
            out.push(width.into_iter().flatten().map(|(x, _)| x).collect());
        }
        Some(out)
    }

    /// `kind = "feet_clearance"`.
    fn feet_clearance_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        let (height, velocity) = self.feet_sites(s, None)?;
        self.need_key(
            s,
            "target_height",
            "expected target_height = the clearance in metres",
        )?;
        let mut num = |key: &str, default: Option<f64>, positive: bool| -> Option<f64> {
            let Some(v) = s.get(key) else {
                return default;
            };
            let x = self.num(v, key)?;
            let ok = if positive { x > 0.0 } else { x >= 0.0 };
            if !ok || x.is_nan() {
                self.d.push(
                    Diagnostic::new(Code::E0135, format!("feet_clearance {key} is {x}"))
                        .at(v.loc.clone())
                        .label(if positive {
                            "expected a number > 0"
                        } else {
                            "expected a number ≥ 0"
                        }),
                );
                return None;
            }
            Some(x)
        };
        let target = num("target_height", None, false)?;
        let max_height = num("max_height", Some(f64::INFINITY), true)?;
        let power = num("power", Some(1.0), false)?;
        if power > crate::limits::MAX_EXPONENT
            && let Some(v) = s.get("power")
        {
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!(
                        "feet_clearance power {power:e} is beyond envc's limit of {}",
                        crate::limits::MAX_EXPONENT
                    ),
                )
                .at(v.loc.clone())
                .label(format!(
                    "expected a power from 0 to {}",
                    crate::limits::MAX_EXPONENT
                ))
                .help("a speed raised to a larger power overflows to inf; see docs/limits.md"),
            );
            return None;
        }
        Some(LeggedTerm::FeetClearance {
            height,
            velocity,
            target,
            max_height,
            power,
            gate: self.gate(s)?,
        })
    }

    /// `kind = "posture"`.
    fn posture_term(&mut self, s: &Section) -> Option<LeggedTerm> {
        let source = self.need_sel(s, "source")?;
        let loc = s.get("source")?.loc.clone();
        let joints = self.hinge_joints(&source, &loc, "posture")?;
        let minus = self.need_sel(s, "minus")?;
        if !self.same_len(&source, &minus, &s.get("minus")?.loc) {
            return None;
        }
        let std = self.need_key(
            s,
            "std",
            "expected std = { \"*\" = 0.3 } (joint pattern = width)",
        )?;
        let sigma = self.posture_std(std, &joints)?;
        let speed = match s.get("speed") {
            Some(v) => self.selections(v, "speed")?,
            None => vec![],
        };
        let thresholds = match s.get("thresholds") {
            Some(v) => match &v.kind {
                ValKind::Array(a) => a
                    .iter()
                    .map(|x| self.num(x, "thresholds"))
                    .collect::<Option<Vec<_>>>()?,
                _ => {
                    self.d
                        .push(v.type_error("thresholds", "an array of speeds"));
                    return None;
                }
            },
            None => vec![],
        };
        let ascending = thresholds.windows(2).all(|w| w[0] < w[1]);
        if thresholds.len() + 1 != sigma.len()
            || speed.is_empty() != thresholds.is_empty()
            || !ascending
            || thresholds.iter().any(|t| !t.is_finite())
        {
            self.d.push(
                Diagnostic::new(
                    Code::E0135,
                    format!(
                        "a posture with {} std tables needs {} ascending finite thresholds and a speed; {} thresholds were given{}",
                        sigma.len(),
                        sigma.len() - 1,
                        thresholds.len(),
                        if speed.is_empty() { ", no speed" } else { "" }
                    ),
                )
                .at(std.loc.clone())
                .label("regime r holds while speed < thresholds[r]; the last from the last threshold up"),
            );
            return None;
        }
        Some(LeggedTerm::Posture {
            source,
            minus,
            speed,
            thresholds,
            sigma,
        })
    }
}
