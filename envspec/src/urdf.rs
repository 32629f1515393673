//! URDF models: names and numbering as MuJoCo 3.17 compiles a URDF file (no MuJoCo linking).
//! The structure is read with the `urdf-rs` crate; MuJoCo's `<mujoco>` extension element (its
//! `<compiler fusestatic>` and `<option timestep>`) with roxmltree.
//!
//! What MuJoCo does with a URDF (checked against MuJoCo 3.17 on several URDFs, and at run time by
//! the runtime's model check):
//! * every link is a body; a root link named `world` is the world body itself;
//! * the tree is walked depth first from the root links (in `<link>` document order); the children
//!   of a link come in the document order of the joints that attach them;
//! * joints: `revolute`/`continuous` → hinge, `prismatic` → slide, `floating` → free,
//!   `spherical` → ball, `planar` → three joints `<name>_TX`, `<name>_TY` (slide) and `<name>_RZ`
//!   (hinge), `fixed` → no joint;
//! * `fusestatic` is on by default for URDF: a body without joints (a root link, or a link attached
//!   by a `fixed` joint) is merged into its parent, its children taking its place. A URDF can turn
//!   that off with `<mujoco><compiler fusestatic="false"/></mujoco>` (then such links keep their
//!   bodies, e.g. a fingertip link whose position a spec reads);
//! * a URDF has no sites, tendons or actuators; actuators come from the spec's `[actuators]`.

use std::collections::HashMap;
use std::path::Path;

use crate::diagnostic::{Code, Diagnostic};
use crate::mjcf::{Joint, JointKind, ModelInfo};
use crate::source::read_source;

fn malformed(path: &Path, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::new(Code::E0302, format!("{}: {}", path.display(), msg.into()))
        .label("expected a well-formed URDF")
}

fn unreadable(path: &Path, e: crate::limits::ReadError) -> Diagnostic {
    Diagnostic::new(
        e.code(Code::E0301),
        format!("cannot read model file {}: {e}", path.display()),
    )
    .label("expected an existing, readable MJCF or URDF file")
}

/// A model file's text (a file that is not UTF-8 is located at its first bad byte).
fn read_model(path: &Path) -> Result<String, Diagnostic> {
    let limit = crate::limits::MAX_MODEL_BYTES;
    read_source(path, limit, Code::E0301, "model", |e| unreadable(path, e)).map(|f| f.text.clone())
}

/// Whether the text is a URDF (its root element is `<robot>`).
fn is_urdf(text: &str) -> bool {
    roxmltree::Document::parse(text).is_ok_and(|d| d.root_element().tag_name().name() == "robot")
}

impl ModelInfo {
    /// Read a model file: a URDF when its root element is `<robot>`, MJCF otherwise.
    pub fn from_file(path: &Path) -> Result<ModelInfo, Diagnostic> {
        let text = read_model(path)?;
        if is_urdf(text.as_str()) {
            ModelInfo::from_urdf_str(path, &text)
        } else {
            ModelInfo::from_mjcf(path)
        }
    }

    /// Read a URDF given as text (`path` is used for messages).
    pub fn from_urdf_str(path: &Path, text: &str) -> Result<ModelInfo, Diagnostic> {
        let ext = mujoco_extension(path, text)?;
        let robot = urdf_rs::read_from_string(text).map_err(|e| malformed(path, e.to_string()))?;
        if robot.links.len() > crate::limits::MAX_BODIES {
            let name = &robot.links[crate::limits::MAX_BODIES].name;
            return Err(crate::limits::too_many_bodies(&format!(
                "{}: link `{name}`",
                path.display()
            )));
        }

        let mut index: HashMap<&str, usize> = HashMap::new();
        for (i, l) in robot.links.iter().enumerate() {
            if index.insert(l.name.as_str(), i).is_some() {
                return Err(malformed(path, format!("two links are named `{}`", l.name)));
            }
        }
        let link = |name: &str, joint: &str| {
            index.get(name).copied().ok_or_else(|| {
                malformed(
                    path,
                    format!("joint `{joint}` refers to link `{name}`, which is not defined"),
                )
            })
        };
        // children[link] = joints attaching a child link, in joint document order.
        let mut children: Vec<Vec<usize>> = vec![vec![]; robot.links.len()];
        let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
        for (j, joint) in robot.joints.iter().enumerate() {
            let p = link(&joint.parent.link, &joint.name)?;
            let c = link(&joint.child.link, &joint.name)?;
            if parent_joint[c].is_some() {
                return Err(malformed(
                    path,
                    format!("link `{}` is the child of two joints", joint.child.link),
                ));
            }
            parent_joint[c] = Some(j);
            children[p].push(j);
        }

        let mut info = ModelInfo {
            path: path.to_path_buf(),
            timestep: ext.timestep.unwrap_or(0.002),
            bodies: vec!["world".into()],
            joints: vec![],
            sites: vec![],
            site_bodies: vec![],
            geoms: vec![],
            actuators: vec![],
            tendons: vec![],
            nq: 0,
            nv: 0,
            keyframes: vec![],
            sensors: vec![],
            mocap: vec![],
        };
        let mut walk = Walk {
            robot: &robot,
            index: &index,
            children: &children,
            fuse: ext.fusestatic,
            info: &mut info,
            visited: 0,
            depth: 0,
            too_deep: None,
        };
        for (i, l) in robot.links.iter().enumerate() {
            if parent_joint[i].is_some() {
                continue;
            }
            if l.name == "world" {
                // The world body itself: its children are children of the world.
                walk.visited += 1;
                walk.children_of(i);
            } else {
                walk.body(i, None);
            }
        }
        if let Some(l) = walk.too_deep {
            let limit = crate::limits::MAX_NESTING;
            return Err(Diagnostic::new(
                Code::E0110,
                format!(
                    "{}: link `{}` is {} links deep in its chain, beyond envc's limit of {limit}",
                    path.display(),
                    robot.links[l].name,
                    limit + 1
                ),
            )
            .label(format!("expected chains of at most {limit} links"))
            .help("MuJoCo's compiler and envc's readers recurse per level; see docs/limits.md"));
        }
        if walk.visited != robot.links.len() {
            return Err(malformed(
                path,
                "the joints form a cycle (some links are not reachable from a root link)",
            ));
        }
        Ok(info)
    }
}

