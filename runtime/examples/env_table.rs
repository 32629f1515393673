//! Print the README's table of bundled envs: `cargo run -p envc --example env_table`.
fn main() -> Result<(), envc::EnvError> {
    print!("{}", envc::registry::env_table_markdown()?);
    Ok(())
}
