//! Every element name envc prints (`envc show`, diffs, `Selection::names`) pastes back into a
//! spec as a selector of exactly that element (`qpos[root:z]`, `xpos[torso].x` and
//! `xpos[torso][x]` among them). Checked over every selection of every bundled task spec, and
//! over every row of the fields a spec reads.

use envspec::diagnostic::{Location, SourceFile};
use envspec::selector::{self, Selection};

fn paste(name: &str, spec: &envspec::ResolvedSpec) -> Selection {
    let file = SourceFile::new("pasted.toml", name.to_string());
    let loc = Location::new(&file, 0..name.len());
    selector::resolve(name, &loc, &spec.model, &|p| {
        Err(envspec::Diagnostic::new(
            envspec::Code::E0201,
            format!("no ${p}"),
        ))
    })
    .unwrap_or_else(|d| panic!("{}: `{name}` does not paste back: {d}", spec.id))
}

#[test]
fn printed_names_paste_back_as_the_same_element() {
    let mut checked = 0;
    for e in envspec::registry::bundled().filter(|e| e.task) {
        let spec = envspec::load(&e.path, &[]).unwrap();
        // `derived[...]` names a spec's own tables: it pastes back within that spec (the
        // resolver's), not through the model alone.
        for s in spec
            .sources()
            .filter(|s| s.field != envspec::selector::Field::Derived)
        {
            for (name, &index) in s.names.iter().zip(&s.indices) {
                // The goal vector is the spec's, not the model's: its names are its indices.
                if s.field == envspec::Field::Goal {
                    assert_eq!(name, &format!("goal[{index}]"), "{}", spec.id);
                    checked += 1;
                    continue;
                }
                let back = paste(name, &spec);
                assert_eq!(
                    (back.field, back.indices.as_slice()),
                    (s.field, [index].as_slice()),
                    "{}: `{name}`",
                    spec.id
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 2000, "{checked}");
}

#[test]
fn columns_by_name_and_by_dot() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/gymnasium/ant.toml");
    let spec = envspec::load(root.as_ref(), &[]).unwrap();
    let a = paste("xpos[torso][x]", &spec);
    let b = paste("xpos[torso].x", &spec);
    let c = paste("xpos[torso][0]", &spec);
    assert_eq!(a.indices, c.indices);
    assert_eq!(b.indices, c.indices);
    assert_eq!(paste("qpos[root:z]", &spec).indices, vec![2]);
    assert_eq!(
        paste("qpos[root]", &spec).indices,
        (0..7).collect::<Vec<_>>()
    );
    let file = SourceFile::new("bad.toml", "xpos[torso][w]".into());
    let loc = Location::new(&file, 0..14);
    let err =
        selector::resolve("xpos[torso][w]", &loc, &spec.model, &|_| unreachable!()).unwrap_err();
    assert!(
        err.message.contains("`w` is not a column of `xpos`"),
        "{}",
        err.message
    );
}

#[test]
fn a_site_that_is_a_body_points_to_xpos() {
    // hopper.xml has no site `foot` but a body `foot` (as a URDF's links are bodies, never sites).
    let root = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../specs/gymnasium/hopper.toml"
    );
    let spec = envspec::load(root.as_ref(), &[]).unwrap();
    let file = SourceFile::new("bad.toml", "site_xpos[foot]".into());
    let loc = Location::new(&file, 0..15);
    let err =
        selector::resolve("site_xpos[foot]", &loc, &spec.model, &|_| unreachable!()).unwrap_err();
    assert_eq!(
        err.help.as_deref(),
        Some("`foot` is a body of this model, not a site: its position is `xpos[foot]`")
    );
}

#[test]
fn name_ranges_select_every_row_between_two_names() {
    let ant = concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/gymnasium/ant.toml");
    let spec = envspec::load(ant.as_ref(), &[]).unwrap();
    // Ant's joints: root (7 qpos, 6 dofs), then hip_1, ankle_1, …, hip_4, ankle_4.
    assert_eq!(
        paste("qpos[hip_1:ankle_4]", &spec).indices,
        (7..15).collect::<Vec<_>>()
    );
    assert_eq!(
        paste("qvel[hip_1:ankle_4]", &spec).indices,
        (6..14).collect::<Vec<_>>()
    );
    // A range may start inside a joint (`root:z`), and it names its rows as single names do.
    let s = paste("qpos[root:z:ankle_1]", &spec);
    assert_eq!(s.indices, (2..9).collect::<Vec<_>>());
    assert_eq!(s.names.first().map(String::as_str), Some("qpos[root:z]"));
    assert_eq!(s.names.last().map(String::as_str), Some("qpos[ankle_1]"));
    // Bodies too, and integer slices are still slices.
    assert_eq!(paste("xpos[torso:front_left_leg]", &spec).indices.len(), 6);
    assert_eq!(paste("qpos[2:4]", &spec).indices, vec![2, 3]);
    // Fetch's names hold `:` themselves: only one split names two joints.
    let fetch = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../specs/robotics/fetch/push.toml"
    );
    let fetch = envspec::load(fetch.as_ref(), &[]).unwrap();
    assert_eq!(
        paste("qpos[robot0:slide0:robot0:slide2]", &fetch).indices,
        vec![0, 1, 2]
    );
    // Backwards is an error that says so.
    let text = "qpos[ankle_1:hip_1]";
    let file = SourceFile::new("bad.toml", text.into());
    let loc = Location::new(&file, 0..text.len());
    let err = selector::resolve(text, &loc, &spec.model, &|_| unreachable!()).unwrap_err();
    assert_eq!(err.code, envspec::Code::E0401);
    assert!(err.message.contains("name range"), "{}", err.message);
}
