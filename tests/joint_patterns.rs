//! Joint properties by glob pattern, spec keyframes and keyframe / root-pose resets, plane
//! floors, commands in agents' observations and the `minus` pairing warning, over
//! `tests/fixtures/joint_patterns/` (a floating robot whose model has no floor, actuators or
//! keyframe, as mjlab's robots come).

use envc::Env;
use envc::multi_agent::MultiAgentEnv;

const BOT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/joint_patterns/bot.toml"
);

fn edit(old: &str, new: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(BOT).unwrap();
    assert!(text.contains(old), "{old}");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/joint_patterns");
    let p = dir.join(format!("tmp-{}-{}.toml", std::process::id(), old.len()));
    std::fs::write(&p, text.replace(old, new)).unwrap();
    p
}

#[test]
fn later_rows_override_earlier_ones_key_by_key_and_rows_override_actuator_tables() {
    let env = Env::from_spec_file(BOT, &[]).unwrap();
    let m = env.model().ffi();
    // SAFETY: nv = 8 (free joint 6 + hip + knee), nu = 2.
    let (arm, damp, gain, bias, force) = unsafe {
        (
            std::slice::from_raw_parts(m.dof_armature, 8).to_vec(),
            std::slice::from_raw_parts(m.dof_damping, 8).to_vec(),
            std::slice::from_raw_parts(m.actuator_gainprm, 20).to_vec(),
            std::slice::from_raw_parts(m.actuator_biasprm, 20).to_vec(),
            std::slice::from_raw_parts(m.actuator_forcerange, 4).to_vec(),
        )
    };
    // "*" sets armature 0.01 and damping 0.1; "kn?e" overrides the knee's armature only.
    assert_eq!(&arm[6..], &[0.01, 0.03]);
    assert_eq!(&damp[6..], &[0.1, 0.1]);
    // kp 20 from the row overrides the table's 5: gainprm[0] = kp, biasprm[1] = −kp, [2] = −kv.
    assert_eq!((gain[0], gain[10]), (20.0, 20.0));
    assert_eq!(
        (bias[1], bias[2], bias[11], bias[12]),
        (-20.0, -1.0, -20.0, -1.0)
    );
    // effort 12.5 on the knee only: forcerange [−12.5, 12.5] and forcelimited.
    assert_eq!(&force[2..], &[-12.5, 12.5]);
    // SAFETY: nu flags.
    let limited = unsafe { std::slice::from_raw_parts(m.actuator_forcelimited, 2) }.to_vec();
    assert_eq!(limited, vec![false, true]);
    // The per-joint table `envc show` prints.
    let rows = envc::describe::joint_table::joint_table(&env);
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[1].rows, vec!["*".to_string(), "kn?e".to_string()]);
    assert_eq!((rows[1].kp, rows[1].kv), (Some(20.0), Some(1.0)));
}

#[test]
fn a_pattern_matching_nothing_and_an_unknown_keyframe_are_located_errors() {
    let p = edit("\"kn?e\" = {", "\"elbow*\" = {");
    let e = envc::envspec::load(&p, &[]).unwrap_err();
    let _ = std::fs::remove_file(&p);
    assert_eq!(e.0[0].code, envc::envspec::Code::E0160, "{e}");
    assert_eq!(
        e.0[0]
            .location
            .as_ref()
            .unwrap()
            .file
            .line_col(e.0[0].location.as_ref().unwrap().span.start)
            .0,
        22
    );
    let p = edit("keyframe = \"stand\"", "keyframe = \"sit\"");
    let e = envc::envspec::load(&p, &[]).unwrap_err();
    let _ = std::fs::remove_file(&p);
    assert_eq!(e.0[0].code, envc::envspec::Code::E0162, "{e}");
}

