//! Maze specs: every mistake gets its code, the line:col of the offending text (in the map file
//! when the map is a file of its own), and a suggestion where one exists. Layout codes are
//! E0701–E0705 (docs/errors.md). The robot spec is never read here (envspec checks the maze
//! only).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use envspec::maze::{Cell, from_document, load_maze, registry};
use envspec::value::parse_document;
use envspec::{Code, Diagnostic, Diagnostics, Override, SourceFile};

/// A per-test scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("envspec-maze-errors-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("maps")).expect("create scratch dir");
        Scratch(dir)
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).expect("write scratch file");
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A maze spec whose `map` is on line 5 (`map = ` is 6 characters: the value starts at col 7).
fn spec(map: &str, extra: &str) -> String {
    format!(
        "[maze]\nid = \"M-v0\"\nrobot = \"robot.toml\"\nmaze_size_scaling = 1.0\nmap = {map}\nmaze_height = 0.4\n{extra}"
    )
}

fn errors(s: &Scratch, text: &str, overrides: &[Override]) -> Diagnostics {
    let p = s.write("maze.toml", text);
    match load_maze(&p, overrides) {
        Ok(m) => panic!("accepted: {:?}", m.grid),
        Err(d) => d,
    }
}

/// `line:col` of a diagnostic, and the file it points into.
fn lc(d: &Diagnostic) -> String {
    let l = d.location.as_ref().expect("a location");
    let (line, col) = l.file.line_col(l.span.start);
    format!("{line}:{col}")
}
fn file_of(d: &Diagnostic) -> String {
    let l = d.location.as_ref().expect("a location");
    l.file.path.file_name().unwrap().to_string_lossy().into()
}
/// The text under the caret.
fn marked(d: &Diagnostic) -> String {
    let l = d.location.as_ref().expect("a location");
    l.file.text[l.span.clone()].to_string()
}

#[test]
fn rows_of_different_lengths_are_e0701_at_the_row() {
    let s = Scratch::new("e0701");
    let d = errors(
        &s,
        &spec("\"\"\"\n1 1 1 1\n1 r g\n1 1 1 1\n\"\"\"", ""),
        &[],
    );
    assert_eq!(d.codes(), [Code::E0701]);
    assert_eq!(lc(&d.0[0]), "7:1");
    assert_eq!(marked(&d.0[0]), "1 r g");
    assert_eq!(d.0[0].message, "maze row 1 has 3 cells but row 0 has 4");
    assert_eq!(d.0[0].label.as_deref(), Some("expected 4 cells"));
    // Arrays of rows: the caret is under the row.
    let d = errors(&s, &spec("[[1, 1, 1], [1, \"g\"], [1, 1, 1]]", ""), &[]);
    assert_eq!(d.codes(), [Code::E0701]);
    assert_eq!(lc(&d.0[0]), "5:19");
    assert_eq!(marked(&d.0[0]), "[1, \"g\"]");
}

