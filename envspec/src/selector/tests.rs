//! Selector text → indices, against a small hand-built model whose numbering is written out below,
//! so every expected index is read off that table (MuJoCo's qpos / dof widths: free 7 / 6,
//! hinge and slide 1 / 1; `cfrc_ext` 6 per body, `xpos` 3, per the mjData docs).

use std::path::PathBuf;

use super::parse::{Index, parse};
use super::{Field, ParamIndex, Selection, glob, resolve};
use crate::diagnostic::{Code, Diagnostic, Location, SourceFile};
use crate::mjcf::{Actuator, Joint, JointKind, ModelInfo};

/// bodies: 0 world, 1 torso, 2 thigh, 3 foot, 4 target (mocap)
/// qpos:   0..7 root (x y z qw qx qy qz), 7 hip_1, 8 knee, 9 ankle_4          (nq 10)
/// qvel:   0..6 root (vx vy vz wx wy wz), 6 hip_1, 7 knee, 8 ankle_4          (nv 9)
/// sites:  0 tip, 1 unnamed (`site1`); actuators: 0 a_hip, 1 unnamed (`actuator1`), 2 a_ankle
/// sensordata: 0 touch, 1..4 accel (3 values); tendons: 0 t0
fn model() -> ModelInfo {
    let joint = |name: &str, kind, body, qposadr, dofadr| Joint {
        name: name.into(),
        kind,
        body,
        qposadr,
        dofadr,
    };
    let actuator = |name: &str| Actuator {
        name: name.into(),
        target: None,
    };
    ModelInfo {
        path: PathBuf::from("tiny.xml"),
        timestep: 0.002,
        bodies: ["world", "torso", "thigh", "foot", "target"]
            .map(String::from)
            .to_vec(),
        joints: vec![
            joint("root", JointKind::Free, 1, 0, 0),
            joint("hip_1", JointKind::Hinge, 2, 7, 6),
            joint("knee", JointKind::Slide, 2, 8, 7),
            joint("ankle_4", JointKind::Hinge, 3, 9, 8),
        ],
        sites: vec!["tip".into(), String::new()],
        site_bodies: vec![3, 3],
        actuators: vec![actuator("a_hip"), actuator(""), actuator("a_ankle")],
        tendons: vec!["t0".into()],
        geoms: vec![],
        nq: 10,
        nv: 9,
        keyframes: vec![],
        sensors: vec![("touch".into(), Some(1)), ("accel".into(), Some(3))],
        mocap: vec![4],
    }
}

fn loc(text: &str) -> Location {
    Location::new(&SourceFile::new("spec.toml", text.into()), 0..text.len())
}

fn no_param(p: &str) -> Result<ParamIndex, Diagnostic> {
    panic!("no parameter expected, asked for `{p}`")
}

fn sel(text: &str) -> Selection {
    resolve(text, &loc(text), &model(), &no_param).unwrap_or_else(|e| panic!("{text}: {e:?}"))
}

fn idx(text: &str) -> Vec<usize> {
    sel(text).indices
}

fn err(text: &str) -> Diagnostic {
    match resolve(text, &loc(text), &model(), &no_param) {
        Ok(s) => panic!("{text} resolved to {:?}", s.indices),
        Err(e) => e,
    }
}

fn parsed(text: &str) -> (String, Vec<Index>) {
    parse(text, &loc(text)).unwrap_or_else(|e| panic!("{text}: {e:?}"))
}

fn parse_err(text: &str) -> Diagnostic {
    match parse(text, &loc(text)) {
        Ok((f, i)) => panic!("{text} parsed to {f} {i:?}"),
        Err(e) => e,
    }
}

#[test]
fn parse_reads_the_field_and_each_index_form() {
    let (f, i) = parsed("  qpos ");
    assert_eq!((f.as_str(), i.len()), ("qpos", 0));
    let (f, i) = parsed("qpos[2:]");
    assert_eq!(f, "qpos");
    assert!(matches!(i[..], [Index::Slice(Some(2), None)]));
    assert!(matches!(
        parsed("qpos[:-1]").1[..],
        [Index::Slice(None, Some(-1))]
    ));
    assert!(matches!(
        parsed("qpos[ : ]").1[..],
        [Index::Slice(None, None)]
    ));
    assert!(matches!(parsed("qpos[-3]").1[..], [Index::Int(-3)]));
    assert!(matches!(parsed("qpos[ 4 ]").1[..], [Index::Int(4)]));
    let (_, i) = parsed("site_xpos[tip][0, 2]");
    assert!(matches!(&i[..], [Index::Name(n), Index::List(l)] if n == "tip" && l == &[0, 2]));
    let (_, i) = parsed("xpos[$main_body][0:2]");
    assert!(
        matches!(&i[..], [Index::Param(p), Index::Slice(Some(0), Some(2))] if p == "main_body")
    );
    // A `.column` is the second index, as `xpos[torso][x]`.
    let (_, i) = parsed("xpos[torso].x");
    assert!(matches!(&i[..], [Index::Name(a), Index::Name(b)] if a == "torso" && b == "x"));
}