/// The reset of seed 7, recomputed with numpy from mjlab's formulas (`_sample_se3_range`: six
/// uniforms x, y, z, roll, pitch, yaw; `quat_from_euler_xyz`; `quat_mul(q, delta)`), then two
/// uniforms in ±0.1 added to the joints:
/// ```python
/// rng = np.random.default_rng(7)
/// x = [rng.uniform(a, b) for a, b in [(-.5, .5), (-.4, .3), (.01, .05), (-.2, .1), (-.15, .25), (-3.14, 3.14)]]
/// q = [0, 0, .5, 1, 0, 0, 0, .2, -.4]; q[0:3] += x[0:3]; q[3:7] = quat_mul(q[3:7], quat_from_euler_xyz(*x[3:6]))
/// q[7:9] += [rng.uniform(-.1, .1) for _ in range(2)]
/// ```
const RESET_SEED_7: [f64; 9] = [
    0.12509546660466697,
    0.2280496606787028,
    0.5410274276098077,
    0.38744713703636663,
    -0.011866258596558564,
    -0.06678141336160862,
    0.9193933601776058,
    0.10105306091311494,
    -0.33575431632344677,
];

#[test]
fn keyframe_reset_then_root_pose_then_joint_noise_match_numpy() {
    let mut env = Env::from_spec_file(BOT, &[]).unwrap();
    let obs = env.reset(Some(7)).0.to_vec();
    for (i, (a, b)) in obs[..9].iter().zip(RESET_SEED_7).enumerate() {
        assert!(
            (a - b).abs() <= 4.0 * f64::EPSILON,
            "qpos[{i}]: {a} vs numpy {b}"
        );
    }
    // joints − default_pose: the pose is the keyframe's (hip 0.2 from "*", knee −0.4 after it).
    assert!((obs[9] - (RESET_SEED_7[7] - 0.2)).abs() < 1e-15);
    assert!((obs[10] - (RESET_SEED_7[8] + 0.4)).abs() < 1e-15);
}

#[test]
fn a_plane_floor_keeps_the_model_extent_at_the_robot() {
    let env = Env::from_spec_file(BOT, &[]).unwrap();
    let plane = env.model().ffi().stat.extent;
    let p = edit(
        "[geoms.floor]\ntype = \"plane\"",
        "[geoms.floor]\ntype = \"box\"\nsize = [100.0, 100.0, 0.1]\npos = [0.0, 0.0, -0.1]",
    );
    let boxed = Env::from_spec_file(&p, &[]);
    let _ = std::fs::remove_file(&p);
    let boxed = boxed.unwrap().model().ffi().stat.extent;
    // The robot is under a metre across; a 100 m box floor makes the extent (the default
    // camera's distance) two hundred times that.
    assert!(plane < 2.0, "{plane}");
    assert!(boxed > 100.0, "{boxed}");
}

#[test]
fn minus_pairing_different_joints_is_a_warning() {
    let ok = envc::envspec::load(std::path::Path::new(BOT), &[]).unwrap();
    assert!(ok.warnings.is_empty());
    let p = edit("joint = [\"hip\", \"knee\"]", "joint = [\"knee\", \"hip\"]");
    let r = envc::envspec::load(&p, &[]);
    let _ = std::fs::remove_file(&p);
    let r = r.unwrap();
    assert_eq!(r.warnings.len(), 1);
    assert_eq!(r.warnings[0].code, envc::envspec::Code::W0401);
    assert!(
        r.warnings[0].message.contains("2 of 2 places"),
        "{}",
        r.warnings[0].message
    );
}

#[test]
fn agents_read_the_task_commands() {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../cli/tests/diff_golden/dynamics"
    );
    let mut ma = MultiAgentEnv::from_spec_file(format!("{dir}/agents_old.toml"), &[]).unwrap();
    let mut task = Env::from_spec_file(format!("{dir}/base.toml"), &[]).unwrap();
    let (obs, _) = ma.reset(Some(3));
    task.reset(Some(3));
    let cmd = task.field(envc::envspec::Field::Command).to_vec();
    assert_eq!(cmd.len(), 2);
    // agent_0 (hip): qpos, qvel, then command[twist]; agent_1 (knee): ..., command[twist].ang_vel_z.
    assert_eq!(&obs[0][obs[0].len() - 2..], &cmd[..]);
    assert_eq!(obs[1][obs[1].len() - 1], cmd[1]);
}
