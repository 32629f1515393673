// A spec path that does not exist.
envc::env!("ui/no_such_spec.toml");

fn main() {}
