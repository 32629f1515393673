//! `envspec`'s integration tests, one module per file of this directory: the spec language checked without MuJoCo.
//! One binary instead of one per file, so the suite links once.
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

mod agents_typos;
mod bad_input;
mod commands;
mod dataset_specs;
mod entry_point;
mod events;
mod fixed_params;
mod fuzz_regressions;
mod goal_parts;
mod gymnasium_specs;
mod maze_errors;
mod messages;
mod mjlab_kinds;
mod noise;
mod registry_walks;
mod scratch;
mod selector_roundtrip;
mod source_reads;
mod terrain_errors;
mod v4_terms;

/// A test file that is not declared above would silently never run.
#[test]
fn every_test_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let root = std::fs::read_to_string(dir.join("spec.rs")).unwrap();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs") || stem == "spec" {
            continue;
        }
        assert!(
            root.contains(&format!("mod {stem};")),
            "tests/{stem}.rs is not a module of tests/spec.rs"
        );
    }
}
