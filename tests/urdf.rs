//! URDF models and spec-added actuators: envspec's numbering of a URDF agrees with MuJoCo's (on
//! several URDFs, checked by the runtime's model check and against the compiled model's arrays),
//! `[actuators]` / `[physics]` work on URDF and MJCF models, and the URDF reaching arm runs through
//! the dynamic env, the typed macro and the error paths.

use std::path::{Path, PathBuf};

use envc::envspec::ir::{ActuatorKind, Integrator};
use envc::envspec::mjcf::JointKind;
use envc::envspec::{Code, ModelInfo};
use envc::{Env, Environment};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/urdf")
        .join(name)
}

fn reach_arm() -> PathBuf {
    fixture("reach_arm.toml")
}

/// A spec in a temporary directory (the model path is absolute).
struct TempSpec {
    dir: PathBuf,
}

impl TempSpec {
    fn new(tag: &str) -> TempSpec {
        let dir = std::env::temp_dir().join(format!("envc-urdf-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        TempSpec { dir }
    }
    /// A minimal spec over `model` with extra sections.
    fn spec(&self, model: &Path, extra: &str) -> PathBuf {
        let text = format!(
            "[env]\nid = \"T-v0\"\n[params]\nxml_file = {:?}\nframe_skip = 1\nmax_episode_steps = 10\n\
             [observation.qpos]\nsource = \"qpos\"\n{extra}",
            model.to_str().unwrap()
        );
        let p = self.dir.join("spec.toml");
        std::fs::write(&p, text).unwrap();
        p
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for TempSpec {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Everything envspec derived, compared with the compiled model: sizes (the env's model check does
/// that too), body names, joint names, types, bodies and addresses.
fn assert_model_agrees(env: &Env) {
    let info = &env.spec().model;
    let m = env.model().ffi();
    assert_eq!(
        (m.nq, m.nv, m.nu, m.nbody, m.njnt),
        (
            info.nq as i64,
            info.nv as i64,
            info.nu() as i64,
            info.nbody() as i64,
            info.joints.len() as i64
        )
    );
    // SAFETY: name_*adr have one entry per element, each an offset of a NUL-terminated name.
    let name = |adr: *const i32, i: usize| unsafe {
        std::ffi::CStr::from_ptr(m.names.add(*adr.add(i) as usize))
            .to_string_lossy()
            .into_owned()
    };
    for (i, b) in info.bodies.iter().enumerate() {
        assert_eq!(name(m.name_bodyadr, i), *b, "body {i}");
    }
    for (i, a) in info.actuators.iter().enumerate() {
        assert_eq!(name(m.name_actuatoradr, i), a.name, "actuator {i}");
    }
    for (i, j) in info.joints.iter().enumerate() {
        assert_eq!(name(m.name_jntadr, i), j.name, "joint {i}");
        // SAFETY: the jnt_* arrays have njnt entries.
        let (ty, body, qadr, dadr) = unsafe {
            (
                *m.jnt_type.add(i),
                *m.jnt_bodyid.add(i),
                *m.jnt_qposadr.add(i),
                *m.jnt_dofadr.add(i),
            )
        };
        let kind = match j.kind {
            JointKind::Free => 0,
            JointKind::Ball => 1,
            JointKind::Slide => 2,
            JointKind::Hinge => 3,
        };
        assert_eq!(
            (ty as i64, body as usize, qadr as usize, dadr as usize),
            (kind, j.body, j.qposadr, j.dofadr),
            "joint `{}`",
            j.name
        );
    }
}

fn joint_table(info: &ModelInfo) -> Vec<(&str, JointKind, usize, usize, usize)> {
    info.joints
        .iter()
        .map(|j| (j.name.as_str(), j.kind, j.body, j.qposadr, j.dofadr))
        .collect()
}

#[test]
fn urdf_tree_order_and_fused_static_links() {
    // Links are declared B, A1, base, A, C; joints jB, jA1, jA (fixed), jC. MuJoCo walks from the
    // root `base` and takes children in joint order (B, A, C); with fusestatic (URDF's default)
    // `base` and `A` are merged away and A's child A1 takes A's place.
    let info = ModelInfo::from_file(&fixture("tree_order.urdf")).unwrap();
    assert_eq!(info.bodies, ["world", "B", "A1", "C"]);
    assert_eq!(
        joint_table(&info),
        [
            ("jB", JointKind::Hinge, 1, 0, 0),
            ("jA1", JointKind::Hinge, 2, 1, 1),
            ("jC", JointKind::Slide, 3, 2, 2),
        ]
    );
    assert_eq!(
        (info.nq, info.nv, info.nu(), info.timestep),
        (3, 3, 0, 0.002)
    );

    let tmp = TempSpec::new("tree");
    let env = Env::from_spec_file(tmp.spec(&fixture("tree_order.urdf"), ""), &[]).unwrap();
    assert_model_agrees(&env);
}

#[test]
fn urdf_mujoco_extension_keeps_static_links_and_sets_the_timestep() {
    // The same URDF with <mujoco><compiler fusestatic="false"/><option timestep="0.01"/></mujoco>.
    let tmp = TempSpec::new("nofuse");
    let text = std::fs::read_to_string(fixture("tree_order.urdf")).unwrap().replace(
        "<robot name=\"t\">",
        "<robot name=\"t\">\n<mujoco><compiler fusestatic=\"false\"/><option timestep=\"0.01\"/></mujoco>",
    );
    let urdf = tmp.write("nofuse.urdf", &text);
    let info = ModelInfo::from_file(&urdf).unwrap();
    assert_eq!(info.bodies, ["world", "base", "B", "A", "A1", "C"]);
    assert_eq!(
        joint_table(&info),
        [
            ("jB", JointKind::Hinge, 2, 0, 0),
            ("jA1", JointKind::Hinge, 4, 1, 1),
            ("jC", JointKind::Slide, 5, 2, 2),
        ]
    );
    assert_eq!(info.timestep, 0.01);
    let env = Env::from_spec_file(tmp.spec(&urdf, ""), &[]).unwrap();
    assert_model_agrees(&env);
    assert_eq!(env.model().ffi().opt.timestep, 0.01);
}

#[test]
fn urdf_world_link_floating_planar_and_spherical_joints() {
    // A link named `world` is the world body; floating → free; planar → _TX, _TY slides + _RZ hinge.
    let info = ModelInfo::from_file(&fixture("world_floating_planar.urdf")).unwrap();
    assert_eq!(info.bodies, ["world", "base", "P"]);
    assert_eq!(
        joint_table(&info),
        [
            ("jf", JointKind::Free, 1, 0, 0),
            ("jp_TX", JointKind::Slide, 2, 7, 6),
            ("jp_TY", JointKind::Slide, 2, 8, 7),
            ("jp_RZ", JointKind::Hinge, 2, 9, 8),
        ]
    );
    assert_eq!((info.nq, info.nv), (10, 9));
    let tmp = TempSpec::new("planar");
    let env =
        Env::from_spec_file(tmp.spec(&fixture("world_floating_planar.urdf"), ""), &[]).unwrap();
    assert_model_agrees(&env);

    // spherical → ball (4 qpos, 3 dofs).
    let text = std::fs::read_to_string(fixture("world_floating_planar.urdf"))
        .unwrap()
        .replace("type=\"planar\"", "type=\"spherical\"");
    let urdf = tmp.write("ball.urdf", &text);
    let info = ModelInfo::from_file(&urdf).unwrap();
    assert_eq!(
        joint_table(&info),
        [
            ("jf", JointKind::Free, 1, 0, 0),
            ("jp", JointKind::Ball, 2, 7, 6)
        ]
    );
    let env = Env::from_spec_file(tmp.spec(&urdf, ""), &[]).unwrap();
    assert_model_agrees(&env);
}

#[test]
fn reach_arm_spec_resolves_to_the_urdf_layout_with_added_motors() {
    let spec = envc::envspec::load(&reach_arm(), &[]).unwrap();
    let m = &spec.model;
    assert_eq!(
        m.bodies,
        [
            "world",
            "base",
            "turret",
            "upper_arm",
            "forearm",
            "fingertip",
            "target_x",
            "target"
        ]
    );
    assert_eq!(
        joint_table(m),
        [
            ("shoulder_pan", JointKind::Hinge, 2, 0, 0),
            ("shoulder_lift", JointKind::Hinge, 3, 1, 1),
            ("elbow", JointKind::Hinge, 4, 2, 2),
            ("target_slide_x", JointKind::Slide, 6, 3, 3),
            ("target_slide_y", JointKind::Slide, 7, 4, 4),
        ]
    );
    let names: Vec<&str> = m.actuators.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["shoulder_pan", "shoulder_lift", "elbow"]);
    let targets: Vec<_> = m.actuators.iter().map(|a| a.target.as_deref()).collect();
    assert_eq!(
        targets,
        [Some("shoulder_pan"), Some("shoulder_lift"), Some("elbow")]
    );
    assert_eq!((spec.obs_dim, spec.act_dim()), (15, 3));
    // [physics] timestep 0.005 × frame_skip 4.
    assert_eq!((m.timestep, spec.dt()), (0.005, 0.02));
    let edits = &spec.model_edits;
    assert_eq!(edits.integrator, Some(Integrator::ImplicitFast));
    assert_eq!(edits.actuators.len(), 3);
    assert_eq!(edits.actuators[1].gear, 5.0);
    assert_eq!(edits.actuators[1].ctrlrange, (-1.0, 1.0));
    assert_eq!(edits.actuators[1].kind, ActuatorKind::Motor);
    // Overrides reach the actuators.
    let spec =
        envc::envspec::load(&reach_arm(), &[envc::Override::text("motor_gear", "7.5")]).unwrap();
    assert!(spec.model_edits.actuators.iter().all(|a| a.gear == 7.5));
}

#[test]
fn reach_arm_runs_on_the_compiled_urdf() {
    let mut env = Env::from_spec_file(reach_arm(), &[]).unwrap();
    assert_model_agrees(&env);
    let m = env.model().ffi();
    assert_eq!((m.nu, m.opt.timestep, m.opt.integrator), (3, 0.005, 3));
    // SAFETY: actuator_gear has nu × 6 entries, actuator_trnid nu × 2.
    let (gear, trnid) = unsafe {
        (
            std::slice::from_raw_parts(m.actuator_gear, 18),
            std::slice::from_raw_parts(m.actuator_trnid, 6),
        )
    };
    assert_eq!([gear[0], gear[6], gear[12]], [5.0, 5.0, 5.0]);
    assert_eq!([trnid[0], trnid[2], trnid[4]], [0, 1, 2]);
    assert_eq!(env.action_space().low, [-1.0; 3]);
    assert_eq!(env.action_space().high, [1.0; 3]);
    assert_eq!(env.dt(), 0.02);

    let (obs, info) = env.reset(Some(3));
    let obs = obs.to_vec();
    // The goal is drawn into the target slides: x, y in [-0.4, 0.4) (+ the slides' origin at z 0.25).
    assert!(obs[6].abs() <= 0.4 && obs[7].abs() <= 0.4 && obs[8] == 0.25);
    assert_eq!(info.get("fingertip").map(<[f64]>::len), Some(3));
    // Arm angles near zero (noise ±0.1): cos close to 1.
    assert!(obs[0..3].iter().all(|c| *c > 0.99));

    // Full torque on the pan joint turns the arm about z; the reward is −distance − 0.1 Σ a².
    let mut last = 0.0;
    for _ in 0..5 {
        let s = env.step(&[1.0, 0.0, 0.0]).unwrap();
        let d = s.obs[12..15].iter().map(|x| x * x).sum::<f64>().sqrt();
        let dist = s.info.scalar("reward_dist").unwrap();
        assert!((dist + d).abs() < 1e-12, "{dist} vs {d}");
        assert_eq!(s.info.scalar("reward_ctrl"), Some(-0.1));
        assert!((s.reward - (dist - 0.1)).abs() < 1e-12);
        assert!(!s.terminated && !s.truncated);
        last = s.obs[9];
    }
    assert!(last > 0.5, "pan velocity {last}");
    let (qpos, _) = env.state();
    assert!(qpos[0] > 0.2, "pan angle {}", qpos[0]);
}

#[test]
fn actuators_can_be_added_to_an_mjcf_model() {
    // Reacher's MJCF has two motors; add a position servo on joint0 and a motor on every 1-dof
    // joint (joint0, joint1 hinges and the target_x, target_y slides), after the model's own.
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium/reacher.xml");
    let tmp = TempSpec::new("mjcf");
    let spec = tmp.spec(
        &model,
        "[actuators.servo]\njoint = \"joint0\"\nkind = \"position\"\nkp = 2.0\nctrlrange = [-0.5, 0.5]\n\
         [actuators.all]\njoint = \"*\"\ngear = 3\nforcerange = [-1, 1]\n",
    );
    let env = Env::from_spec_file(&spec, &[]).unwrap();
    assert_model_agrees(&env);
    let names: Vec<&str> = env
        .spec()
        .model
        .actuators
        .iter()
        .map(|a| a.name.as_str())
        .collect();
    assert_eq!(
        names,
        ["", "", "servo", "joint0", "joint1", "target_x", "target_y"]
    );
    let m = env.model().ffi();
    assert_eq!(m.nu, 7);
    // SAFETY: nu × 2 ctrlrange, nu × mjNGAIN gainprm (10), nu × mjNBIAS biasprm (10).
    let (ctrl, gain, bias, force) = unsafe {
        (
            std::slice::from_raw_parts(m.actuator_ctrlrange, 14),
            std::slice::from_raw_parts(m.actuator_gainprm, 70),
            std::slice::from_raw_parts(m.actuator_biasprm, 70),
            std::slice::from_raw_parts(m.actuator_forcerange, 14),
        )
    };
    assert_eq!((ctrl[4], ctrl[5]), (-0.5, 0.5));
    assert_eq!((gain[20], bias[21]), (2.0, -2.0));
    assert_eq!((ctrl[6], ctrl[7]), (-1.0, 1.0));
    assert_eq!((force[12], force[13]), (-1.0, 1.0));
    assert_eq!(env.action_space().dim(), 7);
}

envc::env!(ReachArm = "fixtures/urdf/reach_arm.toml");

#[test]
fn reach_arm_typed_env_agrees_with_the_dynamic_one() {
    assert_eq!((ReachArm::OBS_DIM, ReachArm::ACT_DIM), (15, 3));
    assert_eq!(
        ReachArmAction::ACTUATORS,
        ["shoulder_pan", "shoulder_lift", "elbow"]
    );
    let mut typed = ReachArm::make().unwrap();
    let mut dynamic = Env::from_spec_file(reach_arm(), &[]).unwrap();
    assert_eq!(typed.ctrl_range(), [(-1.0, 1.0); 3]);
    let run = |env: &mut dyn Environment| {
        let mut out = env.reset(Some(11)).0.to_vec();
        for t in 0..60 {
            let a = [(t as f64 * 0.1).sin(), 0.5, -0.3];
            let s = env.step(&a).unwrap();
            out.extend_from_slice(s.obs);
            out.push(s.reward);
        }
        out
    };
    assert_eq!(run(&mut typed), run(&mut dynamic));
}

fn codes(spec: &Path) -> Vec<Code> {
    match Env::from_spec_file(spec, &[]) {
        Ok(_) => vec![],
        Err(envc::EnvError::Spec(d)) => d.codes(),
        Err(e) => vec![e.code()],
    }
}

#[test]
fn actuator_and_physics_errors_have_stable_codes() {
    let tmp = TempSpec::new("errors");
    let arm = fixture("arm.urdf");
    let cases: &[(&str, Code)] = &[
        ("[actuators.a]\njoint = \"elbo\"\n", Code::E0303),
        (
            "[actuators.a]\njoint = \"elbow\"\nkind = \"servo\"\n",
            Code::E0104,
        ),
        ("[actuators.a]\njoint = \"elbow\"\ngaer = 2\n", Code::E0101),
        ("[actuators.a]\nkind = \"motor\"\n", Code::E0103),
        ("[actuators.a]\njoint = 3\n", Code::E0102),
        (
            "[actuators.a]\njoint = \"elbow\"\nctrlrange = [1, -1]\n",
            Code::E0105,
        ),
        (
            "[actuators.a]\njoint = \"elbow\"\ngear = \"no_such_param\"\n",
            Code::E0201,
        ),
        (
            "[actuators.a]\njoint = \"elbow\"\nkind = \"velocity\"\nkv = -1\n",
            Code::E0105,
        ),
        (
            "[actuators.elbow]\njoint = \"elbow\"\n[actuators.b]\njoint = [\"elbow\"]\n",
            Code::E0106,
        ),
        ("[physics]\nintegrator = \"rk4\"\n", Code::E0104),
        ("[physics]\ntimestep = 0\n", Code::E0105),
        ("[physics]\nsubsteps = 2\n", Code::E0101),
    ];
    for (extra, code) in cases {
        assert_eq!(codes(&tmp.spec(&arm, extra)), [*code], "{extra}");
    }
    // A free joint cannot take a scalar actuator.
    let spec = tmp.spec(
        &fixture("world_floating_planar.urdf"),
        "[actuators.a]\njoint = \"jf\"\n",
    );
    assert_eq!(codes(&spec), [Code::E0107]);
    // Broken URDFs: E0302, not a panic.
    for (name, text) in [
        (
            "dangling.urdf",
            "<robot name=\"r\"><link name=\"a\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
        ),
        ("notxml.urdf", "<robot name=\"r\"><link name=\"a\"></robot>"),
        (
            "twoparents.urdf",
            "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>\
             <joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>\
             <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint></robot>",
        ),
        (
            "badjoint.urdf",
            "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"hinge\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
        ),
    ] {
        let urdf = tmp.write(name, text);
        let err = ModelInfo::from_file(&urdf).unwrap_err();
        assert_eq!(err.code, Code::E0302, "{name}: {}", err.message);
        assert_eq!(codes(&tmp.spec(&urdf, "")), [Code::E0302], "{name}");
    }
}
