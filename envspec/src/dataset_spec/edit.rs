//! The one edit envc makes to a dataset spec: storing measured reference scores. The edit is
//! structural (`toml_edit`), so every other table, comment and blank line stays as written.

use std::path::Path;

use toml_edit::{DocumentMut, Item, Table, Value};

use super::RefScores;
use crate::diagnostic::{Code, Diagnostic, Location};

/// The text of the dataset spec at `path` with its `[reference_scores]` set to `scores`: the
/// values replaced in place (their comments kept) when the table is there, else a new table
/// before `[train]` (at the end without one). Both the file and the result must be valid
/// dataset specs (E1801).
pub fn with_reference_scores(path: &Path, scores: &RefScores) -> Result<String, Diagnostic> {
    let file = super::read_file(path)?;
    super::parse(&file)?;
    let mut doc: DocumentMut = file.text.parse().map_err(|e: toml_edit::TomlError| {
        let span = e.span().unwrap_or(0..0);
        Diagnostic::new(Code::E1801, e.message().trim().to_string()).at(Location::new(&file, span))
    })?;
    let values = [
        ("ref_min_score", Value::from(scores.ref_min_score)),
        ("ref_max_score", Value::from(scores.ref_max_score)),
        (
            "num_episodes_average_score",
            Value::from(i64::try_from(scores.num_episodes_average_score).unwrap_or(i64::MAX)),
        ),
    ];
    match doc
        .get_mut("reference_scores")
        .and_then(Item::as_table_like_mut)
    {
        Some(table) => {
            for (key, mut value) in values {
                // In place: the key keeps the comment above it, the value its own.
                match table.get_mut(key) {
                    Some(item) => {
                        if let Some(old) = item.as_value() {
                            *value.decor_mut() = old.decor().clone();
                        }
                        *item = Item::Value(value);
                    }
                    None => {
                        table.insert(key, Item::Value(value));
                    }
                }
            }
        }
        None => {
            let mut table = Table::new();
            for (key, value) in values {
                table.insert(key, Item::Value(value));
            }
            // Where [train] was, blank lines before it included: [train] follows one blank line.
            let train = doc.get_mut("train").and_then(Item::as_table_mut);
            if let Some((train, at)) = train.and_then(|t| t.position().map(|at| (t, at))) {
                if let Some(prefix) = train.decor().prefix().cloned() {
                    table.decor_mut().set_prefix(prefix);
                }
                train.decor_mut().set_prefix("\n");
                shift_from(doc.as_table_mut(), at);
                table.set_position(Some(at));
            }
            doc.insert("reference_scores", Item::Table(table));
        }
    }
    let text = doc.to_string();
    // The result must read back as a dataset spec (scores finite and different).
    super::parse(&crate::diagnostic::SourceFile::new(path, text.clone()))?;
    Ok(text)
}

/// Moves every table written at document position `at` or later one place down, making room
/// for a table at `at`.
fn shift_from(table: &mut Table, at: isize) {
    for (_, item) in table.iter_mut() {
        match item {
            Item::Table(t) => {
                if let Some(p) = t.position().filter(|&p| p >= at) {
                    t.set_position(Some(p + 1));
                }
                shift_from(t, at);
            }
            Item::ArrayOfTables(a) => {
                for t in a.iter_mut() {
                    if let Some(p) = t.position().filter(|&p| p >= at) {
                        t.set_position(Some(p + 1));
                    }
                    shift_from(t, at);
                }
            }
            _ => {}
        }
    }
}
