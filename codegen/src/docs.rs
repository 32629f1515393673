//! Generated rustdoc: layout tables, reward formulas, parameter docs — all from the resolved spec.

use envspec::ir::{CheckKind, CmpOp, Distribution, Divisor, InfoItem, InfoKind, TermKind};
use envspec::{Param, ResolvedSpec, describe};
use syn::Ident;

/// `|` and newlines would break a markdown table cell.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

pub(crate) fn param_doc(p: &Param) -> String {
    let mut d = if p.doc.is_empty() {
        format!("Parameter `{}`.", p.name)
    } else {
        p.doc.clone()
    };
    d.push_str(&format!(
        "\n\nSpec default: `{}` ({}).",
        p.default,
        p.ty.name()
    ));
    d
}

pub(crate) fn segment_doc(r: &ResolvedSpec, name: &str) -> String {
    match r.observation.iter().find(|s| s.name == name) {
        Some(s) => {
            let mut d = format!(
                "Segment `{name}`: `obs[{}..{}]` with the default parameters ({} values, from `{}`).",
                s.offset,
                s.offset + s.len(),
                s.len(),
                s.source.text
            );
            if !s.doc.is_empty() {
                d = format!("{}\n\n{d}", s.doc);
            }
            d
        }
        None => format!(
            "Segment `{name}`: switched off with the default parameters (empty unless an override enables it)."
        ),
    }
}

pub(crate) fn info_doc(r: &ResolvedSpec, it: &InfoItem) -> String {
    let what = match &it.kind {
        InfoKind::Value { source, minus } => match minus {
            Some(m) => format!("`{}` − `{}`", source.text, m.text),
            None => format!("`{}`", source.text),
        },
        InfoKind::Norm { source } => format!("‖`{}`‖₂", source.text),
        InfoKind::Velocity { source } => format!("velocity of `{}` over dt", source.text),
        InfoKind::Term(i) => format!("signed value of reward term `{}`", r.reward[*i].name),
        InfoKind::GoalReached(c) => format!("1 if {} else 0", describe::goal_check(c)),
        InfoKind::GoalsReached(cs) => format!("1 if {} else 0", describe::goal_checks(cs)),
        InfoKind::Condition(cs) => format!("1 if {} else 0", describe::conditions(cs)),
        InfoKind::GoalParts(which) => format!(
            "per [goal] part: {} (1/0, or the completion order)",
            which.name()
        ),
    };
    if it.doc.is_empty() {
        format!("`{}`: {what}.", it.key)
    } else {
        format!("{}\n\n`{}`: {what}.", it.doc, it.key)
    }
}

fn term_formula(t: &envspec::ir::RewardTerm) -> String {
    let mut f = kernel_formula(t);
    if !t.only_if.is_empty() {
        f = format!("{f}, only if {}", describe::conditions(&t.only_if));
    }
    if !t.unless.is_empty() {
        f = format!("{f}, unless {}", describe::conditions(&t.unless));
    }
    f
}

fn kernel_formula(t: &envspec::ir::RewardTerm) -> String {
    let w = t.weight;
    match &t.kind {
        TermKind::Legged(l) => format!("{w} × {}", l.formula()),
        TermKind::Velocity { source } => {
            format!("{w} × (x_after − x_before) / dt, x = `{}`", source.text)
        }
        TermKind::Healthy => format!("{w} × (1 if healthy else 0)"),
        TermKind::SumSquares {
            source,
            clip_input,
            clip,
        } => {
            let x = match clip_input {
                Some((a, b)) => format!("clip(x, {a}, {b})²"),
                None => "x²".into(),
            };
            let core = format!("{w} × Σ {x}, x = `{}`", source.text);
            match clip {
                Some((a, b)) => format!("clip({core}, {a}, {b})"),
                None => core,
            }
        }
        TermKind::Norm { source, minus } => match minus {
            Some(m) => format!("{w} × ‖`{}` − `{}`‖₂", source.text, m.text),
            None => format!("{w} × ‖`{}`‖₂", source.text),
        },
        TermKind::Quadratic {
            source,
            coefs,
            targets,
        } => format!(
            "{w} × Σ cₖ (xₖ − tₖ)², x = `{}`, c = {coefs:?}, t = {targets:?}",
            source.text
        ),
        TermKind::Value { source, divide_by } => match divide_by {
            Some(Divisor::Timestep) => format!("{w} × `{}` / timestep", source.text),
            Some(Divisor::Dt) => format!("{w} × `{}` / dt", source.text),
            None => format!("{w} × `{}`", source.text),
        },
        TermKind::Constant => format!("{w}"),
        TermKind::WeightedSquare { source, target } => {
            format!(
                "({w} × (x − {target})) × (x − {target}), x = `{}`",
                source.text
            )
        }
        TermKind::GoalSparse(c) => format!("{w} × (1 if {} else 0)", describe::goal_check(c)),
        TermKind::GoalDense(g) => format!("{w} × exp(−{})", describe::goal_distance(g)),
        TermKind::GoalMissed(c) => format!("{w} × (1 if not {} else 0)", describe::goal_check(c)),
        TermKind::GoalDistance(g) => format!("{w} × {}", describe::goal_distance(g)),
        TermKind::GoalsMissed(cs) => {
            format!("{w} × ((1 if {} else 0) − 1)", describe::goal_checks(cs))
        }
        TermKind::PartsReached => format!("{w} × the number of [goal] parts reached now"),
    }
}

