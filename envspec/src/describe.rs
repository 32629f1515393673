//! Human-readable formulas for the IR: one wording shared by `envc show`, generated rustdoc and
//! `envc diff`, so a term reads the same everywhere.

use crate::ir::*;
use crate::manipulation::{GoalParts, GoalTable};
use crate::selector::Selection;
use crate::value::format_float;

fn num(x: f64) -> String {
    format_float(x)
}

fn range(lo: f64, hi: f64) -> String {
    format!("[{}, {}]", num(lo), num(hi))
}

fn sel(s: &Selection) -> String {
    s.text.clone()
}

/// A selection with its elements' names when the text does not say them (`qpos[7:10]`
/// → `qpos[7:10] (qpos[finger_l], qpos[finger_r], qpos[goal_x])`), so an index that is off by
/// two shows; long selections are cut after 8 names.
fn named(s: &Selection) -> String {
    if s.names.len() == 1 && s.names[0] == s.text {
        return s.text.clone();
    }
    let shown: Vec<&str> = s.names.iter().take(8).map(String::as_str).collect();
    let more = if s.names.len() > 8 {
        format!(", … {} more", s.names.len() - 8)
    } else {
        String::new()
    };
    format!("{} ({}{more})", s.text, shown.join(", "))
}

/// The kernel of a reward term, without weight and sign, e.g. `Σ clip(cfrc_ext, [-1.0, 1.0])²`.
pub fn kernel(t: &RewardTerm) -> String {
    format!("{}{}", kernel_alone(t), gates(t))
}

/// `, only if …`, `, unless …` of a gated term (empty for others).
fn gates(t: &RewardTerm) -> String {
    let mut g = String::new();
    if !t.only_if.is_empty() {
        g = format!(", only if {}", conditions(&t.only_if));
    }
    if !t.unless.is_empty() {
        g = format!("{g}, unless {}", conditions(&t.unless));
    }
    g
}

/// Conditions joined by `and`, e.g. `qpos[door_hinge] > 0.2`.
pub fn conditions(cs: &[crate::ir::Condition]) -> String {
    use crate::ir::Quantity;
    let quantity = |q: &Quantity| match q {
        Quantity::Value { source, minus } => match minus {
            Some(m) => format!("{} − {}", sel(source), sel(m)),
            None => sel(source),
        },
        Quantity::Norm { source, minus } => match minus {
            Some(m) => format!("‖{} − {}‖₂", sel(source), sel(m)),
            None => format!("‖{}‖₂", sel(source)),
        },
    };
    cs.iter()
        .map(|c| {
            format!(
                "{} {} {}",
                quantity(&c.quantity),
                crate::conditions::op_text(c.op),
                num(c.value)
            )
        })
        .collect::<Vec<_>>()
        .join(" and ")
}

