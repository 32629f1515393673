//! Parameters: typed values with defaults from the spec, overridable at construction
//! (`Override::parse("healthy_z_range=[0.3, 1.0]")`, the typed builder, the CLI's `--set`).
//! Overrides are validated like the spec itself.

use std::fmt;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::syntax::{ParamDecl, Spec};
use crate::value::{Val, ValKind, format_float, parse_literal};

pub mod render;

/// A parameter's declared `type`, which decides how overrides are parsed and checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// `true` or `false`.
    Bool,
    /// An integer.
    Int,
    /// A float (an integer literal is accepted).
    Float,
    /// A pair `[low, high]` of floats (either may be `inf`).
    Range,
    /// Free text.
    String,
    /// A file path; relative paths in the spec resolve against the spec's directory, relative
    /// paths in overrides against the current directory.
    Path,
    /// A body, by id (integer) or name (string).
    Body,
    /// An opaque table (e.g. viewer camera settings).
    Table,
    /// A list of names (strings), e.g. the parts of a checklist goal in play.
    Names,
}

impl ParamType {
    /// The `type` a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            ParamType::Bool => "bool",
            ParamType::Int => "int",
            ParamType::Float => "float",
            ParamType::Range => "range",
            ParamType::String => "string",
            ParamType::Path => "path",
            ParamType::Body => "body",
            ParamType::Table => "table",
            ParamType::Names => "names",
        }
    }
    fn from_name(s: &str) -> ParamType {
        match s {
            "bool" => ParamType::Bool,
            "int" => ParamType::Int,
            "range" => ParamType::Range,
            "string" => ParamType::String,
            "path" => ParamType::Path,
            "body" => ParamType::Body,
            "table" => ParamType::Table,
            "names" => ParamType::Names,
            _ => ParamType::Float,
        }
    }
    fn expected(self) -> &'static str {
        match self {
            ParamType::Bool => "true or false",
            ParamType::Int => "an integer",
            ParamType::Float => "a number",
            ParamType::Range => "a range [low, high]",
            ParamType::String => "a string",
            ParamType::Path => "a file path",
            ParamType::Body => "a body id (integer) or name (string)",
            ParamType::Table => "a table",
            ParamType::Names => "a list of names, e.g. [\"a\", \"b\"]",
        }
    }
}

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    /// A boolean.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// `[low, high]`.
    Range(f64, f64),
    /// A string, path or body name.
    Str(String),
    /// A table, kept as its TOML text.
    Table(String),
    /// A list of names.
    Names(Vec<String>),
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Bool(b) => write!(f, "{b}"),
            ParamValue::Int(i) => write!(f, "{i}"),
            ParamValue::Float(x) => f.write_str(&format_float(*x)),
            ParamValue::Range(a, b) => write!(f, "[{}, {}]", format_float(*a), format_float(*b)),
            ParamValue::Str(s) => write!(f, "{s:?}"),
            ParamValue::Table(t) => f.write_str(t),
            ParamValue::Names(n) => {
                let quoted: Vec<String> = n.iter().map(|s| format!("{s:?}")).collect();
                write!(f, "[{}]", quoted.join(", "))
            }
        }
    }
}

/// Where a parameter's value came from.
#[derive(Clone, Debug)]
pub enum Origin {
    /// The spec's default, where it is written.
    Default(Location),
    /// An override, as the user gave it (e.g. `ctrl_cost_weight=0.1`).
    Override(String),
}

/// A parameter with its final value.
#[derive(Clone, Debug)]
pub struct Param {
    /// The name constructors and overrides use, e.g. `ctrl_cost_weight`.
    pub name: String,
    /// The declared type.
    pub ty: ParamType,
    /// The value in effect: the default, or the last override of it.
    pub value: ParamValue,
    /// The spec's default.
    pub default: ParamValue,
    /// The spec's `doc` text (generated docs and `envc show` print it).
    pub doc: String,
    /// Where `value` came from.
    pub origin: Origin,
    /// Part of the spec but not a constructor argument: overrides are refused.
    pub fixed: bool,
}

/// A request to change a parameter.
#[derive(Clone, Debug)]
pub struct Override {
    /// The parameter it sets.
    pub name: String,
    /// The value it sets.
    pub value: OverrideValue,
}

/// An override's value: text to parse, or a value already typed.
#[derive(Clone, Debug)]
pub enum OverrideValue {
    /// TOML literal text, e.g. `[0.3, 1.0]`, `false`, `"torso"`. Bare words are taken as strings
    /// for string, path and body parameters.
    Text(String),
    /// A value already typed, checked against the parameter's type.
    Value(ParamValue),
}

