//! `envc show SPEC|ID [--set k=v ...]`: the fully resolved spec.

use std::fmt::Write;

use anyhow::Result;
use envspec::describe;
use envspec::params::Origin;

use crate::Outcome;
use envc::JointEnv;

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id.
    spec: String,
    /// Parameter overrides (`key=value`, TOML literal values).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Print the model's inventory instead: joints, actuators, bodies, sites, tendons as the
    /// selector text to paste into a spec, then geoms, cameras and lights.
    #[arg(long)]
    model: bool,
}

/// Comma-joined names wrapped to lines of at most `width` characters, each indented by `indent`.
fn wrap(names: &[String], indent: usize, width: usize) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for n in names {
        if !line.is_empty() && line.len() + n.len() + 2 > width {
            let _ = writeln!(out, "{}{line},", " ".repeat(indent));
            line.clear();
        }
        if !line.is_empty() {
            line.push_str(", ");
        }
        line.push_str(n);
    }
    let _ = write!(out, "{}{line}", " ".repeat(indent));
    out
}

/// `envc show --model`: the model's elements as selectors to paste into a spec, rows numbered.
fn model_inventory(any: &envc::AnyEnv) -> Result<Outcome> {
    let env = any.physics_env();
    let mut o = String::new();
    writeln!(
        o,
        "{}: model {} (selectors to paste into a spec)",
        any.id(),
        env.spec().model_path.display()
    )?;
    for g in envc::describe::inventory::inventory(env.spec(), env.model()) {
        writeln!(o, "\n{} ({}):", g.title, g.lines.len())?;
        let lines: Vec<String> = if g.numbered {
            g.lines
                .iter()
                .enumerate()
                .map(|(i, l)| format!("[{i}] {l}"))
                .collect()
        } else {
            g.lines
        };
        writeln!(o, "{}", wrap(&lines, 2, 100))?;
    }
    print!("{o}");
    Ok(Outcome::Ok)
}

/// The `[derived.*]` tables, in the order they are computed (nothing without them).
fn write_derived(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    if spec.derived.is_empty() {
        return Ok(());
    }
    writeln!(
        o,
        "\nderived (computed in this order after every reset and step):"
    )?;
    for d in &spec.derived {
        writeln!(o, "  {:<20} {}", d.name, describe::derived(d))?;
    }
    Ok(())
}

/// The reward: how the terms are added, then each term.
fn write_reward(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    writeln!(o, "\nreward = {}", describe::reward_sum(spec))?;
    for t in &spec.reward {
        let info = t
            .info
            .as_ref()
            .map(|k| format!("   info `{k}`"))
            .unwrap_or_default();
        writeln!(
            o,
            "  {:<12} {:<12} {}{info}",
            t.name,
            t.kind_name(),
            describe::term(t)
        )?;
    }
    Ok(())
}

pub fn run(args: Args) -> Result<Outcome> {
    let any = crate::target::env(&args.spec, &args.set)?;
    if args.model {
        return model_inventory(&any);
    }
    let env = match any {
        envc::AnyEnv::Task(env) => env,
        envc::AnyEnv::Maze(env) => return crate::kinds::maze::show(&env),
        envc::AnyEnv::MultiAgent(env) => return crate::kinds::multi_agent::show(&env),
    };
    let spec = env.spec().clone();
    let cwd = std::env::current_dir().unwrap_or_default();
    let mut o = String::new();
    write_header(&mut o, &env, &spec, &cwd)?;
    write_parameters(&mut o, &spec, &cwd)?;
    write_observation(&mut o, &spec)?;
    write_action(&mut o, &env, &spec)?;
    if !spec.model_edits.actuators.is_empty() || !spec.model_edits.joints.is_empty() {
        joints(&mut o, &env)?;
    }
    write_manipulation(&mut o, &spec)?;
    write_derived(&mut o, &spec)?;
    write_reward(&mut o, &spec)?;
    write_endings(&mut o, &spec)?;
    write_reset(&mut o, &spec)?;
    if !spec.events.is_empty() {
        randomization(&mut o, &env)?;
    }
    write_info(&mut o, &spec)?;
    print!("{o}");
    Ok(Outcome::Ok)
}