#[test]
fn parse_keeps_names_with_colons_and_name_lists_whole() {
    // A slice's ends are integers or empty; anything else with a `:` is one name.
    for text in ["root:z", "hip_1:ankle_4", "1:b", "1:2:3"] {
        let (_, i) = parsed(&format!("qpos[{text}]"));
        assert!(
            matches!(&i[..], [Index::Name(n)] if n == text),
            "{text}: {i:?}"
        );
    }
    let (_, i) = parsed("qpos[goal_x, goal_y,goal_z]");
    assert!(matches!(&i[..], [Index::Names(l)] if l == &["goal_x", "goal_y", "goal_z"]));
    // Names and integers mixed stay a list of names (the integers are read later).
    let (_, i) = parsed("xpos[torso][1, z]");
    assert!(matches!(&i[1], Index::Names(l) if l == &["1", "z"]));
}

#[test]
fn parse_refuses_malformed_brackets_with_e0401() {
    let cases = [
        ("qpos[1", "missing `]`"),
        ("qpos[]", "empty `[]`"),
        ("qpos[1]x[2]", "expected `[` after `]`"),
        ("qpos[1][2][3]", "at most two indices"),
        ("qpos[a,,b]", "an empty entry in a `,` list"),
        ("xpos[torso].x y", "`.x y` is not a column name"),
        ("xpos[torso].", "`.` is not a column name"),
        (
            "xpos[torso][0].x",
            "a `.column` follows exactly one `[rows]`",
        ),
    ];
    for (text, msg) in cases {
        let e = parse_err(text);
        assert_eq!(e.code, Code::E0401, "{text}");
        assert!(
            e.message.starts_with("cannot read selector: ") && e.message.contains(msg),
            "{text}: {}",
            e.message
        );
    }
}

#[test]
fn whole_fields_and_generated_row_names() {
    let s = sel("qpos");
    assert_eq!(s.indices, (0..10).collect::<Vec<_>>());
    assert_eq!(
        s.names,
        [
            "root:x", "root:y", "root:z", "root:qw", "root:qx", "root:qy", "root:qz", "hip_1",
            "knee", "ankle_4"
        ]
        .map(|n| format!("qpos[{n}]"))
    );
    let s = sel("qvel");
    assert_eq!(s.len(), 9);
    assert_eq!(s.names[3], "qvel[root:wx]");
    assert_eq!(s.names[8], "qvel[ankle_4]");
    // Unnamed elements are named by kind and id.
    assert_eq!(
        sel("ctrl").names,
        ["ctrl[a_hip]", "ctrl[actuator1]", "ctrl[a_ankle]"]
    );
    assert_eq!(sel("site_xpos[1]").names[0], "site_xpos[site1].x");
    // ten_J: one row per (tendon, dof), 1 × 9.
    let s = sel("ten_J");
    assert_eq!(s.len(), 9);
    assert_eq!(s.names[0], "ten_J[t0:root:vx]");
    assert_eq!(s.names[8], "ten_J[t0:ankle_4]");
}

#[test]
fn integers_and_slices_follow_python() {
    assert_eq!(idx("qpos[2:]"), (2..10).collect::<Vec<_>>());
    assert_eq!(idx("qpos[:2]"), [0, 1]);
    assert_eq!(idx("qpos[-1]"), [9]);
    assert_eq!(sel("qpos[-1]").names, ["qpos[ankle_4]"]);
    assert_eq!(idx("qpos[-3:-1]"), [7, 8]);
    assert_eq!(idx("qpos[0,9,-10]"), [0, 9, 0]);
    // Slices clamp (`list(range(10))[5:100] == [5..9]`), an empty one selects nothing.
    assert_eq!(idx("qpos[5:100]"), [5, 6, 7, 8, 9]);
    assert_eq!(idx("qpos[-100:2]"), [0, 1]);
    assert!(idx("qpos[8:2]").is_empty());
    // Rows of 6: body 1..4 of 5 bodies is flat 6..30.
    assert_eq!(idx("cfrc_ext[1:]"), (6..30).collect::<Vec<_>>());
    assert_eq!(idx("cinert[1]").len(), 10);
}

