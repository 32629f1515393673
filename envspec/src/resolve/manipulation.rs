//! `[init]`, `[end_effector]`, `[hold.*]` and `[goal]` (docs/spec-reference.md §22), the
//! `goal[...]` selector and a reset step's `around` (envspec::manipulation has the IR; the reset
//! kinds of these tasks are in `manipulation_reset`).

use super::Ctx;
use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::manipulation::*;
use crate::mjcf::JointKind;
use crate::selector::{Field, Selection};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

pub(super) fn misfit(at: &Location, msg: String, label: &str) -> Diagnostic {
    Diagnostic::new(Code::E0170, msg)
        .at(at.clone())
        .label(label)
}

/// `name` or `name[i]` / `name[a:b]` (Python slice without step, clamped): the name and the
/// indices into a vector of `n` elements.
fn name_and_rows(
    text: &str,
    n_of: impl Fn(&str) -> Option<usize>,
) -> Result<(String, Vec<usize>), String> {
    let text = text.trim();
    let (name, rest) = match text.find('[') {
        Some(i) => (text[..i].trim(), Some(&text[i..])),
        None => (text, None),
    };
    let n = n_of(name).ok_or_else(|| format!("`{name}` is not declared"))?;
    let Some(rest) = rest else {
        return Ok((name.to_string(), (0..n).collect()));
    };
    let inner = rest
        .strip_prefix('[')
        .and_then(|r| r.strip_suffix(']'))
        .ok_or_else(|| format!("`{rest}` is not `[i]` or `[a:b]`"))?
        .trim();
    let int = |s: &str| -> Result<i64, String> {
        s.trim()
            .parse::<i64>()
            .map_err(|_| format!("`{s}` is not an integer"))
    };
    let ni = n as i64;
    let clamp = |x: i64| -> i64 { if x < 0 { (x + ni).max(0) } else { x.min(ni) } };
    let rows = if let Some((a, b)) = inner.split_once(':') {
        let a = if a.trim().is_empty() {
            0
        } else {
            clamp(int(a)?)
        };
        let b = if b.trim().is_empty() {
            ni
        } else {
            clamp(int(b)?)
        };
        (a..b.max(a)).map(|i| i as usize).collect()
    } else {
        let i = int(inner)?;
        let j = if i < 0 { i + ni } else { i };
        if !(0..ni).contains(&j) {
            return Err(format!("index {i} is outside the {n} elements"));
        }
        vec![j as usize]
    };
    Ok((name.to_string(), rows))
}

