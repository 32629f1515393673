//! Bad input at run time is an error value with a stable code, never a panic or an abort, and
//! MuJoCo's messages are captured instead of printed or logged to MUJOCO_LOG.TXT.

use std::path::{Path, PathBuf};

use envc::envspec::Code;
use envc::{Env, EnvError, Override};

fn spec(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(file)
}

/// A scratch directory of one test, removed when the test ends (passed or not).
struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn tempdir(name: &str) -> TempDir {
    let d = std::env::temp_dir().join(format!("envc-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    TempDir(d)
}

#[test]
fn wrong_action_length_is_an_error_and_changes_nothing() {
    let mut env = Env::make("Hopper-v5", &[]).unwrap();
    let obs0 = env.reset(Some(3)).0.to_vec();
    let e = env.step(&[0.1, 0.2]).unwrap_err();
    assert_eq!(e.code(), Code::E1101);
    assert_eq!(
        e.to_string(),
        "error[E1101]: action has 2 entries but Hopper-v5 expects 3"
    );
    assert_eq!(env.obs(), &obs0[..]);
    assert_eq!(env.elapsed_steps(), 0);
    assert!(env.step(&[0.1, 0.2, 0.3]).is_ok());
}

#[test]
fn non_finite_actions_are_rejected() {
    let mut env = Env::make("Ant-v5", &[]).unwrap();
    env.reset(Some(0));
    let mut a = vec![0.0; 8];
    a[5] = f64::NAN;
    let e = env.step(&a).unwrap_err();
    assert_eq!(e.code(), Code::E1102);
    assert!(e.to_string().contains("action[5] is NaN"), "{e}");
    a[5] = f64::NEG_INFINITY;
    assert_eq!(env.step(&a).unwrap_err().code(), Code::E1102);
    assert_eq!(env.elapsed_steps(), 0);
}

#[test]
fn step_before_reset_is_an_error() {
    let mut env = Env::make("Swimmer-v5", &[]).unwrap();
    assert_eq!(env.step(&[0.0, 0.0]).unwrap_err().code(), Code::E1103);
}

#[test]
fn unknown_override_and_bad_override_type() {
    let e = Env::make("Ant-v5", &[Override::text("ctrl_cost_wieght", "0.1")])
        .err()
        .unwrap();
    assert_eq!(e.code(), Code::E0202);
    assert!(
        e.to_string().contains("did you mean `ctrl_cost_weight`?"),
        "{e}"
    );
    let e = Env::make("Ant-v5", &[Override::text("healthy_z_range", "0.5")])
        .err()
        .unwrap();
    assert_eq!(e.code(), Code::E0203);
}

#[test]
fn unknown_env_id_suggests_the_closest() {
    let e = Env::make("Hoper-v5", &[]).err().unwrap();
    assert!(e.to_string().contains("did you mean `Hopper-v5`?"), "{e}");
}

#[test]
fn missing_model_file() {
    let e = Env::from_spec_file(
        spec("ant.toml"),
        &[Override::text("xml_file", "/nonexistent/ant.xml")],
    )
    .err()
    .unwrap();
    assert_eq!(e.code(), Code::E0301);
    assert!(e.to_string().contains("/nonexistent/ant.xml"), "{e}");
}

#[test]
fn a_model_mujoco_rejects_is_a_compile_error() {
    // Well-formed MJCF that envspec can read, but MuJoCo refuses (a sphere with a negative size).
    let dir = tempdir("badmodel");
    let xml = dir.join("bad.xml");
    std::fs::write(
        &xml,
        r#"<mujoco><worldbody><body name="b"><joint name="j" type="hinge"/><geom type="sphere" size="-1"/></body></worldbody>
           <actuator><motor joint="j"/></actuator></mujoco>"#,
    )
    .unwrap();
    let toml = dir.join("bad.toml");
    std::fs::write(
        &toml,
        format!(
            "[env]\nid = \"Bad-v0\"\n[params]\nxml_file = {:?}\nframe_skip = 1\nmax_episode_steps = 10\n[observation.qpos]\nsource = \"qpos\"\n",
            xml.display().to_string()
        ),
    )
    .unwrap();
    let e = Env::from_spec_file(&toml, &[]).err().unwrap();
    assert_eq!(e.code(), Code::E1001, "{e}");
    assert!(e.to_string().contains("bad.xml"), "{e}");
}

/// E1001 points into the model file: MuJoCo's `Element ..., line N` becomes `model.xml:N:col`
/// with the line shown, not a bare message without a location.
#[test]
fn a_compile_error_names_the_model_line() {
    let dir = tempdir("badmodel-line");
    let toml = dir.join("bad.toml");
    std::fs::write(
        &toml,
        "[env]\nid = \"Bad-v0\"\n[params]\nxml_file = \"bad.xml\"\nframe_skip = 1\nmax_episode_steps = 10\n[observation.qpos]\nsource = \"qpos\"\n",
    )
    .unwrap();
    let xml = dir.join("bad.xml");
    let model = |joint_attrs: &str, size: &str| {
        format!(
            "<mujoco>\n  <worldbody>\n    <body name=\"b\">\n      <joint name=\"j\" type=\"hinge\"{joint_attrs}/>\n      <geom type=\"sphere\" size=\"{size}\"/>\n    </body>\n  </worldbody>\n  <actuator><motor joint=\"j\"/></actuator>\n</mujoco>\n"
        )
    };
    // A compile error: the element's line, its tag under the caret.
    std::fs::write(&xml, model("", "-1")).unwrap();
    let e = Env::from_spec_file(&toml, &[]).err().unwrap();
    assert_eq!(e.code(), Code::E1001, "{e}");
    let text = e.to_string();
    assert!(
        text.starts_with(
            "error[E1001]: MuJoCo could not compile {p}: Error: size 0 must be positive in geom\n"
                .replace("{p}", &xml.display().to_string())
                .as_str()
        ),
        "{text}"
    );
    assert!(
        text.contains(&format!(" --> {}:5:7\n", xml.display())),
        "{text}"
    );
    assert!(
        text.contains("5 |       <geom type=\"sphere\" size=\"-1\"/>\n"),
        "{text}"
    );
    assert!(
        text.ends_with("  |       ^^^^^ MuJoCo's error is about this <geom>"),
        "{text}"
    );
    // An XML schema error: the attribute it names.
    std::fs::write(&xml, model(" bogus=\"1\"", "0.1")).unwrap();
    let e = Env::from_spec_file(&toml, &[]).err().unwrap();
    let text = e.to_string();
    assert!(text.contains("unrecognized attribute: 'bogus'\n"), "{text}");
    assert!(
        text.contains(&format!(" --> {}:4:36\n", xml.display())),
        "{text}"
    );
    assert!(
        text.ends_with("^^^^^ MuJoCo's error is about this <joint>"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mujoco_warnings_are_captured_not_logged() {
    // A model with a NaN, which MuJoCo's XML reader warns about at load (the reference prints it
    // and appends it to MUJOCO_LOG.TXT in the working directory).
    let dir = tempdir("cwd");
    let xml = dir.join("nan.xml");
    std::fs::write(
        &xml,
        r#"<mujoco><worldbody><body name="b"><joint name="j" type="slide"/>
           <geom type="sphere" size="0.1" rgba="1 0 0 nan"/></body></worldbody>
           <actuator><motor joint="j"/></actuator></mujoco>"#,
    )
    .unwrap();
    let toml = dir.join("nan.toml");
    std::fs::write(
        &toml,
        format!(
            "[env]\nid = \"Nan-v0\"\n[params]\nxml_file = {:?}\nframe_skip = 1\nmax_episode_steps = 10\n[observation.qpos]\nsource = \"qpos\"\n",
            xml.display().to_string()
        ),
    )
    .unwrap();
    let before = std::env::current_dir().unwrap();
    std::env::set_current_dir(&dir).unwrap();
    let env = Env::from_spec_file(&toml, &[]);
    // HalfCheetah's deprecated settotalmass no longer reaches MuJoCo's compiler (envc applies
    // it), so MuJoCo has nothing to warn about there.
    let cheetah = Env::from_spec_file(spec("half_cheetah.toml"), &[]);
    std::env::set_current_dir(before).unwrap();
    let env = env.unwrap();
    assert!(
        env.warnings().iter().any(|w| w.contains("NaN")),
        "{:?}",
        env.warnings()
    );
    assert!(cheetah.unwrap().warnings().is_empty());
    assert!(!dir.join("MUJOCO_LOG.TXT").exists());
}

#[test]
fn instability_warnings_are_retrievable() {
    // A stiff spring integrated with a huge timestep blows up; MuJoCo warns (and resets the state).
    let dir = tempdir("unstable");
    let xml = dir.join("unstable.xml");
    std::fs::write(
        &xml,
        r#"<mujoco><option timestep="1"/><worldbody><body name="b"><joint name="j" type="slide" stiffness="1e9"/>
           <geom type="sphere" size="0.1"/></body></worldbody><actuator><motor joint="j" gear="1e6"/></actuator></mujoco>"#,
    )
    .unwrap();
    let toml = dir.join("unstable.toml");
    std::fs::write(
        &toml,
        format!(
            "[env]\nid = \"Unstable-v0\"\n[params]\nxml_file = {:?}\nframe_skip = 5\nmax_episode_steps = 10\n[observation.qpos]\nsource = \"qpos\"\n[reset.qpos]\ntarget = \"qpos\"\nkind = \"uniform\"\nscale = 1.0\n",
            xml.display().to_string()
        ),
    )
    .unwrap();
    let mut env = Env::from_spec_file(&toml, &[]).unwrap();
    env.reset(Some(1));
    for _ in 0..5 {
        env.step(&[1.0]).unwrap();
    }
    assert!(
        env.warnings()
            .iter()
            .any(|w| w.contains("Nan, Inf or huge value")),
        "{:?}",
        env.warnings()
    );
}

#[test]
fn errors_are_values_of_one_type() {
    fn code(r: Result<Env, EnvError>) -> Code {
        r.err().unwrap().code()
    }
    assert_eq!(
        code(Env::make("Ant-v5", &[Override::text("frame_skip", "0")])),
        Code::E0105
    );
}

#[test]
fn negative_reset_noise_is_a_spec_error_not_a_panic() {
    let e = Env::make("Hopper-v5", &[Override::text("reset_noise_scale", "-0.1")])
        .err()
        .unwrap();
    assert_eq!(e.code(), Code::E0105);
    assert!(e.to_string().contains("[reset.qpos]"), "{e}");
}

/// A Hopper whose MuJoCo arena (`<size memory>`) holds a contact-free state but overflows once
/// the robot touches the floor: MuJoCo's `mju_error` used to print `ERROR:` on stdout, append to
/// MUJOCO_LOG.TXT in the working directory and end the process with exit(1).
fn hopper_with_arena(dir: &Path, memory: &str) -> PathBuf {
    let xml = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium/hopper.xml"),
    )
    .unwrap()
    .replacen(
        "<worldbody>",
        &format!("<size memory=\"{memory}\"/>\n  <worldbody>"),
        1,
    );
    std::fs::write(dir.join("hopper.xml"), xml).unwrap();
    let toml = std::fs::read_to_string(spec("hopper.toml"))
        .unwrap()
        .replace("../../assets/gymnasium/hopper.xml", "hopper.xml");
    let p = dir.join("hopper.toml");
    std::fs::write(&p, toml).unwrap();
    p
}

#[test]
fn a_mujoco_error_in_a_step_is_an_error_value_and_a_reset_recovers() {
    let dir = tempdir("arena");
    let mut env = Env::from_spec_file(hopper_with_arena(&dir, "17K"), &[]).unwrap();
    // Steps until the arena overflows, from the reset of `seed`.
    let run = |env: &mut Env, seed: u64| -> usize {
        env.reset(Some(seed));
        for n in 1..=1000 {
            if let Err(e) = env.step(&[1.0, -1.0, 1.0]) {
                assert_eq!(e.code(), Code::E1004, "{e}");
                let text = e.to_string();
                assert!(
                    text.contains("mj_stackAlloc: out of memory") && text.contains("in a step"),
                    "{text}"
                );
                return n;
            }
        }
        panic!("no arena overflow in 1000 steps")
    };
    let first = run(&mut env, 7);
    // No step from MuJoCo's mid-error state.
    assert_eq!(env.step(&[0.0; 3]).unwrap_err().code(), Code::E1103);
    // A reset gives exactly the state a fresh env gives for the same seed, and the same run fails
    // at the same step again.
    let mut fresh = Env::make("Hopper-v5", &[]).unwrap();
    assert_eq!(
        env.reset(Some(7)).0.to_vec(),
        fresh.reset(Some(7)).0.to_vec()
    );
    assert_eq!(run(&mut env, 7), first);
    assert!(!dir.join("MUJOCO_LOG.TXT").exists() && !Path::new("MUJOCO_LOG.TXT").exists());
}

#[test]
fn a_model_mujoco_cannot_run_at_all_is_refused_when_the_env_is_built() {
    let dir = tempdir("arena-tiny");
    let e = Env::from_spec_file(hopper_with_arena(&dir, "10K"), &[])
        .err()
        .unwrap();
    assert_eq!(e.code(), Code::E1004, "{e}");
    assert!(
        e.to_string()
            .contains("in a trial mj_forward when building the env"),
        "{e}"
    );
}

/// A PD default pose outside a limited actuator's control range (degrees where the model takes
/// radians) is E1110 naming the range: MuJoCo would clamp every target to it without a word.
#[test]
fn a_default_pose_outside_the_control_range_is_an_error() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("specs/examples/mjlab_velocity_flat_go1.toml"))
        .unwrap()
        .replace("\"*thigh_joint\" = 0.9,", "\"*thigh_joint\" = 51.6,")
        .replace("\"../../assets/", &format!("\"{}/assets/", root.display()));
    let dir = tempdir("degrees");
    let p = dir.join("go1.toml");
    std::fs::write(&p, text).unwrap();
    let Err(e) = Env::from_spec_file(&p, &[]) else {
        panic!("a default pose in degrees must not load");
    };
    assert_eq!(e.code(), Code::E1110, "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("default_pose[1] = 51.6 is outside actuator `FR_thigh_joint`'s control range"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
