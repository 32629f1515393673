//! `[bodies]`, `[sites]`, `[geoms]`, `[cameras]`, `[lights]`: elements a spec adds to the model
//! (a target to reach on an arm whose model has none, a fingertip site on a URDF link, a camera).
//! Resolved with the other model edits, then folded into the `ModelInfo`, so selectors
//! (`xpos[target]`, `qpos[target_x]`, `site_xpos[tip]`) see them.

use crate::diagnostic::{Code, Diagnostic};
use crate::ir::{AddedElement, AddedGeomType};
use crate::mjcf::{Joint, JointKind, ModelInfo};
use crate::syntax::{AddedKind, Section};
use crate::value::{Entry, Val, ValKind};

use super::Ctx;

const AXES: [(&str, [f64; 3]); 3] = [
    ("x", [1., 0., 0.]),
    ("y", [0., 1., 0.]),
    ("z", [0., 0., 1.]),
];

impl Ctx<'_> {
    pub(super) fn added_elements(&mut self) -> Vec<AddedElement> {
        let spec = self.spec;
        let mut out: Vec<AddedElement> = vec![];
        let mut nbody = self.model.nbody();
        for (kind, s) in &spec.added {
            if *kind == AddedKind::Body {
                nbody += 1;
                if nbody > crate::limits::MAX_BODIES {
                    self.d.push(
                        crate::limits::too_many_bodies(&format!("[bodies.{}]", s.name))
                            .at(s.name_loc.clone()),
                    );
                    break;
                }
            }
            if let Some(e) = self.added(*kind, s, &out) {
                out.push(e);
            }
        }
        out
    }

    fn vec_n<const N: usize>(
        &mut self,
        s: &Section,
        key: &str,
        default: [f64; N],
    ) -> Option<[f64; N]> {
        let Some(v) = s.get(key) else {
            return Some(default);
        };
        match &v.kind {
            ValKind::Array(a) if a.len() == N => {
                let mut out = [0.0; N];
                for (o, x) in out.iter_mut().zip(a) {
                    *o = self.num(x, key)?;
                }
                Some(out)
            }
            _ => {
                self.d
                    .push(v.type_error(key, &format!("an array of {N} numbers")));
                None
            }
        }
    }

    /// An optional positive number within envc's magnitude limit (`Some(None)` when absent;
    /// `None` after an error).
    fn optional_positive(&mut self, s: &Section, key: &str) -> Option<Option<f64>> {
        let Some(v) = s.get(key) else {
            return Some(None);
        };
        let x = self.num(v, key)?;
        if x <= 0.0 {
            self.d.push(
                Diagnostic::new(Code::E0105, format!("{key} {x} is not positive"))
                    .at(v.loc.clone())
                    .label("expected a number > 0"),
            );
            return None;
        }
        Some(Some(self.within(
            v,
            x,
            key,
            crate::limits::MAX_MAGNITUDE,
        )?))
    }

    fn rgba(&mut self, s: &Section, default: [f32; 4]) -> Option<[f32; 4]> {
        let v = self.vec_n(s, "rgba", default.map(f64::from))?;
        Some(v.map(|x| x as f32))
    }

    /// The body an element attaches to: the world, a body of the model, or one added before.
    fn parent(&mut self, s: &Section, added: &[AddedElement]) -> Option<String> {
        match s.get("body") {
            None => Some("world".into()),
            Some(v) => self.body_named(v, "body", added),
        }
    }

    /// A body of the model, one added above, or `world`, named by the value of `key`.
    fn body_named(&mut self, v: &Val, key: &str, added: &[AddedElement]) -> Option<String> {
        let Some(name) = v.as_str() else {
            self.d.push(v.type_error(key, "a body name"));
            return None;
        };
        let added_body = added
            .iter()
            .any(|e| matches!(e, AddedElement::Body { name: n, .. } if n == name));
        if name == "world" || self.model.body_id(name).is_some() || added_body {
            return Some(name.to_string());
        }
        self.d.push(
            Diagnostic::new(Code::E0303, format!("the model has no body named `{name}`"))
                .at(v.loc.clone())
                .label("expected a body of the model, one added by [bodies], or `world`")
                .help_opt(crate::diagnostic::suggest(
                    name,
                    self.model.bodies.iter().map(String::as_str),
                )),
        );
        None
    }

    fn geom_type(&mut self, v: Option<&Val>, default: AddedGeomType) -> Option<AddedGeomType> {
        let Some(v) = v else { return Some(default) };
        let t = v.as_str().and_then(AddedGeomType::parse);
        if t.is_none() {
            self.d.push(
                Diagnostic::new(Code::E0104, "unknown geom type")
                    .at(v.loc.clone())
                    .label(format!(
                        "expected one of: {}",
                        AddedGeomType::NAMES.join(", ")
                    )),
            );
        }
        t
    }

    fn added(
        &mut self,
        kind: AddedKind,
        s: &Section,
        added: &[AddedElement],
    ) -> Option<AddedElement> {
        let name = s.name.clone();
        if name.contains('\0') {
            self.d.push(nul_in_name(
                &format!("{kind:?}").to_lowercase(),
                s.name_loc.clone(),
            ));
            return None;
        }
        let taken = match kind {
            AddedKind::Body => self.model.body_id(&name).is_some(),
            AddedKind::Site => self.model.sites.contains(&name),
            _ => false,
        };
        if taken {
            self.d.push(
                Diagnostic::new(
                    Code::E0106,
                    format!("the model already has a {kind:?} named `{name}`").to_lowercase(),
                )
                .at(s.name_loc.clone())
                .label("expected a new name"),
            );
            return None;
        }
        Some(match kind {
            AddedKind::Body => self.added_body(s, name, added)?,
            AddedKind::Site => AddedElement::Site {
                body: self.parent(s, added)?,
                pos: self.vec_n(s, "pos", [0.0; 3])?,
                size: match s.get("size") {
                    Some(v) => self.num(v, "size")?,
                    None => 0.01,
                },
                rgba: self.rgba(s, [0.5, 0.5, 0.5, 1.0])?,
                name,
            },
            AddedKind::Geom => {
                let kind = self.geom_type(s.get("type"), AddedGeomType::Sphere)?;
                // A plane's default draws infinitely, with a 1 m grid.
                let size = if kind == AddedGeomType::Plane {
                    [0.0, 0.0, 1.0]
                } else {
                    [0.02; 3]
                };
                AddedElement::Geom {
                    body: self.parent(s, added)?,
                    kind,
                    pos: self.vec_n(s, "pos", [0.0; 3])?,
                    size: self.vec_n(s, "size", size)?,
                    rgba: self.rgba(s, [0.5, 0.5, 0.5, 1.0])?,
                    contact: match s.get("contact") {
                        None => true,
                        Some(v) => match &v.kind {
                            ValKind::Bool(b) => *b,
                            _ => {
                                self.d.push(v.type_error("contact", "true or false"));
                                return None;
                            }
                        },
                    },
                    mass: self.optional_positive(s, "mass")?,
                    density: self.optional_positive(s, "density")?,
                    name,
                }
            }
            AddedKind::Camera => AddedElement::Camera {
                body: self.parent(s, added)?,
                pos: self.vec_n(s, "pos", [0.0; 3])?,
                xyaxes: match s.get("xyaxes") {
                    None => None,
                    Some(_) => Some(self.vec_n(s, "xyaxes", [0.0; 6])?),
                },
                fovy: match s.get("fovy") {
                    None => None,
                    Some(v) => Some(self.num(v, "fovy")?),
                },
                name,
            },
            AddedKind::Light => AddedElement::Light {
                body: self.parent(s, added)?,
                pos: self.vec_n(s, "pos", [0.0, 0.0, 3.0])?,
                dir: self.vec_n(s, "dir", [0.0, 0.0, -1.0])?,
                name,
            },
        })
    }
    /// A `[bodies.<name>]` table: its joints, mocap, weld, gravity compensation and marker.
    fn added_body(
        &mut self,
        s: &Section,
        name: String,
        added: &[AddedElement],
    ) -> Option<AddedElement> {
        let pos = self.vec_n(s, "pos", [0.0; 3])?;
        let joints = self.body_joints(s)?;
        let mut mocap = match s.get("mocap") {
            None => false,
            Some(v) => self.flag(v, "mocap")?,
        };
        if mocap && !joints.is_empty() {
            // (the body is kept, without mocap, so what names it is not a follow-on)
            mocap = false;
            self.d.push(
                Diagnostic::new(
                    Code::E0170,
                    format!("[bodies.{name}]: a mocap body has no joints"),
                )
                .at(s.get("mocap").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                .label("expected mocap = true without joints, or joints without mocap")
                .help("a mocap body is placed by [init] mocap or the physics never moves it; a body with joints moves"),
            );
        }
        let gravcomp = match s.get("gravcomp") {
            None => 0.0,
            Some(v) => {
                let g = self.num(v, "gravcomp")?;
                self.within(v, g, "gravcomp", crate::limits::MAX_MAGNITUDE)?
            }
        };
        let mass = self.optional_positive(s, "mass")?;
        let weld = match s.get("weld") {
            None => None,
            Some(_) if !mocap => {
                self.d.push(
                    Diagnostic::new(
                        Code::E0170,
                        format!("[bodies.{name}]: only a mocap body is welded by `weld`"),
                    )
                    .at(s.get("weld").map_or(s.name_loc.clone(), |v| v.loc.clone()))
                    .label("expected mocap = true beside weld")
                    .help("a weld ties a mocap target to a robot body, which then follows it ([end_effector])"),
                );
                return None;
            }
            Some(v) => Some(self.body_named(v, "weld", added)?),
        };
        let geom = match s.get("geom") {
            None => None,
            Some(g) => {
                let t = self.geom_type(Some(g), AddedGeomType::Sphere)?;
                let size = match s.get("size") {
                    Some(v) if v.as_f64().is_some() => {
                        let r = self.num(v, "size")?;
                        [r, r, r]
                    }
                    _ => self.vec_n(s, "size", [0.02; 3])?,
                };
                Some((t, size, self.rgba(s, [0.9, 0.2, 0.2, 1.0])?))
            }
        };
        Some(AddedElement::Body {
            name,
            pos,
            joints,
            geom,
            mocap,
            gravcomp,
            mass,
            weld,
        })
    }

    /// A body's `joints = { name = "slide x", ... }`, in the order written.
    fn body_joints(&mut self, s: &Section) -> Option<Vec<(String, JointKind, [f64; 3])>> {
        let mut joints = vec![];
        if let Some(v) = s.get("joints") {
            let Some(t) = v.as_table() else {
                self.d
                    .push(v.type_error("joints", "a table `name = \"slide x\"`"));
                return None;
            };
            for j in t {
                joints.push(self.body_joint(j)?);
            }
        }
        Some(joints)
    }

    /// One joint of an added body: `"slide x|y|z"`, `"hinge x|y|z"`, `"free"` or `"ball"`, under
    /// a name the model does not have.
    fn body_joint(&mut self, j: &Entry) -> Option<(String, JointKind, [f64; 3])> {
        if j.key.contains('\0') {
            self.d.push(nul_in_name("joint", j.key_loc.clone()));
            return None;
        }
        let spec_text = j.value.as_str().unwrap_or("");
        let mut words = spec_text.split_whitespace();
        let (kind, axis) = (words.next(), words.next());
        let jkind = match kind {
            Some("slide") => JointKind::Slide,
            Some("hinge") => JointKind::Hinge,
            Some("free") => JointKind::Free,
            Some("ball") => JointKind::Ball,
            _ => {
                self.d.push(
                    Diagnostic::new(Code::E0104, format!("joint `{}`: `{spec_text}`", j.key))
                        .at(j.value.loc.clone())
                        .label("expected \"slide x|y|z\", \"hinge x|y|z\", \"free\" or \"ball\""),
                );
                return None;
            }
        };
        let axis = match (jkind, axis) {
            (JointKind::Free | JointKind::Ball, None) => Some([0.0, 0.0, 1.0]),
            (JointKind::Free | JointKind::Ball, Some(_)) => None,
            (_, axis) => AXES.iter().find(|(n, _)| Some(*n) == axis).map(|a| a.1),
        };
        let Some(axis) = axis else {
            self.d.push(
                Diagnostic::new(Code::E0104, format!("joint `{}`: `{spec_text}`", j.key))
                    .at(j.value.loc.clone())
                    .label(
                        "expected an axis x, y or z after slide or hinge (free and ball take none)",
                    ),
            );
            return None;
        };
        if self.model.joint(&j.key).is_some() {
            self.d.push(
                Diagnostic::new(
                    Code::E0106,
                    format!("the model already has a joint named `{}`", j.key),
                )
                .at(j.key_loc.clone())
                .label("expected a new name"),
            );
            return None;
        }
        Some((j.key.clone(), jkind, axis))
    }
}

