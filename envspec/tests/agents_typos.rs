//! A typo in a factorization's node name is one error with an honest suggestion: no
//! second, misleading "leaves actuators undriven", and no suggestion picked from several equally
//! close names.

use envspec::Code;

fn load_with(conf_first_node: &str) -> envspec::Diagnostics {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let text = std::fs::read_to_string(format!("{root}/specs/mamujoco/ant.toml"))
        .unwrap()
        .replace(
            "\"../gymnasium/ant.toml\"",
            &format!("\"{root}/specs/gymnasium/ant.toml\""),
        )
        .replacen(
            "[[\"hip1\", \"ankle1\"",
            &format!("[[\"{conf_first_node}\", \"ankle1\""),
            1,
        );
    let dir = std::env::temp_dir().join(format!(
        "envc-agents-typo-{}-{conf_first_node}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ant_agents.toml");
    std::fs::write(&p, text).unwrap();
    let d = envspec::multi_agent::load(&p, &[]).expect_err("a typo must not load");
    std::fs::remove_dir_all(&dir).ok();
    d
}

#[test]
fn a_node_typo_is_one_error() {
    let d = load_with("hipp1");
    assert_eq!(d.codes(), [Code::E0303], "{d}");
    assert_eq!(d.0[0].help.as_deref(), Some("did you mean `hip1`?"));
}

#[test]
fn equally_close_names_are_all_offered() {
    let d = load_with("hip");
    assert_eq!(d.codes(), [Code::E0303], "{d}");
    assert_eq!(
        d.0[0].help.as_deref(),
        Some("did you mean one of `hip1`, `hip2`, `hip3`, `hip4`?")
    );
}
