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
