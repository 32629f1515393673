//! The `envc` binary: the command line of `envc_cli` (src/lib.rs).

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(envc_cli::main_with(std::env::args_os().collect()))
}