/// `p` relative to the working directory when it is under it.
fn rel(cwd: &std::path::Path, p: &std::path::Path) -> String {
    p.strip_prefix(cwd).unwrap_or(p).display().to_string()
}

/// The id, description, model sizes and how an episode ends.
fn write_header(
    o: &mut String,
    env: &envc::Env,
    spec: &envc::envspec::ResolvedSpec,
    cwd: &std::path::Path,
) -> std::fmt::Result {
    writeln!(o, "{}  ({})", spec.id, rel(cwd, &spec.spec_path))?;
    if !spec.description.is_empty() {
        writeln!(o, "  {}", spec.description)?;
    }
    let m = &spec.model;
    writeln!(
        o,
        "model: {}  (nq {}, nv {}, nu {}, nbody {}; timestep {}, frame_skip {}, dt {})",
        rel(cwd, &spec.model_path),
        m.nq,
        m.nv,
        m.nu(),
        m.nbody(),
        m.timestep,
        spec.frame_skip,
        env.dt()
    )?;
    let max = spec
        .max_episode_steps
        .map(|n| n.to_string())
        .unwrap_or_else(|| "none".into());
    let ending = match (spec.health.is_empty(), spec.terminate_when_unhealthy) {
        (true, _) => "no health checks, so no unhealthy ending",
        (false, true) => "an unhealthy state ends it",
        (false, false) => "an unhealthy state does not end it",
    };
    writeln!(o, "episode: truncated after {max} steps; {ending}")?;
    if let Some(t) = spec.reward_threshold {
        writeln!(o, "reward threshold: {t}")?;
    }
    Ok(())
}

/// Every parameter with its type, value and where the value comes from.
fn write_parameters(
    o: &mut String,
    spec: &envc::envspec::ResolvedSpec,
    cwd: &std::path::Path,
) -> std::fmt::Result {
    writeln!(o, "\nparameters:")?;
    let w = spec.params.iter().map(|p| p.name.len()).max().unwrap_or(0);
    for p in &spec.params {
        let origin = match &p.origin {
            // The rendering parameters every spec has without writing them.
            Origin::Default(loc) if loc.span.is_empty() => "built-in".to_string(),
            Origin::Default(loc) => format!(
                "default ({})",
                loc.position().replace(&format!("{}/", cwd.display()), "")
            ),
            Origin::Override(_) => format!("override (default {})", p.default),
        };
        writeln!(
            o,
            "  {:<w$}  {:<6} {:<24} {origin}",
            p.name,
            p.ty.name(),
            p.value.to_string()
        )?;
    }
    Ok(())
}

/// The observation segments, each with the names of its elements.
fn write_observation(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    writeln!(o, "\nobservation ({} float64):", spec.obs_dim)?;
    for s in &spec.observation {
        writeln!(o, "  {}", crate::output::segment_line(s, &s.source.text))?;
        writeln!(o, "{}", wrap(&s.element_names(), 6, 100))?;
    }
    Ok(())
}