fn kernel_alone(t: &RewardTerm) -> String {
    match &t.kind {
        TermKind::Velocity { source } => format!("({0}_after − {0}_before) / dt", sel(source)),
        TermKind::Healthy if t.paid_when_unhealthy => "1 (paid even when unhealthy)".into(),
        TermKind::Healthy => "1 if healthy else 0".into(),
        TermKind::SumSquares {
            source,
            clip_input,
            clip,
        } => {
            let x = match clip_input {
                Some((lo, hi)) => format!("clip({}, {})", sel(source), range(*lo, *hi)),
                None => sel(source),
            };
            let s = format!("Σ {x}²");
            match clip {
                Some((lo, hi)) => format!("clip(weight × {s}, {})", range(*lo, *hi)),
                None => s,
            }
        }
        TermKind::Norm { source, minus } => match minus {
            Some(m) => format!("‖{} − {}‖₂", sel(source), sel(m)),
            None => format!("‖{}‖₂", sel(source)),
        },
        TermKind::WeightedSquare { source, target } => {
            format!(
                "(weight × ({0} − {1})) × ({0} − {1})",
                sel(source),
                num(*target)
            )
        }
        TermKind::Quadratic {
            source,
            coefs,
            targets,
        } => {
            let parts: Vec<String> = (0..source.len())
                .map(|i| {
                    let x = &source.names[i];
                    let d = if targets[i] == 0.0 {
                        x.clone()
                    } else {
                        format!("({x} − {})", num(targets[i]))
                    };
                    if coefs[i] == 1.0 {
                        format!("{d}²")
                    } else {
                        format!("{}·{d}²", num(coefs[i]))
                    }
                })
                .collect();
            // A sum in parentheses, so a cost's sign or a weight applies to all of it.
            if parts.len() > 1 {
                format!("({})", parts.join(" + "))
            } else {
                parts.join(" + ")
            }
        }
        TermKind::Value { source, divide_by } => match divide_by {
            Some(Divisor::Timestep) => format!("{} / timestep", sel(source)),
            Some(Divisor::Dt) => format!("{} / dt", sel(source)),
            None => sel(source),
        },
        TermKind::Constant => "1".into(),
        TermKind::GoalSparse(c) => format!("1 if {} else 0", goal_check(c)),
        TermKind::GoalDense(g) => format!("exp(−{})", goal_distance(g)),
        TermKind::GoalMissed(c) => format!(
            "1 if {} {} {} else 0",
            goal_distance(&c.distance),
            if c.strict { "≥" } else { ">" },
            num(c.threshold)
        ),
        TermKind::GoalDistance(g) => goal_distance(g),
        TermKind::GoalsMissed(cs) => format!("(1 if {} else 0) − 1", goal_checks(cs)),
        TermKind::PartsReached => "the number of [goal] parts still to complete reached now".into(),
        TermKind::Legged(l) => l.formula(),
    }
}

/// A goal distance, e.g. `‖qpos[0:2] − goal‖₂ (pairwise)`.
pub fn goal_distance(g: &GoalDistance) -> String {
    let desired = match &g.desired {
        Desired::Select(s) => sel(s),
        Desired::Goal => "goal".into(),
    };
    if g.norm == GoalNorm::Angle {
        return format!("angle({}, {desired})", sel(&g.achieved));
    }
    format!("‖{} − {desired}‖₂ ({})", sel(&g.achieved), g.norm.name())
}

/// A goal check, e.g. `‖qpos[0:2] − goal‖₂ (blas) ≤ 0.45`.
pub fn goal_check(c: &GoalCheck) -> String {
    let op = if c.strict { "<" } else { "≤" };
    format!("{} {op} {}", goal_distance(&c.distance), num(c.threshold))
}

/// Goal checks that must all hold, joined by "and".
pub fn goal_checks(cs: &[GoalCheck]) -> String {
    cs.iter().map(goal_check).collect::<Vec<_>>().join(" and ")
}

/// A `[termination.*]` condition.
pub fn termination(t: &Termination) -> String {
    format!("terminates when {}", goal_check(&t.reached))
}

/// The full contribution of a term to the reward, e.g. `−0.5 × Σ action²`.
pub fn term(t: &RewardTerm) -> String {
    let text = weighted(t);
    if t.before {
        format!("{text}  (on the state before the step)")
    } else {
        text
    }
}

fn weighted(t: &RewardTerm) -> String {
    let k = kernel(t);
    let sign = if t.cost { "−" } else { "+" };
    match &t.kind {
        // The clip wraps the weighted value; the weight is already inside the kernel text.
        TermKind::SumSquares { clip: Some(_), .. } => {
            format!("{sign}{k}  (weight {})", num(t.weight))
        }
        TermKind::Constant => format!("{sign}{}{}", num(t.weight), gates(t)),
        _ if t.weight == 1.0 => format!("{sign}{k}"),
        _ => format!("{sign}{} × {k}", num(t.weight)),
    }
}

/// The reward as a sum of term names with the grouping that decides rounding.
pub fn reward_sum(spec: &ResolvedSpec) -> String {
    fn go(n: &SumNode, spec: &ResolvedSpec, top: bool) -> String {
        match n {
            SumNode::Term(i) => spec.reward[*i].name.clone(),
            SumNode::Sum(c) => {
                let inner = c
                    .iter()
                    .map(|x| go(x, spec, false))
                    .collect::<Vec<_>>()
                    .join(" + ");
                if top || c.len() == 1 {
                    inner
                } else {
                    format!("({inner})")
                }
            }
        }
    }
    go(&spec.reward_sum, spec, true)
}

