// A misspelt key: located, with the keys that are allowed and the near miss.
envc_codegen::env!("ui/unknown_key.toml");

fn main() {}
