//! Rendering settings as spec data: Gymnasium's `MujocoEnv` rendering arguments (`width`,
//! `height`, `camera_id`, `camera_name`, `max_geom`, `visual_options`) are parameters every task
//! spec has (a spec may declare them itself to change a default), and `default_camera_config` is
//! read here into the viewer camera. Names (cameras, bodies) are kept with their location and
//! looked up in the compiled model by the runtime, which reports E1503 at that location.

use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile};
use crate::params::{Origin, Param, ParamValue};
use crate::value::{Entry, Val, ValKind, parse_literal};

/// A model object named by id or by name.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjRef {
    /// By its index in the model (`camera_id`, `trackbodyid`).
    Id(i64),
    /// By its name in the model (`camera_name`).
    Name(String),
}

/// A value and where it was written (none for an override given in code).
#[derive(Clone, Debug)]
pub struct Located<T> {
    /// The value.
    pub value: T,
    /// Where it was written; None for a default or an override given in code.
    pub loc: Option<Location>,
    /// The parameter it came from, for messages without a location.
    pub param: &'static str,
}

/// Values of `default_camera_config`, applied to the viewer camera in the order written, as
/// Gymnasium's `setattr` loop does.
#[derive(Clone, Debug)]
pub enum CameraKey {
    /// `type`: 0 free, 1 tracking, 2 fixed (or "free", "tracking", "fixed").
    Type(i32),
    /// `fixedcamid`: the camera a fixed view looks through.
    FixedCam(Located<ObjRef>),
    /// `trackbodyid`: the body a tracking view follows.
    TrackBody(Located<ObjRef>),
    /// `lookat`: the point the camera looks at.
    Lookat([f64; 3]),
    /// `distance` from the look-at point.
    Distance(f64),
    /// `azimuth` in degrees.
    Azimuth(f64),
    /// `elevation` in degrees.
    Elevation(f64),
    /// `orthographic`: 1 for an orthographic projection.
    Orthographic(i32),
}

/// Everything the runtime needs to render a task env.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Capacity of the scene's geom buffer (`mjv_makeScene`).
    pub max_geom: u32,
    /// `camera_id` or `camera_name`; None: the free viewer camera.
    pub camera: Option<Located<ObjRef>>,
    /// `default_camera_config`, applied in order to the free camera.
    pub camera_config: Vec<CameraKey>,
    /// `(mjtVisFlag, on)` in the order written.
    pub visual_options: Vec<(usize, bool)>,
    /// `(geom group 0..5, shown)`: `geomgroup_N` keys of `visual_options` (an envc extension;
    /// e.g. a model whose only geoms are collision geoms in group 3).
    pub geom_groups: Vec<(usize, bool)>,
}

/// mjtVisFlag names (MuJoCo 3.17), index = flag.
pub const VIS_FLAGS: &[&str] = &[
    "convexhull",
    "texture",
    "joint",
    "camera",
    "actuator",
    "activation",
    "light",
    "tendon",
    "rangefinder",
    "constraint",
    "inertia",
    "sclinertia",
    "pertforce",
    "pertobj",
    "contactpoint",
    "island",
    "contactforce",
    "contactsplit",
    "transparent",
    "autoconnect",
    "com",
    "select",
    "static",
    "skin",
    "flexvert",
    "flexedge",
    "flexface",
    "flexskin",
    "bodybvh",
    "meshbvh",
    "sdfiter",
];

const CAMERA_KEYS: &[&str] = &[
    "type",
    "fixedcamid",
    "trackbodyid",
    "lookat",
    "distance",
    "azimuth",
    "elevation",
    "orthographic",
];

fn param<'a>(params: &'a [Param], name: &str) -> Option<&'a Param> {
    params.iter().find(|p| p.name == name)
}

fn origin_loc(p: &Param) -> Option<Location> {
    match &p.origin {
        Origin::Default(l) if !l.span.is_empty() => Some(l.clone()),
        _ => None,
    }
}

/// Parse a table parameter's TOML text with locations in the spec file when the value is the
/// spec's default, or in the override text otherwise.
fn table_of(p: &Param, d: &mut Diagnostics) -> Option<Val> {
    let ParamValue::Table(text) = &p.value else {
        return None;
    };
    let (file, shift) = match &p.origin {
        Origin::Default(l) if !l.span.is_empty() => (Arc::clone(&l.file), l.span.start),
        _ => (
            SourceFile::new(format!("<override {}>", p.name), text.clone()),
            0,
        ),
    };
    let own = SourceFile::new(file.path.clone(), text.clone());
    let Some(v) = parse_literal(&own) else {
        d.push(Diagnostic::new(
            Code::E1505,
            format!("`{}` is not a TOML table", p.name),
        ));
        return None;
    };
    // Map the locations back into the spec file (the default's text is a slice of it).
    fn shift_locs(v: &mut Val, file: &Arc<SourceFile>, by: usize) {
        v.loc = Location::new(file, v.loc.span.start + by..v.loc.span.end + by);
        match &mut v.kind {
            ValKind::Array(a) => a.iter_mut().for_each(|x| shift_locs(x, file, by)),
            ValKind::Table(t) => t.iter_mut().for_each(|e| {
                e.key_loc = Location::new(file, e.key_loc.span.start + by..e.key_loc.span.end + by);
                shift_locs(&mut e.value, file, by)
            }),
            _ => {}
        }
    }
    let mut v = v;
    let same_text = file.text.get(shift..shift + text.len()) == Some(text.as_str());
    shift_locs(
        &mut v,
        if same_text { &file } else { &own },
        if same_text { shift } else { 0 },
    );
    Some(v)
}

