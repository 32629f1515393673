//! A `[goal]` of named parts (spec-reference §22), `names` parameters, `[actions] kind =
//! "position_delta"` and the noise `order`: what they resolve to, their located errors, and how
//! `diff` tells a checklist change (reward) from a layout change (observation). Over the bundled
//! arm example (seven hinge and slide joints, two finger actuators), so no installed package is
//! needed.

use std::path::Path;

use envspec::diff::{Category, RuleId, diff};
use envspec::ir::{ActionKind, InfoKind, PartSet, TermKind};
use envspec::{Code, Override, ResolvedSpec, Spec, resolve};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

const BASE: &str = r#"[env]
id = "Parts-v0"

[params]
xml_file = "ARM"
frame_skip = 5
max_episode_steps = 10
tasks = { default = ["a", "b"], type = "names", doc = "The parts in play." }
keep = false

[goal]
in_play = "tasks"
threshold = 0.1
remove_done = "keep"

[goal.parts]
a = { achieved = "qpos[0:2]", desired = [0.1, 0.2] }
b = { achieved = "qpos[2:3]", desired = [0.3] }
c = { achieved = "qpos[3:4]", desired = 0.4 }

[observation.fingers]
source = "qpos[left_finger,right_finger]"
noise = { kind = "uniform", scale = 0.1, level = 0.5, order = "level_scale_draw" }

[observation.q]
source = "qpos[0:5]"

[reward.parts]
kind = "parts_reached"

[info.left]
kind = "goal_parts"
which = "remaining"

[info.done]
kind = "goal_parts"
which = "completed"
in_reset = false
"#;

const PARTS: &str = r#"[goal.parts]
a = { achieved = "qpos[0:2]", desired = [0.1, 0.2] }
b = { achieved = "qpos[2:3]", desired = [0.3] }
c = { achieved = "qpos[3:4]", desired = 0.4 }
"#;

/// The spec above with `edits` (`[old, new]` pairs, each occurring) applied.
fn spec(edits: &[(&str, &str)]) -> Spec {
    let arm = format!("{ROOT}/assets/examples/arm/arm.xml");
    let mut text = BASE.replace("ARM", &arm);
    for (old, new) in edits {
        assert!(text.contains(old), "{old}");
        text = text.replacen(old, new, 1);
    }
    Spec::parse(Path::new("parts.toml"), text).unwrap()
}

fn resolved(s: &Spec, overrides: &[Override]) -> ResolvedSpec {
    resolve(s, overrides).unwrap()
}

/// The codes of the errors resolving gives, and the first message.
fn errors(s: &Spec, overrides: &[Override]) -> (Vec<Code>, String) {
    let d = resolve(s, overrides).unwrap_err();
    let first = d.0.first().map(|e| e.to_string()).unwrap_or_default();
    (d.0.iter().map(|e| e.code).collect(), first)
}

