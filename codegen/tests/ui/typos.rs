// Three misspelt names in one spec (a body, two parameters): all reported, each at its line.
envc_codegen::env!("ui/typos.toml");

fn main() {}