/// Fold added bodies (after the model's own, under the world) and their joints, and added sites
/// (numbered body by body), into the model info.
pub(super) fn apply(added: &[AddedElement], model: &mut ModelInfo) {
    for e in added {
        match e {
            AddedElement::Body {
                name,
                joints,
                mocap,
                ..
            } => {
                let id = model.bodies.len();
                model.bodies.push(name.clone());
                if *mocap {
                    model.mocap.push(id);
                }
                for (j, kind, _) in joints {
                    model.joints.push(Joint {
                        name: j.clone(),
                        kind: *kind,
                        body: id,
                        qposadr: model.nq,
                        dofadr: model.nv,
                    });
                    model.nq += kind.nq();
                    model.nv += kind.nv();
                }
            }
            AddedElement::Site { name, body, .. } => {
                let b = model.body_id(body).unwrap_or(0);
                // After every site of this body and of the bodies before it.
                let at = model.site_bodies.iter().filter(|&&sb| sb <= b).count();
                model.sites.insert(at, name.clone());
                model.site_bodies.insert(at, b);
            }
            // Events find geoms by name (the runtime looks the id up), so the order is immaterial.
            AddedElement::Geom { name, .. } => model.geoms.push(name.clone()),
            _ => {}
        }
    }
}

/// E0102 for an element name holding a NUL byte: MuJoCo's names are C strings.
pub(super) fn nul_in_name(what: &str, at: crate::diagnostic::Location) -> Diagnostic {
    Diagnostic::new(
        Code::E0102,
        format!("the name of this {what} contains a NUL byte"),
    )
    .at(at)
    .label("expected a name without NUL bytes (MuJoCo's names are C strings)")
}

