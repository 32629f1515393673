//! Check a spec and print its errors: `cargo run -p envc --example check_spec -- SPEC [--set k=v ...]`.
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: check_spec SPEC [--set key=value ...]");
        return ExitCode::FAILURE;
    };
    let mut overrides = vec![];
    while let Some(a) = args.next() {
        match (a.as_str(), args.next()) {
            ("--set", Some(kv)) => match envc::Override::parse(&kv) {
                Ok(o) => overrides.push(o),
                Err(d) => {
                    eprintln!("{d}");
                    return ExitCode::FAILURE;
                }
            },
            _ => {
                eprintln!("unexpected argument `{a}`");
                return ExitCode::FAILURE;
            }
        }
    }
    match envc::envspec::load(path.as_ref(), &overrides) {
        Ok(spec) => {
            println!(
                "{}: ok (obs dim {}, action dim {})",
                spec.id,
                spec.obs_dim,
                spec.act_dim()
            );
            ExitCode::SUCCESS
        }
        Err(d) => {
            eprintln!("{d}");
            ExitCode::FAILURE
        }
    }
}
