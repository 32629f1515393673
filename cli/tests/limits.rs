//! Crashes, aborts, runaway memory and hangs found by fuzzing and by users, each as the user met it: every input
//! here once panicked, aborted, grew past gigabytes or never returned. Each now ends within
//! seconds, under a memory cap, with a coded error at the offending line (`envspec::limits` holds
//! the bounds; docs/limits.md explains them).
//!
//! One module per kind of limit (numbers, memory, sizes, runs, inputs); the helpers they share are
//! here.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod inputs;
mod memory;
mod numbers;
mod runs;
mod sizes;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// `envc ARGS` under a 4 GB address-space cap and a 180 s wall clock (a regression must fail the
/// test, not the machine).
fn envc(args: &[&str]) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(r#"ulimit -v 4000000; exec timeout -s KILL 180 "$0" "$@""#)
        .arg(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc")
}

/// The exit status is 1 (problems found) or 2 (refused) and stderr or stdout names `code`; never
/// a signal (abort, OOM kill, timeout) or a panic.
fn refused(o: &Output, code: &str) -> String {
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "status {:?} (a signal is an abort, an OOM kill or the timeout):\n{text}",
        o.status
    );
    assert!(!text.contains("panicked"), "{text}");
    assert!(
        text.contains(&format!("[{code}]")),
        "expected {code}:\n{text}"
    );
    text
}

/// A scratch directory holding a copy of a bundled spec and its model, edited.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("envc-limits-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
    /// `specs/gymnasium/<spec>` with `edit` applied, its model copied beside it with `edit_xml`.
    fn spec(&self, spec: &str, edit: &[(&str, &str)], edit_xml: &[(&str, &str)]) -> PathBuf {
        let mut text =
            std::fs::read_to_string(Path::new(ROOT).join("specs/gymnasium").join(spec)).unwrap();
        let xml_line = text
            .lines()
            .find(|l| l.starts_with("xml_file"))
            .unwrap()
            .to_string();
        let xml_rel = xml_line.split('"').nth(1).unwrap().to_string();
        let mut xml =
            std::fs::read_to_string(Path::new(ROOT).join("specs/gymnasium").join(&xml_rel))
                .unwrap();
        for (a, b) in edit_xml {
            assert!(xml.contains(a), "{a} not in {xml_rel}");
            xml = xml.replacen(a, b, 1);
        }
        std::fs::write(self.0.join("model.xml"), xml).unwrap();
        text = text.replace(&xml_rel, "model.xml");
        for (a, b) in edit {
            assert!(text.contains(a), "{a} not in {spec}");
            text = text.replacen(a, b, 1);
        }
        let p = self.0.join(spec);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Text replacements applied to a spec.
type Edits<'a> = &'a [(&'a str, &'a str)];

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