/// The action: one row per value with its bounds (Cartesian rows for an end effector, else one
/// per actuator), then the `[actions]` mapping.
fn write_action(
    o: &mut String,
    env: &envc::Env,
    spec: &envc::envspec::ResolvedSpec,
) -> std::fmt::Result {
    writeln!(
        o,
        "\naction ({} float64; float32 bounds as Gymnasium's Box):",
        env.act_dim()
    )?;
    let sp = env.action_space();
    if spec.manipulation.end_effector.is_some() {
        for (i, (lo, hi)) in sp.low.iter().zip(&sp.high).enumerate() {
            let what = ["dx", "dy", "dz", "gripper"][i.min(3)];
            writeln!(o, "  {i:>3}  {what:<20} [{lo}, {hi}]")?;
        }
    }
    let ee_actuators = if spec.manipulation.end_effector.is_some() {
        &[][..]
    } else {
        &spec.model.actuators[..]
    };
    for (i, a) in ee_actuators.iter().enumerate() {
        let target = a.target.as_deref().unwrap_or("-");
        let name = if a.name.is_empty() {
            "(unnamed)"
        } else {
            a.name.as_str()
        };
        let added = added_actuator(spec, &a.name);
        writeln!(
            o,
            "  {i:>3}  {name:<20} -> {target:<20} [{}, {}]{added}",
            sp.low[i], sp.high[i]
        )?;
    }

    if let Some(a) = &spec.actions {
        let pose = env.field(envspec::Field::DefaultPose);
        writeln!(o, "  {}", a.describe())?;
        if a.delta.is_none() {
            writeln!(o, "  default_pose = {pose:?}")?;
        }
    }
    Ok(())
}

/// Actuators the spec adds: their kind and gear (the model's own are in its file).
fn added_actuator(spec: &envc::envspec::ResolvedSpec, name: &str) -> String {
    spec.model_edits
        .actuators
        .iter()
        .find(|x| x.name == name)
        .map(|x| {
            let kind = match x.kind {
                envspec::ir::ActuatorKind::Motor => "motor".to_string(),
                envspec::ir::ActuatorKind::Position { kp, kv } => {
                    format!("position kp {kp} kv {}", kv.unwrap_or(0.0))
                }
                envspec::ir::ActuatorKind::Velocity { kv } => format!("velocity kv {kv}"),
            };
            format!("  {kind}, gear {} (added by the spec)", x.gear)
        })
        .unwrap_or_default()
}

/// The manipulation tables (nothing without them).
fn write_manipulation(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    let manipulation = describe::manipulation(spec);
    if !manipulation.is_empty() {
        writeln!(o, "\nmanipulation:")?;
        for line in &manipulation {
            writeln!(o, "  {line}")?;
        }
    }
    Ok(())
}

/// The health checks, then the termination conditions beside them.
fn write_endings(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    writeln!(
        o,
        "\nhealth ({}):",
        if spec.health.is_empty() {
            "always healthy"
        } else {
            "healthy when every check passes"
        }
    )?;
    for c in &spec.health {
        writeln!(o, "  {:<14} {}", c.name, describe::check(c))?;
    }
    if !spec.termination.is_empty() {
        writeln!(o, "\ntermination (beside health):")?;
        for t in &spec.termination {
            writeln!(o, "  {:<14} {}", t.name, describe::termination(t))?;
        }
    }
    Ok(())
}

/// What a reset draws, in order: the reset steps, the commands, then the noise and delays.
fn write_reset(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    writeln!(o, "\nreset (in RNG draw order; then mj_forward):")?;
    for r in &spec.reset {
        writeln!(o, "  {:<14} {}", r.name, describe::reset_step_named(r))?;
    }

    if !spec.commands.is_empty() {
        writeln!(
            o,
            "\ncommands (drawn after the reset steps, in this order):"
        )?;
        for c in &spec.commands {
            writeln!(o, "  {:<14} {}", c.name, c.describe())?;
        }
    }

    let corruption = envspec::describe::corruption(spec);
    if !corruption.is_empty() {
        writeln!(
            o,
            "\nobservation noise and delay, action latency (noise draws after the reset steps and after each step, in this order):"
        )?;
        for l in corruption {
            writeln!(o, "  {l}")?;
        }
    }
    Ok(())
}

/// The info keys, each with when it is reported and what it holds.
fn write_info(o: &mut String, spec: &envc::envspec::ResolvedSpec) -> std::fmt::Result {
    writeln!(o, "\ninfo:")?;
    for i in &spec.info {
        let when = if i.at_reset { "reset+step" } else { "step" };
        writeln!(
            o,
            "  {:<24} {:<10} {}",
            i.key,
            when,
            describe::info(spec, i)
        )?;
    }
    Ok(())
}