/// A health check, e.g. `0.7 ≤ qpos[1] ≤ 1e308 (every element)`.
pub fn check(c: &HealthCheck) -> String {
    let src = c.sources.iter().map(sel).collect::<Vec<_>>().join(", ");
    match c.kind {
        CheckKind::Finite => format!("every element of {src} is finite"),
        CheckKind::InRange {
            lo,
            hi,
            closed: true,
        } => format!("{} ≤ {src} ≤ {} (every element)", num(lo), num(hi)),
        CheckKind::InRange {
            lo,
            hi,
            closed: false,
        } => format!("{} < {src} < {} (every element)", num(lo), num(hi)),
        CheckKind::FailsIf { op, value } => {
            let op = match op {
                CmpOp::Lt => "<",
                CmpOp::Le => "≤",
                CmpOp::Gt => ">",
                CmpOp::Ge => "≥",
            };
            format!("unhealthy if {src} {op} {}", num(value))
        }
    }
}

/// A `[reset.*]` step: its target, how it is set and the distribution drawn.
pub fn reset_step(r: &ResetStep) -> String {
    reset_step_as(r, &sel(&r.target))
}

/// [`reset_step`] with the target's element names (`envc show`).
pub fn reset_step_named(r: &ResetStep) -> String {
    reset_step_as(r, &named(&r.target))
}

fn reset_step_as(r: &ResetStep, target: &str) -> String {
    let dist = match &r.dist {
        Distribution::Uniform { low, high } => uniform(low, high),
        Distribution::Normal { scale } => format!("{} × normal(0, 1)", num(*scale)),
        Distribution::Constant { value } => num(*value),
        Distribution::Values { values } => {
            let v: Vec<String> = values.iter().map(|x| num(*x)).collect();
            format!("[{}]", v.join(", "))
        }
        Distribution::Keyframe { name, .. } => {
            return format!("qpos = keyframe `{name}`");
        }
        Distribution::RootPose { ranges } => return root_pose(target, ranges),
        Distribution::Rotation(rot) => return rotation(target, r.set, rot),
        Distribution::UnitQuaternion => return format!("{target} ← q / ‖q‖"),
        Distribution::Settle(s) => return settle(s),
        Distribution::Meet(m) => return meet(target, m),
        Distribution::TerrainOrigin { rows } => {
            return format!(
                "{}: position += the spawn origin of a [terrain] tile drawn uniformly (rows {} … {}, any column)",
                target, rows.0, rows.1
            );
        }
    };
    let op = if r.set { "=" } else { "= initial +" };
    let until = match r.resample_until {
        Some(Until::NormBelow(x)) => format!(", redrawn until ‖·‖ < {}", num(x)),
        Some(Until::NormAbove(x)) => format!(", redrawn until ‖·‖ > {}", num(x)),
        Some(Until::MinDistance(x)) => {
            format!(
                ", redrawn while closer than {} to where it is drawn around",
                num(x)
            )
        }
        None => String::new(),
    };
    let op = match (&r.around, r.set) {
        (Some(a), _) => format!("= [init] record {a:?} +"),
        (None, _) => op.to_string(),
    };
    let chance = r
        .probability
        .map_or(String::new(), |p| format!(" (with probability {})", num(p)));
    format!("{target} {op} {dist}{until}{chance}")
}

/// Uniform bounds: one interval when every element shares it, else one per element.
fn uniform(low: &[f64], high: &[f64]) -> String {
    let same = low.windows(2).all(|w| w[0] == w[1]) && high.windows(2).all(|w| w[0] == w[1]);
    if same && !low.is_empty() {
        format!("uniform[{}, {})", num(low[0]), num(high[0]))
    } else {
        let pairs: Vec<String> = low
            .iter()
            .zip(high)
            .map(|(l, h)| format!("[{}, {})", num(*l), num(*h)))
            .collect();
        format!("uniform per element {}", pairs.join(" "))
    }
}

