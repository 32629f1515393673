//! `[events]` resolution: the IR of good events (elements in model order, dofs of joints, the
//! compiled timestep) and a located, coded error for each kind of mistake (docs/errors.md).

use std::path::{Path, PathBuf};

use envspec::events::{EventDist, EventField, EventKind, EventMode, Operation};
use envspec::{Code, Diagnostics, ResolvedSpec, load};

fn hopper() -> String {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium/hopper.xml");
    format!(
        "[env]\nid = \"Mini-v0\"\n\n[params]\nxml_file = {:?}\nframe_skip = 4\nmax_episode_steps = 1000\n\n[observation.qpos]\nsource = \"qpos\"\n",
        assets.display().to_string()
    )
}

/// Hopper with `events` appended (they start on line 12).
fn resolve(events: &str) -> Result<ResolvedSpec, Diagnostics> {
    // One directory per call, removed whole (tests run in parallel threads).
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let dir = crate::scratch::ScratchDir::new(&format!("events-{n}"));
    let path: PathBuf = dir.join("spec.toml");
    std::fs::write(&path, format!("{}\n{events}", hopper())).unwrap();
    load(&path, &[])
}

/// The one error's code and line:col.
fn error(events: &str) -> (Code, usize, usize, String) {
    let d = resolve(events).expect_err("an error");
    assert_eq!(d.0.len(), 1, "{d}");
    let e = &d.0[0];
    let loc = e.location.as_ref().expect("located");
    let (line, col) = loc.file.line_col(loc.span.start);
    (e.code, line, col, e.to_string())
}

#[test]
fn events_resolve_in_model_order() {
    let r = resolve(
        r#"[events.damping]
mode = "reset"
field = "joint_damping"
elements = ["foot_joint", "thigh*"]
distribution = "gaussian"
mean = 1.0
std = 0.1
operation = "scale"

[events.g]
mode = "interval"
interval_seconds = [1.0, 2.0]
field = "gravity"
distribution = "log_uniform"
range = [0.5, 2.0]
operation = "scale"
shared = true
"#,
    )
    .unwrap();
    assert_eq!(r.events.len(), 2);
    let e = &r.events[0];
    assert_eq!(e.mode, EventMode::Reset);
    let EventKind::Model {
        field,
        elements,
        dist,
        operation,
        shared,
    } = &e.kind
    else {
        panic!("a model event")
    };
    assert_eq!(*field, EventField::JointDamping);
    // hopper.xml: rootx, rootz, rooty, thigh_joint, leg_joint, foot_joint (dofs 3, 4, 5).
    let got: Vec<(&str, (usize, usize))> =
        elements.iter().map(|x| (x.name.as_str(), x.dofs)).collect();
    assert_eq!(got, [("thigh_joint", (3, 1)), ("foot_joint", (5, 1))]);
    assert_eq!(
        *dist,
        EventDist::Gaussian {
            mean: 1.0,
            std: 0.1
        }
    );
    assert_eq!(*operation, Operation::Scale);
    assert!(!shared);
    assert_eq!(
        r.events[1].mode,
        EventMode::Interval {
            low: 1.0,
            high: 2.0
        }
    );
    // A spec without events has none (and draws nothing for them).
    assert!(resolve("").unwrap().events.is_empty());
}

#[test]
fn each_mistake_is_located_and_coded() {
    let base = |field: &str, extra: &str| {
        format!(
            "[events.e]\nmode = \"startup\"\nfield = \"{field}\"\n{extra}distribution = \"uniform\"\nrange = [0.9, 1.1]\noperation = \"scale\"\n"
        )
    };
    // Line 12: `[events.e]`; 13 mode; 14 field; 15 the extra line.
    let (code, line, col, msg) = error(&base("body_mass", "elements = \"torsoo\"\n"));
    assert_eq!((code, line, col), (Code::E0150, 15, 12), "{msg}");
    assert!(msg.contains("did you mean `torso`?"), "{msg}");
    let (code, line, _, _) = error(&base("body_mass", ""));
    assert_eq!((code, line), (Code::E0152, 12));
    let (code, line, _, _) = error(&base("gravity", "elements = \"torso\"\n"));
    assert_eq!((code, line), (Code::E0152, 15));
    let (code, line, col, msg) = error(&base("body_mas", "elements = \"torso\"\n"));
    assert_eq!((code, line, col), (Code::E0104, 14, 9), "{msg}");
    assert!(msg.contains("did you mean `body_mass`?"), "{msg}");
    // An interval change of mass would need mj_setConst mid-episode.
    let (code, line, _, _) = error(&base("body_mass", "elements = \"torso\"\n").replace(
        "mode = \"startup\"",
        "mode = \"interval\"\ninterval_seconds = 2.0",
    ));
    assert_eq!((code, line), (Code::E0152, 13));
    let (code, line, _, _) = error(
        &base("body_mass", "elements = \"torso\"\n")
            .replace("range = [0.9, 1.1]", "range = [-0.1, 1.1]"),
    );
    assert_eq!((code, line), (Code::E0153, 17));
    let (code, _, _, _) = error(
        &base("geom_friction.sliding", "elements = \"*\"\n").replace(
            "\"uniform\"\nrange = [0.9, 1.1]",
            "\"gaussian\"\nmean = 1.0\nstd = -1.0",
        ),
    );
    assert_eq!(code, Code::E0151);
    // hopper.xml's timestep is 0.002: × 600 leaves (0, 1] s.
    let (code, _, _, msg) = error(
        "[events.t]\nmode = \"reset\"\nfield = \"timestep\"\ndistribution = \"uniform\"\nrange = [1.0, 600.0]\noperation = \"scale\"\n",
    );
    assert_eq!(code, Code::E0153, "{msg}");
    // A push on a body without a free joint.
    let (code, _, _, msg) = error(
        "[events.p]\nkind = \"push\"\nmode = \"interval\"\ninterval_seconds = 1.0\nelements = \"torso\"\nx = [-1.0, 1.0]\n",
    );
    assert_eq!(code, Code::E0152, "{msg}");
    assert!(msg.contains("has none"), "{msg}");
}
