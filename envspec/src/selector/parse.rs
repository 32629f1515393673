//! Reading a selector's text: the field name, then `[rows]` and `[cols]` (or `.col`).

use crate::diagnostic::{Code, Diagnostic, Location};

/// One `[...]` of a selector as written.
#[derive(Debug)]
pub(super) enum Index {
    Int(i64),
    Slice(Option<i64>, Option<i64>),
    List(Vec<i64>),
    /// Names (or integers) listed in order.
    Names(Vec<String>),
    Name(String),
    Param(String),
}

pub(super) fn syntax_error(loc: &Location, msg: &str) -> Diagnostic {
    Diagnostic::new(Code::E0401, format!("cannot read selector: {msg}"))
        .at(loc.clone())
        .label("expected field[rows][cols], e.g. `qpos[2:]` or `xpos[torso][0:2]`")
}

/// A selector split into its field name and its (at most two) indices.
pub(super) fn parse(text: &str, loc: &Location) -> Result<(String, Vec<Index>), Diagnostic> {
    let text = text.trim();
    let (field, mut rest) = match text.find('[') {
        Some(i) => (&text[..i], &text[i..]),
        None => (text, ""),
    };
    let mut indices = vec![];
    while !rest.is_empty() {
        // `.x`, `.tz`: a column by name, as `envc show` prints element names (`xpos[torso].x`).
        if let Some(col) = rest.strip_prefix('.') {
            let col = col.trim();
            if col.is_empty() || !col.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(syntax_error(loc, &format!("`.{col}` is not a column name")));
            }
            if indices.len() != 1 {
                return Err(syntax_error(
                    loc,
                    "a `.column` follows exactly one `[rows]`, as in `xpos[torso].x`",
                ));
            }
            indices.push(Index::Name(col.to_string()));
            break;
        }
        let close = rest
            .find(']')
            .ok_or_else(|| syntax_error(loc, "missing `]`"))?;
        if !rest.starts_with('[') {
            return Err(syntax_error(loc, "expected `[` after `]`"));
        }
        let inner = rest[1..close].trim();
        rest = rest[close + 1..].trim_start();
        let int = |s: &str| -> Result<i64, Diagnostic> {
            s.trim().parse::<i64>().map_err(|_| {
                syntax_error(loc, &format!("`{}` is too large for an index", s.trim()))
            })
        };
        // `joint:part` (`qpos[root:z]`, as `envc show` prints a free joint's elements) is a name,
        // not a slice: a slice's ends are integers (of any size: too large is an error) or empty.
        let slice_end = |x: &str| x.trim().is_empty() || integer_like(x.trim());
        let idx = if let Some(p) = inner.strip_prefix('$') {
            Index::Param(p.trim().to_string())
        } else if let Some((a, b)) = inner
            .split_once(':')
            .filter(|(a, b)| slice_end(a) && slice_end(b))
        {
            let a = if a.trim().is_empty() {
                None
            } else {
                Some(int(a)?)
            };
            let b = if b.trim().is_empty() {
                None
            } else {
                Some(int(b)?)
            };
            Index::Slice(a, b)
        } else if inner.contains(',') && inner.split(',').all(|x| x.trim().parse::<i64>().is_ok()) {
            Index::List(inner.split(',').map(int).collect::<Result<_, _>>()?)
        } else if inner.contains(',') {
            // Names (or indices) listed in order: `qpos[goal_x,goal_y,goal_z]`.
            let parts: Vec<String> = inner.split(',').map(|x| x.trim().to_string()).collect();
            if parts.iter().any(String::is_empty) {
                return Err(syntax_error(loc, "an empty entry in a `,` list"));
            }
            Index::Names(parts)
        } else if integer_like(inner) {
            Index::Int(int(inner)?)
        } else if is_decimal(inner) {
            return Err(syntax_error(
                loc,
                &format!("`{inner}` is not an integer: indices count elements"),
            ));
        } else if inner.is_empty() {
            return Err(syntax_error(loc, "empty `[]`"));
        } else {
            Index::Name(inner.to_string())
        };
        indices.push(idx);
    }
    if indices.len() > 2 {
        return Err(syntax_error(
            loc,
            "at most two indices (rows, then columns)",
        ));
    }
    Ok((field.trim().to_string(), indices))
}

/// An optional `-` and ASCII digits: an index, whatever its size.
fn integer_like(s: &str) -> bool {
    let digits = s.strip_prefix('-').unwrap_or(s);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// Digits with a decimal point (`1.5`, `-0.5`): a number that cannot be an index.
fn is_decimal(s: &str) -> bool {
    s.split_once('.').is_some_and(|(a, b)| {
        integer_like(a) && !b.is_empty() && b.bytes().all(|c| c.is_ascii_digit())
    })
}
