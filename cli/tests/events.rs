//! `[events]` through the command line: `envc show` prints the randomization table (the values
//! each element can take, from the compiled model: Ant's floor friction is 1, ant.xml's default),
//! and `envc diff` reports randomization changes in their own category, saying what each does to
//! the training distribution.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).to_path_buf()
}

/// Ant-v5 with `events` appended, written to `dir/name`, its model path made absolute.
fn spec(dir: &Path, name: &str, events: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("specs/gymnasium/ant.toml")).unwrap();
    let xml = root().join("assets/gymnasium/ant.xml");
    let text = text.replace(
        "default = \"../../assets/gymnasium/ant.xml\"",
        &format!("default = {:?}", xml.display().to_string()),
    );
    let path = dir.join(name);
    std::fs::write(&path, format!("{text}\n{events}")).unwrap();
    path
}

const OLD: &str = r#"
[events.floor_friction]
mode = "startup"
field = "geom_friction.sliding"
elements = "floor"
distribution = "uniform"
range = [0.8, 1.2]
operation = "scale"

[events.payload]
mode = "startup"
field = "body_mass"
elements = "torso"
distribution = "uniform"
range = [-0.5, 0.5]
operation = "add"
"#;

fn envc(args: &[&str]) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
    )
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("envc-cli-events-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn show_prints_the_randomization_table() {
    let dir = tmp("show");
    let p = spec(&dir, "ant.toml", OLD);
    let (code, out) = envc(&["show", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("randomization (2 events in draw order"),
        "{out}"
    );
    let row = out
        .lines()
        .find(|l| l.contains("floor_friction"))
        .unwrap_or_else(|| panic!("{out}"));
    for part in [
        "startup",
        "geom_friction.sliding",
        "floor",
        "uniform[0.8, 1.2]",
        "scale",
        " 1 ",
        "[0.8, 1.2]",
    ] {
        assert!(row.contains(part), "{part:?} in {row}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn diff_says_what_a_randomization_change_does() {
    let dir = tmp("diff");
    let old = spec(&dir, "old.toml", OLD);
    let new_events = OLD
        .replace("range = [0.8, 1.2]", "range = [0.5, 1.5]")
        .replace(
            "mode = \"startup\"\nfield = \"body_mass\"",
            "mode = \"reset\"\nfield = \"body_mass\"",
        )
        .replace("elements = \"torso\"", "elements = \"tors*\"");
    let new = spec(&dir, "new.toml", &new_events);
    let (code, out) = envc(&["diff", old.to_str().unwrap(), new.to_str().unwrap()]);
    assert_eq!(code, 3, "breaking: {out}");
    assert!(
        out.contains("randomization / training distribution —"),
        "{out}"
    );
    assert!(
        out.contains("`geom_friction.sliding` range widened from [0.8, 1.2] to [0.5, 1.5]: the policy trains on a wider distribution; returns are not comparable"),
        "{out}"
    );
    assert!(
        out.contains("! [events-range-changed] events.floor_friction: range"),
        "{out}"
    );
    assert!(
        out.contains("! [events-mode-changed] events.payload: mode: was startup"),
        "{out}"
    );
    // Another pattern matching the same body is no change of behaviour.
    assert!(
        out.contains("   [events-elements-changed] events.payload"),
        "{out}"
    );
    assert!(
        out.contains("the same elements are matched: no effect"),
        "{out}"
    );

    // Removing every event: two removals.
    let plain = spec(&dir, "plain.toml", "");
    let (_, out) = envc(&["diff", old.to_str().unwrap(), plain.to_str().unwrap()]);
    assert_eq!(out.matches("[events-removed]").count(), 2, "{out}");
    std::fs::remove_dir_all(&dir).ok();
}
