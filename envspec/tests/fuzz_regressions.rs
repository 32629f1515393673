//! Inputs the fuzzer (cli/tests/fuzz.rs, docs/fuzzing.md) found crashing a pure reader, each
//! checked to give its diagnostic, rendered, instead.

use envspec::Code;
use envspec::maze::load_maze;

fn scratch(test: &str) -> crate::scratch::ScratchDir {
    crate::scratch::ScratchDir::new(&format!("fuzz-regressions-{test}"))
}

/// A non-ASCII maze cell: its span ended inside the character (`é` is 2 bytes) and rendering the
/// E0702 panicked ("end byte index 135 is not a char boundary"), in a string row and an array row.
#[test]
fn a_non_ascii_maze_cell_is_e0702_under_the_whole_character() {
    let dir = scratch("non-ascii-cell");
    for (map, line, col) in [
        ("\"\"\"\n1 1 1 1\n1 r é 1\n1 g 1 1\n\"\"\"", 6, 5),
        ("'''\n1 1 1\n1é r\n'''", 6, 1),
        ("[\"1 1 1 1\", \"1 r 日本 g\", \"1 1 1 1\"]", 4, 24),
    ] {
        let p = dir.join("maze.toml");
        std::fs::write(
            &p,
            format!(
                "[maze]\nid = \"M-v0\"\nrobot = \"robot.toml\"\nmap = {map}\nmaze_size_scaling = 1.0\nmaze_height = 0.4\n"
            ),
        )
        .unwrap();
        let d = load_maze(&p, &[]).unwrap_err();
        assert_eq!(d.codes()[0], Code::E0702, "{d}");
        let l = d.0[0].location.as_ref().unwrap();
        assert_eq!(l.file.line_col(l.span.start), (line, col), "{map}");
        let marked = &l.file.text[l.span.clone()];
        assert!(marked.contains('é') || marked.contains('日'), "{marked:?}");
        let shown = d.to_string();
        assert!(shown.contains("error[E0702]"), "{shown}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