#[test]
fn parts_in_play_make_the_goal_vector_in_order() {
    let r = resolved(&spec(&[]), &[]);
    let g = r.manipulation.goal.as_ref().unwrap();
    let p = g.parts.as_ref().unwrap();
    let names: Vec<(&str, usize)> = p
        .parts
        .iter()
        .map(|x| (x.name.as_str(), x.offset))
        .collect();
    assert_eq!(names, [("a", 0), ("b", 2)]);
    assert_eq!(g.achieved.indices, [0, 1, 2]);
    assert_eq!(r.goal_dim, 3);
    assert_eq!(
        (p.threshold, p.remove_done, p.terminate_when_done),
        (0.1, false, true)
    );
    assert!(matches!(r.reward[0].kind, TermKind::PartsReached));
    assert!(matches!(
        r.info[0].kind,
        InfoKind::GoalParts(PartSet::Remaining)
    ));
    assert_eq!(r.info[0].len, 2, "one value per part in play");
    assert_eq!(r.reset_info().count(), 1, "`done` is a step entry only");
    // The noise order.
    let n = r.corruption.segments[0].noise.unwrap();
    assert!(n.scale_first);
    // Another list, in another order: a scalar `desired` is one number.
    let over = [Override::text("tasks", r#"["c", "a"]"#)];
    let r = resolved(&spec(&[]), &over);
    let p = r.manipulation.goal.as_ref().unwrap().parts.clone().unwrap();
    let got: Vec<(&str, usize, &[f64])> = p
        .parts
        .iter()
        .map(|x| (x.name.as_str(), x.offset, x.desired.as_slice()))
        .collect();
    assert_eq!(got, [("c", 0, &[0.4][..]), ("a", 1, &[0.1, 0.2][..])]);
    assert_eq!(r.manipulation.goal.unwrap().achieved.indices, [3, 0, 1]);
}

#[test]
fn bad_parts_are_located_coded_errors() {
    // A name that is no part, with the near miss suggested; a name given twice.
    let (codes, msg) = errors(&spec(&[]), &[Override::text("tasks", r#"["a", "bb"]"#)]);
    assert_eq!(codes, [Code::E0105]);
    assert!(
        msg.contains("`bb` is not a part") && msg.contains("`b`"),
        "{msg}"
    );
    let (codes, msg) = errors(&spec(&[]), &[Override::text("tasks", r#"["a", "a"]"#)]);
    assert_eq!(codes, [Code::E0105]);
    assert!(msg.contains("twice"), "{msg}");
    // A names parameter takes strings only.
    let d = resolve(&spec(&[]), &[Override::text("tasks", "[1, 2]")]).unwrap_err();
    assert_eq!(d.0[0].code, Code::E0203);
    // A desired value of another length than the selection.
    let s = spec(&[("desired = [0.3]", "desired = [0.3, 0.1]")]);
    assert_eq!(errors(&s, &[]).0, [Code::E0170]);
    // No threshold; a threshold without parts; `achieved` beside parts.
    assert_eq!(
        errors(&spec(&[("threshold = 0.1\n", "")]), &[]).0,
        [Code::E0103]
    );
    let s = spec(&[("[goal]\n", "[goal]\nachieved = \"qpos[0:2]\"\n")]);
    assert_eq!(errors(&s, &[]).0, [Code::E0170]);
    // The parts' kinds without parts.
    let s = spec(&[
        (
            "in_play = \"tasks\"\nthreshold = 0.1\nremove_done = \"keep\"\n",
            "achieved = \"qpos[0:2]\"\n",
        ),
        (PARTS, ""),
    ]);
    let (codes, _) = errors(&s, &[]);
    assert!(codes.contains(&Code::E0170), "{codes:?}");
    // A marker site: beside parts; unknown; on a goal that is not 3-D.
    let s = spec(&[("[goal]\n", "[goal]\nmarker_site = \"grip\"\n")]);
    assert_eq!(errors(&s, &[]).0, [Code::E0170]);
    let single = |site: &str, sel: &str| {
        spec(&[
            (
                "in_play = \"tasks\"\nthreshold = 0.1\nremove_done = \"keep\"\n",
                &format!("achieved = \"{sel}\"\nmarker_site = \"{site}\"\n"),
            ),
            (PARTS, ""),
            ("[reward.parts]\nkind = \"parts_reached\"\n", ""),
            (
                "[info.left]\nkind = \"goal_parts\"\nwhich = \"remaining\"\n",
                "",
            ),
            (
                "[info.done]\nkind = \"goal_parts\"\nwhich = \"completed\"\nin_reset = false\n",
                "",
            ),
        ])
    };
    let r = resolved(&single("grip", "qpos[0:3]"), &[]);
    assert!(r.manipulation.goal.unwrap().marker_site.is_some());
    let (codes, msg) = errors(&single("gripp", "qpos[0:3]"), &[]);
    assert_eq!(codes, [Code::E0170]);
    assert!(msg.contains("no site `gripp`"), "{msg}");
    assert_eq!(errors(&single("grip", "qpos[0:2]"), &[]).0, [Code::E0170]);
    // An unknown `which`; an unknown noise order.
    let s = spec(&[("which = \"remaining\"", "which = \"left\"")]);
    assert_eq!(errors(&s, &[]).0, [Code::E0104]);
    let s = spec(&[("order = \"level_scale_draw\"", "order = \"scale_first\"")]);
    assert_eq!(errors(&s, &[]).0, [Code::E0104]);
}

#[test]
fn position_delta_actions_read_an_observed_segment() {
    let actions = "[actions]\nkind = \"position_delta\"\nfrom = \"fingers\"\nscale = 2.0\nvelocity = [-1.0, 1.0]\nposition = [[0.0, 0.04], [0.0, 0.03]]\n\n[observation.fingers]";
    let r = resolved(&spec(&[("[observation.fingers]", actions)]), &[]);
    let a = r.actions.as_ref().unwrap();
    assert_eq!(a.kind, ActionKind::PositionDelta);
    let d = a.delta.as_ref().unwrap();
    assert_eq!((d.from.as_str(), d.segment), ("fingers", 0));
    assert_eq!(d.velocity, [(-1.0, 1.0), (-1.0, 1.0)]);
    assert_eq!(d.position, [(0.0, 0.04), (0.0, 0.03)]);
    assert_eq!(a.scale, [2.0, 2.0]);
    // A segment of another length than the actuators; no such segment; a gain beside it.
    let wrong = actions.replace("from = \"fingers\"", "from = \"q\"");
    assert_eq!(
        errors(&spec(&[("[observation.fingers]", &wrong)]), &[]).0,
        [Code::E0132]
    );
    let wrong = actions.replace("from = \"fingers\"", "from = \"finger\"");
    let (codes, msg) = errors(&spec(&[("[observation.fingers]", &wrong)]), &[]);
    assert_eq!(codes, [Code::E0132]);
    assert!(msg.contains("fingers"), "suggests the segment: {msg}");
    let wrong = actions.replace("scale = 2.0", "scale = 2.0\nkp = 10.0");
    assert_eq!(
        errors(&spec(&[("[observation.fingers]", &wrong)]), &[]).0,
        [Code::E0101]
    );
    let wrong = actions.replace("[[0.0, 0.04], [0.0, 0.03]]", "[[0.0, 0.04]]");
    assert_eq!(
        errors(&spec(&[("[observation.fingers]", &wrong)]), &[]).0,
        [Code::E0132]
    );
}

#[test]
fn diff_tells_a_checklist_change_from_a_layout_change() {
    let old = resolved(&spec(&[]), &[]);
    let rules = |new: &Spec| {
        let (a, b) = (spec(&[]), new.clone());
        let d = diff(&a, &old, &b, &resolved(new, &[]));
        d.changes
            .iter()
            .map(|c| (c.rule, c.rule.category()))
            .collect::<Vec<_>>()
    };
    let threshold = spec(&[("threshold = 0.1", "threshold = 0.2")]);
    assert_eq!(
        rules(&threshold),
        [(RuleId::GoalPartsChanged, Category::Reward)]
    );
    let desired = spec(&[("desired = [0.3]", "desired = [0.35]")]);
    assert_eq!(
        rules(&desired),
        [(RuleId::GoalPartsChanged, Category::Reward)]
    );
    let renamed = spec(&[
        ("\nb = {", "\nbb = {"),
        ("[\"a\", \"b\"]", "[\"a\", \"bb\"]"),
    ]);
    let got = rules(&renamed);
    assert!(
        got.contains(&(RuleId::GoalChanged, Category::Observation)),
        "{got:?}"
    );
}
