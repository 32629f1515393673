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

/// The spec fixture with its URDF path made absolute, edited, in a scratch file of its own.
fn edited(tag: &str, edit: impl Fn(String) -> String) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("envc-added-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(SPEC).unwrap().replace(
        "arm.urdf",
        &format!("{}/fixtures/urdf/arm.urdf", env!("CARGO_MANIFEST_DIR")),
    );
    let p = dir.join("spec.toml");
    std::fs::write(&p, edit(text)).unwrap();
    p
}

fn codes(r: &Result<envc::ResolvedSpec, envc::envspec::Diagnostics>) -> Vec<envc::envspec::Code> {
    match r {
        Ok(s) => s.warnings.iter().map(|w| w.code).collect(),
        Err(d) => d.0.iter().map(|e| e.code).collect(),
    }
}

/// A goal on a vertical slide joint falls for ever: W0170 says so at check time, naming the
/// body; a colliding geom or gravity compensation holds it, and a mocap body cannot have joints.
#[test]
fn a_falling_added_body_is_a_warning() {
    use envc::envspec::Code;
    let slide_z = |t: String| {
        t.replace(
            "joints = { goal_x = \"slide x\", goal_y = \"slide y\" }",
            "joints = { goal_x = \"slide x\", goal_y = \"slide y\", goal_z = \"slide z\" }",
        )
    };
    let p = edited("fall", slide_z);
    let r = envc::envspec::load(&p, &[]);
    assert_eq!(codes(&r), [Code::W0170]);
    let w = &r.unwrap().warnings[0];
    assert!(
        w.message
            .contains("[bodies.goal] slides vertically on `goal_z`"),
        "{}",
        w.message
    );
    let p = edited("float", |t| {
        slide_z(t).replace("size = 0.02", "size = 0.02\ngravcomp = 1.0")
    });
    assert!(codes(&envc::envspec::load(&p, &[])).is_empty());
    let p = edited("mocap-joints", |t| {
        t.replace("size = 0.02", "size = 0.02\nmocap = true")
    });
    assert_eq!(codes(&envc::envspec::load(&p, &[])), [Code::E0170]);
    for tag in ["fall", "float", "mocap-joints"] {
        let dir = std::env::temp_dir().join(format!("envc-added-{tag}-{}", std::process::id()));
        std::fs::remove_dir_all(dir).ok();
    }
}

/// A reset that moves a position metres away (a goal box in centimetres) is W0171.
#[test]
fn a_far_reset_draw_is_a_warning() {
    use envc::envspec::Code;
    let p = edited("far", |t| {
        t.replace("low = -0.3\nhigh = 0.3", "low = -30.0\nhigh = 30.0")
    });
    let r = envc::envspec::load(&p, &[]);
    assert_eq!(codes(&r), [Code::W0171]);
    assert!(
        r.unwrap().warnings[0]
            .message
            .contains("[reset.goal] moves a position by up to 30 m")
    );
    std::fs::remove_dir_all(p.parent().unwrap()).ok();
}

