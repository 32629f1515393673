//! `envspec::registry::register` on hostile directories: loops, FIFOs, the whole file system,
//! files that do not parse, ids Gymnasium refuses and one id in two files. Each is a coded
//! error, quickly.

use std::path::Path;
use std::time::{Duration, Instant};

use envspec::Code;
use envspec::registry::register;

fn scratch(name: &str) -> crate::scratch::ScratchDir {
    crate::scratch::ScratchDir::new(&format!("registry-{name}"))
}

fn spec(dir: &Path, file: &str, id: &str) {
    let text = format!("[env]\nid = {id:?}\nmodel = \"m.xml\"\n");
    std::fs::write(dir.join(file), text).unwrap();
}

#[test]
fn symlink_loops_and_the_whole_file_system_do_not_hang_the_registry() {
    let d = scratch("loops");
    let inner = d.join("inner");
    std::fs::create_dir_all(&inner).unwrap();
    spec(&inner, "a.toml", "WalkLoopA-v0");
    std::os::unix::fs::symlink(&d, inner.join("up1")).unwrap();
    std::os::unix::fs::symlink("..", inner.join("up2")).unwrap();
    std::os::unix::fs::symlink(".", inner.join("here")).unwrap();
    let t = Instant::now();
    assert_eq!(register(&inner).unwrap(), ["WalkLoopA-v0"]);
    assert!(t.elapsed() < Duration::from_secs(10));
    // /proc/self leads to / through `root` and `cwd`: bounded, and an error, not a walk of it all.
    let t = Instant::now();
    let e = register(Path::new("/proc/self")).expect_err("refused");
    assert!(matches!(e.code, Code::E0110 | Code::E0600), "{e}");
    assert!(t.elapsed() < Duration::from_secs(60), "{:?}", t.elapsed());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_fifo_a_broken_file_and_a_bad_id_are_named() {
    let d = scratch("fifo");
    spec(&d, "good.toml", "WalkFifoGood-v0");
    let fifo = d.join("pipe.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let e = register(&d).expect_err("a FIFO is named");
        assert!(e.message.contains("pipe.toml"), "{e}");
        std::fs::remove_file(&fifo).unwrap();
    }
    // A file that does not parse: its own error, whether alone or in a directory.
    std::fs::write(d.join("broken.toml"), "[env\nid = \"X-v0\"\n").unwrap();
    let e = register(&d.join("broken.toml")).expect_err("refused");
    assert!(!e.message.contains("holds no spec"), "{e}");
    assert!(
        e.position().is_some_and(|p| p.contains("broken.toml")),
        "{e}"
    );
    let e = register(&d).expect_err("refused");
    assert!(
        e.position().is_some_and(|p| p.contains("broken.toml")),
        "{e}"
    );
    std::fs::remove_file(d.join("broken.toml")).unwrap();
    // Ids Gymnasium cannot register, as `envc check` says (E0111).
    for (i, id) in ["a b-v0", "envc/Foo-v0", ""].into_iter().enumerate() {
        let f = format!("bad{i}.toml");
        spec(&d, &f, id);
        let e = register(&d.join(&f)).expect_err("refused");
        assert_eq!(e.code, Code::E0111, "{id:?}: {e}");
        let e = register(&d).expect_err("refused");
        assert_eq!(e.code, Code::E0111, "{id:?}: {e}");
        std::fs::remove_file(d.join(&f)).unwrap();
    }
    assert_eq!(register(&d).unwrap(), ["WalkFifoGood-v0"]);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn one_id_in_two_files_of_a_directory_is_e0603_naming_both() {
    let d = scratch("twice");
    spec(&d, "one.toml", "WalkTwice-v0");
    spec(&d, "two.toml", "WalkTwice-v0");
    let e = register(&d).expect_err("refused");
    assert_eq!(e.code, Code::E0603, "{e}");
    assert!(
        e.message.contains("one.toml") && e.message.contains("two.toml"),
        "{e}"
    );
    assert!(envspec::registry::lookup("WalkTwice-v0").is_err());
    let _ = std::fs::remove_dir_all(&d);
}

/// What Gymnasium's registration needs of a task comes from its text and parameters, the same
/// as the fully resolved spec says (the family's overrides included), without reading a model.
#[test]
fn registration_facts_are_read_without_the_model() {
    use envspec::registry::{entries, task_registration};
    for id in ["Hopper-v5", "Reacher-v5", "FetchReachDense-v4", "Point-v0"] {
        let e = entries().iter().find(|e| e.id == id).unwrap();
        let full = envspec::load(&e.path, &e.overrides).unwrap();
        assert_eq!(
            task_registration(e),
            Some((full.max_episode_steps, full.reward_threshold)),
            "{id}"
        );
    }
    // A task whose model is missing still registers its time limit; a maze is opened fully.
    let d = scratch("facts");
    std::fs::write(
        d.join("t.toml"),
        "[env]\nid = \"FactsOnly-v0\"\n[params]\nxml_file = \"missing.xml\"\nframe_skip = 1\nmax_episode_steps = 77\n",
    )
    .unwrap();
    let e = envspec::registry::Entry {
        id: "FactsOnly-v0".into(),
        kind: envspec::Kind::Task,
        path: d.join("t.toml"),
        overrides: vec![],
        example: false,
        task: true,
        user: true,
    };
    assert_eq!(task_registration(&e), Some((Some(77), None)));
    let maze = entries()
        .iter()
        .find(|e| e.kind == envspec::Kind::Maze)
        .unwrap();
    assert_eq!(task_registration(maze), None);
    std::fs::remove_dir_all(&d).ok();
}
