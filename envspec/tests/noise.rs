//! Observation noise, delay and action latency in the spec language: what they resolve to, their
//! located errors, and how `diff` reports them (the randomization category, `noise-*` and
//! `latency-*` rules; never `observation-segment-key-changed`).

use std::path::Path;

use envspec::diff::{Category, RuleId, diff};
use envspec::noise::NoiseKind;
use envspec::{Code, Override, ResolvedSpec, Spec, resolve};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// Hopper-v5 with `edit` applied to its text (`[old, new]` pairs, each occurring).
fn hopper(edits: &[(&str, &str)]) -> Spec {
    let mut text = std::fs::read_to_string(format!("{ROOT}/specs/gymnasium/hopper.toml"))
        .unwrap()
        .replace("\"../../assets/", &format!("\"{ROOT}/assets/"));
    for (old, new) in edits {
        assert!(text.contains(old), "{old}");
        text = text.replacen(old, new, 1);
    }
    Spec::parse(Path::new("hopper.toml"), text).unwrap()
}

fn resolved(s: &Spec) -> ResolvedSpec {
    resolve(s, &[]).unwrap()
}

const QVEL: &str = "clip = [-10.0, 10.0]";
const PARAMS: &str = "[params]\n";

#[test]
fn noise_delay_and_latency_resolve_with_parameters() {
    let s = hopper(&[
        (PARAMS, "[params]\nlevel = 0.5\nlag = 2\n"),
        (
            QVEL,
            "clip = [-10.0, 10.0]\nnoise = { kind = \"gaussian\", scale = 0.2, level = \"level\" }\ndelay = \"lag\"",
        ),
        (
            "[observation.qpos]",
            "[latency]\naction = \"lag\"\n\n[observation.qpos]",
        ),
    ]);
    let r = resolved(&s);
    let c = &r.corruption;
    assert_eq!(c.action_latency, 2);
    assert_eq!(c.segments.len(), 1);
    let q = &c.segments[0];
    assert_eq!((q.name.as_str(), q.segment, q.delay), ("qvel", 1, 2));
    let n = q.noise.unwrap();
    assert_eq!((n.kind, n.scale, n.level), (NoiseKind::Gaussian, 0.2, 0.5));
    // Overrides reach them; `delay = 0` and no noise leave nothing.
    let r = resolve(&s, &[Override::text("lag", "0")]).unwrap();
    assert_eq!(r.corruption.action_latency, 0);
    assert_eq!(r.corruption.segments[0].delay, 0);
    // Bundled specs declare none of them.
    assert!(resolved(&hopper(&[])).corruption.is_empty());
}

fn errors(edits: &[(&str, &str)]) -> Vec<(Code, String, String)> {
    let s = hopper(edits);
    let d = resolve(&s, &[]).unwrap_err();
    d.iter()
        .map(|e| {
            let at = e
                .location
                .as_ref()
                .map(|l| l.position())
                .unwrap_or_default();
            (e.code, at, e.message.clone())
        })
        .collect()
}