impl Override {
    /// `name=value` as given on a command line.
    pub fn parse(s: &str) -> Result<Override, Diagnostic> {
        match s.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => Ok(Override::text(k.trim(), v.trim())),
            _ => Err(Diagnostic::new(
                Code::E0202,
                format!("override `{s}` is not of the form name=value"),
            )
            .label("expected name=value, e.g. ctrl_cost_weight=0.1")),
        }
    }
    /// An override of `name` with TOML text, parsed against the parameter's type.
    pub fn text(name: &str, value: &str) -> Override {
        Override {
            name: name.to_string(),
            value: OverrideValue::Text(value.to_string()),
        }
    }
    /// An override of `name` with a typed value (from code, e.g. the Python kwargs).
    pub fn value(name: &str, value: ParamValue) -> Override {
        Override {
            name: name.to_string(),
            value: OverrideValue::Value(value),
        }
    }
}

/// Infer the type of a declared parameter.
pub fn decl_type(p: &ParamDecl) -> ParamType {
    // The required parameters have fixed types; a conflicting `type` makes the default fail to
    // convert (E0102) instead of reaching the resolver with a value it cannot use.
    match p.name.as_str() {
        "xml_file" => return ParamType::Path,
        "frame_skip" | "max_episode_steps" => return ParamType::Int,
        _ => {}
    }
    if let Some((t, _)) = &p.ty {
        return ParamType::from_name(t);
    }
    match &p.default.kind {
        ValKind::Bool(_) => ParamType::Bool,
        ValKind::Int(_) => ParamType::Int,
        ValKind::Float(_) => ParamType::Float,
        ValKind::Str(_) => ParamType::String,
        ValKind::Array(a) if a.first().is_some_and(|v| matches!(v.kind, ValKind::Str(_))) => {
            ParamType::Names
        }
        ValKind::Array(_) => ParamType::Range,
        ValKind::Table(_) => ParamType::Table,
    }
}

/// Convert a written value to a parameter type.
pub fn convert(v: &Val, ty: ParamType) -> Option<ParamValue> {
    match (ty, &v.kind) {
        (ParamType::Bool, ValKind::Bool(b)) => Some(ParamValue::Bool(*b)),
        (ParamType::Int, ValKind::Int(i)) => Some(ParamValue::Int(*i)),
        (ParamType::Float, ValKind::Int(i)) => Some(ParamValue::Float(*i as f64)),
        (ParamType::Float, ValKind::Float(x)) => Some(ParamValue::Float(*x)),
        (ParamType::Range, ValKind::Array(a)) if a.len() == 2 => {
            Some(ParamValue::Range(a[0].as_f64()?, a[1].as_f64()?))
        }
        (ParamType::String | ParamType::Path, ValKind::Str(s)) => Some(ParamValue::Str(s.clone())),
        (ParamType::Body, ValKind::Int(i)) => Some(ParamValue::Int(*i)),
        (ParamType::Body, ValKind::Str(s)) => Some(ParamValue::Str(s.clone())),
        (ParamType::Table, ValKind::Table(_)) => Some(ParamValue::Table(v.to_toml())),
        (ParamType::Names, ValKind::Array(a)) => Some(ParamValue::Names(
            a.iter()
                .map(|x| match &x.kind {
                    ValKind::Str(s) => Some(s.clone()),
                    _ => None,
                })
                .collect::<Option<Vec<_>>>()?,
        )),
        _ => None,
    }
}

fn type_ok(value: &ParamValue, ty: ParamType) -> bool {
    matches!(
        (ty, value),
        (ParamType::Bool, ParamValue::Bool(_))
            | (ParamType::Int, ParamValue::Int(_))
            | (ParamType::Float, ParamValue::Float(_))
            | (ParamType::Range, ParamValue::Range(..))
            | (ParamType::String | ParamType::Path, ParamValue::Str(_))
            | (ParamType::Body, ParamValue::Int(_) | ParamValue::Str(_))
            | (ParamType::Table, ParamValue::Table(_))
            | (ParamType::Names, ParamValue::Names(_))
    )
}

/// NaN is never a meaningful parameter value: every comparison with it is false, so a NaN
/// range or weight silently switches a check or a term off.
fn has_nan(v: &ParamValue) -> bool {
    match v {
        ParamValue::Float(x) => x.is_nan(),
        ParamValue::Range(a, b) => a.is_nan() || b.is_nan(),
        _ => false,
    }
}