pub(crate) fn env_doc(r: &ResolvedSpec, spec: &str) -> String {
    let mut d = format!("`{}`, generated from `{spec}` by `envc::env!`.\n\n", r.id);
    if !r.description.is_empty() {
        d.push_str(&format!("{}\n\n", r.description));
    }
    let max = r
        .max_episode_steps
        .map(|m| m.to_string())
        .unwrap_or_else(|| "none".into());
    d.push_str(&format!(
        "obs dim {} · action dim {} · dt {} s (timestep {} × frame_skip {}) · max episode steps {max}. \
         Tables show the default parameters.\n\n",
        r.obs_dim,
        r.act_dim(),
        r.dt(),
        r.model.timestep,
        r.frame_skip
    ));
    observation_table(&mut d, r);
    action_table(&mut d, r);
    reward_table(&mut d, r);
    health_table(&mut d, r);
    termination_table(&mut d, r);
    reset_table(&mut d, r);
    d.push_str("\n# Parameters\n\nSee the `Config` type: one field per parameter.\n");
    d
}

/// `# Observation`: one row per segment, long element lists shortened.
fn observation_table(d: &mut String, r: &ResolvedSpec) {
    d.push_str("# Observation\n\n| index | segment | elements |\n|---|---|---|\n");
    for s in &r.observation {
        let names = s.element_names();
        let shown = if names.len() > 12 {
            format!(
                "{}, … ({} more), {}",
                names[..6].join(", "),
                names.len() - 7,
                names[names.len() - 1]
            )
        } else {
            names.join(", ")
        };
        let mut extra = String::new();
        if let Some((a, b)) = s.clip {
            extra.push_str(&format!(" clipped to [{a}, {b}]"));
        }
        d.push_str(&format!(
            "| {}..{} | `{}`{extra} | {} |\n",
            s.offset,
            s.offset + s.len(),
            s.name,
            cell(&shown)
        ));
    }
}

/// `# Action`: one row per actuator.
fn action_table(d: &mut String, r: &ResolvedSpec) {
    d.push_str("\n# Action\n\n| index | actuator | drives |\n|---|---|---|\n");
    for (i, a) in r.model.actuators.iter().enumerate() {
        d.push_str(&format!(
            "| {i} | `{}` | {} |\n",
            a.name,
            a.target.as_deref().unwrap_or("")
        ));
    }
    d.push_str("\nControl ranges come from the compiled model: `ctrl_range()`.\n");
}

/// `# Reward`: one row per term with its formula.
fn reward_table(d: &mut String, r: &ResolvedSpec) {
    d.push_str("\n# Reward\n\n| term | kind | signed value | info key |\n|---|---|---|---|\n");
    for t in &r.reward {
        let f = term_formula(t);
        let f = if t.cost { format!("−({f})") } else { f };
        d.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            t.name,
            t.kind_name(),
            cell(&f),
            t.info
                .as_deref()
                .map(|k| format!("`{k}`"))
                .unwrap_or_default()
        ));
    }
}

