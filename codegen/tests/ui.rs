//! Compile-fail tests: spec mistakes in `envc::env!` are compile errors that name the TOML file,
//! line and column, quote the line with a caret, say what was expected and suggest a fix; all
//! errors at once. The expected messages are pinned in `ui/*.stderr`. The cases call the macro as
//! `envc_codegen::env!`, the item `envc::env!` re-exports: the runtime's dependencies stay out of
//! trybuild's build.
#![allow(clippy::unwrap_used)] // Test helpers outside `#[test]` functions unwrap too.

#[test]
fn spec_errors_are_compile_errors() {
    // trybuild compiles each case in a crate under target/; relative spec paths must still
    // resolve against tests/. Its cases' dependencies are built without debug info (only
    // the messages matter).
    // SAFETY: set before any thread that reads the environment is started by this test.
    unsafe {
        std::env::set_var(
            "ENVC_MANIFEST_DIR_OVERRIDE",
            concat!(env!("CARGO_MANIFEST_DIR"), "/tests"),
        );
        std::env::set_var("CARGO_PROFILE_DEV_DEBUG", "false");
    };
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
