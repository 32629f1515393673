//! `envc render`: videos that play back with the frames asked for (ffprobe), replayed actions,
//! GIF, PNG frames (the png crate, no ffmpeg) with the pixels `Env::render` returns, and the failures: no EGL (E1501, naming the packages), an unknown output
//! kind or no ffmpeg for a video (E1506), none leaving a file behind.

use std::path::Path;
use std::process::{Command, Output};

fn envc(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_envc"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run envc")
}

/// (frames, width, height) as ffprobe decodes them.
fn probe(path: &Path) -> String {
    let o = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,width,height",
            "-of",
            "csv=p=0",
        ])
        .arg(path)
        .output()
        .expect("ffprobe (apt-get install ffmpeg)");
    String::from_utf8_lossy(&o.stdout).trim().to_string()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("envc-render-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn videos_decode_back_to_the_frames_rendered() {
    let d = tmp("video");
    // Replay: 7 rows, 2 episodes of InvertedPendulum (never ends within 7 zero-ish steps):
    // episode 1 takes rows 0..4 (--max-steps 4), episode 2 rows 4..7: 5 + 4 frames.
    let a = d.join("a.npy");
    ndarray_npy::write_npy(&a, &ndarray::Array2::<f64>::zeros((7, 1))).unwrap();
    let mp4 = d.join("ip.mp4");
    let o = envc(
        &[
            "render",
            "InvertedPendulum-v5",
            "--policy",
            "replay",
            "--actions",
            a.to_str().unwrap(),
            "--episodes",
            "2",
            "--max-steps",
            "4",
            "--size",
            "96x64",
            "--out",
            mp4.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(probe(&mp4), "96,64,9");
    // An odd size is padded by one pixel for H.264; a GIF keeps it.
    let gif = d.join("h.gif");
    let o = envc(
        &[
            "render",
            "Hopper-v5",
            "--max-steps",
            "2",
            "--size",
            "33x21",
            "--out",
            gif.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(probe(&gif), "33,21,3");
    std::fs::remove_dir_all(&d).unwrap();
}

/// (width, height, rgb bytes) of an 8-bit RGB PNG, decoded by the `png` crate.
fn decode_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn png_frames_need_no_ffmpeg_and_hold_the_rendered_pixels() {
    let d = tmp("png");
    let frames = d.join("frames/");
    // No ffmpeg on PATH: PNG frames are written by the png crate.
    let o = envc(
        &[
            "render",
            "Ant-v5",
            "--camera",
            "track",
            "--seed",
            "7",
            "--max-steps",
            "3",
            "--size",
            "40x30",
            "--out",
            frames.to_str().unwrap(),
        ],
        &[("PATH", "/nonexistent")],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut pngs: Vec<_> = std::fs::read_dir(&frames)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    pngs.sort();
    let names: Vec<_> = pngs
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    // A frame after the reset and after each of the 3 steps, numbered from 1.
    assert_eq!(
        names,
        [
            "frame_000001.png",
            "frame_000002.png",
            "frame_000003.png",
            "frame_000004.png"
        ]
    );
    let decoded: Vec<_> = pngs.iter().map(|p| decode_png(p)).collect();
    assert!(decoded.iter().all(|(w, h, _)| (*w, *h) == (40, 30)));
    // Frame 0 is what `Env::render` draws after the same seed's reset.
    let o: Vec<envc::Override> = [
        ("camera_name", "\"track\""),
        ("width", "40"),
        ("height", "30"),
    ]
    .iter()
    .map(|(k, v)| envc::Override::text(k, v))
    .collect();
    let mut env = envc::Env::make("Ant-v5", &o).unwrap();
    env.reset(Some(7));
    let f = env.render(envc::render::RenderMode::RgbArray).unwrap();
    let want = f.rgb.unwrap();
    assert_eq!(want.len(), 40 * 30 * 3);
    assert!(decoded[0].2 == want, "frame 0 differs from Env::render");
    // The steps moved the robot: a later frame differs (the PNGs are not all one image).
    assert!(decoded[3].2 != want);
    std::fs::remove_dir_all(&d).unwrap();
}

/// The Go1 joystick spec with its commands, observation noise and events (randomized masses and
/// friction at startup, trunk pushes) on, their intervals shortened so a few steps see several
/// command draws and pushes: `envc render` runs it, and every frame is what an `Env` of the same
/// spec draws after the same seed and steps (so commands, noise and events ran the same way).
#[test]
fn go1_joystick_with_commands_noise_and_events_renders() {
    let go1 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/models/unitree_go1/scene.xml"
    );
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../specs/examples/go1_joystick.toml"
    ))
    .unwrap();
    let push = "interval_seconds = [5.0, 10.0]";
    assert!(text.contains(push));
    let d = tmp("go1");
    let spec = d.join("go1_joystick.toml");
    std::fs::write(&spec, text.replace(push, "interval_seconds = [0.04, 0.1]")).unwrap();
    let sets = [
        ("xml_file", format!("{go1:?}")),
        ("observation_noise", "true".to_string()),
        ("domain_randomization", "true".to_string()),
        ("command_resample_seconds", "0.1".to_string()),
    ];
    let frames = d.join("frames/");
    const STEPS: usize = 12;
    let mut args: Vec<String> = [
        "render",
        spec.to_str().unwrap(),
        "--policy",
        "zero",
        "--seed",
        "2",
        "--max-steps",
        &STEPS.to_string(),
        "--size",
        "32x24",
        "--out",
        frames.to_str().unwrap(),
    ]
    .map(String::from)
    .into();
    for (k, v) in &sets {
        args.push("--set".into());
        args.push(format!("{k}={v}"));
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = envc(&args, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut pngs: Vec<_> = std::fs::read_dir(&frames)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    pngs.sort();
    assert_eq!(pngs.len(), 1 + STEPS);

    let mut ov: Vec<envc::Override> = sets
        .iter()
        .map(|(k, v)| envc::Override::text(k, v))
        .collect();
    ov.push(envc::Override::text("width", "32"));
    ov.push(envc::Override::text("height", "24"));
    let mut env = envc::Env::from_spec_file(&spec, &ov).unwrap();
    env.reset(Some(2));
    let zeros = vec![0.0; env.act_dim()];
    let mut commands = std::collections::BTreeSet::new();
    for (t, png) in pngs.iter().enumerate() {
        if t > 0 {
            let s = env.step(&zeros).unwrap();
            assert!(!s.terminated && !s.truncated);
        }
        let o = env.obs();
        commands.insert(format!("{:?}", &o[o.len() - 3..]));
        let (w, h, got) = decode_png(png);
        assert_eq!((w, h), (32, 24));
        let f = env.render(envc::render::RenderMode::RgbArray).unwrap();
        assert!(got == f.rgb.unwrap(), "frame {t} differs from Env::render");
    }
    assert!(commands.len() >= 3, "the command was redrawn: {commands:?}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn failures_are_coded_and_leave_nothing_behind() {
    let d = tmp("fail");
    let out = d.join("x.mp4");
    // A machine without libEGL (simulated: the library it loads does not exist).
    let o = envc(
        &[
            "render",
            "Hopper-v5",
            "--max-steps",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("ENVC_EGL_LIBRARY", "/nonexistent/libEGL.so.1")],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("E1501") && err.contains("libegl1"), "{err}");
    let o = envc(
        &[
            "render",
            "Hopper-v5",
            "--out",
            d.join("x.avi").to_str().unwrap(),
        ],
        &[],
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("E1506"));
    // A video without ffmpeg names the Debian package.
    let o = envc(
        &[
            "render",
            "Hopper-v5",
            "--max-steps",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PATH", "/nonexistent")],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("E1506") && err.contains("apt-get install ffmpeg"),
        "{err}"
    );
    let o = envc(
        &[
            "render",
            "Hopper-v5",
            "--camera",
            "nope",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("E1503"));
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        0,
        "no output, no partial file"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn max_steps_zero_is_an_argument_error_and_renders_nothing() {
    let d = tmp("zero");
    let out = d.join("frames");
    let o = envc(
        &[
            "render",
            "InvertedPendulum-v5",
            "--max-steps",
            "0",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("--max-steps"));
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
