//! What a diagnostic prints is for people: a long line is clipped around the caret,
//! control and bidi characters are escaped wherever input is echoed, a file that is not UTF-8 is
//! located at its first bad byte, and a cycle of `[agents] base` files is one error naming it.

use std::path::{Path, PathBuf};

use envspec::{Code, Diagnostics, Spec};

/// A per-test scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("envspec-messages-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch dir");
        Scratch(dir)
    }
    fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, bytes).expect("write scratch file");
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn parse(text: &str) -> Diagnostics {
    Spec::parse(Path::new("s.toml"), text.to_string()).expect_err("the spec must be rejected")
}

#[test]
fn a_two_megabyte_line_is_shown_as_a_window_around_the_caret() {
    let long = "a".repeat(2_000_000);
    let d = parse(&format!("[env]\nid = \"X-v0\"\nbogus = \"{long}\"\n"));
    let out = d.to_string();
    assert!(out.len() < 2_000, "{} bytes printed", out.len());
    let e = d.iter().find(|e| e.code == Code::E0101).expect("E0101");
    assert_eq!(e.position().as_deref(), Some("s.toml:3:1"));
    let shown = e.to_string();
    // The window starts at the line's start (the caret is at column 1) and is clipped after.
    assert!(
        shown.contains(&format!("3 | bogus = \"{}…\n", "a".repeat(111))),
        "{shown}"
    );
    assert!(shown.contains("  | ^^^^^ "), "{shown}");

    // A caret deep in the line: the window is clipped on both sides, the caret stays under it.
    // (a TOML syntax error: the doubled comma at column 300 006)
    let d = parse(&format!(
        "[env]\nid = \"X-v0\"\nx = [{}, \"q\"{}]\n",
        "1, ".repeat(100_000),
        ", 2".repeat(100_000)
    ));
    let e = d.iter().next().expect("a diagnostic");
    assert_eq!(e.position().as_deref(), Some("s.toml:3:300006"));
    let shown = e.to_string();
    let snippet = shown.lines().nth(3).expect("the line");
    let caret = shown.lines().nth(4).expect("the caret line");
    assert!(
        snippet.starts_with("3 | …") && snippet.ends_with('…'),
        "{shown}"
    );
    assert!(snippet.chars().count() < 140, "{shown}");
    let col = caret.chars().position(|c| c == '^').expect("a caret");
    let under: String = snippet.chars().skip(col).take(5).collect();
    assert_eq!(under, ", \"q\"", "{shown}");
}

#[test]
fn a_two_megabyte_name_is_clipped_in_the_message() {
    let key = "k".repeat(2_000_000);
    let d = parse(&format!("[env]\nid = \"X-v0\"\n{key} = 1\n"));
    let out = d.to_string();
    assert!(out.len() < 3_000, "{} bytes printed", out.len());
    let e = d.iter().find(|e| e.code == Code::E0101).expect("E0101");
    assert!(
        e.message.ends_with("… (1999623 more characters)"),
        "{}",
        &e.message[e.message.len() - 100..]
    );
}

#[test]
fn bidi_and_control_characters_are_escaped_in_names_values_and_lines() {
    // A key holding a raw right-to-left override and an escaped ESC.
    let d = parse("[env]\nid = \"X-v0\"\n\"ab\u{202e}cd\\u001b[2J\" = 1\n");
    let e = d
        .iter()
        .find(|e| e.code == Code::E0101)
        .unwrap_or_else(|| panic!("{d}"));
    let shown = e.to_string();
    assert!(
        e.message.contains("unknown key `ab\\u{202e}cd\\u{1b}[2J`"),
        "{}",
        e.message
    );
    for raw in ['\u{202e}', '\u{1b}'] {
        assert!(!shown.contains(raw), "raw {raw:?} printed: {shown}");
    }
    assert!(
        shown.contains("3 | \"ab\\u{202e}cd\\u001b[2J\" = 1"),
        "{shown}"
    );
    // The caret spans the key as shown (23 characters, quotes included).
    assert!(
        shown.contains(&format!("  | {} ", "^".repeat(23))),
        "{shown}"
    );
    // A raw control character in a line (a TOML syntax error) is escaped too.
    let d = parse("[env]\nid = \"X-v0\"\n\"a\u{1b}[2J\" = 1\n");
    let shown = d.to_string();
    assert!(!shown.contains('\u{1b}'), "{shown}");
    assert!(shown.contains("3 | \"a\\u{1b}[2J\" = 1"), "{shown}");
    // A value: an isolate in a string the reader rejects.
    let d = parse("[env]\nid = \"X-v0\"\nframe_skip = \"\u{2066}4\u{2069}\"\n");
    let shown = d.to_string();
    assert!(!shown.contains('\u{2066}'), "{shown}");
    assert!(shown.contains("\"\\u{2066}4\\u{2069}\""), "{shown}");
}