#[test]
fn errors_are_coded_and_located() {
    let bad = |noise: &str| errors(&[(QVEL, &format!("clip = [-10.0, 10.0]\nnoise = {noise}"))]);
    // Line 30 is the `noise` line (hopper.toml's qvel clip is on line 29).
    let e = bad("{ kind = \"gausian\", scale = 0.1 }");
    assert_eq!(
        (e[0].0, e[0].1.as_str()),
        (Code::E0104, "hopper.toml:30:18")
    );
    assert!(e[0].2.contains("unknown noise kind `gausian`"), "{e:?}");
    let e = bad("{ kind = \"uniform\", scael = 0.1 }");
    assert_eq!(
        e.iter().map(|x| x.0).collect::<Vec<_>>(),
        [Code::E0101, Code::E0103]
    );
    assert_eq!(e[0].1, "hopper.toml:30:29");
    let e = bad("{ kind = \"uniform\", scale = 0.1, level = -1.0 }");
    assert_eq!(
        (e[0].0, e[0].1.as_str()),
        (Code::E0140, "hopper.toml:30:50")
    );
    let e = bad("{ kind = \"uniform\", scale = 1e4, level = 1e3 }");
    assert_eq!((e[0].0, e[0].1.as_str()), (Code::E0140, "hopper.toml:30:9"));
    let e = bad("0.1");
    assert_eq!((e[0].0, e[0].1.as_str()), (Code::E0102, "hopper.toml:30:9"));
    let e = errors(&[(QVEL, "clip = [-10.0, 10.0]\ndelay = 1.5")]);
    assert_eq!((e[0].0, e[0].1.as_str()), (Code::E0102, "hopper.toml:30:9"));
    let e = errors(&[(QVEL, "clip = [-10.0, 10.0]\ndelay = 10001")]);
    assert_eq!((e[0].0, e[0].1.as_str()), (Code::E0141, "hopper.toml:30:9"));
    let e = errors(&[(
        "[observation.qpos]",
        "[latency]\naction = \"nope\"\n\n[observation.qpos]",
    )]);
    assert_eq!(e[0].0, Code::E0201, "{e:?}");
    // A switched-off segment is still checked.
    let e = errors(&[(
        "drop_first = { count = 1,",
        "when = false\ndelay = -2\ndrop_first = { count = 1,",
    )]);
    assert_eq!(e[0].0, Code::E0141, "{e:?}");
    // Unknown keys of [latency] are syntax errors (E0101).
    let text = std::fs::read_to_string(format!("{ROOT}/specs/gymnasium/hopper.toml"))
        .unwrap()
        .replacen(
            "[observation.qpos]",
            "[latency]\nactoin = 1\n\n[observation.qpos]",
            1,
        );
    let d = Spec::parse(Path::new("hopper.toml"), text).unwrap_err();
    assert_eq!(d.iter().next().unwrap().code, Code::E0101);
}

#[test]
fn diff_reports_the_training_distribution() {
    let with = |scale: &str, delay: &str, latency: &str| {
        hopper(&[
            (
                QVEL,
                &format!(
                    "clip = [-10.0, 10.0]\nnoise = {{ kind = \"uniform\", scale = {scale} }}\ndelay = {delay}"
                ),
            ),
            (
                "[observation.qpos]",
                &format!("[latency]\naction = {latency}\n\n[observation.qpos]"),
            ),
        ])
    };
    let (a, b) = (with("0.1", "1", "1"), with("0.3", "2", "3"));
    let report = diff(&a, &resolved(&a), &b, &resolved(&b));
    let rules: Vec<RuleId> = report.changes.iter().map(|c| c.rule).collect();
    assert_eq!(
        rules,
        [
            RuleId::NoiseChanged,
            RuleId::LatencyObservationChanged,
            RuleId::LatencyActionChanged
        ]
    );
    assert!(
        report
            .changes
            .iter()
            .all(|c| c.category() == Category::Randomization && c.breaking)
    );
    let noise = &report.changes[0];
    // uniform ±0.1 has std 0.1/√3.
    assert_eq!(
        noise.witness.as_deref(),
        Some("noise std 0.057735 → 0.173205 on 6 elements (× 3.0)")
    );
    assert_eq!(noise.was.as_deref(), Some("uniform ±0.1"));
    assert_eq!(report.changes[2].now.as_deref(), Some("3 steps (0.024 s)"));
    // Spelling the same scale as a parameter changes nothing.
    let c = hopper(&[
        (PARAMS, "[params]\ns = 0.1\n"),
        (
            QVEL,
            "clip = [-10.0, 10.0]\nnoise = { kind = \"uniform\", scale = \"s\" }\ndelay = 1",
        ),
        (
            "[observation.qpos]",
            "[latency]\naction = 1\n\n[observation.qpos]",
        ),
    ]);
    let report = diff(&a, &resolved(&a), &c, &resolved(&c));
    assert!(
        report.changes.iter().all(|c| !c.breaking),
        "{}",
        report.to_text()
    );
    // Added to a plain spec: noise-added, and the segment's layout rules stay silent.
    let plain = hopper(&[]);
    let report = diff(&plain, &resolved(&plain), &a, &resolved(&a));
    let ids: Vec<&str> = report.changes.iter().map(|c| c.rule.id()).collect();
    assert_eq!(
        ids,
        [
            "noise-added",
            "latency-observation-changed",
            "latency-action-changed"
        ]
    );
}
