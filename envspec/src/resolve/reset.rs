//! `[reset.*]`: the steps that draw the initial state of an episode, in declared order (the
//! kinds with their own tables are in `keyframes`, `terrain` and `manipulation_reset`).

use crate::diagnostic::{Code, Diagnostic, suggest};
use crate::ir::*;
use crate::limits;
use crate::mjcf::JointKind;
use crate::selector::{Field, Selection};
use crate::syntax::{Section, Spec};
use crate::value::{Val, ValKind};

use super::Ctx;

/// W0171: a reset step that puts a position (a slide joint, a free joint's x, y, z, the goal
/// vector) further than `limits::PLAUSIBLE_DISTANCE` from where it is drawn: centimetres written
/// for metres, most likely.
pub(super) fn far_draws(spec: &Spec, r: &ResolvedSpec) -> Vec<Diagnostic> {
    let positional = |s: &Selection, k: usize| -> bool {
        match s.field {
            Field::Goal => true,
            Field::Qpos => r.model.joints.iter().any(|j| {
                let i = s.indices[k];
                match j.kind {
                    JointKind::Slide => j.qposadr == i,
                    JointKind::Free => (j.qposadr..j.qposadr + 3).contains(&i),
                    _ => false,
                }
            }),
            _ => false,
        }
    };
    let mut out = vec![];
    for step in &r.reset {
        let widest = (0..step.target.len())
            .filter(|&k| positional(&step.target, k))
            .map(|k| match &step.dist {
                Distribution::Uniform { low, high } => low[k].abs().max(high[k].abs()),
                Distribution::Values { values } => values[k].abs(),
                Distribution::Constant { value } if step.around.is_some() || !step.set => {
                    value.abs()
                }
                _ => 0.0,
            })
            .fold(0.0, f64::max);
        if widest > limits::PLAUSIBLE_DISTANCE {
            let at = spec
                .reset
                .iter()
                .find(|s| s.name == step.name)
                .map(|s| s.name_loc.clone());
            out.push(
                Diagnostic::new(
                    Code::W0171,
                    format!(
                        "[reset.{}] moves a position by up to {widest} m (more than {} m)",
                        step.name,
                        limits::PLAUSIBLE_DISTANCE
                    ),
                )
                .at_opt(at)
                .label("a draw this far puts the body (or goal) far outside a robot's workspace")
                .help("MuJoCo lengths are metres: 15 cm is 0.15"),
            );
        }
    }
    out
}

/// Why no draw of `dist` (n values) can meet `until`, if that is certain: a norm below a bound ≤ 0,
/// a uniform box whose nearest point is not below the bound, or whose farthest is not above it.
fn unmet(dist: &Distribution, n: usize, until: Until) -> Option<String> {
    let norm = |f: &dyn Fn(usize) -> f64| (0..n).map(|i| f(i) * f(i)).sum::<f64>().sqrt();
    // The smallest and largest norm a draw can have.
    let (lo, hi) = match dist {
        Distribution::Uniform { low, high } => (
            norm(&|i| {
                if low[i] <= 0.0 && 0.0 <= high[i] {
                    0.0
                } else {
                    low[i].abs().min(high[i].abs())
                }
            }),
            norm(&|i| low[i].abs().max(high[i].abs())),
        ),
        Distribution::Normal { scale } if *scale == 0.0 => (0.0, 0.0),
        Distribution::Normal { .. } => (0.0, f64::INFINITY),
        Distribution::Constant { value } => {
            let v = norm(&|_| *value);
            (v, v)
        }
        Distribution::Values { values } => {
            let v = norm(&|i| values[i]);
            (v, v)
        }
        // (no `resample_until` on these kinds)
        Distribution::Keyframe { .. }
        | Distribution::RootPose { .. }
        | Distribution::Meet(_)
        | Distribution::Rotation(_)
        | Distribution::UnitQuaternion
        | Distribution::Settle(_)
        | Distribution::TerrainOrigin { .. } => (0.0, f64::INFINITY),
    };
    match until {
        Until::NormBelow(x) if x <= 0.0 => Some(format!("a norm is never below {x}")),
        Until::NormBelow(x) if lo >= x => Some(format!(
            "the smallest norm a draw can have is {lo}, not below {x}"
        )),
        Until::NormAbove(x) if hi <= x => Some(format!(
            "the largest norm a draw can have is {hi}, not above {x}"
        )),
        Until::MinDistance(x) if hi < x => Some(format!(
            "the largest distance a draw can have is {hi}, not {x} or more"
        )),
        _ => None,
    }
}

