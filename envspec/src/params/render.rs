//! The rendering parameters every task spec has (Gymnasium's `MujocoEnv` arguments), declared
//! here (overridable as any other) and read by [`crate::camera`].

use crate::diagnostic::Location;
use crate::params::{Origin, Param, ParamType, ParamValue};
use crate::syntax::Spec;

/// The rendering parameters every task spec has: name, type, default, doc.
pub const RENDER_PARAMS: &[(&str, ParamType, &str, &str)] = &[
    (
        "width",
        ParamType::Int,
        "480",
        "Rendered frame width in pixels.",
    ),
    (
        "height",
        ParamType::Int,
        "480",
        "Rendered frame height in pixels.",
    ),
    (
        "camera_id",
        ParamType::Int,
        "-1",
        "Model camera to render from (-1: the free viewer camera of default_camera_config).",
    ),
    (
        "camera_name",
        ParamType::String,
        "\"\"",
        "Model camera to render from, by name (empty: none).",
    ),
    (
        "max_geom",
        ParamType::Int,
        "1000",
        "Most geoms in a rendered scene.",
    ),
    (
        "visual_options",
        ParamType::Table,
        "{}",
        "mjvOption flags, e.g. { contactpoint = true } (names of mjtVisFlag without mjVIS_, or their numbers).",
    ),
];

/// Append the rendering parameters the spec does not declare itself (called by
/// `params::resolve_params` before the overrides are applied, so they are overridable).
pub fn add_render_params(spec: &Spec, params: &mut Vec<Param>) {
    for (name, ty, default, doc) in RENDER_PARAMS {
        if params.iter().any(|p| p.name == *name) {
            continue;
        }
        let value = match ty {
            ParamType::Int => ParamValue::Int(default.parse().unwrap_or(0)),
            ParamType::String => ParamValue::Str(String::new()),
            _ => ParamValue::Table(default.to_string()),
        };
        params.push(Param {
            name: name.to_string(),
            ty: *ty,
            default: value.clone(),
            value,
            doc: doc.to_string(),
            // Implicit: there is no text to point at, so the location is the spec's first byte.
            origin: Origin::Default(Location::new(&spec.file, 0..0)),
            fixed: false,
        });
    }
}
