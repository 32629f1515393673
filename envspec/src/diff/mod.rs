//! Semantic diff of two specs, for reviewers: what a change does to trained policies and to
//! published returns.
//!
//! Two levels are compared. The written spec (sections matched by name, renames detected, every
//! key "was X, now Y" with file:line on both sides) says *what* changed; the resolved specs under
//! default parameters say *whether it matters* (a weight rewritten as a parameter reference with
//! the same value is not a reward change) and give witnesses (observation indices, element names).
//! Whether a resolved item changed is decided on behaviour keys built from the IR's fields
//! (module `behaviour`), not on names or spelling. Compiled-model differences (dynamics) need MuJoCo;
//! the runtime adds them to the report.
//!
//! Every change is an instance of a rule of [`rules::RULES`] (stable id, category, breaking by
//! default, description; listed in `docs/diff-rules.md`). Besides task specs, [`diff_multi_agent`]
//! compares multi-agent factorizations and [`diff_mazes`] maze specs.

mod behaviour;
mod change;
mod commands;
mod derived;
mod events;
mod info;
mod manipulation;
mod maze;
mod multi_agent;
mod noise;
mod observation;
mod params;
mod report;
pub mod rules;
mod sections;
mod whole;

pub use change::{Change, Pos};
pub use maze::diff_mazes;
pub use multi_agent::diff_multi_agent;
pub use report::{Report, Verdict};
pub use rules::{Category, RULES, Rule, RuleId};

use crate::ir::ResolvedSpec;
use crate::syntax::Spec;

fn pos(loc: &crate::diagnostic::Location) -> Pos {
    let (line, _) = loc.file.line_col(loc.span.start);
    Pos {
        file: loc.file.path.display().to_string(),
        line,
    }
}

/// The two specs being compared and the changes found so far.
struct Ctx<'a> {
    old: &'a Spec,
    new: &'a Spec,
    old_r: &'a ResolvedSpec,
    new_r: &'a ResolvedSpec,
    changes: Vec<Change>,
}

impl Ctx<'_> {
    fn add(&mut self, c: Change) {
        self.changes.push(c);
    }
}

/// Diff two task specs (each with its resolution under default parameters).
pub fn diff(old: &Spec, old_r: &ResolvedSpec, new: &Spec, new_r: &ResolvedSpec) -> Report {
    let mut cx = Ctx {
        old,
        new,
        old_r,
        new_r,
        changes: vec![],
    };
    task_rules(&mut cx);
    model_edit_rules(&mut cx);
    events::events(&mut cx);
    manipulation::manipulation(&mut cx);
    derived::derived(&mut cx);

    let mut report = Report::new(
        &old_r.id,
        &new_r.id,
        old.path().display().to_string(),
        new.path().display().to_string(),
    );
    report.extend(cx.changes);
    report
}

/// The rules of a task's own tables, from `[env]` and parameters to commands and actions, in
/// report order.
fn task_rules(cx: &mut Ctx) {
    let (old, new) = (cx.old, cx.new);
    params::env_section(cx);
    params::params(cx);
    observation::observation(cx);
    noise::noise(cx);
    sections::sections(
        cx,
        &sections::REWARD,
        &old.reward,
        &new.reward,
        &|r: &ResolvedSpec, n: &str| r.reward.iter().find(|t| t.name == n).map(behaviour::term),
    );
    whole::reward_sum(cx);
    sections::sections(
        cx,
        &sections::HEALTH,
        &old.health,
        &new.health,
        &|r: &ResolvedSpec, n: &str| r.health.iter().find(|c| c.name == n).map(behaviour::check),
    );
    sections::sections(
        cx,
        &sections::TERMINATION,
        &old.termination,
        &new.termination,
        &|r: &ResolvedSpec, n: &str| {
            r.termination
                .iter()
                .find(|c| c.name == n)
                .map(|t| behaviour::goal_check(&t.reached))
        },
    );
    whole::episode(cx);
    sections::sections(
        cx,
        &sections::RESET,
        &old.reset,
        &new.reset,
        &|r: &ResolvedSpec, n: &str| {
            r.reset
                .iter()
                .find(|c| c.name == n)
                .map(behaviour::reset_step)
        },
    );
    whole::reset_order(cx);
    whole::terrain(cx);
    whole::observation_refresh(cx);
    whole::physics_options(cx);
    info::info_items(cx);
    commands::commands(cx);
    commands::actions(cx);
}

/// Model edits, judged by what they resolve to: the actuators a table adds, the whole
/// per-joint table (rows override each other), a keyframe's positions.
fn model_edit_rules(cx: &mut Ctx) {
    let (old, new) = (cx.old, cx.new);
    sections::sections(
        cx,
        &sections::ACTUATORS,
        &old.actuators,
        &new.actuators,
        &|r: &ResolvedSpec, n: &str| {
            let a: Vec<&crate::ir::AddedActuator> = r
                .model_edits
                .actuators
                .iter()
                .filter(|a| a.section == n)
                .collect();
            (!a.is_empty()).then(|| format!("{a:?}"))
        },
    );
    sections::sections(
        cx,
        &sections::JOINT_PROPERTIES,
        &old.joint_properties,
        &new.joint_properties,
        &|r: &ResolvedSpec, n: &str| {
            // What the row itself sets, on which joints (actuator tables are diffed on their own).
            r.model_edits
                .joint_rows
                .iter()
                .find(|row| row.0 == n)
                .map(|row| format!("{:?} {:?}", row.1, row.2))
        },
    );
    sections::sections(
        cx,
        &sections::GEOM_PROPERTIES,
        &old.geom_properties,
        &new.geom_properties,
        &|r: &ResolvedSpec, n: &str| {
            r.model_edits
                .geom_rows
                .iter()
                .find(|row| row.0 == n)
                .map(|row| format!("{:?} {:?}", row.1, row.2))
        },
    );
    sections::sections(
        cx,
        &sections::KEYFRAMES,
        &old.keyframes,
        &new.keyframes,
        &|r: &ResolvedSpec, n: &str| {
            r.model_edits
                .keyframes
                .iter()
                .find(|k| k.name == n)
                .map(|k| format!("{k:?}"))
        },
    );
}

/// E0905: the two sides of a diff are different kinds of spec (`kind` names them, e.g. `maze`,
/// `multi-agent`, `task`); their changes cannot be compared rule by rule.
pub fn kind_mismatch(
    old_kind: &str,
    old: &std::path::Path,
    new_kind: &str,
    new: &std::path::Path,
) -> crate::Diagnostic {
    crate::Diagnostic::new(
        crate::Code::E0905,
        format!(
            "cannot diff a {old_kind} spec ({}) against a {new_kind} spec ({})",
            crate::diagnostic::show_path(old),
            crate::diagnostic::show_path(new)
        ),
    )
    .label("two specs of the same kind: task specs, multi-agent (`[agents]`) specs or maze (`[maze]`) specs")
    .help("a maze's `robot` and a multi-agent spec's base env are task specs: diff those against a task spec")
}