impl Ctx<'_> {
    pub(super) fn reset(&mut self, terrain: Option<&crate::ir::Terrain>) -> Vec<ResetStep> {
        let mut out = vec![];
        // One tile per episode: a second spawn would redraw and overwrite the first.
        let mut spawn: Option<&str> = None;
        for s in &self.spec.reset {
            if s.kind("") == "terrain_origin" {
                if let Some(first) = spawn {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0162,
                            format!(
                                "[reset.{}] is a second terrain_origin reset (the first is [reset.{first}])",
                                s.name
                            ),
                        )
                        .at(s.name_loc.clone())
                        .label("expected one terrain_origin reset: each episode spawns on one tile"),
                    );
                    continue;
                }
                spawn = Some(&s.name);
                out.extend(self.terrain_origin(s, terrain));
                continue;
            }
            if let Some(step) = self.keyframe_reset(s) {
                out.extend(step);
                continue;
            }
            if s.kind("") == "settle" {
                out.extend(self.settle(s));
                continue;
            }
            out.extend(self.drawn_reset(s));
        }
        out
    }

    /// A reset step that draws its target; None when `when` switches it off, or when it has an
    /// error (reported).
    fn drawn_reset(&mut self, s: &Section) -> Option<ResetStep> {
        let enabled = match s.get("when") {
            Some(w) => self.flag(w, "when").unwrap_or(true),
            None => true,
        };
        let target = self.reset_target(s)?;
        let n = target.len();
        let kind = s.kind("");
        let dist = self.reset_dist(s, kind, n)?;
        if self.draw_too_large(s, &dist) || self.empty_uniform(s, &dist, n) {
            return None;
        }
        let set = self.reset_mode(s, kind);
        let (around, probability) = self.reset_placement(s, n);
        let resample_until = s
            .get("resample_until")
            .and_then(|v| self.resample_until(s, v, &dist, n));
        if !enabled {
            return None;
        }
        Some(ResetStep {
            name: s.name.clone(),
            doc: s.doc(),
            target,
            dist,
            set,
            resample_until,
            around,
            probability,
        })
    }

    /// A reset step's `target`: a selection of qpos, qvel, goal, mocap_pos or mocap_quat (E0107
    /// otherwise).
    fn reset_target(&mut self, s: &Section) -> Option<Selection> {
        let target = self.sel_key(s, "target")?;
        if !matches!(
            target.field,
            Field::Qpos | Field::Qvel | Field::Goal | Field::MocapPos | Field::MocapQuat
        ) {
            self.d.push(
                Diagnostic::new(
                    Code::E0107,
                    format!(
                        "reset target `{}` is not qpos, qvel, goal, mocap_pos or mocap_quat",
                        target.text
                    ),
                )
                .at(s
                    .get("target")
                    .expect("`target` was read just above")
                    .loc
                    .clone())
                .label("expected a selection of qpos, qvel, goal, mocap_pos or mocap_quat"),
            );
            return None;
        }
        Some(target)
    }

    /// E0110 when a draw can be beyond `limits::MAX_COORDINATE`; true when reported.
    fn draw_too_large(&mut self, s: &Section, dist: &Distribution) -> bool {
        let widest = match dist {
            Distribution::Uniform { low, high } => {
                low.iter().chain(high).fold(0.0, |m: f64, x| m.max(x.abs()))
            }
            Distribution::Normal { scale } => scale.abs(),
            Distribution::Constant { value } => value.abs(),
            Distribution::Values { values } => values.iter().fold(0.0, |m: f64, x| m.max(x.abs())),
            Distribution::Meet(m) => m
                .offset
                .iter()
                .fold(m.scale.abs() + m.gap.abs(), |a, x| a.max(x.abs())),
            Distribution::Keyframe { .. }
            | Distribution::RootPose { .. }
            | Distribution::Rotation(_)
            | Distribution::UnitQuaternion
            | Distribution::Settle(_)
            | Distribution::TerrainOrigin { .. } => 0.0,
        };
        if widest > limits::MAX_COORDINATE {
            let at = ["scale", "low", "high", "value"]
                .iter()
                .find_map(|k| s.get(k))
                .map(|v| v.loc.clone())
                .unwrap_or(s.name_loc.clone());
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!("[reset.{}]: a draw as large as {widest:e} is beyond envc's limit of {:e}", s.name, limits::MAX_COORDINATE),
                )
                .at(at)
                .label("expected a distribution within ±1e6")
                .help("MuJoCo takes seconds per step from such a state, or resets it; see docs/limits.md"),
            );
            return true;
        }
        false
    }

    /// E0105 when a uniform's bounds are empty or infinite; true when reported.
    fn empty_uniform(&mut self, s: &Section, dist: &Distribution, n: usize) -> bool {
        if let Distribution::Uniform { low, high } = dist {
            // numpy refuses these (and so would reset); report them with the spec's location.
            if let Some(i) = (0..n).find(|&i| {
                low[i].partial_cmp(&high[i]).is_none_or(|o| o.is_gt())
                    || !(high[i] - low[i]).is_finite()
            }) {
                let at = s
                    .get("scale")
                    .or(s.get("low"))
                    .map(|v| v.loc.clone())
                    .unwrap_or(s.name_loc.clone());
                self.d.push(
                    Diagnostic::new(
                        Code::E0105,
                        format!(
                            "[reset.{}]: uniform bounds [{}, {}) are empty or infinite",
                            s.name, low[i], high[i]
                        ),
                    )
                    .at(at)
                    .label("expected low <= high with a finite width (scale >= 0)"),
                );
                return true;
            }
        }
        false
    }

    /// A reset step's `mode`: "set" (true: the draw is the value) or "add" (the draw is added to
    /// the initial value); a constant sets by default, the others add.
    fn reset_mode(&mut self, s: &Section, kind: &str) -> bool {
        match s.get("mode") {
            None => kind == "constant",
            Some(m) => match m.as_str() {
                Some("add") => false,
                Some("set") => true,
                _ => {
                    self.d.push(
                        Diagnostic::new(Code::E0104, "unknown reset mode")
                            .at(m.loc.clone())
                            .label("expected \"add\" (initial value + draw) or \"set\" (the draw)"),
                    );
                    false
                }
            },
        }
    }

    /// A reset step's `resample_until` (read from `v`): a condition some draw of `dist` can meet.
    fn resample_until(
        &mut self,
        s: &Section,
        v: &Val,
        dist: &Distribution,
        n: usize,
    ) -> Option<Until> {
        let until = self.until(v)?;
        if matches!(until, Until::MinDistance(_)) && s.get("around").is_none() {
            self.d.push(
                Diagnostic::new(
                    Code::E0170,
                    format!("[reset.{}]: min_distance needs `around`", s.name),
                )
                .at(v.loc.clone())
                .label("min_distance is measured from the `around` point")
                .help("add around = \"<record>\" (an `[init] record`)"),
            );
            return None;
        }
        match unmet(dist, n, until) {
            None => Some(until),
            Some(why) => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0110,
                        format!("[reset.{}]: resample_until can never be met: {why}", s.name),
                    )
                    .at(v.loc.clone())
                    .label("expected a condition some draw of the distribution meets")
                    .help("the reference would redraw for ever at reset"),
                );
                None
            }
        }
    }

    /// The distribution of a `uniform`, `normal` or `constant` reset step of `n` elements.
    fn reset_dist(&mut self, s: &Section, kind: &str, n: usize) -> Option<Distribution> {
        Some(match kind {
            "uniform" => {
                if let Some(scale) = s.get("scale") {
                    let sc = self.num(scale, "scale")?;
                    Distribution::Uniform {
                        low: vec![-sc; n],
                        high: vec![sc; n],
                    }
                } else {
                    let low = self.bound(s, "low", n);
                    let high = self.bound(s, "high", n);
                    Distribution::Uniform {
                        low: low?,
                        high: high?,
                    }
                }
            }
            "normal" => {
                let scale = s
                    .get("scale")
                    .map(|v| self.num(v, "scale"))
                    .unwrap_or(Some(1.0))?;
                Distribution::Normal { scale }
            }
            "constant" => match s.get("value") {
                Some(v) if matches!(v.kind, ValKind::Array(_)) => Distribution::Values {
                    values: self.bound(s, "value", n)?,
                },
                v => Distribution::Constant {
                    value: v.map(|v| self.num(v, "value")).unwrap_or(Some(0.0))?,
                },
            },
            "meet" => return self.meet(s, n),
            "rotation" | "unit_quaternion" => return self.rotation(s, kind, n),
            _ => return None,
        })
    }

    /// `low`/`high` of a uniform: one number for all elements, or one per element.
    fn bound(&mut self, s: &Section, key: &str, n: usize) -> Option<Vec<f64>> {
        let Some(v) = s.get(key) else {
            self.d.push(
                Diagnostic::new(
                    Code::E0103,
                    format!("missing `{key}` in [reset.{}]", s.name),
                )
                .at(s.name_loc.clone())
                .label("expected `scale`, or both `low` and `high`"),
            );
            return None;
        };
        match &v.kind {
            ValKind::Array(a) if a.len() == n => a.iter().map(|x| self.num(x, key)).collect(),
            ValKind::Array(a) => {
                self.d.push(v.type_error(
                    key,
                    &format!(
                        "a number or an array of {n} numbers (one per target element; {} given)",
                        a.len()
                    ),
                ));
                None
            }
            _ => self.num(v, key).map(|x| vec![x; n]),
        }
    }

    fn until(&mut self, v: &Val) -> Option<Until> {
        let t = v.as_table().filter(|t| t.len() == 1);
        let Some(e) = t.map(|t| &t[0]) else {
            self.d.push(v.type_error(
                "resample_until",
                "{ norm_below = x }, { norm_above = x } or { min_distance = x }",
            ));
            return None;
        };
        let x = self.num(&e.value, &e.key)?;
        match e.key.as_str() {
            "norm_below" => Some(Until::NormBelow(x)),
            "norm_above" => Some(Until::NormAbove(x)),
            "min_distance" => Some(Until::MinDistance(x)),
            k => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0101,
                        format!("unknown condition `{k}` in resample_until"),
                    )
                    .at(e.key_loc.clone())
                    .label("expected norm_below, norm_above or min_distance")
                    .help_opt(suggest(k, ["norm_below", "norm_above", "min_distance"])),
                );
                None
            }
        }
    }
}