/// A root pose drawn around the initial one; ranges that are 0 are left out.
fn root_pose(target: &str, ranges: &[(f64, f64); 6]) -> String {
    let v: Vec<String> = crate::resolve::ROOT_POSE_KEYS
        .iter()
        .zip(ranges)
        .filter(|(_, r)| r.0 != 0.0 || r.1 != 0.0)
        .map(|(k, r)| format!("{k} uniform[{}, {})", num(r.0), num(r.1)))
        .collect();
    format!(
        "{}: position += (x, y, z), quat ← quat ⊗ euler_xyz(roll, pitch, yaw); {}",
        target,
        if v.is_empty() {
            "every range 0".into()
        } else {
            v.join(", ")
        }
    )
}

/// A random rotation, set or composed with the initial orientation.
fn rotation(target: &str, set: bool, rot: &Rotation) -> String {
    let Rotation {
        axis,
        angle,
        parallel,
    } = rot;
    let parallel = if *parallel {
        " ⊗ one of 24 axis-aligned orientations"
    } else {
        ""
    };
    let axis = match axis {
        Some(a) => format!("{a:?}"),
        None => "uniform[-1, 1)³".to_string(),
    };
    let op = if set { "=" } else { "← q ⊗" };
    format!(
        "{target} {op} quat_from_angle_and_axis(uniform[{}, {}), {axis}){parallel}",
        num(angle.0),
        num(angle.1)
    )
}

/// Control steps with action 0, the reset starting over unless the watched value exceeds its bound.
fn settle(s: &Settle) -> String {
    let watch = match &s.require {
        Some((sel, above)) => format!(
            ", then again from the first step unless {} > {}",
            sel.text,
            num(*above)
        ),
        None => String::new(),
    };
    format!("{} control steps with action 0{watch}", s.steps)
}

/// Points brought together near a drawn meeting point, or left as they are.
fn meet(target: &str, m: &Meet) -> String {
    let pts = |v: &[usize]| {
        v.iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "{}: points [{}] and one of [{}] meet {} short of record{:?} + {:?} + {} × normal(0, 1)³; with probability {} unchanged",
        target,
        pts(&m.always),
        pts(&m.one_of),
        num(m.gap),
        m.center,
        m.offset,
        num(m.scale),
        num(m.unchanged)
    )
}

/// An info entry: what it reports and how it is computed.
pub fn info(spec: &ResolvedSpec, i: &InfoItem) -> String {
    match &i.kind {
        InfoKind::Value { source, minus } => match minus {
            Some(m) => format!("{} − {}", sel(source), sel(m)),
            None => sel(source),
        },
        InfoKind::Norm { source } => format!("‖{}‖₂", sel(source)),
        InfoKind::Velocity { source } => format!("({0}_after − {0}_before) / dt", sel(source)),
        InfoKind::Term(t) => format!("signed value of reward term `{}`", spec.reward[*t].name),
        InfoKind::GoalReached(c) => format!("1 if {} else 0", goal_check(c)),
        InfoKind::GoalsReached(cs) => format!("1 if {} else 0", goal_checks(cs)),
        InfoKind::Condition(cs) => format!("1 if {} else 0", conditions(cs)),
        InfoKind::GoalParts(which) => {
            format!("the [goal] parts {} (a list of names)", which.name())
        }
    }
}

/// An added actuator, e.g. `FR_hip_joint: position kp 35 kv 0.5, force [-23.7, 23.7]`.
pub fn actuator(a: &AddedActuator) -> String {
    let kind = match a.kind {
        ActuatorKind::Motor => format!("motor gear {}", num(a.gear)),
        ActuatorKind::Position { kp, kv } => match kv {
            Some(kv) => format!("position kp {} kv {}", num(kp), num(kv)),
            None => format!("position kp {}", num(kp)),
        },
        ActuatorKind::Velocity { kv } => format!("velocity kv {}", num(kv)),
    };
    let mut s = format!(
        "{} on {}: {kind}, ctrl {}",
        a.name,
        a.joint,
        range(a.ctrlrange.0, a.ctrlrange.1)
    );
    if let Some((lo, hi)) = a.forcerange {
        s.push_str(&format!(", force {}", range(lo, hi)));
    }
    s
}

