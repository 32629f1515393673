//! Gymnasium spaces as Minari serializes them (`minari/serialization.py`).

use serde_json::Value;

use crate::json::{PyJson, number, parse_lenient};

/// Element types of stored arrays (numpy names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// `float64`.
    F64,
    /// `float32`.
    F32,
    /// `int64`.
    I64,
    /// `int32`.
    I32,
    /// `int16`.
    I16,
    /// `int8`.
    I8,
    /// `uint8`.
    U8,
    /// `bool`.
    Bool,
}

impl Dtype {
    /// numpy's name for the type.
    pub fn numpy_name(self) -> &'static str {
        match self {
            Dtype::F64 => "float64",
            Dtype::F32 => "float32",
            Dtype::I64 => "int64",
            Dtype::I32 => "int32",
            Dtype::I16 => "int16",
            Dtype::I8 => "int8",
            Dtype::U8 => "uint8",
            Dtype::Bool => "bool",
        }
    }
    /// The type of a numpy name or dtype string (`float64`, `<f8`, ...).
    pub fn from_numpy(name: &str) -> Option<Dtype> {
        Some(match name {
            "float64" | "f8" | "<f8" | "double" => Dtype::F64,
            "float32" | "f4" | "<f4" | "single" => Dtype::F32,
            "int64" | "i8" | "<i8" => Dtype::I64,
            "int32" | "i4" | "<i4" => Dtype::I32,
            "int16" | "i2" | "<i2" => Dtype::I16,
            "int8" | "i1" => Dtype::I8,
            "uint8" | "u1" => Dtype::U8,
            "bool" | "?" => Dtype::Bool,
            _ => return None,
        })
    }
}

/// A space as stored in `metadata.json`. Spaces envc cannot decode are kept as their JSON.
#[derive(Clone, Debug, PartialEq)]
pub enum Space {
    /// A Gymnasium `Box`.
    Box {
        /// Element type.
        dtype: Dtype,
        /// Dimensions, e.g. `[27]`.
        shape: Vec<usize>,
        /// Lower bounds, flat.
        low: Vec<f64>,
        /// Upper bounds, flat.
        high: Vec<f64>,
    },
    /// A Gymnasium `Discrete`.
    Discrete {
        /// Number of values.
        n: i64,
        /// The smallest value.
        start: i64,
    },
    /// Keys in the order stored (gymnasium sorts them on load).
    Dict(Vec<(String, Space)>),
    /// A Gymnasium `Tuple`.
    Tuple(Vec<Space>),
    /// A space envc does not decode, as its JSON.
    Other(Value),
}

impl Space {
    /// A 1-D Box. float32 bounds are rounded to float32, as `space.low.tolist()` gives them.
    pub fn box1(dtype: Dtype, low: &[f64], high: &[f64]) -> Space {
        let round = |v: &[f64]| -> Vec<f64> {
            if dtype == Dtype::F32 {
                v.iter().map(|x| *x as f32 as f64).collect()
            } else {
                v.to_vec()
            }
        };
        Space::Box {
            dtype,
            shape: vec![low.len()],
            low: round(low),
            high: round(high),
        }
    }

    /// Number of elements per row of a Box (product of the shape).
    pub fn flat_len(&self) -> Option<usize> {
        match self {
            Space::Box { shape, .. } => Some(shape.iter().product()),
            // A Dict of Boxes: the children's rows concatenated in the listed key order (how a
            // writer receives dict observations, e.g. a maze env's).
            Space::Dict(items) => items.iter().map(|(_, s)| s.flat_len()).sum(),
            _ => None,
        }
    }