/// The `[events]` table: one row per value an event writes, with the values it can take.
fn randomization(o: &mut String, env: &envc::Env) -> Result<()> {
    let rows = envc::events::table(env.spec(), env.model())?;
    writeln!(
        o,
        "\nrandomization ({} events in draw order; values from the compiled model):",
        env.spec().events.len()
    )?;
    let w = |f: &dyn Fn(&envc::events::Row) -> usize, min: usize| {
        rows.iter().map(f).max().unwrap_or(0).max(min)
    };
    let (we, wm, wf, wl, wd) = (
        w(&|r| r.event.len(), 5),
        w(&|r| r.mode.chars().count(), 4),
        w(&|r| r.field.len(), 5),
        w(&|r| r.element.len(), 7),
        w(&|r| r.distribution.len(), 12),
    );
    writeln!(
        o,
        "  {:<we$}  {:<wm$}  {:<wf$}  {:<wl$}  {:<wd$}  {:<9}  {:>10}  values",
        "event", "mode", "field", "element", "distribution", "operation", "compiled"
    )?;
    for r in &rows {
        let compiled = r.compiled.map(num).unwrap_or("-".into());
        let mode_pad = wm - r.mode.chars().count().min(wm);
        writeln!(
            o,
            "  {:<we$}  {}{}  {:<wf$}  {:<wl$}  {:<wd$}  {:<9}  {:>10}  [{}, {}]",
            r.event,
            r.mode,
            " ".repeat(mode_pad),
            r.field,
            r.element,
            r.distribution,
            r.operation,
            compiled,
            num(r.range.0),
            num(r.range.1)
        )?;
    }
    Ok(())
}

/// The resolved per-joint table (`[actuators.*]` and `[joint_properties]`), from the compiled
/// model.
fn joints(o: &mut String, env: &envc::Env) -> Result<()> {
    let rows = envc::describe::joint_table::joint_table(env);
    let opt = |x: Option<f64>| x.map(num).unwrap_or("-".into());
    let range = |r: Option<(f64, f64)>| {
        r.map(|(a, b)| format!("[{}, {}]", num(a), num(b)))
            .unwrap_or("-".into())
    };
    let cells: Vec<[String; 13]> = rows
        .iter()
        .map(|r| {
            [
                r.joint.clone(),
                r.actuator
                    .as_ref()
                    .map(|(n, i)| format!("{i}:{n}"))
                    .unwrap_or("-".into()),
                opt(r.action_scale),
                r.kind.to_string(),
                opt(r.kp),
                opt(r.kv),
                opt(r.gear),
                range(r.forcerange),
                range(r.ctrlrange),
                num(r.armature),
                num(r.damping),
                num(r.frictionloss),
                if r.rows.is_empty() {
                    "-".into()
                } else {
                    r.rows.join(", ")
                },
            ]
        })
        .collect();
    let head = [
        "joint",
        "actuator",
        "scale",
        "kind",
        "kp",
        "kv",
        "gear",
        "forcerange",
        "ctrlrange",
        "armature",
        "damping",
        "frictionloss",
        "[joint_properties] rows",
    ];
    let w: Vec<usize> = (0..13)
        .map(|i| {
            cells
                .iter()
                .map(|c| c[i].chars().count())
                .chain([head[i].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    writeln!(
        o,
        "\njoints ({} hinge and slide; values from the compiled model; rows apply in file order, later ones win):",
        rows.len()
    )?;
    let line = |c: &[&str]| {
        let mut s = String::from(" ");
        for (i, x) in c.iter().enumerate() {
            let pad = w[i] - x.chars().count().min(w[i]);
            s.push(' ');
            s.push_str(x);
            if i + 1 < c.len() {
                s.push_str(&" ".repeat(pad + 1));
            }
        }
        s
    };
    writeln!(o, "{}", line(&head))?;
    for c in &cells {
        let c: Vec<&str> = c.iter().map(String::as_str).collect();
        writeln!(o, "{}", line(&c))?;
    }
    Ok(())
}

/// At most 6 decimals, trailing zeros dropped.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}