/// A joint's spec-set properties, e.g. `FR_hip_joint: armature 0.01, damping 0.5`.
pub fn joint_edit(j: &JointEdit) -> String {
    let mut v = vec![];
    for (k, x) in [
        ("armature", j.armature),
        ("damping", j.damping),
        ("frictionloss", j.frictionloss),
    ] {
        if let Some(x) = x {
            v.push(format!("{k} {}", num(x)));
        }
    }
    format!("{}: {}", j.joint, v.join(", "))
}

/// A spec keyframe: where it starts and what it writes, by joint name.
pub fn keyframe(r: &ResolvedSpec, k: &SpecKeyframe) -> String {
    let base = match k.from {
        Some(i) => format!(
            "model keyframe `{}`",
            r.model.keyframes.get(i).map(String::as_str).unwrap_or("?")
        ),
        None => "qpos0".into(),
    };
    let vals: Vec<String> = k
        .values
        .iter()
        .map(|(adr, x)| format!("qpos[{adr}] = {}", num(*x)))
        .collect();
    if vals.is_empty() {
        base
    } else {
        format!("{base} with {}", vals.join(", "))
    }
}

/// The manipulation tables, one line each (`envc show`); empty for a spec without them.
pub fn manipulation(spec: &ResolvedSpec) -> Vec<String> {
    let m = &spec.manipulation;
    let mut out = vec![];
    if let Some(i) = &m.init {
        let joints: Vec<String> = i
            .qpos
            .iter()
            .map(|(j, _, v)| {
                let v: Vec<String> = v.iter().map(|x| num(*x)).collect();
                format!("{j} = {}", v.join(" "))
            })
            .collect();
        if !joints.is_empty() {
            out.push(format!("[init] qpos: {}", joints.join(", ")));
        }
        if i.reset_welds {
            out.push("[init] weld poses reset to the identity".into());
        }
        for p in &i.mocap {
            let at = p.site.map_or(String::new(), |s| {
                format!(" + site_xpos[{}]", spec.model.sites[s])
            });
            let o: Vec<String> = p.offset.iter().map(|x| num(*x)).collect();
            let q: Vec<String> = p.quat.iter().map(|x| num(*x)).collect();
            out.push(format!(
                "[init] mocap {}: pos = [{}]{at}, quat = [{}]",
                p.body,
                o.join(", "),
                q.join(", ")
            ));
        }
        out.push(format!(
            "[init] then {} settling steps of frame_skip × mj_step",
            i.settle_steps
        ));
        for r in &i.records {
            out.push(format!(
                "[init] record {} = {} (values {}..{})",
                r.name,
                r.source.text,
                r.offset,
                r.offset + r.source.len()
            ));
        }
    }
    if let Some(e) = &m.end_effector {
        let g = if e.block_gripper {
            "blocked (0)".to_string()
        } else if e.gripper.is_empty() {
            "drives no actuator".to_string()
        } else {
            let names: Vec<&str> = e
                .gripper
                .iter()
                .map(|&i| spec.model.actuators[i].name.as_str())
                .collect();
            format!("to {}", names.join(", "))
        };
        let r: Vec<String> = e.rotation.iter().map(|x| num(*x)).collect();
        out.push(format!(
            "[end_effector] mocap {}: pos = xpos[welded] + {} × clip(action[0:3]), quat = xquat[welded] + [{}]{}",
            e.mocap,
            num(e.scale),
            r.join(", "),
            if e.gripper_action {
                format!("; action[3] (gripper) {g}")
            } else {
                String::new()
            }
        ));
    }
    for h in &m.hold {
        out.push(format!(
            "[hold.{}] qpos {:?} = {} after every step, then mj_forward",
            h.name,
            h.qpos,
            num(h.value)
        ));
    }
    if let Some(g) = &m.goal {
        match &g.parts {
            None => out.push(format!(
                "[goal] achieved_goal = {} ({} values); desired_goal = goal",
                g.achieved.text,
                g.achieved.len()
            )),
            Some(p) => out.extend(goal_parts(g, p)),
        }
    }
    out
}

