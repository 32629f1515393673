//! `envc show` says what the env computes without misleading: a cost that is a sum is
//! printed in parentheses (InvertedDoublePendulum-v5's reference: `reward = alive_bonus −
//! dist_penalty − vel_penalty`, `dist_penalty = 0.01·x² + (y − 2)²`), and an env with no health
//! checks does not claim that an unhealthy state ends it. A URDF spec shows its compiled layout.

use std::process::Command;

fn show(id: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["show", id])
        .output()
        .expect("run envc");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn a_cost_that_is_a_sum_is_parenthesized() {
    let out = show("InvertedDoublePendulum-v5");
    assert!(
        out.contains("−(0.01·site_xpos[tip].x² + (site_xpos[tip].z − 2.0)²)"),
        "{out}"
    );
    assert!(
        out.contains("−(0.001·qvel[hinge]² + 0.005·qvel[hinge2]²)"),
        "{out}"
    );
}

#[test]
fn no_health_checks_means_no_unhealthy_ending() {
    let out = show("Swimmer-v5");
    assert!(
        out.contains("no health checks, so no unhealthy ending"),
        "{out}"
    );
    assert!(!out.contains("an unhealthy state ends it"), "{out}");
    assert!(show("Hopper-v5").contains("an unhealthy state ends it"));
}

#[test]
fn show_model_lists_the_inventory_as_pasteable_selectors() {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["show", "Ant-v5", "--model"])
        .output()
        .expect("run envc");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    // ant.xml: a free joint `root`, 8 unnamed motors, the `torso` body, camera `track`.
    for want in [
        "qpos[root:z]",
        "qvel[root:wz]",
        "action[actuator7]",
        "xpos[torso]",
        "cameras (1):\n  track",
        "torso_geom",
    ] {
        assert!(out.contains(want), "{want} missing from\n{out}");
    }
}

#[test]
fn actuators_the_spec_adds_show_their_kind_and_gear() {
    let spec = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/urdf/reach_arm.toml"
    );
    let out = show(spec);
    // reach_arm.toml: `kind = "motor"`, `gear = "motor_gear"` (default 5.0) on three joints.
    assert!(
        out.contains("elbow                -> elbow                [-1, 1]  motor, gear 5 (added by the spec)"),
        "{out}"
    );
}

#[test]
fn a_urdf_spec_shows_its_compiled_layout() {
    let spec = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/urdf/reach_arm.toml"
    );
    let text = show(spec);
    assert!(
        text.contains("nq 5, nv 5, nu 3, nbody 8; timestep 0.005"),
        "{text}"
    );
    assert!(
        text.contains("shoulder_lift        -> shoulder_lift"),
        "{text}"
    );
}