/// MuJoCo's `<mujoco>` extension of URDF: the settings that change names or numbering.
struct Extension {
    fusestatic: bool,
    timestep: Option<f64>,
}

fn mujoco_extension(path: &Path, text: &str) -> Result<Extension, Diagnostic> {
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| malformed(path, format!("not well-formed XML: {e}")))?;
    let source = crate::diagnostic::SourceFile::new(path.display().to_string(), text.to_string());
    if let Some(d) = crate::limits::check_xml_depth(&doc, &source) {
        return Err(d);
    }
    let mut ext = Extension {
        fusestatic: true,
        timestep: None,
    };
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        return Err(malformed(
            path,
            format!("root element is <{}>, not <robot>", root.tag_name().name()),
        ));
    }
    for mj in root.children().filter(|n| n.has_tag_name("mujoco")) {
        for el in mj.children().filter(|n| n.is_element()) {
            match el.tag_name().name() {
                "compiler" => {
                    if let Some(v) = el.attribute("fusestatic") {
                        ext.fusestatic = match v.trim() {
                            "true" => true,
                            "false" => false,
                            other => {
                                return Err(malformed(
                                    path,
                                    format!("<compiler fusestatic=\"{other}\"> is not true/false"),
                                ));
                            }
                        };
                    }
                }
                "option" => {
                    if let Some(ts) = el.attribute("timestep") {
                        ext.timestep = Some(ts.trim().parse().map_err(|_| {
                            malformed(path, format!("option timestep `{ts}` is not a number"))
                        })?);
                    }
                }
                _ => {}
            }
        }
    }
    Ok(ext)
}

struct Walk<'a> {
    robot: &'a urdf_rs::Robot,
    index: &'a HashMap<&'a str, usize>,
    children: &'a [Vec<usize>],
    fuse: bool,
    info: &'a mut ModelInfo,
    visited: usize,
    /// Links on the current chain; the walk stops at the first link beyond `MAX_NESTING`.
    depth: usize,
    too_deep: Option<usize>,
}

impl Walk<'_> {
    /// The body of link `l`, attached by joint `via` (None for a root link), then its subtree.
    fn body(&mut self, l: usize, via: Option<usize>) {
        if self.too_deep.is_some() {
            return;
        }
        if self.depth >= crate::limits::MAX_NESTING {
            self.too_deep = Some(l);
            return;
        }
        self.depth += 1;
        self.body_at(l, via);
        self.depth -= 1;
    }

    fn body_at(&mut self, l: usize, via: Option<usize>) {
        self.visited += 1;
        let joints = via
            .map(|j| joints_of(&self.robot.joints[j]))
            .unwrap_or_default();
        if joints.is_empty() && self.fuse {
            // Fused into the parent: the children take this body's place.
            self.children_of(l);
            return;
        }
        let id = self.info.bodies.len();
        self.info.bodies.push(self.robot.links[l].name.clone());
        for (name, kind) in joints {
            self.info.joints.push(Joint {
                name,
                kind,
                body: id,
                qposadr: self.info.nq,
                dofadr: self.info.nv,
            });
            self.info.nq += kind.nq();
            self.info.nv += kind.nv();
        }
        self.children_of(l);
    }

    fn children_of(&mut self, l: usize) {
        for &j in &self.children[l] {
            let c = self.index[self.robot.joints[j].child.link.as_str()];
            self.body(c, Some(j));
        }
    }
}

/// The MuJoCo joints a URDF joint becomes.
fn joints_of(j: &urdf_rs::Joint) -> Vec<(String, JointKind)> {
    use urdf_rs::JointType as T;
    match j.joint_type {
        T::Revolute | T::Continuous => vec![(j.name.clone(), JointKind::Hinge)],
        T::Prismatic => vec![(j.name.clone(), JointKind::Slide)],
        T::Floating => vec![(j.name.clone(), JointKind::Free)],
        T::Spherical => vec![(j.name.clone(), JointKind::Ball)],
        T::Planar => vec![
            (format!("{}_TX", j.name), JointKind::Slide),
            (format!("{}_TY", j.name), JointKind::Slide),
            (format!("{}_RZ", j.name), JointKind::Hinge),
        ],
        T::Fixed => vec![],
    }
}
