//! Maze parity: envc's maze envs replay trajectories recorded from Gymnasium-Robotics 1.4.2
//! (tests/reference/record_maze.py) bit for bit: dict observations, rewards, termination,
//! truncation, success and the robot's info, across seeded and unseeded resets.
//!
//! `ENVC_MAZE_DIR=<dir>` replays a fresh recording instead of the committed fixtures (the live
//! check in scripts/test.sh).

use std::path::{Path, PathBuf};

use envc::maze::{MazeEnv, ResetOptions};
use envc::{EnvError, Override};
use serde_json::Value;

/// Third-party models (MuJoCo Menagerie's) the tests use, in a directory beside the repository.
const SHARED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared");

fn dir() -> PathBuf {
    match std::env::var_os("ENVC_MAZE_DIR") {
        Some(d) => PathBuf::from(d),
        None => envc_tests::fixtures_of("maze"),
    }
}

fn unhex(s: &str) -> Vec<f64> {
    let b: Vec<u8> = (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect();
    b.chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

struct Check {
    case: String,
    errors: Vec<String>,
}

impl Check {
    fn eq(&mut self, t: usize, what: &str, ours: &[f64], theirs: &[f64]) {
        if bits(ours) != bits(theirs) && self.errors.len() < 20 {
            self.errors.push(format!(
                "{} event {t}: {what}: envc {ours:?} != reference {theirs:?}",
                self.case
            ));
        }
    }
    fn flag(&mut self, t: usize, what: &str, ours: bool, theirs: bool) {
        if ours != theirs && self.errors.len() < 20 {
            self.errors.push(format!(
                "{} event {t}: {what}: envc {ours} != reference {theirs}",
                self.case
            ));
        }
    }
}

fn check_obs(c: &mut Check, t: usize, env: &MazeEnv, ev: &Value) {
    let o = env.obs();
    let r = &ev["obs"];
    c.eq(
        t,
        "observation",
        &o.observation,
        &unhex(r["observation"].as_str().unwrap()),
    );
    c.eq(
        t,
        "achieved_goal",
        &o.achieved_goal,
        &unhex(r["achieved_goal"].as_str().unwrap()),
    );
    c.eq(
        t,
        "desired_goal",
        &o.desired_goal,
        &unhex(r["desired_goal"].as_str().unwrap()),
    );
}

fn check_info(c: &mut Check, t: usize, info: envc::Info<'_>, ev: &Value) {
    let theirs = ev["info"].as_object().unwrap();
    let ours: Vec<&str> = info.keys().collect();
    let mut their_keys: Vec<&str> = theirs.keys().map(|k| k.as_str()).collect();
    let mut ours_sorted = ours.clone();
    ours_sorted.sort();
    their_keys.sort();
    if ours_sorted != their_keys {
        c.errors.push(format!(
            "{} event {t}: info keys {ours:?} != {their_keys:?}",
            c.case
        ));
        return;
    }
    for (k, v) in theirs {
        c.eq(
            t,
            &format!("info[{k}]"),
            info.get(k).unwrap(),
            &unhex(v.as_str().unwrap()),
        );
    }
}

/// The maze recording's profile: its own `numerics` key, else its directory's manifest.json.
fn recorded_profile(path: &Path) -> envc::numerics::Profile {
    let rec: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    if rec.get("numerics").is_some() {
        return envc_tests::recorded_profile(&rec);
    }
    let m = path.parent().unwrap().join("manifest.json");
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&m).unwrap_or_else(|e| {
        panic!(
            "{}: no `numerics` key and no readable manifest.json: {e}",
            path.display()
        )
    }))
    .unwrap();
    envc_tests::recorded_profile(&m)
}

