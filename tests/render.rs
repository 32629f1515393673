//! Rendering from Rust (docs/rendering.md): frames of the spec's size, settings as parameters,
//! camera and body names checked when the env is built (E1503 at the value's location), bad
//! settings (E1505), envs rendering from several threads. Frame-for-frame equality with
//! Gymnasium is tests/python/test_render.py.

use envc::render::RenderMode;
use envc::{Env, EnvError, Environment, JointEnv, Override};
use envspec::Code;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

fn hopper(o: &[(&str, &str)]) -> Result<Env, EnvError> {
    let o: Vec<Override> = o.iter().map(|(k, v)| Override::text(k, v)).collect();
    Env::make("Hopper-v5", &o)
}

/// The rgb bytes of the current state.
fn rgb(env: &mut Env) -> Vec<u8> {
    let f = env.render(RenderMode::RgbArray).unwrap();
    assert!(f.depth.is_none());
    f.rgb.unwrap().to_vec()
}

#[test]
fn frames_have_the_spec_size_and_follow_the_state() {
    let mut env = hopper(&[("width", "160"), ("height", "96")]).unwrap();
    env.reset(Some(0));
    let a = rgb(&mut env);
    assert_eq!(a.len(), 96 * 160 * 3);
    // Not blank: the sky (top row) and the floor (bottom row) differ.
    assert_ne!(a[..160 * 3], a[95 * 160 * 3..]);
    assert_eq!(rgb(&mut env), a, "same state, same frame");
    for _ in 0..10 {
        env.step(&[1.0, -1.0, 1.0]).unwrap();
    }
    assert_ne!(rgb(&mut env), a, "the hopper moved");
    let f = env.render(RenderMode::RgbdTuple).unwrap();
    let depth = f.depth.unwrap();
    assert_eq!(
        (f.rgb.unwrap().len(), depth.len()),
        (96 * 160 * 3, 96 * 160)
    );
    assert!(depth.iter().all(|d| (0.0..=1.0).contains(d)));
    assert!(
        depth.iter().any(|&d| d < 0.99),
        "something is nearer than the far plane"
    );
    // The default is Gymnasium's 480 × 480.
    let mut env = hopper(&[]).unwrap();
    env.reset(Some(0));
    let f = env.render(RenderMode::DepthArray).unwrap();
    assert_eq!(
        (f.width, f.height, f.depth.unwrap().len()),
        (480, 480, 480 * 480)
    );
}

#[test]
fn typed_envs_render_through_environment() {
    let mut env = hopper(&[("width", "32"), ("height", "32")]).unwrap();
    Environment::reset(&mut env, Some(1));
    let f = JointEnv::render(&mut env, RenderMode::RgbArray).unwrap();
    assert_eq!(f.rgb.unwrap().len(), 32 * 32 * 3);
}

