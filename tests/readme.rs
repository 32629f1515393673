//! The README's environment table is generated from the specs; this keeps it from going stale.

#[test]
fn readme_env_table_matches_the_specs() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap();
    let start = readme.find("<!-- env-table:start").expect("start marker");
    let body = &readme[start..];
    let body = &body[body.find('\n').unwrap() + 1..];
    let end = body.find("<!-- env-table:end").expect("end marker");
    let expected = envc::registry::env_table_markdown().unwrap();
    assert_eq!(
        body[..end].trim(),
        expected.trim(),
        "README table is stale: run `cargo run -p envc --example env_table`"
    );
    assert!(expected.contains("| Ant-v5 | 105 | 8 | 0.05 | 1000 |"));
}