impl Ctx<'_> {
    /// The manipulation tables. `[goal]` first: it fixes the goal vector's length, which
    /// `goal[...]` selectors and `desired = "goal"` terms then use.
    pub(super) fn manipulation(&mut self) -> Manipulation {
        let goal = self.spec.goal.clone().and_then(|s| self.goal_table(&s));
        let init = self.spec.init.clone().and_then(|s| self.init(&s));
        let end_effector = self
            .spec
            .end_effector
            .clone()
            .and_then(|s| self.end_effector(&s));
        let mut hold = vec![];
        for s in self.spec.hold.clone() {
            if let Some(h) = self.hold(&s) {
                hold.push(h);
            }
        }
        let m = Manipulation {
            init,
            end_effector,
            hold,
            goal,
        };
        self.records = m
            .init
            .as_ref()
            .map(|i| {
                i.records
                    .iter()
                    .map(|r| (r.name.clone(), r.offset, r.source.len()))
                    .collect()
            })
            .unwrap_or_default();
        m
    }

    fn goal_table(&mut self, s: &Section) -> Option<GoalTable> {
        if let Some(t) = s.get("parts") {
            return self.goal_table_of_parts(s, t);
        }
        for key in [
            "in_play",
            "threshold",
            "norm",
            "remove_done",
            "terminate_when_done",
        ] {
            if let Some(v) = s.get(key) {
                self.d.push(misfit(
                    &v.loc,
                    format!("[goal] {key} applies to a goal of parts"),
                    "expected it beside [goal.parts], or remove it",
                ));
            }
        }
        let Some(v) = s.get("achieved") else {
            self.d.push(
                Diagnostic::new(Code::E0103, "missing `achieved` in [goal]")
                    .at(s.name_loc.clone())
                    .label("expected achieved = a selector, e.g. \"site_xpos[grip]\""),
            );
            return None;
        };
        let achieved = self.selection(v, "achieved")?;
        if achieved.is_empty() || achieved.field == Field::Goal {
            self.d.push(misfit(
                &v.loc,
                format!(
                    "[goal] achieved `{}` selects no simulation element",
                    achieved.text
                ),
                "expected a selector of the simulation, e.g. \"site_xpos[grip]\"",
            ));
            return None;
        }
        self.goal_dim = Some((achieved.len(), v.loc.clone()));
        let marker = match s.get("marker") {
            None => None,
            Some(m) => {
                let body = self.body_name(m, "[goal] marker")?;
                if achieved.len() != 3 {
                    self.d.push(misfit(
                        &m.loc,
                        format!(
                            "[goal] marker: the goal has {} elements; a marker body takes a 3-D goal",
                            achieved.len()
                        ),
                        "expected an `achieved` of 3 elements (a position)",
                    ));
                    return None;
                }
                Some(body)
            }
        };
        let marker_site = match s.get("marker_site") {
            None => None,
            Some(m) if achieved.len() != 3 => {
                self.d.push(misfit(
                    &m.loc,
                    format!(
                        "[goal] marker_site: the goal has {} elements; a marker site takes a 3-D goal",
                        achieved.len()
                    ),
                    "expected an `achieved` of 3 elements (a position)",
                ));
                return None;
            }
            Some(m) => Some(self.site_id(m, "[goal] marker_site")?),
        };
        Some(GoalTable {
            achieved,
            marker,
            marker_site,
            parts: None,
        })
    }

    /// `[goal]` with `parts`: the achieved goal is the parts' selections end to end.
    fn goal_table_of_parts(&mut self, s: &Section, t: &Val) -> Option<GoalTable> {
        for key in ["achieved", "marker", "marker_site"] {
            if let Some(v) = s.get(key) {
                self.d.push(misfit(
                    &v.loc,
                    format!("[goal] {key} does not apply to a goal of parts"),
                    "each part names what it achieves",
                ));
            }
        }
        let (achieved, parts) = self.goal_parts(s, t)?;
        self.goal_dim = Some((achieved.len(), t.loc.clone()));
        self.goal_parts = parts.parts.len();
        Some(GoalTable {
            achieved,
            marker: None,
            marker_site: None,
            parts: Some(parts),
        })
    }

    /// `goal`, `goal[i]`, `goal[a:b]`: elements of the env-held goal vector.
    pub(super) fn goal_selection(&mut self, text: &str, loc: &Location) -> Option<Selection> {
        let dim = self.goal_dim.as_ref().map(|(n, _)| *n);
        match name_and_rows(text, |n| (n == "goal").then_some(dim).flatten()) {
            Ok((_, rows)) => Some(Selection {
                field: Field::Goal,
                names: rows.iter().map(|i| format!("goal[{i}]")).collect(),
                indices: rows,
                text: text.trim().to_string(),
            }),
            Err(why) => {
                let why = if dim.is_none() {
                    "the spec has no [goal] table (it fixes the goal vector's length)".to_string()
                } else {
                    why
                };
                self.d.push(misfit(
                    loc,
                    format!("cannot select `{}`: {why}", text.trim()),
                    "expected goal, goal[i] or goal[a:b]",
                ));
                None
            }
        }
    }

    /// A reset step's `around = "record[...]"`: indices into the flat record vector, as many as
    /// the step's target has elements.
    pub(super) fn around(&mut self, v: &Val, n: usize, what: &str) -> Option<Vec<usize>> {
        let Some(text) = v.as_str() else {
            self.d
                .push(v.type_error("around", "the name of an [init] record, e.g. \"grip[0:2]\""));
            return None;
        };
        let records = self.records.clone();
        let found = name_and_rows(text, |name| {
            records.iter().find(|r| r.0 == name).map(|r| r.2)
        });
        match found {
            Ok((name, rows)) if rows.len() == n => {
                let off = records.iter().find(|r| r.0 == name).map_or(0, |r| r.1);
                Some(rows.into_iter().map(|i| off + i).collect())
            }
            Ok((_, rows)) => {
                self.d.push(misfit(
                    &v.loc,
                    format!(
                        "{what}: `around` `{text}` has {} elements but the target has {n}",
                        rows.len()
                    ),
                    "expected as many elements as the target",
                ));
                None
            }
            Err(why) => {
                let names: Vec<String> = records.iter().map(|r| r.0.clone()).collect();
                self.d.push(
                    misfit(
                        &v.loc,
                        format!("{what}: `around` `{text}`: {why}"),
                        "expected an [init] record, e.g. \"grip\" or \"grip[0:2]\"",
                    )
                    .help_opt(suggest(
                        text.split('[').next().unwrap_or(""),
                        names.iter().map(String::as_str),
                    )),
                );
                None
            }
        }
    }

    /// A reset step's `around` and `probability`.
    pub(super) fn reset_placement(
        &mut self,
        s: &Section,
        n: usize,
    ) -> (Option<Vec<usize>>, Option<f64>) {
        let around = s
            .get("around")
            .and_then(|v| self.around(v, n, &format!("[reset.{}]", s.name)));
        let probability = s.get("probability").and_then(|v| {
            let p = self.num(v, "probability")?;
            if (0.0..=1.0).contains(&p) {
                Some(p)
            } else {
                self.d.push(
                    Diagnostic::new(
                        Code::E0105,
                        format!("[reset.{}]: probability {p} is outside [0, 1]", s.name),
                    )
                    .at(v.loc.clone())
                    .label("expected a probability in [0, 1]"),
                );
                None
            }
        });
        (around, probability)
    }

    /// A list of numbers (or numeric parameters) of length `n`.
    /// Each within `limits::MAX_COORDINATE` (a pose, an offset, a quaternion).
    pub(super) fn number_list(&mut self, v: &Val, what: &str, n: usize) -> Option<Vec<f64>> {
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a
                .iter()
                .map(|x| {
                    let y = self.num(x, what)?;
                    self.within(x, y, what, crate::limits::MAX_COORDINATE)
                })
                .collect(),
            _ => {
                self.d
                    .push(v.type_error(what, &format!("an array of {n} numbers")));
                None
            }
        }
    }

    fn joint_qpos(&mut self, name: &str, at: &Location, what: &str) -> Option<(usize, JointKind)> {
        match self.model.joint(name) {
            Some(j) => Some((j.qposadr, j.kind)),
            None => {
                let names: Vec<&str> = self.model.joints.iter().map(|j| j.name.as_str()).collect();
                self.d.push(
                    misfit(
                        at,
                        format!("{what}: the model has no joint `{name}`"),
                        "expected a joint of the model",
                    )
                    .help_opt(suggest(name, names.iter().copied())),
                );
                None
            }
        }
    }

    fn site_id(&mut self, v: &Val, what: &str) -> Option<usize> {
        let Some(name) = v.as_str() else {
            self.d.push(v.type_error(what, "a site name"));
            return None;
        };
        let found = self.model.sites.iter().position(|s| s == name);
        if found.is_none() {
            self.d.push(
                misfit(
                    &v.loc,
                    format!("{what}: the model has no site `{name}`"),
                    "expected a site of the model",
                )
                .help_opt(suggest(name, self.model.sites.iter().map(String::as_str))),
            );
        }
        found
    }

    fn body_name(&mut self, v: &Val, what: &str) -> Option<String> {
        let Some(name) = v.as_str() else {
            self.d.push(v.type_error(what, "a body name"));
            return None;
        };
        if self.model.body_id(name).is_none() {
            self.d.push(
                misfit(
                    &v.loc,
                    format!("{what}: the model has no body `{name}`"),
                    "expected a (mocap) body of the model",
                )
                .help_opt(suggest(name, self.model.bodies.iter().map(String::as_str))),
            );
            return None;
        }
        Some(name.to_string())
    }

    fn init(&mut self, s: &Section) -> Option<Init> {
        let qpos = self.init_qpos(s);
        let reset_welds = match s.get("reset_welds") {
            Some(v) => self.flag(v, "reset_welds").unwrap_or(false),
            None => false,
        };
        let reset_data = match s.get("reset_data") {
            Some(v) => self.flag(v, "reset_data").unwrap_or(true),
            None => true,
        };
        let mocap = self.init_mocap(s);
        let settle_steps = self.settle_steps(s);
        let records = self.init_records(s);
        // Kept even when a part failed (its error is already reported): the records it did
        // resolve spare the reset steps that use them a follow-on error.
        Some(Init {
            qpos,
            reset_welds,
            mocap,
            settle_steps,
            records,
            reset_data,
        })
    }

    /// `[init] qpos = { joint = value(s) }`: the rows that resolve, as (joint, qpos address,
    /// values).
    fn init_qpos(&mut self, s: &Section) -> Vec<(String, usize, Vec<f64>)> {
        let mut qpos = vec![];
        if let Some(v) = s.get("qpos") {
            match v.as_table() {
                Some(rows) => {
                    for e in rows {
                        let Some((adr, kind)) = self.joint_qpos(&e.key, &e.key_loc, "[init] qpos")
                        else {
                            continue;
                        };
                        let n = kind.nq();
                        let values = match &e.value.kind {
                            ValKind::Array(_) => self.number_list(&e.value, "[init] qpos", n),
                            _ if n == 1 => self.num(&e.value, "[init] qpos").and_then(|x| {
                                self.within(
                                    &e.value,
                                    x,
                                    "[init] qpos",
                                    crate::limits::MAX_COORDINATE,
                                )
                                .map(|x| vec![x])
                            }),
                            _ => self.number_list(&e.value, "[init] qpos", n),
                        };
                        if let Some(values) = values {
                            qpos.push((e.key.clone(), adr, values));
                        }
                    }
                }
                None => {
                    self.d
                        .push(v.type_error("[init] qpos", "a table joint = value(s)"));
                }
            }
        }
        qpos
    }

    /// `[init] mocap`: one placement, or an array of them.
    fn init_mocap(&mut self, s: &Section) -> Vec<MocapPlacement> {
        let mut mocap = vec![];
        if let Some(v) = s.get("mocap") {
            let tables: Vec<&[crate::value::Entry]> = match &v.kind {
                ValKind::Table(t) => vec![t.as_slice()],
                ValKind::Array(a) => a.iter().filter_map(Val::as_table).collect(),
                _ => vec![],
            };
            if tables.is_empty() {
                self.d.push(v.type_error(
                    "[init] mocap",
                    "{ body, site, offset, lift, quat } or an array of them",
                ));
            }
            mocap.extend(
                tables
                    .into_iter()
                    .filter_map(|t| self.mocap_placement(t, &v.loc)),
            );
        }
        mocap
    }

    /// `[init] settle_steps`: a count of control steps, bounded by the physics steps they take
    /// (0 by default).
    fn settle_steps(&mut self, s: &Section) -> u32 {
        // Bounded in physics steps: every env of a vector env runs them when it is made.
        let most = crate::limits::MAX_SETTLE_PHYSICS_STEPS / u64::from(self.frame_skip.max(1));
        match s.get("settle_steps") {
            None => 0,
            Some(v) => match v.kind {
                ValKind::Int(n) if n >= 0 && (n as u64) <= most => n as u32,
                _ => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0110,
                            format!(
                                "[init] settle_steps must be a step count from 0 to {most} ({} physics steps at frame_skip {})",
                                crate::limits::MAX_SETTLE_PHYSICS_STEPS,
                                self.frame_skip
                            ),
                        )
                        .at(v.loc.clone())
                        .label(format!("expected a whole number from 0 to {most}")),
                    );
                    0
                }
            },
        }
    }

    /// `[init] record = { name = selector }`: named selections, each at its offset in the flat
    /// record vector.
    fn init_records(&mut self, s: &Section) -> Vec<Record> {
        let mut records = vec![];
        let mut offset = 0;
        if let Some(v) = s.get("record") {
            match v.as_table() {
                Some(rows) => {
                    for e in rows {
                        let Some(source) = self.selection(&e.value, "[init] record") else {
                            continue;
                        };
                        if source.field == Field::Goal {
                            self.d.push(misfit(
                                &e.value.loc,
                                "[init] record cannot read the goal vector".into(),
                                "expected a selector of the simulation",
                            ));
                            continue;
                        }
                        let n = source.len();
                        records.push(Record {
                            name: e.key.clone(),
                            source,
                            offset,
                        });
                        offset += n;
                    }
                }
                None => {
                    self.d
                        .push(v.type_error("[init] record", "a table name = selector"));
                }
            }
        }
        records
    }

    fn mocap_placement(
        &mut self,
        t: &[crate::value::Entry],
        at: &Location,
    ) -> Option<MocapPlacement> {
        let get = |k: &str| t.iter().find(|e| e.key == k).map(|e| &e.value);
        for e in t {
            if !MOCAP_KEYS.contains(&e.key.as_str()) {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("unknown key `{}` in [init] mocap", e.key),
                    )
                    .at(e.key_loc.clone())
                    .label(format!("expected one of: {}", MOCAP_KEYS.join(", ")))
                    .help_opt(suggest(&e.key, MOCAP_KEYS.iter().copied())),
                );
            }
        }
        let Some(body) = get("body") else {
            self.d.push(
                Diagnostic::new(Code::E0103, "missing `body` in [init] mocap")
                    .at(at.clone())
                    .label("expected body = the mocap body's name"),
            );
            return None;
        };
        let body = self.body_name(body, "[init] mocap body");
        let site = match get("site") {
            Some(v) => Some(self.site_id(v, "[init] mocap site")?),
            None => None,
        };
        let offset = match get("offset") {
            Some(v) => self.number_list(v, "[init] mocap offset", 3)?,
            None => vec![0.0; 3],
        };
        let lift = match get("lift") {
            Some(v) => {
                let x = self.num(v, "[init] mocap lift")?;
                self.within(v, x, "[init] mocap lift", crate::limits::MAX_COORDINATE)?
            }
            None => 0.0,
        };
        let quat = match get("quat") {
            Some(v) => self.number_list(v, "[init] mocap quat", 4)?,
            None => vec![1.0, 0.0, 0.0, 0.0],
        };
        Some(MocapPlacement {
            body: body?,
            site,
            // numpy's `np.array([x, y, z + lift])`: the sum is rounded before the site is added.
            offset: [offset[0], offset[1], offset[2] + lift],
            quat: [quat[0], quat[1], quat[2], quat[3]],
        })
    }

    fn end_effector(&mut self, s: &Section) -> Option<EndEffector> {
        let Some(mv) = s.get("mocap") else {
            self.d.push(
                Diagnostic::new(Code::E0103, "missing `mocap` in [end_effector]")
                    .at(s.name_loc.clone())
                    .label("expected mocap = the mocap body welded to the robot"),
            );
            return None;
        };
        let mocap = self.body_name(mv, "[end_effector] mocap");
        let scale = match s.get("scale") {
            Some(v) => {
                let x = self.num(v, "[end_effector] scale")?;
                self.within(v, x, "[end_effector] scale", crate::limits::MAX_MAGNITUDE)?
            }
            None => 1.0,
        };
        let rotation = match s.get("rotation") {
            Some(v) => self.number_list(v, "[end_effector] rotation", 4)?,
            None => vec![0.0; 4],
        };
        let gripper_action = match s.get("gripper_action") {
            Some(v) => self.flag(v, "gripper_action")?,
            None => s.get("gripper").is_some(),
        };
        let mut gripper = vec![];
        if let Some(v) = s.get("gripper") {
            let Some(names) = v.as_array() else {
                self.d
                    .push(v.type_error("[end_effector] gripper", "an array of actuator names"));
                return None;
            };
            for n in names {
                let Some(name) = n.as_str() else {
                    self.d
                        .push(n.type_error("[end_effector] gripper", "an actuator name"));
                    return None;
                };
                match self.model.actuators.iter().position(|a| a.name == name) {
                    Some(i) => gripper.push(i),
                    None => {
                        self.d.push(
                            misfit(
                                &n.loc,
                                format!(
                                    "[end_effector] gripper: the model has no actuator `{name}`"
                                ),
                                "expected an actuator of the model",
                            )
                            .help_opt(suggest(
                                name,
                                self.model.actuators.iter().map(|a| a.name.as_str()),
                            )),
                        );
                        return None;
                    }
                }
            }
            if !gripper_action && !gripper.is_empty() {
                self.d.push(misfit(
                    &v.loc,
                    "[end_effector] names gripper actuators but gripper_action is false".into(),
                    "expected gripper_action = true (the action's fourth element drives them)",
                ));
                return None;
            }
        }
        let block_gripper = match s.get("block_gripper") {
            Some(v) => self.flag(v, "block_gripper")?,
            None => false,
        };
        Some(EndEffector {
            mocap: mocap?,
            scale,
            rotation: [rotation[0], rotation[1], rotation[2], rotation[3]],
            gripper_action,
            gripper,
            block_gripper,
        })
    }

    fn hold(&mut self, s: &Section) -> Option<Hold> {
        let enabled = match s.get("when") {
            Some(w) => self.flag(w, "when").unwrap_or(true),
            None => true,
        };
        let v = s.get("joints")?;
        let Some(names) = v.as_array() else {
            self.d
                .push(v.type_error("[hold] joints", "an array of joint names"));
            return None;
        };
        let mut qpos = vec![];
        for n in names {
            let Some(name) = n.as_str() else {
                self.d.push(n.type_error("[hold] joints", "a joint name"));
                return None;
            };
            let (adr, kind) = self.joint_qpos(name, &n.loc, &format!("[hold.{}]", s.name))?;
            if !matches!(kind, JointKind::Hinge | JointKind::Slide) {
                self.d.push(misfit(
                    &n.loc,
                    format!("[hold.{}]: `{name}` is not a hinge or slide joint", s.name),
                    "expected a hinge or slide joint (one qpos each)",
                ));
                return None;
            }
            qpos.push(adr);
        }
        let value = match s.get("value") {
            Some(v) => {
                let x = self.num(v, "[hold] value")?;
                self.within(v, x, "[hold] value", crate::limits::MAX_COORDINATE)?
            }
            None => 0.0,
        };
        enabled.then(|| Hold {
            name: s.name.clone(),
            qpos,
            value,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::name_and_rows;

    #[test]
    fn rows_of_a_named_vector() {
        let n = |name: &str| (name == "grip").then_some(3);
        assert_eq!(name_and_rows("grip", n).unwrap().1, vec![0, 1, 2]);
        assert_eq!(name_and_rows("grip[0:2]", n).unwrap().1, vec![0, 1]);
        assert_eq!(name_and_rows("grip[-1]", n).unwrap().1, vec![2]);
        assert_eq!(name_and_rows("grip[1:99]", n).unwrap().1, vec![1, 2]);
        assert!(name_and_rows("grip[3]", n).is_err());
        assert!(name_and_rows("grap", n).is_err());
    }
}