/// A `[goal]` of parts: the checklist's rules, then each part in play.
fn goal_parts(g: &GoalTable, p: &GoalParts) -> Vec<String> {
    let mut out = vec![format!(
        "[goal] {} parts, each done when its ‖achieved − desired‖ ({}) < {}; a part done {}; {}",
        p.parts.len(),
        p.norm.name(),
        num(p.threshold),
        if p.remove_done {
            "leaves the list"
        } else {
            "stays on the list"
        },
        if p.terminate_when_done {
            "terminated once every part is done"
        } else {
            "no termination"
        }
    )];
    for part in &p.parts {
        let names = &g.achieved.names[part.offset..part.offset + part.len()];
        out.push(format!(
            "  {:?}: {} -> {:?}",
            part.name,
            names.join(", "),
            part.desired
        ));
    }
    out
}

/// A derived value, e.g. `(site_xpos[a] − site_xpos[b]) / derived[len]`, `(at reset)` when
/// measured once per episode.
pub fn derived(d: &crate::derived::Derived) -> String {
    use crate::derived::DerivedKind;
    let diff = |s: &crate::selector::Selection, m: &Option<crate::selector::Selection>| match m {
        Some(m) => format!("{} − {}", sel(s), sel(m)),
        None => sel(s),
    };
    let text = match &d.kind {
        DerivedKind::Difference {
            source,
            minus,
            divide_by,
        } => match divide_by {
            Some(v) => format!("({}) / {}", diff(source, minus), sel(v)),
            None => diff(source, minus),
        },
        DerivedKind::Norm { source, minus } => format!("‖{}‖₂", diff(source, minus)),
        DerivedKind::Dot { source, with } => format!("{} · {}", sel(source), sel(with)),
        DerivedKind::Contact { a, b, value } => {
            let what = crate::derived::CONTACT_VALUES
                .iter()
                .find(|(_, v)| v == value)
                .map_or("?", |(n, _)| n);
            let side = |s: &crate::derived::ContactSide| {
                format!("{} `{}`", if s.body { "body" } else { "geom" }, s.name)
            };
            match b {
                Some(b) => format!("contact {what} of {} with {}", side(a), side(b)),
                None => format!("contact {what} of {} with anything", side(a)),
            }
        }
    };
    if d.at_reset {
        format!("{text} (at reset)")
    } else {
        text
    }
}

/// One line per corrupted segment, then the action latency, for `envc show` (draw order:
/// segments with noise draw in this order, one value per element, at reset and after each step).
pub fn corruption(r: &crate::ResolvedSpec) -> Vec<String> {
    let dt = r.dt();
    let steps = |n: usize| {
        let s = if n == 1 { "" } else { "s" };
        format!(
            "{n} step{s} ({} s)",
            crate::value::format_float(n as f64 * dt)
        )
    };
    let mut out = vec![];
    for c in &r.corruption.segments {
        let seg = &r.observation[c.segment];
        let mut parts = vec![];
        if let Some(n) = &c.noise {
            let clip = seg
                .clip
                .map(|(lo, hi)| format!(", then clipped to [{lo}, {hi}]"))
                .unwrap_or_default();
            parts.push(format!("noise {n}{clip}"));
        }
        if c.delay > 0 {
            parts.push(format!("delayed {}", steps(c.delay)));
        }
        out.push(format!(
            "{:<14} [{}:{}]  {}",
            c.name,
            seg.offset,
            seg.offset + seg.len(),
            parts.join("; ")
        ));
    }
    if r.corruption.action_latency > 0 {
        out.push(format!(
            "action latency {} (zeros after a reset)",
            steps(r.corruption.action_latency)
        ));
    }
    out
}
