//! `envc diff` misses no dynamics change: actuator gains and force ranges, joint armature and
//! damping, geom contact properties, keyframes, pushes, solver options, per-joint action scales, posture widths, a weld's
//! partner, a model
//! change only the binary comparison sees, and a multi-agent default factorization. Each case is one file of `cli/tests/diff_golden/dynamics/` against
//! `base.toml`; the reports are pinned in `cli/tests/diff_golden/dynamics.txt` (ENVC_BLESS=1
//! regenerates it; review the change).

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

const DIR: &str = "cli/tests/diff_golden/dynamics";

fn diff(old: &str, new: &str) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .current_dir(root())
        .args(["diff", &format!("{DIR}/{old}"), &format!("{DIR}/{new}")])
        .output()
        .expect("run envc");
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.stderr.is_empty(),
        "{old} → {new}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    (o.status.code().unwrap_or(-1), text)
}

/// (file, expected exit status, lines the report must have)
const CASES: &[(&str, &str, i32, &[&str])] = &[
    (
        "base.toml",
        "kp.toml",
        3,
        &[
            "  ! [actuators-key-changed] actuators.legs: kp: was 20.0 (cli/tests/diff_golden/dynamics/base.toml:18), now 30.0 (cli/tests/diff_golden/dynamics/kp.toml:18)",
            "  ! [model-array-changed] model: actuator_gainprm[hip]: was [20.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], now [30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
        ],
    ),
    (
        "base.toml",
        "forcerange.toml",
        3,
        &[
            "  ! [joint-properties-key-changed] joint_properties.knee: forcerange: was [-15.0, 15.0] (cli/tests/diff_golden/dynamics/base.toml:24), now [-10.0, 10.0] (cli/tests/diff_golden/dynamics/forcerange.toml:24)",
            "  ! [model-array-changed] model: actuator_forcerange[knee]: was [1.0, -15.0, 15.0], now [1.0, -10.0, 10.0]",
        ],
    ),
    (
        "base.toml",
        "armature.toml",
        3,
        &[
            "  ! [joint-properties-key-changed] joint_properties.*: armature: was 0.01 (cli/tests/diff_golden/dynamics/base.toml:23), now 0.02 (cli/tests/diff_golden/dynamics/armature.toml:23)",
        ],
    ),
    (
        "base.toml",
        "damping.toml",
        3,
        &[
            "  ! [joint-properties-key-changed] joint_properties.*: damping: was 0.1 (cli/tests/diff_golden/dynamics/base.toml:23), now 0.3 (cli/tests/diff_golden/dynamics/damping.toml:23)",
        ],
    ),
    (
        "base.toml",
        "keyframe.toml",
        3,
        &[
            "  ! [keyframes-key-changed] keyframes.stand: joints: was { hip = 0.2, knee = -0.4 } (cli/tests/diff_golden/dynamics/base.toml:28), now { hip = 0.3, knee = -0.4 } (cli/tests/diff_golden/dynamics/keyframe.toml:28)",
        ],
    ),
    (
        "base.toml",
        "push.toml",
        3,
        &[
            "      drawn every 3–6 s during episodes instead of drawn every 1–2 s during episodes: the policy sees the randomization at another rate; returns are not comparable",
        ],
    ),
    // The same gain written as a parameter with the same default: no behaviour change.
    ("base.toml", "gain_param.toml", 1, &[]),
    // A contact softness (geom solimp) is outside the arrays compared by name: the rollout decides.
    (
        "base.toml",
        "residual.toml",
        3,
        &[
            "  ! [model-binary-changed] model: compiled model: was one binary model, now another (outside the compared arrays)",
        ],
    ),
    (
        "base.toml",
        "solver.toml",
        3,
        &[
            "  ! [physics-option-changed] physics: iterations: was the model's, now 20 (cli/tests/diff_golden/dynamics/solver.toml:11)",
            "  ! [model-option-changed] model: opt.iterations: was 100, now 20",
        ],
    ),
    (
        "geoms_old.toml",
        "geoms_new.toml",
        3,
        &[
            "  ! [geom-properties-key-changed] geom_properties.foot: friction: was [0.8] (cli/tests/diff_golden/dynamics/geoms_old.toml:25), now [0.5] (cli/tests/diff_golden/dynamics/geoms_new.toml:25)",
            "  ! [model-array-changed] model: geom_friction[foot]: was [0.8, 0.005, 0.0001], now [0.5, 0.005, 0.0001]",
        ],
    ),
    (
        "scale_old.toml",
        "scale_new.toml",
        3,
        &[
            "  ! [actions-mapping-changed] actions: scale: was knee 0.25 (cli/tests/diff_golden/dynamics/scale_old.toml:29), now knee 0.4 (cli/tests/diff_golden/dynamics/scale_new.toml:29)",
        ],
    ),
    (
        "scale_old.toml",
        "posture_new.toml",
        3,
        &[
            "  ! [reward-term-key-changed] reward.pose: std: was [{ * = 0.1 }, { hip = 0.3, knee = 0.5 }] (cli/tests/diff_golden/dynamics/scale_old.toml:53), now [{ * = 0.1 }, { hip = 0.3, knee = 0.6 }] (cli/tests/diff_golden/dynamics/posture_new.toml:53)",
        ],
    ),
    (
        "weld_old.toml",
        "weld_new.toml",
        3,
        &["  ! [model-array-changed] model: eq_obj2id[#0]: was 7, now 6"],
    ),
    (
        "agents_old.toml",
        "agents_new.toml",
        3,
        &[
            "  ! [agents-default-conf-changed] agents: default agent_conf: was 2x1 (cli/tests/diff_golden/dynamics/agents_old.toml:6), now 1x2 (cli/tests/diff_golden/dynamics/agents_new.toml:6)",
            "  ! [agents-default-obsk-changed] agents: default agent_obsk: was 0 (cli/tests/diff_golden/dynamics/agents_old.toml:7), now 1 (cli/tests/diff_golden/dynamics/agents_new.toml:7)",
        ],
    ),
];

#[test]
fn every_dynamics_change_is_reported_with_its_line_and_judged_by_effect() {
    let mut all = String::new();
    let mut failures = vec![];
    for (old, new, status, lines) in CASES {
        let (code, text) = diff(old, new);
        if code != *status {
            failures.push(format!(
                "{old} → {new}: exit {code}, expected {status}\n{text}"
            ));
        }
        for l in *lines {
            if !text.lines().any(|x| x == *l) {
                failures.push(format!("{old} → {new}: missing `{l}` in\n{text}"));
            }
        }
        assert!(
            !text.contains("drawn during episodes instead of drawn during episodes"),
            "{text}"
        );
        all.push_str(&format!("## {old} → {new} (exit {code})\n{text}\n"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    let golden = root().join("cli/tests/diff_golden/dynamics.txt");
    if std::env::var_os("ENVC_BLESS").is_some() {
        std::fs::write(&golden, &all).unwrap();
    } else {
        let want = std::fs::read_to_string(&golden).unwrap_or_default();
        assert_eq!(
            all,
            want,
            "differs from {} (ENVC_BLESS=1 to update)",
            golden.display()
        );
    }
}
