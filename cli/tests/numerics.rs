//! `--numerics`, `ENVC_NUMERICS` and `envc info`: profile choices at the CLI's edges.

use std::process::{Command, Output};

fn envc(args: &[&str], vars: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_envc"));
    c.args(args);
    for k in [
        "OPENBLAS_CORETYPE",
        "NPY_ENABLE_CPU_FEATURES",
        "NPY_DISABLE_CPU_FEATURES",
        "ENVC_NUMERICS",
    ] {
        c.env_remove(k);
    }
    c.envs(vars.iter().copied());
    c.output().expect("run envc")
}

fn info(vars: &[(&str, &str)]) -> serde_json::Value {
    let o = envc(&["info", "--format", "json"], vars);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn auto_follows_the_reference_overrides() {
    let v = info(&[
        ("OPENBLAS_CORETYPE", "prescott"),
        ("NPY_DISABLE_CPU_FEATURES", "X86_V4"),
    ]);
    assert_eq!(v["auto"]["profile"], "openblas-prescott");
    // OpenBLAS's Zen core is its Haswell kernel; SVML only where the CPU has X86_V4.
    let v = info(&[("OPENBLAS_CORETYPE", "Zen")]);
    let svml = v["cpu"]["features"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f == "numpy X86_V4");
    let want = if svml {
        "openblas-haswell+svml"
    } else {
        "openblas-haswell"
    };
    assert_eq!(v["auto"]["profile"], want);
    assert_eq!(v["default"], want);
    assert_eq!(v["profiles"].as_array().unwrap().len(), 10);
}

#[test]
fn a_named_profile_wins_over_auto() {
    let v = info(&[("ENVC_NUMERICS", "openblas-nehalem+svml")]);
    assert_eq!(v["default"], "openblas-nehalem+svml");
    let o = envc(
        &[
            "--numerics",
            "openblas-skylakex",
            "info",
            "--format",
            "json",
        ],
        &[("ENVC_NUMERICS", "openblas-nehalem")],
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["default"], "openblas-skylakex");
}

#[test]
fn bad_profiles_are_coded_errors() {
    let o = envc(&["--numerics", "openblas-zen", "info"], &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("E1301") && err.contains("openblas-zen"),
        "{err}"
    );
    let o = envc(
        &["run", "Reacher-v5", "--episodes", "1"],
        &[("ENVC_NUMERICS", "fast")],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("E1301"));
    // Settings numpy refuses to import with leave `auto` nothing to follow.
    let o = envc(
        &["run", "Reacher-v5", "--episodes", "1"],
        &[
            ("NPY_ENABLE_CPU_FEATURES", "X86_V3"),
            ("NPY_DISABLE_CPU_FEATURES", "X86_V4"),
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("E1302"));
    // A named profile needs no numpy settings at all.
    let o = envc(
        &[
            "--numerics",
            "openblas-haswell",
            "run",
            "Reacher-v5",
            "--episodes",
            "1",
        ],
        &[
            ("NPY_ENABLE_CPU_FEATURES", "X86_V3"),
            ("NPY_DISABLE_CPU_FEATURES", "X86_V4"),
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