#[test]
fn unknown_camera_and_body_names_are_spec_errors_with_locations() {
    let e = hopper(&[("camera_name", "trak")])
        .err()
        .expect("unknown camera");
    assert_eq!(e.code(), Code::E1503);
    assert!(e.to_string().contains("no camera `trak`"), "{e}");
    // In a spec file: the error points at the value.
    let dir = std::env::temp_dir().join(format!("envc-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(format!("{ROOT}/specs/gymnasium/hopper.toml"))
        .unwrap()
        .replace(
            "\"../../assets/gymnasium/hopper.xml\"",
            &format!("{:?}", format!("{ROOT}/assets/gymnasium/hopper.xml")),
        )
        .replace("trackbodyid = 2,", "trackbodyid = \"torsoo\",");
    let spec = dir.join("hopper.toml");
    std::fs::write(&spec, &text).unwrap();
    let e = Env::from_spec_file(&spec, &[]).err().expect("unknown body");
    assert_eq!(e.code(), Code::E1503);
    let line = text.lines().position(|l| l.contains("\"torsoo\"")).unwrap() + 1;
    let msg = e.to_string();
    assert!(msg.contains(&format!("hopper.toml:{line}:")), "{msg}");
    assert!(msg.contains("did you mean `torso`?"), "{msg}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_settings_are_e1505() {
    for (k, v) in [
        ("width", "0"),
        ("max_geom", "0"),
        ("camera_id", "-2"),
        ("visual_options", "{ contactpont = true }"),
        ("default_camera_config", "{ distnce = 2.0 }"),
    ] {
        let e = hopper(&[(k, v)])
            .err()
            .unwrap_or_else(|| panic!("{k}={v} accepted"));
        assert_eq!(e.code(), Code::E1505, "{k}={v}: {e}");
    }
    let e = hopper(&[("camera_id", "0"), ("camera_name", "track")])
        .err()
        .unwrap();
    assert_eq!(e.code(), Code::E1505);
    assert!(e.to_string().contains("both `camera_id` and `camera_name`"));
    let e = envc::render::RenderMode::parse("human").unwrap_err();
    assert_eq!(e.code(), Code::E1504);
}

#[test]
fn envs_render_from_several_threads() {
    let run = |seed: u64| {
        let mut env = hopper(&[("width", "64"), ("height", "64")]).unwrap();
        env.reset(Some(seed));
        let mut frames = vec![];
        for _ in 0..3 {
            env.step(&[0.5, 0.5, -0.5]).unwrap();
            frames.push(rgb(&mut env));
        }
        frames
    };
    let alone: Vec<_> = (0..4).map(run).collect();
    let threaded: Vec<_> = std::thread::scope(|s| {
        let h: Vec<_> = (0..4).map(|seed| s.spawn(move || run(seed))).collect();
        h.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(alone, threaded);
    // An env made on one thread renders on another.
    let mut env = hopper(&[("width", "16"), ("height", "16")]).unwrap();
    env.reset(Some(0));
    let here = rgb(&mut env);
    let there = std::thread::spawn(move || rgb(&mut env)).join().unwrap();
    assert_eq!(here, there);
}

// A per-thread counting allocator: a frame after the first allocates nothing.

#[test]
fn a_frame_reuses_the_renderers_buffers() {
    let mut env = hopper(&[("width", "48"), ("height", "40")]).unwrap();
    env.reset(Some(0));
    env.render(RenderMode::RgbdTuple).unwrap();
    for _ in 0..5 {
        env.step(&[0.1, 0.2, 0.3]).unwrap();
        let frames = envc_tests::allocations(|| {
            for mode in [
                RenderMode::RgbArray,
                RenderMode::DepthArray,
                RenderMode::RgbdTuple,
            ] {
                let f = env.render(mode).unwrap();
                std::hint::black_box(f.width);
            }
        });
        assert_eq!(frames, 0, "rendering allocated");
    }
}

#[test]
fn vector_envs_render_each_env() {
    let o = [
        Override::text("width", "24"),
        Override::text("height", "24"),
    ];
    let mut v = envc::VecEnv::make("Hopper-v5", &o, 3, 2, envc::Autoreset::NextStep).unwrap();
    v.reset(Some(0));
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|i| {
            v.render(i, RenderMode::RgbArray)
                .unwrap()
                .rgb
                .unwrap()
                .to_vec()
        })
        .collect();
    // Different seeds, different starting poses, different frames; each as a single env's.
    assert_ne!(frames[0], frames[1]);
    let mut one = hopper(&[("width", "24"), ("height", "24")]).unwrap();
    one.reset(Some(1));
    assert_eq!(rgb(&mut one), frames[1]);
}

#[test]
fn color_agents_tints_each_agents_limbs_and_nothing_else() {
    use envc::multi_agent::MultiAgentEnv;
    let mut env = MultiAgentEnv::from_spec_file(
        format!(
            "{}/specs/mamujoco/ant.toml",
            env!("CARGO_MANIFEST_DIR").trim_end_matches("/tests")
        ),
        &[
            envc::Override::text("width", "160"),
            envc::Override::text("height", "120"),
        ],
    )
    .unwrap();
    env.reset(Some(0));
    let plain = env
        .render(RenderMode::RgbArray)
        .unwrap()
        .rgb
        .unwrap()
        .to_vec();
    env.color_agents(true);
    let tinted = env
        .render(RenderMode::RgbArray)
        .unwrap()
        .rgb
        .unwrap()
        .to_vec();
    env.color_agents(false);
    let again = env
        .render(RenderMode::RgbArray)
        .unwrap()
        .rgb
        .unwrap()
        .to_vec();
    assert_eq!(
        plain, again,
        "switching the colours off restores the model's"
    );
    // Pixels that are clearly blue (agent 0) and clearly orange (agent 1) appear only when tinted:
    // the Ant's own colours are beige limbs on a checkered floor.
    let count = |f: &[u8], pred: fn(i32, i32, i32) -> bool| {
        f.chunks_exact(3)
            .filter(|p| pred(p[0] as i32, p[1] as i32, p[2] as i32))
            .count()
    };
    let blue = |r: i32, g: i32, b: i32| b > r + 60 && b > g + 20;
    // Ratios, so that shading (which scales every channel) keeps the hue: the Ant's beige is
    // r/g 1.33, the palette's orange 2.
    let orange = |r: i32, g: i32, b: i32| r > 60 && 10 * r > 16 * g && g > 2 * b;
    assert_eq!((count(&plain, blue), count(&plain, orange)), (0, 0));
    assert!(count(&tinted, blue) > 20, "{}", count(&tinted, blue));
    assert!(count(&tinted, orange) > 20, "{}", count(&tinted, orange));
    // The torso keeps its colour: only the agents' limbs change.
    let changed = plain
        .chunks_exact(3)
        .zip(tinted.chunks_exact(3))
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed < plain.len() / 3 / 4, "{changed} pixels changed");
}
