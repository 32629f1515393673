//! JSON as Python's `json` module writes and reads it. Minari stores spaces and the env spec as
//! JSON *strings* written by `json.dumps`, which spells infinite bounds `Infinity` / `-Infinity` (and
//! NaN `NaN`). serde_json can neither emit nor parse those tokens, so this module writes such text
//! by hand (a small value type) and reads it by turning the bare tokens into marker strings before
//! serde_json parses it.

use serde_json::Value;

/// A JSON value that can hold any f64, written with Python's `", "` / `": "` separators.
#[derive(Clone, Debug)]
pub enum PyJson {
    Null,
    Bool(bool),
    Int(i128),
    Float(f64),
    Str(String),
    List(Vec<PyJson>),
    Obj(Vec<(String, PyJson)>),
}

pub fn py_float(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x == f64::INFINITY {
        "Infinity".into()
    } else if x == f64::NEG_INFINITY {
        "-Infinity".into()
    } else {
        // `{:?}` always keeps a decimal point or an exponent, so Python reads a float back.
        format!("{x:?}")
    }
}

impl PyJson {
    pub fn dump(&self) -> String {
        let mut s = String::new();
        self.write(&mut s);
        s
    }
    fn write(&self, out: &mut String) {
        match self {
            PyJson::Null => out.push_str("null"),
            PyJson::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            PyJson::Int(i) => out.push_str(&i.to_string()),
            PyJson::Float(x) => out.push_str(&py_float(*x)),
            PyJson::Str(s) => out.push_str(&Value::String(s.clone()).to_string()),
            PyJson::List(v) => {
                out.push('[');
                for (i, x) in v.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    x.write(out);
                }
                out.push(']');
            }
            PyJson::Obj(v) => {
                out.push('{');
                for (i, (k, x)) in v.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    out.push_str(&Value::String(k.clone()).to_string());
                    out.push_str(": ");
                    x.write(out);
                }
                out.push('}');
            }
        }
    }
}

const INF: &str = "\u{0}envc:Infinity";
const NEG_INF: &str = "\u{0}envc:-Infinity";
const NAN: &str = "\u{0}envc:NaN";

/// Parse JSON that may contain Python's bare `Infinity`, `-Infinity` and `NaN` tokens; read numbers
/// back with [`number`].
pub fn parse_lenient(text: &str) -> Result<Value, serde_json::Error> {
    let mut out = String::with_capacity(text.len());
    let mut in_str = false;
    let mut escaped = false;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if in_str {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_str = false;
            }
            rest = &rest[c.len_utf8()..];
            continue;
        }
        let token = [("-Infinity", NEG_INF), ("Infinity", INF), ("NaN", NAN)]
            .into_iter()
            .find(|(t, _)| rest.starts_with(t));
        if let Some((t, marker)) = token {
            out.push_str(&Value::String(marker.into()).to_string());
            rest = &rest[t.len()..];
            continue;
        }
        if c == '"' {
            in_str = true;
        }
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    serde_json::from_str(&out)
}

/// A number from [`parse_lenient`] output (also the infinity / NaN markers).
pub fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) if s == INF => Some(f64::INFINITY),
        Value::String(s) if s == NEG_INF => Some(f64::NEG_INFINITY),
        Value::String(s) if s == NAN => Some(f64::NAN),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_tokens_round_trip() {
        let v = PyJson::Obj(vec![
            (
                "low".into(),
                PyJson::List(vec![PyJson::Float(f64::NEG_INFINITY), PyJson::Float(-0.4)]),
            ),
            ("s".into(), PyJson::Str("Infinity \"x\"".into())),
        ]);
        let text = v.dump();
        assert_eq!(text, r#"{"low": [-Infinity, -0.4], "s": "Infinity \"x\""}"#);
        let back = parse_lenient(&text).unwrap();
        assert_eq!(number(&back["low"][0]), Some(f64::NEG_INFINITY));
        assert_eq!(number(&back["low"][1]), Some(-0.4));
        assert_eq!(back["s"], "Infinity \"x\"");
    }
}
