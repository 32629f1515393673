//! A spec adds to its model: `tests/fixtures/urdf/reach_added_goal.toml` puts a goal
//! body on two slide joints, a fingertip site, a camera and a light on a URDF arm that has none
//! of them. The compiled model agrees with what the spec resolved (E1002 would say otherwise), the
//! selectors read the added elements, and their values are what the geometry says.

use envc::{Env, Override};

const SPEC: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/urdf/reach_added_goal.toml"
);

fn seg<'a>(spec: &envc::ResolvedSpec, obs: &'a [f64], name: &str) -> &'a [f64] {
    let s = spec.observation.iter().find(|s| s.name == name).unwrap();
    &obs[s.offset..s.offset + s.len()]
}

#[test]
fn added_bodies_sites_cameras_and_lights_are_in_the_model() {
    let mut env = Env::from_spec_file(SPEC, &[]).unwrap();
    let spec = std::sync::Arc::clone(env.spec());
    let m = env.model().ffi();
    // arm.urdf: 8 bodies (world + 7 links), 5 joints, no site, no camera, no light.
    assert_eq!(
        (m.nbody, m.njnt, m.nsite, m.ncam, m.nlight),
        (9, 7, 1, 1, 1)
    );
    for seed in [0, 1, 2] {
        let obs = env.reset(Some(seed)).0.to_vec();
        // The goal: its slide joints were drawn in [-0.3, 0.3), and the body sits there at the
        // height it was added at.
        let q = seg(&spec, &obs, "goal_q").to_vec();
        assert!(q.iter().all(|x| (-0.3..0.3).contains(x)), "{q:?}");
        assert_eq!(seg(&spec, &obs, "goal"), &[q[0], q[1], 0.05]);
        // The site is at the fingertip link's origin: the same position.
        assert_eq!(seg(&spec, &obs, "tip"), seg(&spec, &obs, "fingertip"));
        let s = env.step(&[0.3, -0.2, 0.1]).unwrap();
        let (tip, goal) = (seg(&spec, s.obs, "tip"), seg(&spec, s.obs, "goal"));
        let d = ((tip[0] - goal[0]).powi(2) + (tip[1] - goal[1]).powi(2)).sqrt();
        assert!(
            (s.reward - (-d).exp()).abs() < 1e-12,
            "{} vs {}",
            s.reward,
            (-d).exp()
        );
    }
}

#[test]
fn added_names_collide_with_a_coded_error() {
    let dir = std::env::temp_dir().join(format!("envc-added-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(SPEC)
        .unwrap()
        .replace(
            "arm.urdf",
            &format!("{}/fixtures/urdf/arm.urdf", env!("CARGO_MANIFEST_DIR")),
        )
        .replace("[bodies.goal]", "[bodies.fingertip]")
        .replace("xpos[goal]", "xpos[fingertip]");
    let p = dir.join("clash.toml");
    std::fs::write(&p, text).unwrap();
    let Err(e) = Env::from_spec_file(&p, &[Override::text("frame_skip", "2")]) else {
        panic!("a body named like one of the model's must not load");
    };
    assert_eq!(e.code(), envc::envspec::Code::E0106, "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gear_can_be_one_per_joint() {
    let dir = std::env::temp_dir().join(format!("envc-gears-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(SPEC)
        .unwrap()
        .replace(
            "arm.urdf",
            &format!("{}/fixtures/urdf/arm.urdf", env!("CARGO_MANIFEST_DIR")),
        )
        .replace("gear = 5.0", "gear = [5.0, 4.0, 3.0]");
    let p = dir.join("gears.toml");
    std::fs::write(&p, &text).unwrap();
    let env = Env::from_spec_file(&p, &[]).unwrap();
    let m = env.model().ffi();
    // SAFETY: actuator_gear holds nu × 6 numbers.
    let gear = unsafe { std::slice::from_raw_parts(m.actuator_gear, m.nu as usize * 6) };
    assert_eq!([gear[0], gear[6], gear[12]], [5.0, 4.0, 3.0]);
    // Two gears for three joints: a coded error.
    std::fs::write(&p, text.replace("[5.0, 4.0, 3.0]", "[5.0, 4.0]")).unwrap();
    let Err(e) = Env::from_spec_file(&p, &[]) else {
        panic!("two gears for three joints must not load");
    };
    assert_eq!(e.code(), envc::envspec::Code::E0403, "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
