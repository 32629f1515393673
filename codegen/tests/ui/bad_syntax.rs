// Not the macro's syntax: the spec path must be a string literal.
envc_codegen::env!(specs::ant);

fn main() {}
