//! TOML values with their locations, converted once from the `toml` crate's spanned parse tree, so
//! every later stage can point at the exact text it is complaining about.

use std::sync::Arc;

use toml::de::{DeTable, DeValue};

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile};

/// A TOML value and where it was written.
#[derive(Clone, Debug)]
pub struct Val {
    /// What the value is.
    pub kind: ValKind,
    /// Where it was written (the whole value's span).
    pub loc: Location,
}

/// The TOML types a spec can hold (dates are refused when read).
#[derive(Clone, Debug)]
pub enum ValKind {
    /// `true` or `false`.
    Bool(bool),
    /// An integer literal.
    Int(i64),
    /// A float literal.
    Float(f64),
    /// A string, escapes already resolved.
    Str(String),
    /// An array, inline or of tables.
    Array(Vec<Val>),
    /// Entries in document order, each with the location of its key.
    Table(Vec<Entry>),
}

/// One `key = value` of a table, the key located apart from its value.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The key as written, quotes removed.
    pub key: String,
    /// Where the key was written (for unknown-key errors).
    pub key_loc: Location,
    /// The value it maps to.
    pub value: Val,
}

impl Val {
    /// The TOML type's name, as error messages print it.
    pub fn type_name(&self) -> &'static str {
        match self.kind {
            ValKind::Bool(_) => "boolean",
            ValKind::Int(_) => "integer",
            ValKind::Float(_) => "float",
            ValKind::Str(_) => "string",
            ValKind::Array(_) => "array",
            ValKind::Table(_) => "table",
        }
    }
    /// The string, if the value is one.
    pub fn as_str(&self) -> Option<&str> {
        match &self.kind {
            ValKind::Str(s) => Some(s),
            _ => None,
        }
    }
    /// The number as f64, integers included.
    pub fn as_f64(&self) -> Option<f64> {
        match self.kind {
            ValKind::Float(x) => Some(x),
            ValKind::Int(i) => Some(i as f64),
            _ => None,
        }
    }
    /// The elements, if the value is an array.
    pub fn as_array(&self) -> Option<&[Val]> {
        match &self.kind {
            ValKind::Array(a) => Some(a),
            _ => None,
        }
    }
    /// The entries, if the value is a table.
    pub fn as_table(&self) -> Option<&[Entry]> {
        match &self.kind {
            ValKind::Table(t) => Some(t),
            _ => None,
        }
    }
    /// An error saying this value has the wrong type.
    pub fn type_error(&self, what: &str, expected: &str) -> Diagnostic {
        // An array says how long it is: most array mistakes are a wrong count, not a wrong type.
        let found = match &self.kind {
            ValKind::Array(a) if a.len() == 1 => "an array of 1 value".to_string(),
            ValKind::Array(a) => format!("an array of {} values", a.len()),
            _ => self.type_name().to_string(),
        };
        Diagnostic::new(
            Code::E0102,
            format!("{what} must be {expected}, found {found}"),
        )
        .at(self.loc.clone())
        .label(format!("expected {expected}"))
    }
    /// The value rendered back as a TOML literal (for reports and `envc show`).
    pub fn to_toml(&self) -> String {
        match &self.kind {
            ValKind::Bool(b) => b.to_string(),
            ValKind::Int(i) => i.to_string(),
            ValKind::Float(x) => format_float(*x),
            ValKind::Str(s) => format!("{s:?}"),
            ValKind::Array(a) => {
                format!(
                    "[{}]",
                    a.iter().map(Val::to_toml).collect::<Vec<_>>().join(", ")
                )
            }
            ValKind::Table(t) => format!(
                "{{ {} }}",
                t.iter()
                    .map(|e| format!("{} = {}", e.key, e.value.to_toml()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// A float as TOML writes it (`inf`, `-inf`, `nan`, and always with a `.` or exponent).
pub fn format_float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        let s = format!("{x:?}");
        if s.contains(['.', 'e', 'E']) {
            s
        } else {
            format!("{s}.0")
        }
    }
}

/// Read and parse a TOML file with locations: the one reader of every spec, map and registry
/// file. An unreadable file is E0600 (located at `at`, the value that named it, when given);
/// `what` names the file in the message ("spec", "map file", ...).
pub fn read_document(
    path: &std::path::Path,
    at: Option<&Location>,
    what: &str,
) -> Result<(Arc<SourceFile>, Val), Diagnostics> {
    let limit = crate::limits::MAX_SPEC_BYTES;
    let file = crate::source::read_source(path, limit, Code::E0600, what, |e| {
        Diagnostic::new(
            e.code(Code::E0600),
            format!("cannot read {what} {}: {e}", path.display()),
        )
        .at_opt(at.cloned())
        .label(format!("expected a readable TOML {what} file"))
    })?;
    let root = parse_document(&file)?;
    Ok((file, root))
}

/// Parse a whole TOML document. Syntax errors are reported with their location.
pub fn parse_document(file: &Arc<SourceFile>) -> Result<Val, Diagnostics> {
    let (table, errors) = DeTable::parse_recoverable(&file.text);
    // The first syntax error only: the parser's recovery turns one missing `]` into dozens of
    // errors on the lines after it.
    if let Some(e) = errors.first() {
        let span = e.span().unwrap_or(0..0);
        let message = e.message().trim();
        let mut d = Diagnostic::new(Code::E0100, format!("invalid TOML: {message}"));
        // An array left open shows where the next line starts: point at its `[`.
        d = match message
            .contains("array")
            .then(|| unclosed_bracket(&file.text, span.start))
            .flatten()
            .filter(|&open| file.text[open..span.start.max(open)].contains('\n'))
            .map(Some)
        {
            Some(Some(open)) => d
                .at(Location::new(file, open..open + 1))
                .label("this `[` is not closed (the next line was read as more of the array)"),
            _ => d.at(Location::new(file, span)).label("TOML syntax error"),
        };
        if errors.len() > 1 {
            d = d.help(format!(
                "{} more syntax errors follow from this one; fix it and check again",
                errors.len() - 1
            ));
        }
        return Err(Diagnostics::from(d));
    }
    let span = 0..file.text.len();
    let mut diags = Diagnostics::default();
    let entries = convert_table(file, table.get_ref(), &mut diags);
    diags.into_result(Val {
        kind: ValKind::Table(entries),
        loc: Location::new(file, span),
    })
}

/// The last `[` before `end` that no `]` closes (strings and comments skipped).
fn unclosed_bracket(text: &str, end: usize) -> Option<usize> {
    let b = text.as_bytes();
    let end = end.min(b.len());
    let mut open: Vec<usize> = vec![];
    let mut i = 0;
    while i < end {
        match b[i] {
            b'#' => {
                while i < end && b[i] != b'\n' {
                    i += 1;
                }
            }
            q @ (b'"' | b'\'') => {
                i += 1;
                while i < end && b[i] != q && b[i] != b'\n' {
                    // (a basic string's escape skips the escaped byte)
                    i += if q == b'"' && b[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'[' => open.push(i),
            b']' => {
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    open.pop()
}

/// Parse one TOML value written on its own, e.g. the right-hand side of `--set key=value`.
/// Returns None when the text is not a TOML value (callers may treat it as a bare string).
pub fn parse_literal(file: &Arc<SourceFile>) -> Option<Val> {
    let value = DeValue::parse(&file.text).ok()?;
    let mut diags = Diagnostics::default();
    let v = convert(file, value.get_ref(), value.span(), &mut diags);
    diags.is_empty().then_some(v)
}

fn convert_table(file: &Arc<SourceFile>, t: &DeTable<'_>, diags: &mut Diagnostics) -> Vec<Entry> {
    t.iter()
        .map(|(k, v)| Entry {
            key: k.get_ref().to_string(),
            key_loc: Location::new(file, k.span()),
            value: convert(file, v.get_ref(), v.span(), diags),
        })
        .collect()
}

fn convert(
    file: &Arc<SourceFile>,
    v: &DeValue<'_>,
    span: std::ops::Range<usize>,
    diags: &mut Diagnostics,
) -> Val {
    let loc = Location::new(file, span);
    let kind = match v {
        DeValue::Boolean(b) => ValKind::Bool(*b),
        DeValue::String(s) => ValKind::Str(s.to_string()),
        DeValue::Integer(i) => {
            let digits: String = i.as_str().chars().filter(|&c| c != '_').collect();
            let digits = digits
                .trim_start_matches("0x")
                .trim_start_matches("0o")
                .trim_start_matches("0b");
            match i64::from_str_radix(digits, i.radix()) {
                Ok(n) => ValKind::Int(n),
                Err(_) => {
                    diags.push(
                        Diagnostic::new(Code::E0105, "integer does not fit in 64 bits")
                            .at(loc.clone())
                            .label("expected a 64-bit integer"),
                    );
                    ValKind::Int(0)
                }
            }
        }
        DeValue::Float(x) => {
            let text: String = x.as_str().chars().filter(|&c| c != '_').collect();
            match text.parse::<f64>() {
                Ok(f) => ValKind::Float(f),
                Err(_) => {
                    diags.push(
                        Diagnostic::new(Code::E0105, format!("cannot read float `{text}`"))
                            .at(loc.clone())
                            .label("expected a float"),
                    );
                    ValKind::Float(f64::NAN)
                }
            }
        }
        DeValue::Datetime(_) => {
            diags.push(
                Diagnostic::new(Code::E0102, "dates and times have no meaning in a spec")
                    .at(loc.clone())
                    .label("expected a number, string, boolean, array or table"),
            );
            ValKind::Str(String::new())
        }
        DeValue::Array(a) => ValKind::Array(
            a.iter()
                .map(|e| convert(file, e.get_ref(), e.span(), diags))
                .collect(),
        ),
        DeValue::Table(t) => ValKind::Table(convert_table(file, t, diags)),
    };
    Val { kind, loc }
}
