//! `envc show` lists observation noise, delay and action latency (docs/spec-reference.md §19) with their
//! amplitudes, clip order and durations; a spec without them prints no such block.

use std::process::Command;

fn show(spec: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["show", spec])
        .output()
        .expect("run envc");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn show_lists_noise_delay_and_latency() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let out = show(&format!("{root}/tests/noise/hopper_noisy.toml"));
    for line in [
        "  qpos           [0:5]  noise uniform ±0.01",
        "  qvel           [5:11]  noise gaussian std 0.1, then clipped to [-10, 10]; delayed 1 step (0.008 s)",
        "  action latency 1 step (0.008 s) (zeros after a reset)",
    ] {
        assert!(out.contains(line), "missing {line:?} in:\n{out}");
    }
    assert!(!show("Hopper-v5").contains("action latency"));
}
