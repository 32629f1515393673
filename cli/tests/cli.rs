//! `cli`'s integration tests, one module per file of this directory: the `envc` binary is run by most (`CARGO_BIN_EXE_envc`, or `ENVC_BIN` for the release build in scripts/test.sh).
//! One binary instead of one per file, so the suite links once.
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

mod catalogue;
mod command_matrix;
mod dataset_faults;
mod diff_changelog;
mod diff_dynamics;
mod diff_flags;
mod diff_maze;
mod diff_rules;
mod events;
mod exit_status;
mod fuzz;
mod limits;
mod multi_agent;
mod numerics;
mod render;
mod rollout_policy;
mod run_endings;
mod show_noise;
mod show_text;
mod tutorial;

/// A test file that is not declared above would silently never run.
#[test]
fn every_test_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let root = std::fs::read_to_string(dir.join("cli.rs")).unwrap();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs") || stem == "cli" {
            continue;
        }
        assert!(
            root.contains(&format!("mod {stem};")),
            "tests/{stem}.rs is not a module of tests/cli.rs"
        );
    }
}
