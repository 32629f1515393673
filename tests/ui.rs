//! Compile-fail tests: spec mistakes in `envc::env!` are compile errors that name the TOML file,
//! line and column, quote the line with a caret, say what was expected and suggest a fix; all
//! errors at once. The expected messages are pinned in `ui/*.stderr`.
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

#[test]
fn spec_errors_are_compile_errors() {
    // trybuild compiles each case in a crate under target/; relative spec paths must still
    // resolve against this directory.
    // SAFETY: set before any thread that reads the environment is started by this test.
    unsafe { std::env::set_var("ENVC_MANIFEST_DIR_OVERRIDE", env!("CARGO_MANIFEST_DIR")) };
    let t = trybuild::TestCases::new();
    t.compile_fail("ui/*.rs");
}
