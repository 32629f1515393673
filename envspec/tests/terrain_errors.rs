//! `[terrain]` and `kind = "terrain_origin"` mistakes: each a located, coded error.

use std::path::{Path, PathBuf};

use envspec::{Code, Diagnostics, load};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("root")
        .to_path_buf()
}

/// A spec's text with its repository-relative model path made absolute, to be written outside the
/// repository: a file written (even briefly) under `specs/` makes cargo rebuild envspec, which
/// embeds that directory, and everything above it.
fn absolute_model(text: &str) -> String {
    text.replace(
        "\"../../assets/",
        &format!("\"{}/assets/", repo().display()),
    )
}

/// The rough example with `from` replaced by `to`, loaded from a temporary file.
fn errors(test: &str, from: &str, to: &str) -> Diagnostics {
    let original = repo().join("specs/examples/mjlab_velocity_rough_go1.toml");
    let text = std::fs::read_to_string(&original).expect("the rough spec");
    assert_eq!(text.matches(from).count(), 1, "`{from}` must occur once");
    let p = std::env::temp_dir().join(format!(
        "envc-terrain-errors-{}-{test}.toml",
        std::process::id()
    ));
    std::fs::write(&p, absolute_model(&text.replacen(from, to, 1))).expect("write the spec");
    let r = load(&p, &[]);
    let _ = std::fs::remove_file(&p);
    match r {
        Ok(_) => panic!("{test}: accepted"),
        Err(d) => d,
    }
}

fn line_of(d: &Diagnostics, i: usize) -> String {
    d.0[i]
        .position()
        .expect("a position")
        .rsplit(':')
        .nth(1)
        .expect("line")
        .to_string()
}

#[test]
fn mistakes_in_terrain_are_located_and_coded() {
    // An unknown generator kind, with the allowed ones.
    let d = errors(
        "kind",
        "[terrain.hf_pyramid_slope]\nkind = \"pyramid_slope\"",
        "[terrain.hf_pyramid_slope]\nkind = \"pyramid_slop\"",
    );
    assert_eq!(d.codes(), [Code::E0104]);
    assert_eq!(
        d.0[0].help.as_deref(),
        Some("did you mean `pyramid_slope`?")
    );
    // An unknown key of a generator, and of [terrain] itself.
    let d = errors(
        "key",
        "step_width = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
        "step_widht = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
    );
    assert_eq!(d.codes(), [Code::E0101]);
    let d = errors("top", "rows = 10\n", "rowz = 10\n");
    assert_eq!(d.codes(), [Code::E0101]);
    // A heightfield border narrower than one cell.
    let d = errors(
        "border",
        "platform_width = 2.0\nborder_width = 0.25\n\n[terrain.hf_pyramid_slope_inv]",
        "platform_width = 2.0\nborder_width = 0.05\n\n[terrain.hf_pyramid_slope_inv]",
    );
    assert_eq!(d.codes(), [Code::E0105]);
    assert!(
        d.0[0].message.contains("narrower than one cell"),
        "{}",
        d.0[0].message
    );
    // A reversed range, a negative step.
    let d = errors(
        "range",
        "proportion = 0.2\nstep_height = [0.0, 0.1]\nstep_width = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
        "proportion = 0.2\nstep_height = [0.1, 0.0]\nstep_width = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
    );
    assert!(
        d.codes().iter().all(|c| *c == Code::E0105),
        "{:?}",
        d.codes()
    );
    let d = errors(
        "step",
        "step_width = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
        "step_width = -0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]",
    );
    assert_eq!(d.codes(), [Code::E0105]);
    // `cols` that contradicts the curriculum layout's one column per generator.
    let d = errors("cols", "rows = 10\n", "rows = 10\ncols = 20\n");
    assert_eq!(d.codes(), [Code::E0105]);
    assert!(
        d.0[0].message.contains("one column per generator (6)"),
        "{}",
        d.0[0].message
    );
    // Too many tiles for the limit.
    let d = errors(
        "tiles",
        "rows = 10\nlayout = \"curriculum\"",
        "rows = 10\ncols = 300\nlayout = \"random\"",
    );
    assert_eq!(d.codes(), [Code::E0110]);
    assert!(
        d.0[0].message.contains("10 × 300 = 3000 tiles"),
        "{}",
        d.0[0].message
    );
}

#[test]
fn terrain_origin_needs_a_terrain_and_rows_it_has() {
    let d = errors("rows", "rows = [0, 5]", "rows = [0, 10]");
    assert_eq!(d.codes(), [Code::E0105]);
    assert!(d.0[0].message.contains("rows 0 … 9"), "{}", d.0[0].message);
    let d = errors("fraction", "rows = [0, 5]", "rows = [0.5, 5]");
    assert_eq!(d.codes(), [Code::E0105]);
    // Without [terrain] (the whole table and its generators renamed away is too much text: an
    // empty generator list is its own error).
    let original = repo().join("specs/examples/mjlab_velocity_rough_go1.toml");
    let text = std::fs::read_to_string(&original).expect("the rough spec");
    let start = text.find("\n[terrain]\n").expect("[terrain]") + 1;
    let end = text.find("[sites.base]").expect("[sites.base]");
    let p = std::env::temp_dir().join(format!(
        "envc-terrain-errors-{}-none.toml",
        std::process::id()
    ));
    std::fs::write(
        &p,
        absolute_model(&format!("{}{}", &text[..start], &text[end..])),
    )
    .expect("write");
    let d = load(&p, &[]).expect_err("refused");
    let _ = std::fs::remove_file(&p);
    assert_eq!(d.codes(), [Code::E0162], "{}", d.0[0]);
    assert!(
        d.0[0].message.contains("needs a [terrain]"),
        "{}",
        d.0[0].message
    );
    assert!(!line_of(&d, 0).is_empty());
}
