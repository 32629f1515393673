//! envc's integration tests, one module per file of this directory (fixtures and reference
//! scripts live in `reference/`). One binary instead of one per file: each links MuJoCo, HDF5 and
//! the whole runtime, so linking was most of the suite's build time.
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

#[global_allocator]
static A: envc_tests::ThreadCounting = envc_tests::ThreadCounting;

mod added_elements;
mod adroit;
mod error_codes;
mod events;
mod fetch;
mod goal_terms;
mod golden;
mod hand;
mod invariants;
mod joint_patterns;
mod joystick_terms;
mod kitchen;
mod mamujoco;
mod maze;
mod minari;
mod mjlab_terms;
mod no_alloc;
mod numerics;
mod obs_noise;
mod parity;
mod pd_actions;
mod provenance;
mod readme;
mod render;
mod rng_numpy;
mod runtime_errors;
mod sensors;
mod terrain;
mod typed;
mod urdf;
mod vector;

/// A test file that is not declared above would silently never run.
#[test]
fn every_test_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = std::fs::read_to_string(dir.join("integration.rs")).unwrap();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs")
            || ["integration", "no_alloc_vector", "build"].contains(&stem)
        {
            continue;
        }
        assert!(
            root.contains(&format!("mod {stem};")),
            "tests/{stem}.rs is not a module of tests/integration.rs"
        );
    }
}