fn replay(path: &Path) -> Result<(usize, Vec<String>), EnvError> {
    let rec: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let overrides: Vec<Override> = rec["overrides"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| Override::text(k, &v.as_str().unwrap().replace("$SHARED", SHARED)))
        .collect();
    let mut env = MazeEnv::make(rec["id"].as_str().unwrap(), &overrides)?;
    env.set_numerics(recorded_profile(path));
    let mut c = Check {
        case: rec["name"].as_str().unwrap().to_string(),
        errors: vec![],
    };
    let events = rec["events"].as_array().unwrap();
    for (t, ev) in events.iter().enumerate() {
        if ev.get("reset").is_some() {
            let seed = ev["reset"].as_u64();
            let options = ev["options"].as_object().map(|o| {
                let cell = |k: &str| {
                    o.get(k).and_then(|v| v.as_array()).map(|a| {
                        [
                            a[0].as_u64().unwrap() as usize,
                            a[1].as_u64().unwrap() as usize,
                        ]
                    })
                };
                ResetOptions {
                    goal_cell: cell("goal_cell"),
                    reset_cell: cell("reset_cell"),
                }
            });
            let (_, success) = env.reset(seed, options)?;
            c.flag(
                t,
                "reset success",
                success,
                ev["success"].as_bool().unwrap(),
            );
            check_obs(&mut c, t, &env, ev);
            check_info(&mut c, t, env.robot().reset_info(), ev);
        } else {
            let action = unhex(ev["action"].as_str().unwrap());
            let s = env.step(&action)?;
            let (reward, term, trunc, success) = (s.reward, s.terminated, s.truncated, s.success);
            c.eq(
                t,
                "reward",
                &[reward],
                &unhex(ev["reward"].as_str().unwrap()),
            );
            c.flag(t, "terminated", term, ev["terminated"].as_bool().unwrap());
            c.flag(t, "truncated", trunc, ev["truncated"].as_bool().unwrap());
            c.flag(t, "success", success, ev["success"].as_bool().unwrap());
            check_obs(&mut c, t, &env, ev);
            check_info(&mut c, t, env.robot().step_info(), ev);
        }
    }
    Ok((events.len(), c.errors))
}

#[test]
fn maze_parity() {
    parity_of(&dir());
}