/// `# Health`: one row per check (nothing without checks).
fn health_table(d: &mut String, r: &ResolvedSpec) {
    if r.health.is_empty() {
        return;
    }
    d.push_str(&format!(
        "\n# Health\n\nUnhealthy {} the episode.\n\n| check | condition |\n|---|---|\n",
        if r.terminate_when_unhealthy {
            "terminates"
        } else {
            "does not terminate"
        }
    ));
    for h in &r.health {
        let src: Vec<String> = h.sources.iter().map(|s| format!("`{}`", s.text)).collect();
        d.push_str(&format!(
            "| `{}` | {}: {} |\n",
            h.name,
            src.join(", "),
            check_condition(&h.kind)
        ));
    }
}

/// A health check's condition as the table shows it.
fn check_condition(kind: &CheckKind) -> String {
    match kind {
        CheckKind::Finite => "finite".to_string(),
        CheckKind::InRange { lo, hi, closed } => {
            let (l, r) = if *closed { ('[', ']') } else { ('(', ')') };
            format!("in {l}{lo}, {hi}{r}")
        }
        CheckKind::FailsIf { op, value } => {
            let op = match op {
                CmpOp::Lt => "<",
                CmpOp::Le => "≤",
                CmpOp::Gt => ">",
                CmpOp::Ge => "≥",
            };
            format!("unhealthy if {op} {value}")
        }
    }
}

/// `# Termination` (nothing without conditions), then the goal vector's note.
fn termination_table(d: &mut String, r: &ResolvedSpec) {
    if !r.termination.is_empty() {
        d.push_str("\n# Termination\n\n| condition | terminates when |\n|---|---|\n");
        for t in &r.termination {
            let when = describe::goal_check(&t.reached);
            d.push_str(&format!("| `{}` | {} |\n", t.name, cell(&when)));
        }
    }
    if r.goal_dim > 0 {
        d.push_str(&format!(
            "\nGoal terms with `desired = \"goal\"` read the env-held goal vector ({} values): \
             `inner_mut().goal_mut()` sets it.\n",
            r.goal_dim
        ));
    }
}

/// `# Reset`: one row per step, in RNG draw order (nothing without steps).
fn reset_table(d: &mut String, r: &ResolvedSpec) {
    if r.reset.is_empty() {
        return;
    }
    d.push_str("\n# Reset (RNG draw order)\n\n| step | target | distribution |\n|---|---|---|\n");
    for s in &r.reset {
        let mode = if s.set { "set" } else { "add" };
        d.push_str(&format!(
            "| `{}` | `{}` | {} ({mode}) |\n",
            s.name,
            s.target.text,
            distribution(&s.dist)
        ));
    }
}

/// A reset distribution as the table shows it.
fn distribution(dist: &Distribution) -> String {
    match dist {
        Distribution::Uniform { low, high } => {
            if low.iter().all(|x| *x == low[0]) && high.iter().all(|x| *x == high[0]) {
                format!("uniform({}, {})", low[0], high[0])
            } else {
                "uniform (per element)".into()
            }
        }
        Distribution::Normal { scale } => format!("{scale} × normal"),
        Distribution::Constant { value } => format!("constant {value}"),
        Distribution::Values { values } => format!("constant {values:?}"),
        Distribution::Keyframe { name, .. } => format!("keyframe `{name}`"),
        Distribution::RootPose { .. } => "root pose (x, y, z, roll, pitch, yaw)".into(),
        Distribution::TerrainOrigin { rows } => {
            format!("a terrain tile's origin (rows {} … {})", rows.0, rows.1)
        }
        Distribution::Meet(_) => "points brought together (meet)".into(),
        Distribution::Rotation(_) => "a rotation (angle and axis)".into(),
        Distribution::UnitQuaternion => "quaternion normalised".into(),
        Distribution::Settle(_) => "settling steps".into(),
    }
}

pub(crate) fn action_doc(r: &ResolvedSpec, env: &Ident) -> String {
    let mut d = format!(
        "An action of `{}`: one value per actuator, in this order (see [`{env}`]).\n\n| index | actuator |\n|---|---|\n",
        r.id
    );
    for (i, a) in r.model.actuators.iter().enumerate() {
        d.push_str(&format!("| {i} | `{}` |\n", actuator_label(a)));
    }
    d
}

/// An actuator's name, or what it drives when it has none (Gymnasium's MJCFs rarely name them).
pub(crate) fn actuator_label(a: &envspec::mjcf::Actuator) -> &str {
    match (&a.name, &a.target) {
        (n, Some(t)) if n.is_empty() => t,
        (n, _) => n,
    }
}
