// A model that includes itself: the same located error as `envc check` and `envc diff REV:path`.
envc_codegen::env!("ui/include_cycle.toml");

fn main() {}
