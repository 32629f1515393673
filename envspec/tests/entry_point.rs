//! `[env] entry_point`: carried into the IR as written, checked for `module.path:Class` form.
use std::path::{Path, PathBuf};

use envspec::{Code, Spec, load};

fn bundled(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(file)
}

/// An `[env]` table with the given `entry_point` line (syntax only: no model is read).
fn parse(entry: &str) -> Result<Spec, envspec::Diagnostics> {
    let text = format!(
        "[env]\nid = \"E-v0\"\n{entry}\n\n[params]\nxml_file = \"m.xml\"\nframe_skip = 1\nmax_episode_steps = 10\n"
    );
    Spec::parse(Path::new("e.toml"), text)
}

#[test]
fn bundled_specs_carry_gymnasiums_entry_point() {
    // Gymnasium 1.4.0's registry (`gym.spec(id).entry_point`).
    let cases = [
        ("hopper.toml", "gymnasium.envs.mujoco.hopper_v5:HopperEnv"),
        (
            "humanoidstandup_v4.toml",
            "gymnasium.envs.mujoco.humanoidstandup_v4:HumanoidStandupEnv",
        ),
    ];
    for (file, entry) in cases {
        let spec = load(&bundled(file), &[]).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(spec.entry_point.as_deref(), Some(entry), "{file}");
    }
}

#[test]
fn entry_point_is_optional() {
    let spec = parse("").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.entry_point, None);
    let spec = parse("entry_point = \"my_pkg.envs_v0:MyEnv\"").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.entry_point.as_deref(), Some("my_pkg.envs_v0:MyEnv"));
}

#[test]
fn malformed_entry_points_are_e0104() {
    for bad in [
        "gymnasium.envs.mujoco.hopper_v5.HopperEnv",
        "gymnasium..mujoco:HopperEnv",
        ":HopperEnv",
        "pkg.mod:",
        "pkg.mod:Hopper:Env",
        "pkg.1mod:HopperEnv",
        "pkg-name.mod:HopperEnv",
    ] {
        let d = parse(&format!("entry_point = \"{bad}\""))
            .err()
            .unwrap_or_else(|| panic!("`{bad}` was accepted"));
        assert_eq!(d.codes(), [Code::E0104], "{bad}");
        assert_eq!(d.0[0].position().as_deref(), Some("e.toml:3:15"), "{bad}");
    }
}

#[test]
fn a_non_string_entry_point_is_e0102() {
    let d = parse("entry_point = 3").expect_err("accepted a number");
    assert_eq!(d.codes(), [Code::E0102]);
}
