//! Gymnasium-Robotics' Shadow Dexterous Hand envs (specs/robotics/hand/) against the reference's
//! own numbers, recorded by tests/reference/record_robotics.py (fixtures/hand/) and replayed as
//! the Fetch recordings are (tests/fetch.rs): `HandReach-v3` and its dense twin, whose goal is a
//! `meet` reset draw and whose actions span the control ranges (`[actions] kind = "ctrlrange"`).

use crate::fetch::replay_family;

#[test]
fn hand_reach() {
    replay_family("hand", "HandReach-v3");
    replay_family("hand", "HandReachDense-v3");
}

#[test]
fn hand_manipulate_block() {
    for variant in ["", "Full", "RotateZ", "RotateXYZ", "RotateParallel"] {
        for reward in ["", "Dense"] {
            replay_family("hand", &format!("HandManipulateBlock{variant}{reward}-v1"));
        }
    }
}

/// The pen: not turned at reset, compared without its turn about Z (`angle_ignoring_z`).
#[test]
fn hand_manipulate_pen() {
    for variant in ["", "Full", "Rotate"] {
        for reward in ["", "Dense"] {
            replay_family("hand", &format!("HandManipulatePen{variant}{reward}-v1"));
        }
    }
}

#[test]
fn hand_manipulate_egg() {
    for variant in ["", "Full", "Rotate"] {
        for reward in ["", "Dense"] {
            replay_family("hand", &format!("HandManipulateEgg{variant}{reward}-v1"));
        }
    }
}

/// The touch-sensor models: the 92 sensors' values, or whether each is touched, observed.
#[test]
fn hand_manipulate_touch_sensors() {
    for object in [
        "Block",
        "BlockRotateZ",
        "BlockRotateXYZ",
        "BlockRotateParallel",
        "Egg",
        "EggRotate",
    ] {
        for touch in ["Continuous", "Boolean"] {
            for reward in ["", "Dense"] {
                replay_family(
                    "hand",
                    &format!("HandManipulate{object}_{touch}TouchSensors{reward}-v1"),
                );
            }
        }
    }
}

/// `manipulate.toml` with its model paths made absolute (to be written elsewhere).
fn manipulate_spec() -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    std::fs::read_to_string(root.join("specs/robotics/hand/manipulate.toml"))
        .unwrap()
        .replace(
            "\"../../../assets/",
            &format!("\"{}/assets/", root.display()),
        )
}

/// Mistakes in the hand manipulation tables are located, coded errors before anything runs.
#[test]
fn hostile_hand_tables_are_coded_errors() {
    use envc::envspec::Code;
    let text = manipulate_spec();
    let dir = std::env::temp_dir().join(format!("envc-hand-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, (from, to, code)) in [
        // A rotation of three numbers.
        (
            "[reset.object_rotation]\ndoc = \"The block turned by a drawn rotation: about a drawn axis (xyz) or the vertical (z).\"\ntarget = \"qpos[object:joint:qw,object:joint:qx,object:joint:qy,object:joint:qz]\"",
            "[reset.object_rotation]\ntarget = \"qpos[object:joint:qx,object:joint:qy,object:joint:qz]\"",
            Code::E0170,
        ),
        ("steps = 10", "steps = 0", Code::E0170),
        ("record = [\"object\"]", "record = [\"objekt\"]", Code::E0170),
        ("above = 0.04", "", Code::E0170),
        ("kind = \"ctrlrange\"", "kind = \"ctrlrange\"\nscale = 2.0", Code::E0101),
        (
            "norm = \"rotation_norm\", strict = true },\n]\nwhen = \"reward_type == 'sparse' and target_position == 'random'\"",
            "norm = \"rotation_norm\", strict = true, weight = 2 },\n]\nwhen = \"reward_type == 'sparse' and target_position == 'random'\"",
            Code::E0101,
        ),
        (
            "achieved = \"qpos[object:joint:qw,object:joint:qx,object:joint:qy,object:joint:qz]\"\ndesired = \"goal[3:7]\"",
            "achieved = \"qpos[object:joint:qx,object:joint:qy,object:joint:qz]\"\ndesired = \"goal[4:7]\"",
            Code::E0801,
        ),
        ("axis = [0.0, 0.0, 1.0]\nwhen", "axis = [0.0, 0.0, 0.0]\nwhen", Code::E0170),
        (
            "when = \"target_rotation == 'xyz' and randomize_rotation\"\n\n[reset.object_rotation_z]",
            "angle = [1.0, -1.0]\nwhen = \"target_rotation == 'xyz'\"\n\n[reset.object_rotation_z]",
            Code::E0105,
        ),
        ("rotation_norm = { default = \"angle\"", "rotation_norm = { default = \"angel\"", Code::E0802),
    ]
    .into_iter()
    .enumerate()
    {
        assert!(text.contains(from), "{from}");
        let p = dir.join(format!("case{i}.toml"));
        std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
        let codes: Vec<Code> = match envc::envspec::load(&p, &[]) {
            Ok(_) => vec![],
            Err(d) => d.0.iter().map(|e| e.code).collect(),
        };
        assert!(codes.contains(&code), "case {i} ({to}): {codes:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A settle step whose check never holds starts the reset over 1,000 times, then the reset
/// fails with E1104 naming the step (the reference would loop for ever).
#[test]
fn a_settle_check_that_never_holds_is_e1104() {
    let text = manipulate_spec()
        .replace("steps = 10", "steps = 1")
        .replace("above = 0.04", "above = 10.0");
    let dir = std::env::temp_dir().join(format!("envc-hand-settle-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("spec.toml");
    std::fs::write(&p, text).unwrap();
    let mut env = envc::Env::from_spec_file(&p, &[]).unwrap();
    env.reset(Some(0));
    let e = env.reset_error().expect("the reset fails");
    assert_eq!(e.code(), envc::envspec::Code::E1104);
    assert!(
        e.to_string().contains("[reset.settle] ran 1000 times"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