    /// The JSON Minari writes for this space (as a value; `to_json_string` for the text).
    pub fn to_py(&self) -> PyJson {
        match self {
            Space::Box {
                dtype,
                shape,
                low,
                high,
            } => {
                fn nest(v: &[f64], shape: &[usize]) -> PyJson {
                    match shape.split_first() {
                        None => PyJson::Float(v.first().copied().unwrap_or(0.0)),
                        Some((&n, rest)) => {
                            let inner: usize = rest.iter().product();
                            PyJson::List(
                                (0..n)
                                    .map(|i| nest(&v[i * inner..(i + 1) * inner], rest))
                                    .collect(),
                            )
                        }
                    }
                }
                PyJson::Obj(vec![
                    ("type".into(), PyJson::Str("Box".into())),
                    ("dtype".into(), PyJson::Str(dtype.numpy_name().into())),
                    (
                        "shape".into(),
                        PyJson::List(shape.iter().map(|&d| PyJson::Int(d as i128)).collect()),
                    ),
                    ("low".into(), nest(low, shape)),
                    ("high".into(), nest(high, shape)),
                ])
            }
            Space::Discrete { n, start } => PyJson::Obj(vec![
                ("type".into(), PyJson::Str("Discrete".into())),
                ("dtype".into(), PyJson::Str("int64".into())),
                ("start".into(), PyJson::Int(*start as i128)),
                ("n".into(), PyJson::Int(*n as i128)),
            ]),
            Space::Dict(items) => PyJson::Obj(vec![
                ("type".into(), PyJson::Str("Dict".into())),
                (
                    "subspaces".into(),
                    PyJson::Obj(items.iter().map(|(k, s)| (k.clone(), s.to_py())).collect()),
                ),
            ]),
            Space::Tuple(items) => PyJson::Obj(vec![
                ("type".into(), PyJson::Str("Tuple".into())),
                (
                    "subspaces".into(),
                    PyJson::List(items.iter().map(Space::to_py).collect()),
                ),
            ]),
            Space::Other(v) => json_to_py(v),
        }
    }

    /// The space as Minari writes it into `metadata.json`.
    pub fn to_json_string(&self) -> String {
        self.to_py().dump()
    }

    /// Parse the space string stored in `metadata.json`.
    pub fn parse(text: &str) -> Result<Space, String> {
        let v = parse_lenient(text).map_err(|e| format!("space is not JSON: {e}"))?;
        Space::from_value(&v)
    }