#[test]
fn a_file_that_is_not_utf8_is_located_at_its_first_bad_byte() {
    let s = Scratch::new("utf8");
    let p = s.write("bad.toml", b"[env]\nid = \"caf\xe9-v0\"\n");
    let d = envspec::open_file(&p, &[]).expect_err("not UTF-8");
    assert_eq!(d.codes(), [Code::E0600], "{d}");
    let e = &d.0[0];
    assert_eq!(e.message, "the spec file is not UTF-8 text");
    assert_eq!(e.position(), Some(format!("{}:2:10", p.display())), "{d}");
    assert_eq!(e.label.as_deref(), Some("invalid UTF-8 byte 0xe9"));
    assert!(e.to_string().contains("2 | id = \"caf\u{fffd}-v0\""), "{e}");

    // A model file likewise (E0301, the model's own code).
    let m = s.write("m.xml", b"<mujoco>\n<worldbody>\xff</worldbody></mujoco>\n");
    let d = envspec::ModelInfo::from_file(&m).expect_err("not UTF-8");
    assert_eq!(d.code, Code::E0301);
    assert_eq!(d.position(), Some(format!("{}:2:12", m.display())));
}

#[test]
fn a_base_that_is_its_own_file_is_one_cycle_error() {
    let s = Scratch::new("self");
    let a = s.write(
        "a.toml",
        "[agents]\nbase = \"a.toml\"\nagent_conf = \"2x1\"\n",
    );
    let d = envspec::open_file(&a, &[]).expect_err("a cycle");
    assert_eq!(d.codes(), [Code::E0120], "{d}");
    let e = &d.0[0];
    assert_eq!(e.message, "`base` names this file itself");
    assert_eq!(e.position(), Some(format!("{}:2:8", a.display())));
    let help = e.help.as_deref().unwrap_or_default();
    assert!(help.contains("a.toml → "), "{help}");
}

#[test]
fn a_longer_cycle_of_bases_is_named_link_by_link() {
    let s = Scratch::new("cycle");
    let a = s.write("a.toml", "[agents]\nbase = \"b.toml\"\n");
    s.write("b.toml", "[agents]\nbase = \"./c.toml\"\n");
    s.write("c.toml", "[agents]\nbase = \"a.toml\"\n");
    let d = envspec::open_file(&a, &[]).expect_err("a cycle");
    assert_eq!(d.codes(), [Code::E0120], "{d}");
    let e = &d.0[0];
    let dir = s.0.display();
    assert_eq!(
        e.message,
        format!(
            "`base` leads back to a spec already on its chain: {dir}/a.toml → {dir}/b.toml → {dir}/c.toml → {dir}/a.toml"
        )
    );
    assert_eq!(e.position(), Some(format!("{dir}/a.toml:2:8")));
}

#[test]
fn a_base_that_is_a_multi_agent_spec_names_the_task_it_splits() {
    let s = Scratch::new("chain");
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/gymnasium/ant.toml");
    let a = s.write("a.toml", "[agents]\nbase = \"b.toml\"\n");
    s.write("b.toml", format!("[agents]\nbase = {root:?}\n"));
    let d = envspec::open_file(&a, &[]).expect_err("a chain");
    assert_eq!(d.codes(), [Code::E0121], "{d}");
    let e = &d.0[0];
    let dir = s.0.display();
    assert_eq!(
        e.message,
        format!("`base` names a multi-agent spec, not a task spec: {dir}/a.toml → {dir}/b.toml")
    );
    let help = e.help.as_deref().unwrap_or_default();
    assert!(help.ends_with("specs/gymnasium/ant.toml"), "{help}");
}

#[test]
fn one_is_singular() {
    let text = "[maze]\nid = \"M-v0\"\nrobot = \"r.toml\"\nmaze_size_scaling = 1.0\nmaze_height = 0.4\nmap = \"1 1\\n1\"\n";
    let file = envspec::SourceFile::new("m.toml", text.to_string());
    let root = envspec::value::parse_document(&file).expect("TOML");
    let d = envspec::maze::from_document(&file, &root, &[]).expect_err("ragged");
    assert_eq!(d.0[0].message, "maze row 1 has 1 cell but row 0 has 2");
    assert_eq!(d.0[0].label.as_deref(), Some("expected 2 cells"));
    assert!(d.to_string().ends_with("\n1 error found"), "{d}");
}