/// Defaults from the spec, then the overrides, each checked. All problems are reported together.
pub fn resolve_params(spec: &Spec, overrides: &[Override]) -> Result<Vec<Param>, Diagnostics> {
    let mut d = Diagnostics::default();
    let mut params = defaults(spec, &mut d);
    // Gymnasium's rendering arguments, which every task spec has.
    render::add_render_params(spec, &mut params);
    for (i, o) in overrides.iter().enumerate() {
        if overrides[..i].iter().any(|earlier| earlier.name == o.name) {
            d.push(
                Diagnostic::new(
                    Code::E0205,
                    format!("parameter `{}` is overridden more than once", o.name),
                )
                .label("expected each parameter at most once")
                .help("keep the one value you mean; envc does not let the last one win silently"),
            );
            continue;
        }
        apply_override(spec, o, &mut params, &mut d);
    }
    d.into_result(params)
}

/// The parameters the spec declares, at their defaults (a default of the wrong type, or NaN,
/// is reported and leaves its parameter out).
fn defaults(spec: &Spec, d: &mut Diagnostics) -> Vec<Param> {
    let mut params = vec![];
    for p in &spec.params {
        let ty = decl_type(p);
        match convert(&p.default, ty) {
            Some(value) if has_nan(&value) => d.push(
                Diagnostic::new(
                    Code::E0105,
                    format!("default of parameter `{}` is NaN", p.name),
                )
                .at(p.default.loc.clone())
                .label("expected a number (NaN compares false with everything)"),
            ),
            Some(value) => params.push(Param {
                name: p.name.clone(),
                ty,
                default: value.clone(),
                value,
                doc: p.doc.clone(),
                origin: Origin::Default(p.default.loc.clone()),
                fixed: p.fixed,
            }),
            None => d.push(
                Diagnostic::new(
                    Code::E0102,
                    format!("default of parameter `{}` is not {}", p.name, ty.expected()),
                )
                .at(p.default.loc.clone())
                .label(format!("expected {} (type {})", ty.expected(), ty.name())),
            ),
        }
    }
    params
}

/// Set the parameter `o` names to its value: unless it names none, a fixed one, or gives a value
/// of the wrong type (each reported).
fn apply_override(spec: &Spec, o: &Override, params: &mut [Param], d: &mut Diagnostics) {
    let Some(param) = params.iter_mut().find(|p| p.name == o.name) else {
        d.push(
            Diagnostic::new(
                Code::E0202,
                format!("unknown parameter `{}` for {}", o.name, spec.id),
            )
            .label(format!(
                "expected one of: {}",
                spec.params
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
            .help_opt(suggest(
                &o.name,
                spec.params.iter().map(|p| p.name.as_str()),
            )),
        );
        return;
    };
    if param.fixed {
        d.push(
            Diagnostic::new(
                Code::E0204,
                format!(
                    "parameter `{}` is fixed in {}: it is not a constructor argument",
                    o.name, spec.id
                ),
            )
            .label(format!("its value is {}", param.default))
            .help("copy the spec and change the value there (or remove `fixed = true`)"),
        );
        return;
    }
    let (value, loc) = override_value(o, param);
    match value {
        Some(v) if has_nan(&v) => d.push(
            Diagnostic::new(Code::E0105, format!("override of `{}` is NaN", o.name))
                .at_opt(loc)
                .label(format!(
                    "expected a number; the default is {}",
                    param.default
                )),
        ),
        Some(v) => {
            param.value = v;
            param.origin = Origin::Override(o.name.clone());
        }
        None => d.push(
            Diagnostic::new(
                Code::E0203,
                format!(
                    "override of `{}` is not {} (type {})",
                    o.name,
                    param.ty.expected(),
                    param.ty.name()
                ),
            )
            .at_opt(loc)
            .label(format!(
                "expected {}; the default is {}",
                param.ty.expected(),
                param.default
            )),
        ),
    }
}

/// An override's value converted to its parameter's type (None: it does not convert), and the
/// location of its text (None for a value given as a value).
fn override_value(o: &Override, param: &Param) -> (Option<ParamValue>, Option<Location>) {
    match &o.value {
        OverrideValue::Value(v) => {
            // Integers are acceptable floats.
            let v = match (param.ty, v) {
                (ParamType::Float, ParamValue::Int(i)) => ParamValue::Float(*i as f64),
                _ => v.clone(),
            };
            (type_ok(&v, param.ty).then_some(v), None)
        }
        OverrideValue::Text(text) => {
            let file = SourceFile::new(format!("<override {}>", o.name), text.clone());
            let loc = Location::new(&file, 0..text.len());
            let parsed = parse_literal(&file);
            let v = match (&parsed, param.ty) {
                (Some(v), ty) => convert(v, ty),
                (None, ParamType::String | ParamType::Path | ParamType::Body) => {
                    Some(ParamValue::Str(text.clone()))
                }
                (None, _) => None,
            };
            (v, Some(loc))
        }
    }
}