/// W0170: an added body on a vertical slide joint, with no geom that collides and no gravity
/// compensation, falls for ever under gravity (a goal marker written as slides, say): envc says
/// so at check time, where the reference would only show a return of −30,000.
pub(super) fn falling(spec: &crate::syntax::Spec, r: &crate::ir::ResolvedSpec) -> Vec<Diagnostic> {
    let added = &r.model_edits.added;
    let mut out = vec![];
    for e in added {
        let AddedElement::Body {
            name,
            joints,
            gravcomp,
            ..
        } = e
        else {
            continue;
        };
        let vertical = joints
            .iter()
            .find(|(_, k, axis)| *k == JointKind::Slide && axis[2] != 0.0);
        let collides = added
            .iter()
            .any(|g| matches!(g, AddedElement::Geom { body, contact: true, .. } if body == name));
        if let (Some((joint, _, _)), false, true) = (vertical, collides, *gravcomp < 1.0) {
            let at = spec
                .added
                .iter()
                .find(|(k, s)| *k == AddedKind::Body && s.name == *name)
                .map(|(_, s)| s.name_loc.clone());
            out.push(
                Diagnostic::new(
                    Code::W0170,
                    format!(
                        "[bodies.{name}] slides vertically on `{joint}` with nothing to hold it: it falls under gravity"
                    ),
                )
                .at_opt(at)
                .label("a body on a vertical slide joint, without a colliding geom or gravity compensation")
                .help("for a goal or target marker: `mocap = true` and no joints (or the [goal] table's goal vector); to float: `gravcomp = 1`"),
            );
        }
    }
    out
}