/// Recorded on an AVX2-only profile (`openblas-haswell`: glibc `exp` for the dense reward).
#[test]
fn maze_parity_avx2_recording() {
    parity_of(&Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/fixtures/avx2/maze"));
}

fn parity_of(d: &Path) {
    let mut files: Vec<PathBuf> = std::fs::read_dir(d)
        .unwrap_or_else(|e| panic!("{}: {e} (run tests/reference/record_maze.py)", d.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.extension().is_some_and(|x| x == "json")
                && !p.ends_with("npexp.json")
                && !p.ends_with("manifest.json")
        })
        .collect();
    files.sort();
    assert!(
        files.len() >= 40,
        "expected the maze cases in {}",
        d.display()
    );
    let mut errors = vec![];
    let mut events = 0;
    for f in &files {
        match replay(f) {
            Ok((n, e)) => {
                events += n;
                errors.extend(e);
            }
            Err(e) => errors.push(format!("{}: {e}", f.display())),
        }
    }
    eprintln!(
        "maze parity: {} cases, {events} events from {}",
        files.len(),
        d.display()
    );
    assert!(
        errors.is_empty(),
        "{} mismatches:\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// The dense reward's `exp` against numpy's `np.exp` (SVML on AVX512 machines), bit for bit.
#[test]
fn numpy_exp() {
    let rec: Value =
        serde_json::from_str(&std::fs::read_to_string(dir().join("npexp.json")).unwrap()).unwrap();
    let svml = envc_tests::recorded_profile(&rec);
    let xs = unhex(rec["x"].as_str().unwrap());
    let ys = unhex(rec["exp"].as_str().unwrap());
    let bad: Vec<_> = xs
        .iter()
        .zip(&ys)
        .filter(|(x, y)| envc::numerics::exp(svml, **x).to_bits() != y.to_bits())
        .take(5)
        .collect();
    assert!(bad.is_empty(), "np.exp differs at (x, numpy): {bad:?}");
    assert!(xs.len() >= 6000);
}

/// The Go1 placed in a maze by spec only (specs/examples/go1_maze.toml over its own task spec):
/// the world has the U-maze's 18 walls (2 m cells), the observation is the Go1 spec's, and the
/// episode runs with the goal task's reward.
#[test]
fn go1_in_a_maze_by_spec() {
    let spec = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/examples/go1_maze.toml");
    let xml = format!("{SHARED}/models/unitree_go1/scene.xml");
    let mut env = MazeEnv::make(spec.to_str().unwrap(), &[Override::text("xml_file", &xml)])
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(env.layout().walls.len(), 18);
    assert_eq!(env.observation_dim(), env.robot().obs_dim());
    assert_eq!(env.act_dim(), 12);
    let (obs, success) = env.reset(Some(3), None).unwrap();
    let start = obs.achieved_goal;
    assert!(!success);
    // UMaze has no r/g/c cells, so every free cell is a start candidate; the start is within the
    // noise (±0.25·s) of one of their centres.
    assert!(
        env.layout()
            .resets
            .iter()
            .any(|c| (c[0] - start[0]).abs() <= 0.5 && (c[1] - start[1]).abs() <= 0.5)
    );
    let mut steps = 0;
    for _ in 0..40 {
        let s = env.step(&[0.0; 12]).unwrap();
        assert!(s.reward > 0.0 && s.reward <= 1.0);
        assert!(!s.terminated && !s.truncated);
        steps += 1;
    }
    assert_eq!(steps, 40);
}

/// User input never panics: bad maze specs give stable error codes.
#[test]
fn maze_spec_errors_have_codes() {
    let dir = std::env::temp_dir().join(format!("envc-maze-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let robot = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/robotics/maze/point.toml");
    let case = |body: &str| {
        let p = dir.join("m.toml");
        std::fs::write(
            &p,
            format!(
                "[maze]\nid = \"X-v0\"\nrobot = {:?}\n{body}",
                robot.display().to_string()
            ),
        )
        .unwrap();
        MazeEnv::make(p.to_str().unwrap(), &[])
            .err()
            .map(|e| e.code())
    };
    use envspec::Code;
    let base = "maze_size_scaling = 1.0\nmaze_height = 0.4\n";
    assert_eq!(
        case(&format!("{base}map = \"1 1 1\\n1 x 1\\n1 1 1\"")),
        Some(Code::E0702)
    );
    assert_eq!(
        case(&format!("{base}map = \"1 1 1\\n1 0\\n1 1 1\"")),
        Some(Code::E0701)
    );
    assert_eq!(
        case(&format!("{base}map = \"1 1 1\\n1 1 1\"")),
        Some(Code::E0703)
    );
    assert_eq!(case("map = \"1 0 1\""), Some(Code::E0103));
    assert_eq!(
        case(&format!(
            "{base}map = \"1 0 1\"\nreward_type = \"negative\""
        )),
        Some(Code::E0104)
    );
    assert_eq!(
        case(&format!("{base}map = \"1 0 1\"\nmaze_colour = 1")),
        Some(Code::E0101)
    );
    assert_eq!(
        case(&format!("{base}map = \"maps/none.toml\"")),
        Some(Code::E0600)
    );
    assert_eq!(case(&format!("{base}map = \"1 0 g 1\"")), None);
    // A wall cell as a reset option and an unknown id.
    let mut env = MazeEnv::make("PointMaze_UMaze-v3", &[]).unwrap();
    let opt = ResetOptions {
        goal_cell: Some([0, 0]),
        reset_cell: None,
    };
    assert_eq!(
        env.reset(Some(0), Some(opt)).err().map(|e| e.code()),
        Some(Code::E0708)
    );
    assert!(env.step(&[0.0, 0.0]).is_err());
    assert_eq!(
        MazeEnv::make("PointMaze_UMase-v3", &[])
            .err()
            .map(|e| e.code()),
        Some(Code::E0601)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The checks `MazeEnv::new` makes on the compiled world point at the spec: a robot wider than a
/// cell (E0706, at `maze_size_scaling`), a robot without root x, y (E0707, at `robot`), and a
/// layout without goals on a spec built by hand (E0703).
#[test]
fn runtime_maze_checks_point_at_the_spec() {
    let dir = std::env::temp_dir().join(format!("envc-maze-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let specs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/robotics/maze");
    let first = |e: EnvError| match e {
        EnvError::Spec(d) => d.0[0].clone(),
        e => panic!("not a spec error: {e}"),
    };
    let write = |robot: &Path, scaling: &str| {
        let p = dir.join("m.toml");
        std::fs::write(
            &p,
            format!(
                "[maze]\nid = \"X-v0\"\nrobot = {:?}\nmaze_height = 0.4\nmaze_size_scaling = {scaling}\nmap = \"1 r 0 g 1\"\n",
                robot.display().to_string()
            ),
        )
        .unwrap();
        p
    };
    // The point robot is a ball of radius 0.1 (assets/robotics/point.xml): 0.2 wide.
    let p = write(&specs.join("point.toml"), "0.15");
    let d = first(MazeEnv::from_spec_file(&p, &[]).err().unwrap());
    assert_eq!(d.code, envspec::Code::E0706);
    assert!(d.position().unwrap().ends_with("m.toml:5:21"), "{d}");
    assert!(d.message.contains("0.200 × 0.200"), "{d}");
    assert!(MazeEnv::from_spec_file(&write(&specs.join("point.toml"), "0.25"), &[]).is_ok());
    // An override of the cell size is pointed at in its own text.
    let d = first(
        MazeEnv::from_spec_file(&p, &[Override::text("maze_size_scaling", "0.1")])
            .err()
            .unwrap(),
    );
    assert_eq!(d.code, envspec::Code::E0706);
    assert_eq!(
        d.position().as_deref(),
        Some("<override maze_size_scaling>:1:1")
    );
    // One hinge: nq = 1.
    std::fs::write(
        dir.join("hinge.xml"),
        "<mujoco><worldbody><body><joint name=\"h\" type=\"hinge\"/><geom size=\"0.05\"/></body></worldbody><actuator><motor joint=\"h\"/></actuator></mujoco>",
    )
    .unwrap();
    std::fs::write(
        dir.join("hinge.toml"),
        "[env]\nid = \"Hinge-v0\"\n[params]\nxml_file = \"hinge.xml\"\nframe_skip = 1\nmax_episode_steps = 0\n[observation.qpos]\nsource = \"qpos\"\n",
    )
    .unwrap();
    let d = first(
        MazeEnv::from_spec_file(&write(&dir.join("hinge.toml"), "1.0"), &[])
            .err()
            .unwrap(),
    );
    assert_eq!(d.code, envspec::Code::E0707);
    assert!(d.message.contains("has 1 qpos entry;"), "{d}");
    assert!(d.position().unwrap().ends_with("m.toml:3:9"), "{d}");
    // A spec changed after reading skips the reader's checks; `new` still refuses it.
    let mut spec = envspec::maze::load_maze(&specs.join("point_maze.toml"), &[]).unwrap();
    for row in &mut spec.grid {
        row.fill(envspec::maze::Cell::Wall);
    }
    let d = first(MazeEnv::new(spec).err().unwrap());
    assert_eq!(d.code, envspec::Code::E0703);
    // (at the grid, in the map file the spec names)
    assert!(
        d.position().unwrap().ends_with("maps/umaze.toml:4:8"),
        "{d}"
    );
    // A reset option outside the 5×5 U-maze.
    let mut env = MazeEnv::make("PointMaze_UMaze-v3", &[]).unwrap();
    let opt = ResetOptions {
        goal_cell: None,
        reset_cell: Some([1, 9]),
    };
    let d = first(env.reset(Some(0), Some(opt)).err().unwrap());
    assert_eq!(d.code, envspec::Code::E0708);
    assert_eq!(
        d.message,
        "reset_cell [1, 9] is not a free cell of the 5×5 maze"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Errors found while building a maze's robot point into the maze spec, each at its
/// location: a missing robot file at `robot`, a bad `robot_params` value at its entry, a robot
/// that is a maze (or the maze itself) or a multi-agent spec as one error at `robot`, a robot
/// model using the maze's own names (E0106), a negative `goal_threshold` (E0803) and a reset
/// option on a wall (E0708) at the map.
#[test]
fn maze_errors_about_the_robot_point_into_the_maze_spec() {
    let dir = std::env::temp_dir().join(format!("envc-maze-located-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let point = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/robotics/maze/point.toml");
    let first = |e: EnvError| match e {
        EnvError::Spec(d) => {
            assert_eq!(d.len(), 1, "{d}");
            d.0[0].clone()
        }
        e => panic!("not a spec error: {e}"),
    };
    let case = |robot: &str, extra: &str| {
        let p = dir.join("m.toml");
        std::fs::write(
            &p,
            format!(
                "[maze]\nid = \"X-v0\"\nrobot = {robot:?}\nmaze_height = 0.4\nmaze_size_scaling = 1.0\nmap = \"1 r 0 g 1\"\n{extra}"
            ),
        )
        .unwrap();
        let d = first(MazeEnv::from_spec_file(&p, &[]).err().expect("rejected"));
        let at = d.position().expect("a location");
        let at = at.rsplit('/').next().unwrap_or_default().to_string();
        (d, at)
    };
    let point = point.display().to_string();
    use envspec::Code;

    let (d, at) = case("nothing.toml", "");
    assert_eq!((d.code, at.as_str()), (Code::E0600, "m.toml:3:9"), "{d}");
    let (d, at) = case(&point, "robot_params = { velocity = 1.0 }");
    assert_eq!((d.code, at.as_str()), (Code::E0202, "m.toml:7:18"), "{d}");
    let (d, at) = case(&point, "robot_params = { frame_skip = \"x\" }");
    assert_eq!((d.code, at.as_str()), (Code::E0203, "m.toml:7:18"), "{d}");
    let (d, at) = case(&point, "robot_params = { frame_skip = -3 }");
    assert_eq!((d.code, at.as_str()), (Code::E0105, "m.toml:7:18"), "{d}");
    assert_eq!(d.message, "frame_skip must be a positive integer");

    let (d, at) = case("m.toml", "");
    assert_eq!((d.code, at.as_str()), (Code::E0108, "m.toml:3:9"), "{d}");
    assert_eq!(d.message, "`robot` names this maze file itself");
    let agents = Path::new(env!("CARGO_MANIFEST_DIR")).join("../specs/mamujoco/ant.toml");
    let (d, at) = case(&agents.display().to_string(), "");
    assert_eq!((d.code, at.as_str()), (Code::E0122, "m.toml:3:9"), "{d}");

    let (d, at) = case(&point, "goal_threshold = -0.5");
    assert_eq!((d.code, at.as_str()), (Code::E0803, "m.toml:7:18"), "{d}");

    // A robot whose own goal terms use a goal vector of 1 element (the maze's has 2).
    let goal_robot = std::fs::read_to_string(&point).unwrap().replace(
        "../../../assets",
        &format!("{}/../assets", env!("CARGO_MANIFEST_DIR")),
    ) + "\n[reward.near]\nkind = \"goal_sparse\"\nachieved = \"qpos[0:1]\"\ndesired = \"goal\"\nthreshold = 0.1\n";
    std::fs::write(dir.join("goal_robot.toml"), goal_robot).unwrap();
    let (d, at) = case("goal_robot.toml", "");
    assert_eq!((d.code, at.as_str()), (Code::E0801, "m.toml:3:9"), "{d}");
    assert_eq!(
        d.label.as_deref(),
        Some("the robot spec, with goal terms of its own")
    );

    // A robot model with a site named `target`, the maze's goal marker.
    std::fs::write(
        dir.join("clash.xml"),
        "<mujoco><worldbody><site name=\"target\"/><body><joint name=\"x\" type=\"slide\" axis=\"1 0 0\"/><joint name=\"y\" type=\"slide\" axis=\"0 1 0\"/><geom size=\"0.05\"/></body></worldbody><actuator><motor joint=\"x\"/><motor joint=\"y\"/></actuator></mujoco>",
    )
    .unwrap();
    std::fs::write(
        dir.join("clash.toml"),
        "[env]\nid = \"Clash-v0\"\n[params]\nxml_file = \"clash.xml\"\nframe_skip = 1\nmax_episode_steps = 0\n[observation.qpos]\nsource = \"qpos\"\n",
    )
    .unwrap();
    let (d, at) = case("clash.toml", "");
    assert_eq!((d.code, at.as_str()), (Code::E0106, "m.toml:3:9"), "{d}");
    assert!(
        d.message.ends_with(
            "already has an element named `target`, the name the maze gives its goal marker"
        ),
        "{d}"
    );

    // A reset option on a wall: at that cell of the map file; outside the map: at the grid.
    let mut env = MazeEnv::make("PointMaze_UMaze-v3", &[]).unwrap();
    let opt = ResetOptions {
        goal_cell: Some([0, 0]),
        reset_cell: None,
    };
    let d = first(env.reset(Some(0), Some(opt)).err().unwrap());
    assert_eq!(d.code, Code::E0708);
    assert!(
        d.position().unwrap().ends_with("maps/umaze.toml:5:1"),
        "{d}"
    );
    let opt = ResetOptions {
        goal_cell: None,
        reset_cell: Some([7, 0]),
    };
    let d = first(env.reset(Some(0), Some(opt)).err().unwrap());
    assert!(
        d.position().unwrap().ends_with("maps/umaze.toml:4:8"),
        "{d}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