#[test]
fn out_of_range_integers_are_e0304() {
    for (text, msg) in [
        ("qpos[10]", "index 10 is out of range for 10 entries"),
        ("qpos[-11]", "index -11 is out of range for 10 entries"),
        ("qpos[0,10]", "index 10 is out of range for 10 entries"),
        ("xpos[torso][3]", "index 3 is out of range for 3 entries"),
    ] {
        let e = err(text);
        assert_eq!((e.code, e.message.as_str()), (Code::E0304, msg), "{text}");
    }
}

#[test]
fn names_select_an_elements_rows() {
    assert_eq!(idx("qpos[root]"), [0, 1, 2, 3, 4, 5, 6]);
    assert_eq!(idx("qvel[root]"), [0, 1, 2, 3, 4, 5]);
    assert_eq!(idx("qpos[knee]"), [8]);
    assert_eq!(idx("qvel[knee]"), [7]);
    // One element of a free joint, by the name `envc show` prints.
    assert_eq!(idx("qpos[root:z]"), [2]);
    assert_eq!(idx("qvel[root:wz]"), [5]);
    assert_eq!(idx("ctrl[actuator1]"), [1]);
    assert_eq!(idx("site_xpos[site1]"), [3, 4, 5]);
    assert_eq!(idx("sensordata[accel]"), [1, 2, 3]);
    assert_eq!(idx("sensordata[accel:2]"), [3]);
    assert_eq!(idx("mocap_pos[target]"), [0, 1, 2]);
    assert_eq!(idx("mocap_quat[target]"), [0, 1, 2, 3]);
    assert_eq!(idx("mass_center[y]"), [1]);
    // Names and integers listed in order, repeats kept.
    assert_eq!(idx("qpos[ankle_4, 0, hip_1]"), [9, 0, 7]);
}

#[test]
fn name_ranges_include_both_ends() {
    assert_eq!(idx("qpos[hip_1:ankle_4]"), [7, 8, 9]);
    assert_eq!(idx("qvel[hip_1 : knee]"), [6, 7]);
    // From a whole joint's first row to the last's last row.
    assert_eq!(idx("qpos[root:knee]"), (0..=8).collect::<Vec<_>>());
    // `root:z:knee` splits only as `root:z` .. `knee` (`z:knee` names nothing).
    assert_eq!(idx("qpos[root:z:knee]"), (2..=8).collect::<Vec<_>>());
    assert_eq!(idx("xpos[thigh:foot]"), (6..12).collect::<Vec<_>>());
    let e = err("qpos[ankle_4:hip_1]");
    assert_eq!(e.code, Code::E0401);
    assert_eq!(e.message, "cannot read the name range `ankle_4:hip_1`");
    assert!(e.label.unwrap().contains("`ankle_4` comes after `hip_1`"));
}

#[test]
fn columns_by_index_name_or_dot() {
    // torso is body 1: xpos rows of 3 start at 3.
    assert_eq!(idx("xpos[torso]"), [3, 4, 5]);
    assert_eq!(idx("xpos[torso][0:2]"), [3, 4]);
    assert_eq!(idx("xpos[torso][-1]"), [5]);
    assert_eq!(idx("xpos[torso].z"), [5]);
    assert_eq!(idx("xpos[torso][y]"), [4]);
    assert_eq!(idx("xpos[torso][z, 0]"), [5, 3]);
    assert_eq!(idx("site_xpos[tip][0,2]"), [0, 2]);
    assert_eq!(
        sel("xpos[torso][0:2]").names,
        ["xpos[torso].x", "xpos[torso].y"]
    );
    // cfrc_ext is (rotational, translational): `tz` is column 5 of body 3 → 3·6 + 5.
    assert_eq!(idx("cfrc_ext[foot].tz"), [23]);
    assert_eq!(sel("xquat[torso].w").names, ["xquat[torso].w"]);
    assert_eq!(idx("xquat[torso].w"), [4]);
}

