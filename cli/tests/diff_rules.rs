//! docs/diff-rules.md and `envspec::diff::RULES` list the same rules (id, category, breaking,
//! description) both ways, and every rule id a pinned report prints is in the table.

use std::collections::BTreeMap;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// `| `id` | category | yes/no | description |` rows of the docs.
fn documented() -> BTreeMap<String, (String, String, String)> {
    let doc = std::fs::read_to_string(root().join("docs/diff-rules.md")).unwrap();
    let mut out = BTreeMap::new();
    for line in doc.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line
            .trim_matches('|')
            .splitn(4, " | ")
            .map(str::trim)
            .collect();
        assert_eq!(cells.len(), 4, "malformed row: {line}");
        let id = cells[0].trim_matches('`').to_string();
        let row = (
            cells[1].to_string(),
            cells[2].to_string(),
            cells[3].to_string(),
        );
        assert!(out.insert(id.clone(), row).is_none(), "{id} listed twice");
    }
    out
}

#[test]
fn docs_and_rule_table_agree() {
    let docs = documented();
    let table: BTreeMap<String, (String, String, String)> = envspec::diff::RULES
        .iter()
        .map(|r| {
            (
                r.id.to_string(),
                (
                    r.category.key().to_string(),
                    if r.breaking { "yes" } else { "no" }.to_string(),
                    r.description.to_string(),
                ),
            )
        })
        .collect();
    assert!(table.len() >= 80, "{}", table.len());
    let undocumented: Vec<_> = table.keys().filter(|k| !docs.contains_key(*k)).collect();
    let stale: Vec<_> = docs.keys().filter(|k| !table.contains_key(*k)).collect();
    let differ: Vec<String> = table
        .iter()
        .filter_map(|(k, v)| {
            let d = docs.get(k)?;
            (d != v).then(|| format!("{k}: docs {d:?}, code {v:?}"))
        })
        .collect();
    assert!(
        undocumented.is_empty() && stale.is_empty() && differ.is_empty(),
        "rules in the code but not in docs/diff-rules.md: {undocumented:?}; in the docs but not \
         in the code: {stale:?}; rows that differ:\n{}",
        differ.join("\n")
    );
}

#[test]
fn pinned_reports_print_known_rule_ids() {
    let ids: Vec<&str> = envspec::diff::RULES.iter().map(|r| r.id).collect();
    let mut seen = 0;
    for e in std::fs::read_dir(root().join("cli/tests/diff_golden")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "txt") {
            continue;
        }
        for line in std::fs::read_to_string(&p).unwrap().lines() {
            // Change lines: two spaces, the mark, a space, `[id]`.
            if let Some(rest) = line.get(4..).filter(|_| line.starts_with("  "))
                && let Some(rest) = rest.strip_prefix('[')
            {
                let id = &rest[..rest.find(']').unwrap()];
                assert!(ids.contains(&id), "{}: unknown rule `{id}`", p.display());
                seen += 1;
            }
        }
    }
    assert!(seen > 200, "only {seen} change lines found");
}
