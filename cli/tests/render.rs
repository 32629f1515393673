//! `envc render`: videos that play back with the frames asked for (ffprobe), replayed actions,
//! GIF and PNG frames, and the failures: no EGL (E1501, naming the packages), an unknown output
//! kind (E1506), neither leaving a file behind.

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
    let frames = d.join("frames/");
    let o = envc(
        &[
            "render",
            "Ant-v5",
            "--camera",
            "track",
            "--max-steps",
            "1",
            "--size",
            "40x30",
            "--out",
            frames.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let pngs: Vec<_> = std::fs::read_dir(&frames).unwrap().flatten().collect();
    assert_eq!(pngs.len(), 2);
    assert_eq!(probe(&pngs[0].path()), "40,30,1");
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
