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
    errors_in("mjlab_velocity_rough_go1", test, from, to)
}

/// `specs/examples/<example>.toml` with `from` replaced by `to`, loaded from a temporary file.
fn errors_in(example: &str, test: &str, from: &str, to: &str) -> Diagnostics {
    let original = repo().join(format!("specs/examples/{example}.toml"));
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

/// What a terrain makes is bounded before anything is allocated: stairs so fine that they would
/// ask for billions of boxes, heightfield scales that would need billions of height levels or
/// saturate the integer heights, all located at the key that asks for them.
#[test]
fn terrain_work_beyond_the_limits_is_located_e0110() {
    let stairs = "step_width = 0.3\nplatform_width = 3.0\nborder_width = 1.0\n\n[terrain.pyramid_stairs_inv]";
    for width in ["1e-6", "0.0005", "0.002"] {
        let d = errors(
            &format!("boxes-{width}"),
            stairs,
            &stairs.replace("0.3", width),
        );
        assert_eq!(d.codes(), [Code::E0110], "{width}: {}", d.0[0]);
        assert!(d.0[0].message.contains("geoms"), "{}", d.0[0].message);
        assert!(d.0[0].message.contains("20000"), "{}", d.0[0].message);
        assert_eq!(line_of(&d, 0), "67", "{}", d.0[0]);
    }
    // Default stairs on 1000 m tiles.
    let d = errors(
        "big-tiles",
        "tile_size = [8.0, 8.0]",
        "tile_size = [1000.0, 1000.0]",
    );
    assert!(d.codes().contains(&Code::E0110), "{:?}", d.codes());
    let rough = "noise = [0.02, 0.10]\nnoise_step = 0.02\n";
    for (name, to, key) in [
        (
            "levels",
            "noise = [-1000.0, 1000.0]\nnoise_step = 1e-6\nvertical_scale = 1e-6\n",
            "noise_step",
        ),
        (
            "saturation",
            "noise = [0.02, 0.10]\nnoise_step = 0.02\nvertical_scale = 1e-300\n",
            "vertical_scale",
        ),
    ] {
        let d = errors(name, rough, to);
        assert_eq!(d.codes(), [Code::E0110], "{name}: {}", d.0[0]);
        assert!(d.0[0].message.contains("height levels"), "{}", d.0[0]);
        let line = line_of(&d, 0);
        let spec =
            std::fs::read_to_string(repo().join("specs/examples/mjlab_velocity_rough_go1.toml"))
                .unwrap()
                .replacen(rough, to, 1);
        let at = spec
            .lines()
            .nth(line.parse::<usize>().unwrap() - 1)
            .unwrap();
        assert!(at.starts_with(key), "{name}: located at `{at}`");
    }
    // A pyramid slope too tall for its vertical scale: at `slope`.
    let slope = "slope = [0.0, 1.0]\nplatform_width = 2.0\nborder_width = 0.25\n\n[terrain.hf_pyramid_slope_inv]";
    let d = errors(
        "slope",
        slope,
        &slope.replace("[0.0, 1.0]", "[0.0, 1000.0]").replace(
            "border_width = 0.25\n",
            "border_width = 0.25\nvertical_scale = 1e-4\n",
        ),
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    assert!(d.0[0].message.contains("hf_pyramid_slope "), "{}", d.0[0]);
}

#[test]
fn a_second_terrain_origin_reset_is_refused() {
    let d = errors(
        "two-spawns",
        "[reset.spawn]",
        "[reset.spawn0]\nkind = \"terrain_origin\"\n\n[reset.spawn]",
    );
    assert_eq!(d.codes(), [Code::E0162], "{}", d.0[0]);
    assert!(
        d.0[0].message.contains("second terrain_origin"),
        "{}",
        d.0[0]
    );
}

/// The numbers of `[joint_properties]`, `[keyframes]`, `[geom_properties]` and the legged terms
/// are bounded like `[actions]`: 1e308 is E0110 at its key, not a simulation that resets itself
/// every step.
#[test]
fn huge_magnitudes_in_the_tables_are_e0110() {
    let kp = "\"*_calf_joint\" = { kp = 35.76429596977857, kv = 2.2768257959818006, effort = 35.55, armature = 0.009059202 }";
    for (key, from, to) in [
        ("kp", "kp = 35.76429596977857", "kp = 1e308"),
        ("kv", "kv = 2.2768257959818006", "kv = 1e7"),
        ("effort", "effort = 35.55", "effort = 1e308"),
        ("armature", "armature = 0.009059202", "armature = 1e308"),
        (
            "gear",
            "armature = 0.009059202",
            "armature = 0.009059202, gear = 1e308",
        ),
        (
            "forcerange",
            "effort = 35.55",
            "forcerange = [-1e308, 1e308]",
        ),
    ] {
        let d = errors(&format!("jp-{key}"), kp, &kp.replace(from, to));
        assert_eq!(d.codes(), [Code::E0110], "{key}: {}", d.0[0]);
        assert!(d.0[0].message.contains("beyond envc's limit"), "{}", d.0[0]);
    }
    let d = errors(
        "keyframe",
        "root_pos = [0.0, 0.0, 0.278]",
        "root_pos = [0.0, 0.0, 1e308]",
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    let d = errors(
        "keyframe-joint",
        "\"*thigh_joint\" = 0.9",
        "\"*thigh_joint\" = 1e308",
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    let d = errors(
        "geom-margin",
        "condim = 6, priority = 1,",
        "condim = 6, priority = 1, margin = 1e308,",
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    let d = errors(
        "geom-friction",
        "friction = [1.0, 5e-3, 5e-4]",
        "friction = [1e308, 5e-3, 5e-4]",
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    // self_collisions threshold below zero, feet_clearance power beyond the limit.
    let d = errors("threshold", "threshold = 10.0", "threshold = -1.0");
    assert_eq!(d.codes(), [Code::E0135], "{}", d.0[0]);
    let d = errors_in(
        "mjlab_velocity_flat_g1",
        "power",
        "kind = \"feet_clearance\"\n",
        "kind = \"feet_clearance\"\npower = 1e308\n",
    );
    assert_eq!(d.codes(), [Code::E0110], "{}", d.0[0]);
    assert!(d.0[0].message.contains("power"), "{}", d.0[0]);
}

#[test]
fn a_nul_byte_in_a_keyframe_name_is_e0102() {
    let d = errors(
        "nul-key",
        "[keyframes.init_state]",
        "[keyframes.\"a\\u0000b\"]\nroot_pos = [0.0, 0.0, 0.3]\n\n[keyframes.init_state]",
    );
    assert_eq!(d.codes(), [Code::E0102], "{}", d.0[0]);
    assert!(d.0[0].message.contains("NUL byte"), "{}", d.0[0]);
}
