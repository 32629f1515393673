// A spec path that does not exist.
envc_codegen::env!("ui/no_such_spec.toml");

fn main() {}