    fn from_value(v: &Value) -> Result<Space, String> {
        let ty = v
            .get("type")
            .and_then(Value::as_str)
            .ok_or("space without a \"type\"")?;
        match ty {
            "Box" => {
                let dtype_name = v
                    .get("dtype")
                    .and_then(Value::as_str)
                    .ok_or("Box without a dtype")?;
                let dtype = Dtype::from_numpy(dtype_name)
                    .ok_or_else(|| format!("Box dtype {dtype_name} is not supported"))?;
                let shape = v
                    .get("shape")
                    .and_then(Value::as_array)
                    .ok_or("Box without a shape")?
                    .iter()
                    .map(|d| {
                        d.as_u64()
                            .map(|d| d as usize)
                            .ok_or("Box shape entries must be integers")
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                let n: usize = shape.iter().product();
                let flat = |key: &str| -> Result<Vec<f64>, String> {
                    let mut out = vec![];
                    fn walk(v: &Value, out: &mut Vec<f64>) -> Result<(), String> {
                        match v {
                            Value::Array(a) => a.iter().try_for_each(|x| walk(x, out)),
                            x => number(x)
                                .map(|f| out.push(f))
                                .ok_or_else(|| format!("bound {x} is not a number")),
                        }
                    }
                    walk(
                        v.get(key).ok_or_else(|| format!("Box without {key}"))?,
                        &mut out,
                    )?;
                    if out.len() != n {
                        return Err(format!(
                            "Box {key} has {} values for shape {shape:?}",
                            out.len()
                        ));
                    }
                    Ok(out)
                };
                Ok(Space::Box {
                    dtype,
                    shape: shape.clone(),
                    low: flat("low")?,
                    high: flat("high")?,
                })
            }
            "Discrete" => Ok(Space::Discrete {
                n: v.get("n")
                    .and_then(Value::as_i64)
                    .ok_or("Discrete without n")?,
                start: v
                    .get("start")
                    .and_then(Value::as_i64)
                    .ok_or("Discrete without start")?,
            }),
            "Dict" => {
                let subs = v
                    .get("subspaces")
                    .and_then(Value::as_object)
                    .ok_or("Dict without subspaces")?;
                Ok(Space::Dict(
                    subs.iter()
                        .map(|(k, s)| Ok((k.clone(), Space::from_value(s)?)))
                        .collect::<Result<_, String>>()?,
                ))
            }
            "Tuple" => {
                let subs = v
                    .get("subspaces")
                    .and_then(Value::as_array)
                    .ok_or("Tuple without subspaces")?;
                Ok(Space::Tuple(
                    subs.iter()
                        .map(Space::from_value)
                        .collect::<Result<_, _>>()?,
                ))
            }
            _ => Ok(Space::Other(v.clone())),
        }
    }

    /// One-line description, e.g. `Box(float64, [105], -inf..inf)`.
    pub fn describe(&self) -> String {
        match self {
            Space::Box {
                dtype,
                shape,
                low,
                high,
            } => {
                let lo = low.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = high.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                format!("Box({}, {shape:?}, {lo}..{hi})", dtype.numpy_name())
            }
            Space::Discrete { n, start } => format!("Discrete({n}, start={start})"),
            Space::Dict(items) => {
                let parts: Vec<String> = items
                    .iter()
                    .map(|(k, s)| format!("{k}: {}", s.describe()))
                    .collect();
                format!("Dict({})", parts.join(", "))
            }
            Space::Tuple(items) => format!(
                "Tuple({})",
                items
                    .iter()
                    .map(Space::describe)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Space::Other(v) => v
                .get("type")
                .and_then(Value::as_str)
                .unwrap_or("unknown")
                .to_string(),
        }
    }
}

fn json_to_py(v: &Value) -> PyJson {
    match v {
        Value::Null => PyJson::Null,
        Value::Bool(b) => PyJson::Bool(*b),
        Value::Number(n) => match n.as_i64() {
            Some(i) => PyJson::Int(i as i128),
            None => PyJson::Float(n.as_f64().unwrap_or(f64::NAN)),
        },
        Value::String(s) => match number(v) {
            Some(x) if s.starts_with('\u{0}') => PyJson::Float(x),
            _ => PyJson::Str(s.clone()),
        },
        Value::Array(a) => PyJson::List(a.iter().map(json_to_py).collect()),
        Value::Object(o) => {
            PyJson::Obj(o.iter().map(|(k, v)| (k.clone(), json_to_py(v))).collect())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_text_is_minaris() {
        let obs = Space::box1(Dtype::F64, &[f64::NEG_INFINITY; 2], &[f64::INFINITY; 2]);
        assert_eq!(
            obs.to_json_string(),
            r#"{"type": "Box", "dtype": "float64", "shape": [2], "low": [-Infinity, -Infinity], "high": [Infinity, Infinity]}"#
        );
        let act = Space::box1(Dtype::F32, &[-3.0], &[3.0]);
        assert_eq!(
            act.to_json_string(),
            r#"{"type": "Box", "dtype": "float32", "shape": [1], "low": [-3.0], "high": [3.0]}"#
        );
        assert_eq!(Space::parse(&obs.to_json_string()).unwrap(), obs);
        let nested = Space::Box {
            dtype: Dtype::U8,
            shape: vec![2, 3],
            low: vec![0.0; 6],
            high: vec![255.0; 6],
        };
        assert!(
            nested
                .to_json_string()
                .contains("[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]")
        );
        assert_eq!(Space::parse(&nested.to_json_string()).unwrap(), nested);
    }
}
