//! `[actions]` over a model with a tendon-driven gripper (tests/fixtures/tendon_gripper/): a
//! keyframe gives a joint servo the keyframe's `qpos` at its joint and a tendon actuator the
//! keyframe's `ctrl`; `kp`, `kd` and `damping` change the joint servos alone; a `scale` row may
//! name the tendon. The values are read back from MuJoCo's compiled model and data.

use envc::Env;

const SPEC: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/tendon_gripper/reach.toml"
);

#[test]
fn a_tendon_gripper_keeps_its_gains_and_takes_the_keyframes_ctrl() {
    let mut env = Env::from_spec_file(SPEC, &[]).unwrap();
    let m = env.model();
    // The joint servo: gainprm[0] = kp, biasprm[1] = -kp, biasprm[2] = -kd, its joint's damping.
    assert_eq!(m.actuator_gainprm()[0][0], 50.0);
    assert_eq!(&m.actuator_biasprm()[0][..3], &[0.0, -50.0, -2.0]);
    assert_eq!(m.dof_damping()[0], 0.5);
    // The tendon actuator and the finger joints keep the model's values.
    assert_eq!(m.actuator_gainprm()[1][0], 0.01568);
    assert_eq!(&m.actuator_biasprm()[1][..3], &[0.0, -100.0, -10.0]);
    assert_eq!(&m.dof_damping()[1..3], &[0.0, 0.0]);
    let obs = env.reset(Some(0)).0.to_vec();
    // default_pose: the keyframe's qpos at the shoulder, its ctrl for the tendon actuator.
    assert_eq!(&obs[3..5], &[0.5, 200.0]);
    let s = env.step(&[0.5, -0.2]).unwrap();
    // ctrl = default_pose + scale × action, the tendon row by name.
    assert_eq!(&s.obs[5..7], &[0.5 + 0.25 * 0.5, 200.0 + 127.5 * -0.2]);
}