fn int_param(params: &[Param], name: &str, min: i64, max: i64, d: &mut Diagnostics) -> i64 {
    let Some(p) = param(params, name) else {
        return 0;
    };
    let ParamValue::Int(v) = p.value else {
        return 0;
    };
    if v < min || v > max {
        d.push(
            Diagnostic::new(Code::E1505, format!("`{name}` is {v}"))
                .at_opt(origin_loc(p))
                .label(format!("expected an integer from {min} to {max}")),
        );
    }
    v
}

fn obj_ref(
    v: &Val,
    param: &'static str,
    what: &str,
    d: &mut Diagnostics,
) -> Option<Located<ObjRef>> {
    let value = match &v.kind {
        ValKind::Int(i) => ObjRef::Id(*i),
        ValKind::Str(s) => ObjRef::Name(s.clone()),
        _ => {
            d.push(
                v.type_error(what, "an id (integer) or a name (string)")
                    .with_code(Code::E1505),
            );
            return None;
        }
    };
    Some(Located {
        value,
        loc: Some(v.loc.clone()),
        param,
    })
}

impl RenderSettings {
    /// Read the rendering settings from a resolved parameter table. Problems are E1505, each
    /// at its location; names are checked against the model by the runtime (E1503).
    pub fn from_params(params: &[Param]) -> Result<RenderSettings, Diagnostics> {
        let mut d = Diagnostics::default();
        let width = int_param(params, "width", 1, 16384, &mut d) as u32;
        let height = int_param(params, "height", 1, 16384, &mut d) as u32;
        let max_geom = int_param(params, "max_geom", 1, 1 << 24, &mut d) as u32;
        let id = int_param(params, "camera_id", -1, i32::MAX as i64, &mut d);
        let camera = camera(params, id, &mut d);
        let camera_config = camera_config(params, &mut d);
        let (visual_options, geom_groups) = visual_options(params, &mut d);
        d.into_result(RenderSettings {
            width,
            height,
            max_geom,
            camera,
            camera_config,
            visual_options,
            geom_groups,
        })
    }
}

/// The model camera to render from: `camera_id` (`id`, already read) or `camera_name`, not both.
fn camera(params: &[Param], id: i64, d: &mut Diagnostics) -> Option<Located<ObjRef>> {
    let name = param(params, "camera_name").and_then(|p| match &p.value {
        ParamValue::Str(s) if !s.is_empty() => Some((s.clone(), p)),
        _ => None,
    });
    let id_param = param(params, "camera_id");
    match (id, name) {
        (-1, None) => None,
        (-1, Some((n, p))) => Some(Located {
            value: ObjRef::Name(n),
            loc: origin_loc(p),
            param: "camera_name",
        }),
        (i, None) => Some(Located {
            value: ObjRef::Id(i),
            loc: id_param.and_then(origin_loc),
            param: "camera_id",
        }),
        (_, Some((_, p))) => {
            // Gymnasium: "Both `camera_id` and `camera_name` cannot be specified at the same time."
            d.push(
                Diagnostic::new(Code::E1505, "both `camera_id` and `camera_name` are set")
                    .at_opt(origin_loc(p))
                    .label("expected one of them (camera_id = -1 or camera_name = \"\")"),
            );
            None
        }
    }
}

/// `default_camera_config`: the viewer camera's attributes, in the order written.
fn camera_config(params: &[Param], d: &mut Diagnostics) -> Vec<CameraKey> {
    let mut camera_config = vec![];
    if let Some(p) = param(params, "default_camera_config")
        && let Some(t) = table_of(p, d)
    {
        for e in t.as_table().unwrap_or(&[]) {
            camera_config.extend(camera_key(e, d));
        }
    }
    camera_config
}

