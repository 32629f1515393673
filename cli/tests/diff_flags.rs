//! A change that alters results under the same env id is flagged for a version bump, whatever
//! it alters: a dynamics-only breaking change raises the flag too, as Gymnasium bumps ids for
//! physics, reward and termination fixes.

use std::process::Command;

#[test]
fn a_dynamics_only_change_under_the_same_id_is_flagged() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let dir = std::env::temp_dir().join(format!("envc-diff-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(format!("{root}/specs/gymnasium/hopper.toml"))
        .unwrap()
        .replace("\"../../assets/", &format!("\"{root}/assets/"));
    let old = dir.join("old.toml");
    let new = dir.join("new.toml");
    std::fs::write(&old, &text).unwrap();
    let changed = text.replace("frame_skip = { default = 4,", "frame_skip = { default = 5,");
    assert_ne!(changed, text);
    std::fs::write(&new, changed).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["diff", old.to_str().unwrap(), new.to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(3), "{out}");
    assert!(
        out.contains("flag: this change alters results (dynamics: returns are not comparable) but the env id stays `Hopper-v5`: bump its version"),
        "{out}"
    );
    // The same change with a bumped id is not flagged.
    std::fs::write(
        &new,
        std::fs::read_to_string(&new)
            .unwrap()
            .replace("\"Hopper-v5\"", "\"Hopper-v6\""),
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["diff", old.to_str().unwrap(), new.to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(!out.contains("flag:"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Ant-v5 with its floor's friction changed: MuJoCo takes the larger friction of two geoms in
/// contact, and the ant's geoms have 1.0, so a floor at 0.6 changes no contact (a rollout is
/// bit-identical: compatible, not breaking dynamics), while a floor at 1.5 does (breaking).
#[test]
fn a_model_change_that_reaches_no_rollout_is_compatible() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let dir = std::env::temp_dir().join(format!("envc-diff-friction-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let xml = std::fs::read_to_string(format!("{root}/assets/gymnasium/ant.xml")).unwrap();
    let spec = std::fs::read_to_string(format!("{root}/specs/gymnasium/ant.toml")).unwrap();
    let write = |name: &str, floor: Option<&str>| {
        let x = match floor {
            Some(f) => xml.replacen(
                "name=\"floor\"",
                &format!("name=\"floor\" friction=\"{f} 0.005 0.0001\""),
                1,
            ),
            None => xml.clone(),
        };
        let xp = dir.join(format!("{name}.xml"));
        std::fs::write(&xp, x).unwrap();
        let s = spec.replace(
            "\"../../assets/gymnasium/ant.xml\"",
            &format!("{:?}", xp.display().to_string()),
        );
        let sp = dir.join(format!("{name}.toml"));
        std::fs::write(&sp, s).unwrap();
        sp.display().to_string()
    };
    let base = write("base", None);
    let diff = |new: &str| {
        let o = Command::new(env!("CARGO_BIN_EXE_envc"))
            .args(["diff", &base, new])
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    let (code, out) = diff(&write("low", Some("0.6")));
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("no effect on a rollout"), "{out}");
    assert!(out.contains("geom_friction"), "{out}");
    let (code, out) = diff(&write("high", Some("1.5")));
    assert_eq!(code, Some(3), "{out}");
    assert!(!out.contains("no effect on a rollout"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A new default for a parameter whose every use is switched off by default (Ant-v4's
/// `contact_cost_weight`, read only with `use_contact_forces = false`) changes nothing a default
/// env computes: compatible, and said so; moving the term's lines is no change at all
/// (never "resolved value: was absent, now absent — same text, different value").
#[test]
fn a_default_read_only_by_switched_off_terms_is_compatible() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let dir = std::env::temp_dir().join(format!("envc-diff-dormant-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(format!("{root}/specs/gymnasium/ant_v4.toml"))
        .unwrap()
        .replace("\"../../assets/", &format!("\"{root}/assets/"));
    let old = dir.join("old.toml");
    std::fs::write(&old, &text).unwrap();
    let changed = text
        .replace(
            "contact_cost_weight = { default = 5e-4,",
            "contact_cost_weight = { default = 1e-3,",
        )
        .replace("[reward.contact]", "# moved\n# down\n[reward.contact]");
    let new = dir.join("new.toml");
    std::fs::write(&new, changed).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(["diff", old.to_str().unwrap(), new.to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(
        out.contains(
            "used by reward.contact, switched off under the default parameters before and after"
        ),
        "{out}"
    );
    assert!(!out.contains("now absent"), "{out}");
    assert!(!out.contains("flag:"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `git -C dir ARGS` (a scratch repository: its own identity, no hooks or signing).
fn git(dir: &std::path::Path, args: &[&str]) {
    let o = Command::new("git")
        .args(["-c", "user.name=envc", "-c", "user.email=envc@localhost"])
        .args(["-c", "commit.gpgsign=false", "-C"])
        .arg(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "git {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `envc diff` run in `dir`, within 60 s (a walk that never ends fails the test, not the machine).
fn diff_in(dir: &std::path::Path, old: &str, new: &str) -> (Option<i32>, String) {
    let o = Command::new("timeout")
        .args([
            "-s",
            "KILL",
            "60",
            env!("CARGO_BIN_EXE_envc"),
            "diff",
            old,
            new,
        ])
        .current_dir(dir)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    (o.status.code(), text)
}

/// A `REV:path` side is read through envspec's one reader at that revision, the model's
/// `<include>`s too: Hopper-v5 whose model includes the Hopper MJCF, the included file's gears
/// halved on disk after the commit, is a breaking actuator change against `HEAD`. A model that
/// includes itself at a revision is the same located E0302 as on disk, named `REV:file`.
#[test]
fn a_git_revision_side_is_read_through_the_one_reader() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let dir = std::env::temp_dir().join(format!("envc-diff-rev-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let spec = std::fs::read_to_string(format!("{root}/specs/gymnasium/hopper.toml"))
        .unwrap()
        .replace("\"../../assets/gymnasium/hopper.xml\"", "\"model.xml\"");
    let hopper = std::fs::read_to_string(format!("{root}/assets/gymnasium/hopper.xml")).unwrap();
    std::fs::write(dir.join("hopper.toml"), &spec).unwrap();
    std::fs::write(
        dir.join("model.xml"),
        "<mujoco>\n  <include file=\"parts/hopper.xml\"/>\n</mujoco>\n",
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(dir.join("parts/hopper.xml"), &hopper).unwrap();
    git(&dir, &["init", "-q"]);
    git(&dir, &["add", "."]);
    git(&dir, &["commit", "-q", "-m", "hopper"]);

    // Unchanged: the same spec and model at HEAD and on disk.
    let (status, out) = diff_in(&dir, "HEAD:hopper.toml", "hopper.toml");
    assert_eq!(status, Some(0), "{out}");
    // The included file changed on disk only.
    let halved = hopper.replace("gear=\"200\"", "gear=\"100\"");
    assert_ne!(halved, hopper);
    std::fs::write(dir.join("parts/hopper.xml"), &halved).unwrap();
    let (status, out) = diff_in(&dir, "HEAD:hopper.toml", "hopper.toml");
    assert_ne!(
        status,
        Some(0),
        "the old side read the disk's include:\n{out}"
    );
    assert_ne!(status, Some(2), "{out}");

    // A self-including model at a revision: one located error, at once.
    let own = "<mujoco>\n  <include file=\"model.xml\"/>\n</mujoco>\n";
    std::fs::write(dir.join("model.xml"), own).unwrap();
    git(&dir, &["commit", "-q", "-am", "a cycle"]);
    let (status, out) = diff_in(&dir, "HEAD:hopper.toml", "HEAD~1:hopper.toml");
    assert_eq!(status, Some(2), "{out}");
    assert!(out.contains("error[E0302]: <include> cycle"), "{out}");
    assert!(out.contains("--> HEAD:model.xml:2:18"), "{out}");

    // An include that leaves the repository is not taken from anywhere at that revision.
    let escape = "<mujoco>\n  <include file=\"../escape.xml\"/>\n</mujoco>\n";
    std::fs::write(dir.join("model.xml"), escape).unwrap();
    git(&dir, &["commit", "-q", "-am", "an include outside"]);
    let (status, out) = diff_in(&dir, "HEAD:hopper.toml", "HEAD~2:hopper.toml");
    assert_eq!(status, Some(2), "{out}");
    assert!(out.contains("error[E0301]"), "{out}");
    assert!(
        out.contains("../escape.xml is outside the repository"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
