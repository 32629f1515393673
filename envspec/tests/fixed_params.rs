//! `fixed = true`: a parameter that is part of the spec but not a constructor argument.
use std::path::PathBuf;

use envspec::{Code, Override, load};

fn spec(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(file)
}

#[test]
fn overriding_a_fixed_parameter_is_refused() {
    // Hopper-v4's constructor has neither xml_file nor frame_skip (Gymnasium 1.4.0).
    let e = load(
        &spec("hopper_v4.toml"),
        &[Override::text("frame_skip", "3")],
    )
    .unwrap_err();
    assert_eq!(e.codes(), vec![Code::E0204]);
    assert!(
        e.to_string()
            .contains("parameter `frame_skip` is fixed in Hopper-v4"),
        "{e}"
    );
    let r = load(&spec("hopper_v4.toml"), &[]).unwrap();
    assert_eq!(r.frame_skip, 4);
    assert!(
        r.params
            .iter()
            .find(|p| p.name == "frame_skip")
            .unwrap()
            .fixed
    );
    // Ant-v4 does take xml_file.
    assert!(
        !load(&spec("ant_v4.toml"), &[])
            .unwrap()
            .params
            .iter()
            .find(|p| p.name == "xml_file")
            .unwrap()
            .fixed
    );
}

#[test]
fn fixed_must_be_a_bool() {
    let text = std::fs::read_to_string(spec("hopper_v4.toml"))
        .unwrap()
        .replacen("fixed = true", "fixed = \"yes\"", 1);
    let e = envspec::Spec::parse(&spec("hopper_v4.toml"), text).unwrap_err();
    assert_eq!(e.codes(), vec![Code::E0102]);
}