/// One `default_camera_config` entry (None: reported).
fn camera_key(e: &Entry, d: &mut Diagnostics) -> Option<CameraKey> {
    let v = &e.value;
    let num = |d: &mut Diagnostics| {
        v.as_f64().or_else(|| {
            d.push(v.type_error(&e.key, "a number").with_code(Code::E1505));
            None
        })
    };
    match e.key.as_str() {
        "type" => match &v.kind {
            ValKind::Int(i @ 0..=2) => Some(CameraKey::Type(*i as i32)),
            ValKind::Str(s) => match s.as_str() {
                "free" => Some(CameraKey::Type(0)),
                "tracking" => Some(CameraKey::Type(1)),
                "fixed" => Some(CameraKey::Type(2)),
                _ => None,
            },
            _ => None,
        }
        .or_else(|| {
            d.push(
                Diagnostic::new(Code::E1505, "unknown camera `type`")
                    .at(v.loc.clone())
                    .label("expected \"free\", \"tracking\", \"fixed\" or 0, 1, 2"),
            );
            None
        }),
        "fixedcamid" => {
            obj_ref(v, "default_camera_config", "fixedcamid", d).map(CameraKey::FixedCam)
        }
        "trackbodyid" => {
            obj_ref(v, "default_camera_config", "trackbodyid", d).map(CameraKey::TrackBody)
        }
        "lookat" => match &v.kind {
            ValKind::Array(a) if a.len() == 3 && a.iter().all(|x| x.as_f64().is_some()) => {
                let x: Vec<f64> = a.iter().filter_map(Val::as_f64).collect();
                Some(CameraKey::Lookat([x[0], x[1], x[2]]))
            }
            _ => {
                d.push(
                    v.type_error("lookat", "an array of 3 numbers")
                        .with_code(Code::E1505),
                );
                None
            }
        },
        "distance" => num(d).map(CameraKey::Distance),
        "azimuth" => num(d).map(CameraKey::Azimuth),
        "elevation" => num(d).map(CameraKey::Elevation),
        "orthographic" => match v.kind {
            ValKind::Bool(b) => Some(CameraKey::Orthographic(b as i32)),
            ValKind::Int(i) => Some(CameraKey::Orthographic((i != 0) as i32)),
            _ => {
                d.push(
                    v.type_error("orthographic", "true or false")
                        .with_code(Code::E1505),
                );
                None
            }
        },
        other => {
            d.push(
                Diagnostic::new(
                    Code::E1505,
                    format!("`{other}` is not a viewer camera attribute"),
                )
                .at(e.key_loc.clone())
                .label(format!("expected one of: {}", CAMERA_KEYS.join(", ")))
                .help_opt(crate::diagnostic::suggest(
                    other,
                    CAMERA_KEYS.iter().copied(),
                )),
            );
            None
        }
    }
}

/// `(index, on)` pairs in the order written: mjtVisFlag numbers, or geom groups.
type Switches = Vec<(usize, bool)>;

/// `visual_options`: mjtVisFlag switches, and `geomgroup_N` switches, each in the order written.
fn visual_options(params: &[Param], d: &mut Diagnostics) -> (Switches, Switches) {
    let mut visual_options = vec![];
    let mut geom_groups = vec![];
    if let Some(p) = param(params, "visual_options")
        && let Some(t) = table_of(p, d)
    {
        for e in t.as_table().unwrap_or(&[]) {
            let group = e
                .key
                .strip_prefix("geomgroup_")
                .and_then(|g| g.parse::<usize>().ok())
                .filter(|&g| g < 6);
            if let (Some(g), ValKind::Bool(on)) = (group, &e.value.kind) {
                geom_groups.push((g, *on));
                continue;
            }
            let flag = VIS_FLAGS
                .iter()
                .position(|f| f.eq_ignore_ascii_case(e.key.trim_start_matches("mjVIS_")))
                .or_else(|| e.key.parse::<usize>().ok().filter(|&i| i < VIS_FLAGS.len()));
            let on = match e.value.kind {
                ValKind::Bool(b) => Some(b),
                ValKind::Int(i) => Some(i != 0),
                _ => None,
            };
            match (flag, on) {
                    (Some(f), Some(on)) => visual_options.push((f, on)),
                    (None, _) => d.push(
                        Diagnostic::new(Code::E1505, format!("`{}` is not a visual option", e.key))
                            .at(e.key_loc.clone())
                            .label("expected an mjtVisFlag name without mjVIS_ (e.g. contactpoint), its number, or geomgroup_0 … geomgroup_5")
                            .help_opt(crate::diagnostic::suggest(&e.key, VIS_FLAGS.iter().copied())),
                    ),
                    (_, None) => d.push(e.value.type_error(&e.key, "true or false").with_code(Code::E1505)),
                }
        }
    }
    (visual_options, geom_groups)
}

trait WithCode {
    fn with_code(self, code: Code) -> Self;
}

impl WithCode for Diagnostic {
    fn with_code(mut self, code: Code) -> Self {
        self.code = code;
        self
    }
}