#[test]
fn column_refusals() {
    let e = err("xpos[torso][w]");
    assert_eq!(e.code, Code::E0401);
    assert_eq!(e.message, "`w` is not a column of `xpos`");
    let e = err("xpos[torso][x, w]");
    assert_eq!(e.code, Code::E0401);
    assert_eq!(e.message, "`w` is not a column of `xpos`");
    // A vector field takes one index.
    let e = err("ctrl[0][0]");
    assert_eq!(e.code, Code::E0401);
    assert_eq!(
        e.message,
        "cannot read selector: `ctrl` is a vector: one index only"
    );
}

#[test]
fn unknown_fields_and_names() {
    let e = err("qpoz[0]");
    assert_eq!(e.code, Code::E0402);
    assert_eq!(e.message, "unknown field `qpoz` in selector `qpoz[0]`");
    assert_eq!(e.help.as_deref(), Some("did you mean `qpos`?"));
    // Without `[`, `.x` is part of the field name.
    assert_eq!(err("qpos.x").code, Code::E0402);
    let e = err("xpos[torsoo]");
    assert_eq!(e.code, Code::E0303);
    assert_eq!(e.message, "the model tiny.xml has no body named `torsoo`");
    assert_eq!(e.help.as_deref(), Some("did you mean `torso`?"));
    // A site selector naming a body points at xpos.
    let e = err("site_xpos[torso]");
    assert_eq!(e.code, Code::E0303);
    assert_eq!(
        e.help.as_deref(),
        Some("`torso` is a body of this model, not a site: its position is `xpos[torso]`")
    );
    // `1.5` is no integer, and an integer beyond 64 bits is no index: syntax errors.
    let e = err("qpos[1.5]");
    assert_eq!(e.code, Code::E0401);
    assert!(
        e.message.contains("`1.5` is not an integer"),
        "{}",
        e.message
    );
    for text in ["qpos[99999999999999999999:]", "qpos[99999999999999999999]"] {
        let e = err(text);
        assert_eq!(e.code, Code::E0401, "{text}");
        assert!(
            e.message.contains("too large for an index"),
            "{}",
            e.message
        );
    }
}

#[test]
fn params_give_a_name_or_an_index() {
    let m = model();
    type Looked = Result<ParamIndex, Diagnostic>;
    let name = |_: &str| -> Looked { Ok(ParamIndex::Name("knee".into())) };
    let int = |_: &str| -> Looked { Ok(ParamIndex::Int(-2)) };
    let l = loc("qpos[$j]");
    assert_eq!(resolve("qpos[$j]", &l, &m, &name).unwrap().indices, [8]);
    assert_eq!(resolve("qpos[$j]", &l, &m, &int).unwrap().indices, [8]);
    let refused =
        |p: &str| -> Looked { Err(Diagnostic::new(Code::E0303, format!("no parameter `{p}`"))) };
    let e = resolve("qpos[$j]", &l, &m, &refused).unwrap_err();
    assert_eq!(e.message, "no parameter `j`");
}

#[test]
fn field_table_matches_mjdata_widths() {
    let mut names: Vec<&str> = super::FIELDS.iter().map(|(n, _)| *n).collect();
    for (n, f) in super::FIELDS {
        assert_eq!(f.name(), *n);
    }
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), super::FIELDS.len(), "a field name twice");
    // mjData: cfrc_ext / cvel 6 per body, cinert 10, xquat 4, site_xmat 9, xpos 3.
    for (f, cols) in [
        (Field::CfrcExt, 6),
        (Field::Cvel, 6),
        (Field::Cinert, 10),
        (Field::Xquat, 4),
        (Field::SiteXmat, 9),
        (Field::Xpos, 3),
        (Field::Qpos, 1),
        (Field::Ctrl, 1),
    ] {
        assert_eq!(f.cols(), cols, "{}", f.name());
    }
}

#[test]
fn drop_first_and_glob_edges() {
    let mut s = sel("qpos[0:4]");
    s.drop_first(2);
    assert_eq!(s.indices, [2, 3]);
    assert_eq!(s.names, ["qpos[root:z]", "qpos[root:qw]"]);
    s.drop_first(5);
    assert!(s.is_empty() && s.names.is_empty());
    assert!(glob("", ""));
    assert!(glob("*", ""));
    assert!(!glob("?", ""));
    assert!(glob("**a", "a"));
    // Backtracking past a first partial match.
    assert!(glob("*ab", "aab"));
    assert!(glob("hip_?", "hip_1"));
    assert!(!glob("hip_?", "hip_12"));
}