#[test]
fn unknown_cells_are_e0702_with_the_allowed_ones() {
    let s = Scratch::new("e0702");
    let d = errors(
        &s,
        &spec("\"\"\"\n1 1 1 1\n1 r x 1\n1 1 1 1\n\"\"\"", ""),
        &[],
    );
    assert_eq!(d.codes(), [Code::E0702]);
    assert_eq!(lc(&d.0[0]), "7:5");
    assert_eq!(d.0[0].message, "unknown maze cell `x`");
    assert_eq!(
        d.0[0].help.as_deref(),
        Some("a cell is one of 1 (wall), 0 (free), r (reset), g (goal), c (reset and goal)")
    );
    // An escaped newline in a one-line string: the column is the one in the file.
    let d = errors(&s, &spec("\"1 1 1\\n1 G 1\\n1 1 1\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0702]);
    assert_eq!(lc(&d.0[0]), "5:17");
    assert_eq!(marked(&d.0[0]), "G");
    assert_eq!(
        d.0[0].help.as_deref(),
        Some("cells are lowercase: did you mean `g`?")
    );
    // Cells run together.
    let d = errors(&s, &spec("'''\n1111\n1rg1\n1111'''", ""), &[]);
    assert_eq!(d.codes(), [Code::E0702, Code::E0702, Code::E0702]);
    assert_eq!(lc(&d.0[1]), "7:1");
    assert!(
        d.0[1]
            .help
            .as_deref()
            .unwrap()
            .starts_with("separate cells with spaces: `1 r g 1`"),
        "{}",
        d.0[1]
    );
    // Array cells.
    let d = errors(&s, &spec("[[1, 1, 1], [1, \"q\", 1], [1, 1, 1]]", ""), &[]);
    assert_eq!(d.codes(), [Code::E0702]);
    assert_eq!(lc(&d.0[0]), "5:23");
    assert_eq!(marked(&d.0[0]), "\"q\"");
}

#[test]
fn no_goal_or_no_reset_is_e0703_e0704_after_the_reference_fallbacks() {
    let s = Scratch::new("e0703");
    // Only reset cells and walls: the fallback (free cells become goals) finds no free cell.
    let d = errors(&s, &spec("\"1 r 1\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0703]);
    assert_eq!(lc(&d.0[0]), "5:7");
    assert_eq!(d.0[0].message, "the maze has no goal cell");
    let d = errors(&s, &spec("\"1 g 1\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0704]);
    assert_eq!(d.0[0].message, "the maze has no reset cell");
    assert_eq!(lc(&d.0[0]), "5:7");
    // All walls: neither.
    let d = errors(&s, &spec("\"1 1\\n1 1\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0703, Code::E0704]);
    // As Gymnasium-Robotics: a free cell is a goal when there is no g/c, a reset when no r/c.
    for ok in ["\"1 r 0 1\"", "\"1 0 g 1\"", "\"1 0 0 1\""] {
        let p = s.write("ok.toml", &spec(ok, ""));
        assert!(load_maze(&p, &[]).is_ok(), "{ok}");
    }
}

#[test]
fn an_unreachable_goal_is_e0705_at_the_goal_cell() {
    let s = Scratch::new("e0705");
    let walled = "\"\"\"\n1 1 1 1 1\n1 r 1 g 1\n1 1 1 1 1\n\"\"\"";
    let d = errors(&s, &spec(walled, ""), &[]);
    assert_eq!(d.codes(), [Code::E0705]);
    assert_eq!(lc(&d.0[0]), "7:7");
    assert_eq!(marked(&d.0[0]), "g");
    assert_eq!(
        d.0[0].message,
        "goal cell (row 1, col 3) cannot be reached from any reset cell"
    );
    // Free cells meeting only at a corner are not connected (the wall blocks meet there).
    let diagonal = "\"\"\"\n1 1 1 1\n1 r 1 1\n1 1 g 1\n1 1 1 1\n\"\"\"";
    let d = errors(&s, &spec(diagonal, ""), &[]);
    assert_eq!(d.codes(), [Code::E0705]);
    assert_eq!(lc(&d.0[0]), "8:5");
    // Several cut-off goals: one diagnostic, counting the others.
    let two = "\"\"\"\n1 1 1 1 1\n1 r 1 g 1\n1 0 1 g 1\n1 1 1 1 1\n\"\"\"";
    let d = errors(&s, &spec(two, ""), &[]);
    assert_eq!(d.codes(), [Code::E0705]);
    assert!(
        d.0[0].message.ends_with("(and 1 more goal cell)"),
        "{}",
        d.0[0]
    );
    // A goal whose only reset cell is its own cell (a lone `c`): the reset draw skips the goal's
    // cell, so no episode could start elsewhere.
    let d = errors(&s, &spec("\"1 c 1\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0705]);
    assert_eq!(lc(&d.0[0]), "5:10");
    // Reachable around a corner.
    let p = s.write(
        "ok.toml",
        &spec("\"\"\"\n1 1 1 1\n1 r 0 1\n1 1 g 1\n1 1 1 1\n\"\"\"", ""),
    );
    let m = load_maze(&p, &[]).unwrap();
    assert_eq!(m.grid[3], [Cell::Wall; 4]);
}

#[test]
fn map_file_errors_point_into_the_map_file() {
    let s = Scratch::new("map_file");
    s.write(
        "maps/bad.toml",
        "name = \"Bad\"\ngrid = \"\"\"\n1 1 1 1\n1 r 0 1\n1 0 gg 1\n1 1 1 1\n\"\"\"\n",
    );
    let d = errors(&s, &spec("\"maps/bad.toml\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0702]);
    assert_eq!(file_of(&d.0[0]), "bad.toml");
    assert_eq!(lc(&d.0[0]), "5:5");
    // Unknown keys of a map file.
    s.write("maps/key.toml", "nmae = \"X\"\ngrid = \"1 r g 1\"\n");
    let d = errors(&s, &spec("\"maps/key.toml\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0101]);
    assert_eq!(
        (file_of(&d.0[0]), lc(&d.0[0])),
        ("key.toml".into(), "1:1".into())
    );
    assert_eq!(d.0[0].help.as_deref(), Some("did you mean `name`?"));
    // A missing map file: E0600 at the `map` value.
    let d = errors(&s, &spec("\"maps/none.toml\"", ""), &[]);
    assert_eq!(d.codes(), [Code::E0600]);
    assert_eq!(
        (file_of(&d.0[0]), lc(&d.0[0])),
        ("maze.toml".into(), "5:7".into())
    );
}

#[test]
fn keys_and_values_of_maze_are_located() {
    let s = Scratch::new("keys");
    let d = errors(&s, &spec("\"1 r g 1\"", "maze_size_scalling = 2.0\n"), &[]);
    assert_eq!(d.codes(), [Code::E0101]);
    assert_eq!(lc(&d.0[0]), "7:1");
    assert_eq!(
        d.0[0].help.as_deref(),
        Some("did you mean `maze_size_scaling`?")
    );
    let d = errors(&s, &spec("\"1 r g 1\"", "reward_type = \"sparce\"\n"), &[]);
    assert_eq!(d.codes(), [Code::E0104]);
    assert_eq!(lc(&d.0[0]), "7:15");
    assert_eq!(d.0[0].help.as_deref(), Some("did you mean `sparse`?"));
    let text = spec("\"1 r g 1\"", "max_episode_steps = -3\n").replace("0.4", "0.0");
    let d = errors(&s, &text, &[]);
    assert_eq!(d.codes(), [Code::E0105, Code::E0105]);
    assert_eq!(lc(&d.0[0]), "6:15");
    assert_eq!(lc(&d.0[1]), "7:21");
    let d = errors(&s, &spec("\"1 r g 1\"", "continuing_task = 1\n"), &[]);
    assert_eq!(d.codes(), [Code::E0102]);
    assert_eq!(lc(&d.0[0]), "7:19");
    let d = errors(&s, "[maze]\nid = \"M-v0\"\nmap = \"1 r g 1\"\n", &[]);
    assert_eq!(d.codes(), [Code::E0103, Code::E0103, Code::E0103]);
    assert_eq!(lc(&d.0[0]), "1:2");
    assert_eq!(d.0[0].message, "missing `robot` in [maze]");
}

#[test]
fn overrides_are_located_in_their_own_text() {
    let s = Scratch::new("overrides");
    let text = spec("\"1 r g 1\"", "");
    let d = errors(&s, &text, &[Override::text("maze_size_scaling", "-1.0")]);
    assert_eq!(d.codes(), [Code::E0105]);
    assert_eq!(
        d.0[0].position().as_deref(),
        Some("<override maze_size_scaling>:1:1")
    );
    // A grid given as an override: its cells are located in the override text.
    let d = errors(&s, &text, &[Override::text("map", "1 r z 1")]);
    assert_eq!(d.codes(), [Code::E0702]);
    assert_eq!(d.0[0].position().as_deref(), Some("<override map>:1:5"));
    // Unknown names go to the robot, after `robot_params`.
    let p = s.write(
        "ok.toml",
        &spec(
            "\"1 r g 1\"",
            "robot_params = { reset_noise_scale = 0.0 }\n",
        ),
    );
    let m = load_maze(&p, &[Override::text("ctrl_cost_weight", "0.1")]).unwrap();
    let names: Vec<&str> = m.robot_overrides.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["reset_noise_scale", "ctrl_cost_weight"]);
}

#[test]
fn from_document_reads_an_already_parsed_file() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/robotics/maze");
    let path = dir.join("ant_maze.toml");
    let file = SourceFile::new(&path, std::fs::read_to_string(&path).unwrap());
    let root = parse_document(&file).unwrap();
    let m = from_document(&Arc::clone(&file), &root, &[]).unwrap();
    assert_eq!(m.id, "AntMaze_UMaze-v5");
    assert_eq!((m.rows(), m.cols()), (5, 5));
    assert_eq!(m.maze_size_scaling, 4.0);
    let at = m.locations.maze_size_scaling.as_ref().unwrap().position();
    assert!(at.ends_with("ant_maze.toml:11:21"), "{at}");
}

#[test]
fn every_bundled_maze_loads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let reg = registry(&root.join("specs/robotics/maze/registry.toml")).unwrap();
    assert_eq!(reg.len(), 40);
    for r in &reg {
        let m = load_maze(&r.spec, &r.overrides).unwrap_or_else(|d| panic!("{}: {d}", r.id));
        assert!(!m.grid.is_empty(), "{}", r.id);
    }
    let go1 = root.join("specs/examples/go1_maze.toml");
    assert_eq!(load_maze(&go1, &[]).unwrap().id, "Go1Maze_UMaze-v0");
}

#[test]
fn registry_errors_are_located() {
    let s = Scratch::new("registry");
    let p = s.write(
        "registry.toml",
        "[[family]]\nspec = \"m.toml\"\nid = 3\n[family.maps]\nU = \"maps/u.toml\"\n",
    );
    let d = registry(&p).unwrap_err();
    assert_eq!(d.codes(), [Code::E0102]);
    assert_eq!(lc(&d.0[0]), "3:6");
    let p = s.write("registry.toml", "[[famliy]]\nspec = \"m.toml\"\n");
    let d = registry(&p).unwrap_err();
    assert_eq!(d.codes(), [Code::E0101, Code::E0103]);
    assert_eq!(d.0[0].help.as_deref(), Some("did you mean `family`?"));
}

#[test]
fn ids_gymnasium_cannot_register_are_e0111_where_written() {
    let s = Scratch::new("ids");
    for bad in ["a/b-v0", "", "My Maze-v0"] {
        let d = errors(&s, &spec("\"1 r g 1\"", "").replace("M-v0", bad), &[]);
        assert_eq!(d.codes(), [Code::E0111], "{bad:?}");
        assert_eq!(lc(&d.0[0]), "2:6", "{bad:?}");
    }
    // A registry's map key becomes part of the id: located at the key.
    let p = s.write(
        "registry.toml",
        "[[family]]\nspec = \"m.toml\"\nid = \"P_{map}{reward}-v3\"\n[family.maps]\nU = { map = \"u.toml\" }\n\"Big U\" = { map = \"u.toml\" }\n",
    );
    let d = registry(&p).unwrap_err();
    assert_eq!(d.codes(), [Code::E0111, Code::E0111]);
    assert_eq!(lc(&d.0[0]), "6:1");
    assert!(
        d.0[0].message.contains("`P_Big U-v3`"),
        "{}",
        d.0[0].message
    );
}