/// A free object and a mocap goal marker added by the spec: the free joint has 7 positions and
/// 6 velocities (`qpos[cube]`, `xquat[cube]`), the object's geom takes a mass, a
/// `[joint_properties]` row reaches the joints `[bodies]` adds, and `[goal] marker` puts the mocap
/// body at the goal drawn at every reset (it never falls).
#[test]
fn free_objects_mocap_markers_and_properties_of_added_joints() {
    let p = edited("objects", |t| {
        t.replace(
            "\n[sites.tip]\n",
            r#"[bodies.cube]
pos = [0.3, 0.0, 0.5]
joints = { cube = "free" }

[geoms.cube_box]
body = "cube"
type = "box"
size = [0.02, 0.02, 0.02]
mass = 0.25

[bodies.marker]
mocap = true
geom = "sphere"

[joint_properties."goal_*"]
damping = 5.0

[goal]
achieved = "site_xpos[tip]"
marker = "marker"

[reset.target]
target = "goal"
kind = "uniform"
low = -0.2
high = 0.2

[observation.cube]
source = "qpos[cube]"

[observation.cube_quat]
source = "xquat[cube]"

[observation.marker]
source = "xpos[marker]"

[sites.tip]
"#,
        )
    });
    let mut env = Env::from_spec_file(&p, &[]).unwrap();
    let spec = std::sync::Arc::clone(env.spec());
    let m = env.model();
    let cube = m.ffi().nbody as usize - 2;
    assert_eq!(m.body_mass()[cube], 0.25);
    assert_eq!(m.ffi().nmocap, 1);
    // goal_x and goal_y are dofs 5 and 6 (after the arm's five).
    assert_eq!(&m.dof_damping()[5..7], &[5.0, 5.0]);
    for seed in [0, 1] {
        let obs = env.reset(Some(seed)).0.to_vec();
        let goal = env.goal().to_vec();
        assert_eq!(seg(&spec, &obs, "marker"), &goal[..]);
        assert_eq!(
            seg(&spec, &obs, "cube"),
            &[0.3, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(seg(&spec, &obs, "cube_quat"), &[1.0, 0.0, 0.0, 0.0]);
        let mut last = obs.clone();
        for _ in 0..5 {
            last = env.step(&[0.0, 0.0, 0.0]).unwrap().obs.to_vec();
        }
        // The free cube falls (the arm's world has no floor); the mocap marker stays.
        assert!(seg(&spec, &last, "cube")[2] < 0.5);
        assert_eq!(seg(&spec, &last, "marker"), &goal[..]);
    }
    std::fs::remove_dir_all(p.parent().unwrap()).ok();
}

/// Reset steps may target a mocap body's `mocap_pos` / `mocap_quat` by name, and observations
/// read them: MuJoCo's forward pass then puts the body there (`xpos`, `xquat` are MuJoCo's).
#[test]
fn reset_draws_target_mocap_bodies() {
    let p = edited("mocap-reset", |t| {
        t.replace(
            "\n[sites.tip]\n",
            r#"[bodies.beacon]
mocap = true
geom = "sphere"

[reset.beacon_place]
target = "mocap_pos[beacon]"
kind = "constant"
value = [0.25, -0.125, 0.5]

[reset.beacon_turn]
target = "mocap_quat[beacon]"
kind = "constant"
value = [0.0, 1.0, 0.0, 0.0]

[reset.beacon_jitter]
target = "mocap_pos[beacon][0]"
kind = "uniform"
low = -0.5
high = 0.5

[observation.beacon_pos]
source = "mocap_pos[beacon]"

[observation.beacon_xpos]
source = "xpos[beacon]"

[observation.beacon_xquat]
source = "xquat[beacon]"

[sites.tip]
"#,
        )
    });
    let mut env = Env::from_spec_file(&p, &[]).unwrap();
    let spec = std::sync::Arc::clone(env.spec());
    for seed in [0, 7] {
        let obs = env.reset(Some(seed)).0.to_vec();
        let pos = seg(&spec, &obs, "beacon_pos").to_vec();
        let x = pos[0] - 0.25;
        assert!((-0.5..0.5).contains(&x) && x != 0.0, "{pos:?}");
        assert_eq!(&pos[1..], &[-0.125, 0.5]);
        assert_eq!(seg(&spec, &obs, "beacon_xpos"), &pos[..]);
        assert_eq!(seg(&spec, &obs, "beacon_xquat"), &[0.0, 1.0, 0.0, 0.0]);
    }
    // A name that is not a mocap body selects no mocap_pos row.
    let bad = p.with_file_name("bad.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&bad, text.replace("mocap_pos[beacon][0]", "mocap_pos[tip]")).unwrap();
    assert!(envc::envspec::load(&bad, &[]).is_err());
    std::fs::remove_dir_all(p.parent().unwrap()).ok();
}

/// `[bodies.x] mocap = true, weld = "hand"` compiles to the weld MuJoCo's own MJCF compiler
/// makes of `<weld body1="x" body2="hand"/>`: type, bodies, data (the relative pose at qpos0),
/// solver parameters, bit for bit; `[end_effector]` accepts it (E1111 otherwise).
#[test]
fn a_weld_from_the_spec_is_the_mjcf_weld() {
    use envc::mujoco_rs::prelude::MjModel;
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let spec = format!("{root}/specs/examples/arm_pick_and_place.toml");
    // Without `[init] reset_welds`, which rewrites the weld's pose when the env is made.
    let dir = std::env::temp_dir().join(format!("envc-weld-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(&spec)
        .unwrap()
        .replace("reset_welds = true\n", "")
        .replace("../../assets/", &format!("{root}/assets/"));
    std::fs::write(dir.join("spec.toml"), text).unwrap();
    let env = Env::from_spec_file(dir.join("spec.toml"), &[]).unwrap();
    let ours = env.model();
    // The reference: the bare arm with the mocap body written last in its worldbody and the
    // weld in its own <equality>, as a user would edit the file.
    let xml = std::fs::read_to_string(format!("{root}/assets/examples/arm/arm.xml"))
        .unwrap()
        .replace(
            "  </worldbody>",
            "    <body name=\"hand_target\" mocap=\"true\" pos=\"0.4 0 0.76\"/>\n  </worldbody>\n  \
             <equality><weld body1=\"hand_target\" body2=\"hand\"/></equality>",
        );
    let path = dir.join("arm_welded.xml");
    std::fs::write(&path, xml).unwrap();
    let reference = MjModel::from_xml(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!((ours.ffi().neq, reference.ffi().neq), (1, 1));
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(ours.eq_type()[0] as i32, reference.eq_type()[0] as i32);
    assert_eq!(
        ours.eq_objtype()[0] as i32,
        reference.eq_objtype()[0] as i32
    );
    assert_eq!(ours.eq_obj1id(), reference.eq_obj1id());
    assert_eq!(ours.eq_obj2id(), reference.eq_obj2id());
    assert_eq!(ours.eq_active0(), reference.eq_active0());
    assert_eq!(bits(&ours.eq_data()[0]), bits(&reference.eq_data()[0]));
    assert_eq!(bits(&ours.eq_solref()[0]), bits(&reference.eq_solref()[0]));
    assert_eq!(bits(&ours.eq_solimp()[0]), bits(&reference.eq_solimp()[0]));
    // The relative pose is the one at qpos0: the hand 2 cm above where the target was added.
    let rel = &reference.eq_data()[0][3..10];
    assert!((rel[2] - 0.02).abs() < 1e-12 && rel[3] == 1.0, "{rel:?}");
    // With `reset_welds` (the bundled spec), the env's weld is the identity.
    let env = Env::from_spec_file(&spec, &[]).unwrap();
    assert_eq!(
        env.model().eq_data()[0][3..10],
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    );
}

#[test]
fn a_weld_needs_a_mocap_body_and_a_known_body() {
    let cases = [
        ("mocap = true\nweld = \"hnd\"", envc::envspec::Code::E0303),
        ("weld = \"hand\"", envc::envspec::Code::E0170),
    ];
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let text =
        std::fs::read_to_string(format!("{root}/specs/examples/arm_pick_and_place.toml")).unwrap();
    for (i, (body, code)) in cases.iter().enumerate() {
        let dir = std::env::temp_dir().join(format!("envc-weld-bad-{i}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("spec.toml");
        let edited = text
            .replace("mocap = true\nweld = \"hand\"", body)
            .replace("../../assets/", &format!("{root}/assets/"));
        std::fs::write(&p, edited).unwrap();
        let r = envc::envspec::open(p.to_str().unwrap(), &[]).map(|_| ());
        std::fs::remove_dir_all(&dir).unwrap();
        let Err(d) = r else { panic!("{body} opened") };
        assert!(d.0.iter().any(|x| x.code == *code), "{body}: {d:?}");
    }
}
