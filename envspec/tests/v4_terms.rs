//! The spec-language features the Gymnasium v4 specs need: reward terms switched off by `when`
//! (also pruned from `sum`), `at = "before"`, `paid_when_unhealthy`, and info entries of kind
//! `term` with `key` / `when` / `in_reset` / `unweighted`. Behaviour is checked bit for bit against
//! the reference by tests/parity.rs; this file checks resolution and the error paths.

use std::path::{Path, PathBuf};

use envspec::ir::{InfoKind, SumNode};
use envspec::{Code, Override};

fn spec(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(name)
}

fn keys(info: &[envspec::ir::InfoItem]) -> Vec<&str> {
    info.iter().map(|i| i.key.as_str()).collect()
}

#[test]
fn ant_v4_defaults_leave_the_contact_term_out() {
    let s = envspec::load(&spec("ant_v4.toml"), &[]).unwrap();
    assert_eq!(s.obs_dim, 27);
    let names: Vec<&str> = s.reward.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["forward", "healthy", "ctrl"]);
    // [["forward", "healthy"], ["ctrl", "contact"]] without contact.
    assert_eq!(
        s.reward_sum,
        SumNode::Sum(vec![
            SumNode::Sum(vec![SumNode::Term(0), SumNode::Term(1)]),
            SumNode::Sum(vec![SumNode::Term(2)]),
        ])
    );
    assert!(s.reward[1].paid_when_unhealthy);
    assert!(!s.needs_rne_post_constraint);
    assert_eq!(
        keys(&s.info),
        [
            "reward_forward",
            "reward_ctrl",
            "reward_survive",
            "x_position",
            "y_position",
            "distance_from_origin",
            "x_velocity",
            "y_velocity",
            "forward_reward"
        ]
    );
    assert!(matches!(s.info[1].kind, InfoKind::Term(2)));
    assert_eq!(s.reset_info().count(), 0, "v4 reset info is empty");
}

#[test]
fn ant_v4_contact_forces_switch_the_term_and_the_info_source() {
    let o = [
        Override::parse("use_contact_forces=true").unwrap(),
        Override::parse("terminate_when_unhealthy=false").unwrap(),
    ];
    let s = envspec::load(&spec("ant_v4.toml"), &o).unwrap();
    assert_eq!(
        s.obs_dim,
        27 + 14 * 6,
        "every body's cfrc_ext, the world's included"
    );
    assert_eq!(s.reward.len(), 4);
    assert!(!s.reward[1].paid_when_unhealthy);
    assert!(s.needs_rne_post_constraint);
    // reward_ctrl keeps its place but reports the contact term.
    assert_eq!(s.info[1].key, "reward_ctrl");
    let InfoKind::Term(t) = s.info[1].kind else {
        panic!("reward_ctrl is a term entry")
    };
    assert_eq!(s.reward[t].name, "contact");
    assert_eq!(s.info.len(), 9);
}

#[test]
fn before_terms_and_unweighted_info() {
    let r = envspec::load(&spec("reacher_v4.toml"), &[]).unwrap();
    assert!(r.reward[0].before && !r.reward[1].before);
    assert_eq!(r.obs_dim, 11);
    let p = envspec::load(&spec("pusher_v4.toml"), &[]).unwrap();
    assert_eq!(keys(&p.info), ["reward_dist", "reward_ctrl"]);
    assert!(p.info.iter().all(|i| i.unweighted && !i.at_reset));
}

fn check_text(name: &str, text: &str) -> Vec<(Code, String)> {
    let dir = std::env::temp_dir().join(format!("envc-v4-terms-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("spec.toml");
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium");
    std::fs::write(
        &path,
        text.replace("../../assets/gymnasium", &assets.display().to_string()),
    )
    .unwrap();
    let out = match envspec::load(&path, &[]) {
        Ok(_) => vec![],
        Err(d) => d.0.iter().map(|x| (x.code, x.message.clone())).collect(),
    };
    std::fs::remove_dir_all(&dir).ok();
    out
}

fn ant_v4_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(spec("ant_v4.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn unknown_or_switched_off_terms_in_info_are_e0502() {
    let e = check_text(
        "unknown",
        &ant_v4_with("term = \"healthy\"", "term = \"helthy\""),
    );
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, Code::E0502);
    let e = check_text(
        "off",
        &ant_v4_with(
            "term = \"contact\"\nwhen = \"use_contact_forces\"",
            "term = \"contact\"",
        ),
    );
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, Code::E0502);
    assert!(e[0].1.contains("switches off"), "{}", e[0].1);
}

#[test]
fn bad_at_is_e0104_and_duplicate_keys_e0106() {
    let e = check_text(
        "at_velocity",
        &ant_v4_with(
            "kind = \"velocity\"\n",
            "kind = \"velocity\"\nat = \"before\"\n",
        ),
    );
    assert_eq!(
        e.iter().map(|x| x.0).collect::<Vec<_>>(),
        [Code::E0104],
        "{e:?}"
    );
    let e = check_text(
        "at_typo",
        &ant_v4_with("cost = true\n", "cost = true\nat = \"befor\"\n"),
    );
    assert_eq!(
        e.iter().map(|x| x.0).collect::<Vec<_>>(),
        [Code::E0104],
        "{e:?}"
    );
    // Both reward_ctrl entries switched on at once.
    let e = check_text(
        "dup",
        &ant_v4_with("when = \"!use_contact_forces\"", "when = true").replacen(
            "use_contact_forces = { default = false",
            "use_contact_forces = { default = true",
            1,
        ),
    );
    assert_eq!(
        e.iter().map(|x| x.0).collect::<Vec<_>>(),
        [Code::E0106],
        "{e:?}"
    );
    assert!(e[0].1.contains("reward_ctrl"), "{}", e[0].1);
}

#[test]
fn in_reset_is_only_for_value_and_norm() {
    let e = check_text(
        "in_reset",
        &ant_v4_with(
            "kind = \"velocity\"\nsource = \"xpos[torso][0]\"\n\n",
            "kind = \"velocity\"\nsource = \"xpos[torso][0]\"\nin_reset = false\n\n",
        ),
    );
    assert_eq!(
        e.iter().map(|x| x.0).collect::<Vec<_>>(),
        [Code::E0101],
        "{e:?}"
    );
}
