//! Every error code the code can emit has an entry in docs/errors.md (a table row and a section),
//! and every documented code is still emitted somewhere: the table is the contract users read.

use std::collections::BTreeSet;
use std::path::Path;

/// `E` followed by exactly four digits, not inside a longer word.
fn codes_in(text: &str, out: &mut BTreeSet<String>) {
    let b = text.as_bytes();
    for i in 0..b.len() {
        let word_start = i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if b[i] == b'E' && word_start && i + 5 <= b.len() {
            let digits = &b[i + 1..i + 5];
            let word_end = i + 5 == b.len() || !b[i + 5].is_ascii_alphanumeric();
            if digits.iter().all(u8::is_ascii_digit) && word_end {
                out.insert(text[i..i + 5].to_string());
            }
        }
    }
}

fn scan(dir: &Path, out: &mut BTreeSet<String>) {
    if dir.is_file() {
        codes_in(&std::fs::read_to_string(dir).unwrap(), out);
        return;
    }
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            scan(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs" || x == "py") {
            codes_in(&std::fs::read_to_string(&p).unwrap(), out);
        }
    }
}

#[test]
fn every_code_is_documented_and_every_documented_code_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut in_code = BTreeSet::new();
    // The Python package emits codes too (the GPU executor's refusal, a stalled Ray collection
    // and a vector env called from two threads are raised in Python).
    for krate in [
        "envspec/src",
        "runtime/src",
        "datasets/src",
        "cli/src",
        "codegen/src",
        "python/src",
        "python/envc/gpu",
        "python/envc/ray.py",
        "python/envc/_vector.py",
    ] {
        scan(&root.join(krate), &mut in_code);
    }
    let doc = std::fs::read_to_string(root.join("docs/errors.md")).unwrap();
    let mut table = BTreeSet::new();
    let mut sections = BTreeSet::new();
    for line in doc.lines() {
        if let Some(rest) = line.strip_prefix("| [") {
            codes_in(&rest[..rest.len().min(6)], &mut table);
        } else if let Some(rest) = line.strip_prefix("## ") {
            codes_in(rest, &mut sections);
        }
    }
    assert!(in_code.len() >= 30, "found only {in_code:?}");
    let undocumented: Vec<_> = in_code.difference(&table).collect();
    let stale: Vec<_> = table.difference(&in_code).collect();
    let no_section: Vec<_> = table.difference(&sections).collect();
    assert!(
        undocumented.is_empty() && stale.is_empty() && no_section.is_empty(),
        "codes in the code but not in docs/errors.md's table: {undocumented:?}; \
         in the table but emitted nowhere: {stale:?}; in the table without a `## Exxxx` section: {no_section:?}"
    );
}
