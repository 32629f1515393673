//! What the resolver needs to know about a MuJoCo model, read from its MJCF with roxmltree (no
//! MuJoCo linking): element names and their ids in MuJoCo's numbering, joint types and the qpos /
//! dof addresses they imply, sizes and the physics timestep. The runtime checks these against the
//! compiled `mjModel` and refuses to run on any disagreement.
//!
//! MuJoCo numbers bodies in depth-first pre-order of the tree; joints and sites body by body, in
//! document order within a body; actuators and tendons in document order.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::diagnostic::{Code, Diagnostic, Location, SourceFile};
use crate::limits;

/// A MuJoCo joint type, which sets its qpos and dof widths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Six degrees of freedom: position and unit quaternion.
    Free,
    /// Three rotational degrees of freedom: a unit quaternion.
    Ball,
    /// One translational degree of freedom.
    Slide,
    /// One rotational degree of freedom.
    Hinge,
}

impl JointKind {
    /// Width in `qpos`.
    pub fn nq(self) -> usize {
        match self {
            JointKind::Free => 7,
            JointKind::Ball => 4,
            JointKind::Slide | JointKind::Hinge => 1,
        }
    }
    /// Width in `qvel` (degrees of freedom).
    pub fn nv(self) -> usize {
        match self {
            JointKind::Free => 6,
            JointKind::Ball => 3,
            JointKind::Slide | JointKind::Hinge => 1,
        }
    }
    /// Names of the qpos components, for layout tables.
    pub fn qpos_parts(self) -> &'static [&'static str] {
        match self {
            JointKind::Free => &["x", "y", "z", "qw", "qx", "qy", "qz"],
            JointKind::Ball => &["qw", "qx", "qy", "qz"],
            _ => &[""],
        }
    }
    /// Names of the dof components, for layout tables.
    pub fn dof_parts(self) -> &'static [&'static str] {
        match self {
            JointKind::Free => &["vx", "vy", "vz", "wx", "wy", "wz"],
            JointKind::Ball => &["wx", "wy", "wz"],
            _ => &[""],
        }
    }
}

/// A joint as the model declares it.
#[derive(Clone, Debug)]
pub struct Joint {
    /// Its name (unnamed: empty).
    pub name: String,
    /// Its type.
    pub kind: JointKind,
    /// Id of the body it belongs to.
    pub body: usize,
    /// Its first index in `qpos`.
    pub qposadr: usize,
    /// Its first index in `qvel`.
    pub dofadr: usize,
}

/// An actuator as the model declares it.
#[derive(Clone, Debug)]
pub struct Actuator {
    /// Its name (unnamed: empty).
    pub name: String,
    /// The joint (or tendon/site/body) the actuator drives, as written in the MJCF.
    pub target: Option<String>,
}

/// Names and numbering of a model, as MuJoCo will compile it.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    /// The model file (the MJCF or URDF read).
    pub path: PathBuf,
    /// `<option timestep>` (MuJoCo's default 0.002 when absent).
    pub timestep: f64,
    /// Body names by id; id 0 is `world`. Unnamed bodies have an empty name.
    pub bodies: Vec<String>,
    /// Joints in MuJoCo's order.
    pub joints: Vec<Joint>,
    /// Site names in MuJoCo's order (unnamed: empty).
    pub sites: Vec<String>,
    /// The body of each site (sites are numbered body by body, in body order).
    pub site_bodies: Vec<usize>,
    /// Actuators in MuJoCo's order.
    pub actuators: Vec<Actuator>,
    /// Tendon names in MuJoCo's order.
    pub tendons: Vec<String>,
    /// Geom names (unnamed geoms: empty), body by body as MuJoCo numbers them; `[events]` and
    /// contact terms select geoms by name and the runtime looks the ids up in the compiled model.
    pub geoms: Vec<String>,
    /// Length of `qpos`.
    pub nq: usize,
    /// Length of `qvel`.
    pub nv: usize,
    /// Names of the `<keyframe>` keys, in order (legged tasks take a PD default pose from one).
    pub keyframes: Vec<String>,
    /// `<sensor>` elements in MuJoCo's order: name and the number of values each writes to
    /// `sensordata` (None for a kind whose size the MJCF alone does not fix, e.g. a plugin).
    pub sensors: Vec<(String, Option<usize>)>,
    /// The mocap bodies (`mocap="true"`), by body id, in MuJoCo's mocap order (body order).
    pub mocap: Vec<usize>,
}

impl ModelInfo {
    /// Number of bodies, `world` included.
    pub fn nbody(&self) -> usize {
        self.bodies.len()
    }
    /// Number of actuators (the action length when the spec adds none).
    pub fn nu(&self) -> usize {
        self.actuators.len()
    }
    /// The id of the body named `name`.
    pub fn body_id(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b == name)
    }
    /// The joint named `name`.
    pub fn joint(&self, name: &str) -> Option<&Joint> {
        self.joints.iter().find(|j| j.name == name)
    }

    /// Read an MJCF file (following `<include>`s).
    pub fn from_mjcf(path: &Path) -> Result<ModelInfo, Diagnostic> {
        let mut reader = Reader {
            info: ModelInfo {
                path: path.to_path_buf(),
                timestep: 0.002,
                bodies: vec!["world".into()],
                joints: vec![],
                sites: vec![],
                site_bodies: vec![],
                actuators: vec![],
                tendons: vec![],
                geoms: vec![],
                nq: 0,
                nv: 0,
                keyframes: vec![],
                sensors: vec![],
                mocap: vec![],
            },
            asset_dirs: Default::default(),
            in_world: false,
            defaults: HashMap::new(),
            world_children: vec![],
            including: vec![],
            source: None,
            nbody: 0,
        };
        reader.read_file(path, None)?;
        reader.build_tree()?;
        Ok(reader.info)
    }
}

/// A body of the kinematic tree, gathered before numbering (includes may add to `<worldbody>`).
struct BodyNode {
    name: String,
    mocap: bool,
    joints: Vec<(String, JointKind)>,
    sites: Vec<String>,
    geoms: Vec<String>,
    children: Vec<BodyNode>,
}

struct Reader {
    info: ModelInfo,
    /// `<compiler>`'s `assetdir`, `meshdir`, `texturedir`, as far as read.
    asset_dirs: [Option<String>; 3],
    /// default class -> (parent class, joint type set in that class)
    defaults: HashMap<String, (Option<String>, Option<JointKind>)>,
    /// The world body's own joints are not allowed; its sites and child bodies are kept here.
    world_children: Vec<BodyNode>,
    /// The files being read, outermost first (an `<include>` of one of them is a cycle).
    including: Vec<PathBuf>,
    /// The file being read (for locating a body beyond `limits::MAX_BODIES`).
    source: Option<std::sync::Arc<SourceFile>>,
    /// Bodies read so far, every file together.
    nbody: usize,
    /// Reading a file included inside `<worldbody>`: its elements are world children.
    in_world: bool,
}

/// Values a sensor of this MJCF kind writes to `sensordata` (MuJoCo 3.17's fixed sizes); None
/// where the size depends on more than the kind (`contact`, `tactile`, plugins).
fn sensor_dim(tag: &str) -> Option<usize> {
    Some(match tag {
        "touch" | "rangefinder" | "jointpos" | "jointvel" | "tendonpos" | "tendonvel"
        | "actuatorpos" | "actuatorvel" | "actuatorfrc" | "jointactuatorfrc"
        | "tendonactuatorfrc" | "jointlimitpos" | "jointlimitvel" | "jointlimitfrc"
        | "tendonlimitpos" | "tendonlimitvel" | "tendonlimitfrc" | "insidesite" | "distance"
        | "e_potential" | "e_kinetic" | "clock" => 1,
        "camprojection" => 2,
        "accelerometer" | "velocimeter" | "gyro" | "force" | "torque" | "magnetometer"
        | "ballangvel" | "framepos" | "framexaxis" | "frameyaxis" | "framezaxis"
        | "framelinvel" | "frameangvel" | "framelinacc" | "frameangacc" | "subtreecom"
        | "subtreelinvel" | "subtreeangmom" | "normal" => 3,
        "ballquat" | "framequat" => 4,
        "fromto" => 6,
        _ => return None,
    })
}

fn malformed(path: &Path, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::new(Code::E0302, format!("{}: {}", path.display(), msg.into()))
        .label("expected well-formed MJCF")
}

fn parse_kind(s: &str) -> Option<JointKind> {
    match s {
        "free" => Some(JointKind::Free),
        "ball" => Some(JointKind::Ball),
        "slide" => Some(JointKind::Slide),
        "hinge" => Some(JointKind::Hinge),
        _ => None,
    }
}

/// Where an included file's elements go: the model's sections, or the content of a body that
/// holds the `<include>` (Adroit includes its hand inside the arm's body).
enum Dest<'b, 'c> {
    Sections,
    Body(&'b mut BodyNode, Option<&'c str>),
}

impl Reader {
    /// Read one file; `at` is the `<include file>` that names it (None for the model itself).
    fn read_file(&mut self, path: &Path, at: Option<Location>) -> Result<(), Diagnostic> {
        self.read_file_into(path, at, Dest::Sections)
    }

    fn read_file_into(
        &mut self,
        path: &Path,
        at: Option<Location>,
        into: Dest<'_, '_>,
    ) -> Result<(), Diagnostic> {
        let key = crate::path::normalize(path);
        if let Some(first) = self.including.iter().position(|p| *p == key) {
            let mut chain: Vec<&Path> = self.including[first..]
                .iter()
                .map(PathBuf::as_path)
                .collect();
            chain.push(&key);
            return Err(limits::include_cycle(&chain, at));
        }
        if self.including.len() > limits::MAX_INCLUDE_DEPTH {
            return Err(limits::include_too_deep(at));
        }
        self.including.push(key);
        let limit = limits::MAX_MODEL_BYTES;
        let source = crate::source::read_source(path, limit, Code::E0301, "model", |e| {
            Diagnostic::new(
                e.code(Code::E0301),
                format!("cannot read model file {}: {e}", path.display()),
            )
            .label("expected an existing, readable MJCF file")
        })?;
        let doc = roxmltree::Document::parse(&source.text).map_err(|e| {
            let pos = e.pos();
            let at = source.offset(pos.row as usize, pos.col as usize);
            malformed(path, format!("not well-formed XML: {e}"))
                .at_opt(at.map(|o| Location::new(&source, o..o)))
        })?;
        if let Some(d) = limits::check_xml_depth(&doc, &source) {
            return Err(d);
        }
        if let Some(d) = limits::check_mjcf_sizes(&doc, &source).into_iter().next() {
            return Err(d);
        }
        self.check_assets(path, &doc, &source)?;
        let root = doc.root_element();
        match root.tag_name().name() {
            // MuJoCo takes an included file's root by any name; `mujocoinclude` is the old one.
            "mujoco" => {}
            "mujocoinclude" if at.is_some() => {}
            "robot" => {
                return Err(malformed(
                    path,
                    "URDF models are not supported by the spec resolver yet",
                )
                .help("convert it to MJCF first (MuJoCo's `compile` sample or mjSpec save_xml)"));
            }
            other => {
                return Err(malformed(
                    path,
                    format!("root element is <{other}>, not <mujoco>"),
                ));
            }
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let outer = self.source.replace(source.clone());
        match into {
            Dest::Sections => {
                for section in root.children().filter(|n| n.is_element()) {
                    self.read_section(path, dir, section)?;
                }
            }
            Dest::Body(body, childclass) => self.read_body_content(path, root, childclass, body)?,
        }
        self.source = outer;
        self.including.pop();
        Ok(())
    }

    /// The mesh, texture, heightfield and skin files a model names are read by MuJoCo: each one
    /// that exists must be a regular file within `limits::MAX_ASSET_BYTES` (a FIFO or
    /// `/dev/zero` would block or never end). A missing one is MuJoCo's to report.
    fn check_assets(
        &mut self,
        path: &Path,
        doc: &roxmltree::Document,
        source: &std::sync::Arc<SourceFile>,
    ) -> Result<(), Diagnostic> {
        let dir = path.parent().unwrap_or(Path::new("."));
        for node in doc.descendants().filter(|n| n.is_element()) {
            let tag = node.tag_name().name();
            if tag == "compiler" {
                for (i, a) in ["assetdir", "meshdir", "texturedir"].iter().enumerate() {
                    if let Some(v) = node.attribute(*a) {
                        self.asset_dirs[i] = Some(v.to_string());
                    }
                }
                continue;
            }
            let sub = match tag {
                "mesh" | "hfield" | "skin" => self.asset_dirs[1].as_ref(),
                "texture" => self.asset_dirs[2].as_ref(),
                _ => continue,
            }
            .or(self.asset_dirs[0].as_ref());
            let Some(file) = node.attribute_node("file") else {
                continue;
            };
            let full = dir.join(sub.map_or("", String::as_str)).join(file.value());
            if !crate::source::exists(&full) {
                continue;
            }
            if let Err(e) = crate::source::check_asset(&full, limits::MAX_ASSET_BYTES) {
                return Err(Diagnostic::new(
                    e.code(Code::E0301),
                    format!("cannot use <{tag}> file {}: {e}", full.display()),
                )
                .at(Location::new(source, file.range_value()))
                .label("expected a regular file MuJoCo can read"));
            }
        }
        Ok(())
    }

    /// The file an `<include>` names, located at its `file` attribute.
    fn read_include(
        &mut self,
        path: &Path,
        dir: &Path,
        node: roxmltree::Node,
    ) -> Result<(), Diagnostic> {
        let file = node
            .attribute_node("file")
            .ok_or_else(|| malformed(path, "<include> without file"))?;
        let at = self
            .source
            .as_ref()
            .map(|s| Location::new(s, file.range_value()));
        self.read_file(&dir.join(file.value()), at)
    }

    /// One element of `<worldbody>` (or of a file included there).
    fn read_world_child(
        &mut self,
        path: &Path,
        dir: &Path,
        child: roxmltree::Node,
    ) -> Result<(), Diagnostic> {
        match child.tag_name().name() {
            // An include inside <worldbody>: the included file's elements are world children.
            "include" => {
                let was = std::mem::replace(&mut self.in_world, true);
                let read = self.read_include(path, dir, child);
                self.in_world = was;
                read?;
            }
            "body" => {
                let b = self.read_body(path, child, None)?;
                self.world_children.push(b);
            }
            "site" => {
                self.info
                    .sites
                    .push(child.attribute("name").unwrap_or("").into());
                self.info.site_bodies.push(0);
            }
            "geom" => self
                .info
                .geoms
                .push(child.attribute("name").unwrap_or("").into()),
            "frame" => {
                let mut holder = BodyNode {
                    name: String::new(),
                    mocap: false,
                    joints: vec![],
                    sites: vec![],
                    geoms: vec![],
                    children: vec![],
                };
                self.read_body_content(path, child, None, &mut holder)?;
                if !holder.joints.is_empty() {
                    return Err(malformed(path, "joints in the world body"));
                }
                self.info.site_bodies.extend(holder.sites.iter().map(|_| 0));
                self.info.sites.extend(holder.sites);
                self.info.geoms.extend(holder.geoms);
                self.world_children.extend(holder.children);
            }
            "joint" | "freejoint" => {
                return Err(malformed(path, "joints in the world body"));
            }
            tag @ ("replicate" | "attach" | "composite" | "flexcomp") => {
                return Err(malformed(
                    path,
                    format!("<{tag}> is not supported by the spec resolver yet"),
                ));
            }
            _ => {}
        }
        Ok(())
    }

    fn read_section(
        &mut self,
        path: &Path,
        dir: &Path,
        node: roxmltree::Node,
    ) -> Result<(), Diagnostic> {
        if self.in_world {
            return self.read_world_child(path, dir, node);
        }
        match node.tag_name().name() {
            "include" => self.read_include(path, dir, node)?,
            "option" => {
                if let Some(ts) = node.attribute("timestep") {
                    self.info.timestep = ts.trim().parse().map_err(|_| {
                        malformed(path, format!("option timestep `{ts}` is not a number"))
                    })?;
                }
            }
            "default" => self.read_default(path, node, None)?,
            "keyframe" => {
                for key in node.children().filter(|n| n.has_tag_name("key")) {
                    self.info
                        .keyframes
                        .push(key.attribute("name").unwrap_or("").into());
                }
            }
            "worldbody" => {
                for child in node.children().filter(|n| n.is_element()) {
                    self.read_world_child(path, dir, child)?;
                }
            }
            "actuator" => {
                for a in node.children().filter(|n| n.is_element()) {
                    let target = [
                        "joint",
                        "jointinparent",
                        "tendon",
                        "site",
                        "body",
                        "cranksite",
                    ]
                    .iter()
                    .find_map(|k| a.attribute(*k))
                    .map(str::to_string);
                    self.info.actuators.push(Actuator {
                        name: a.attribute("name").unwrap_or("").into(),
                        target,
                    });
                }
            }
            "tendon" => {
                for t in node.children().filter(|n| n.is_element()) {
                    self.info
                        .tendons
                        .push(t.attribute("name").unwrap_or("").into());
                }
            }
            "sensor" => {
                for t in node.children().filter(|n| n.is_element()) {
                    let dim = match t.tag_name().name() {
                        // (a size beyond any real sensor's is left to MuJoCo: unnumbered here)
                        "user" => t
                            .attribute("dim")
                            .and_then(|d| d.trim().parse().ok())
                            .filter(|&d: &usize| d <= crate::limits::MAX_SENSOR_DIM),
                        tag => sensor_dim(tag),
                    };
                    self.info
                        .sensors
                        .push((t.attribute("name").unwrap_or("").into(), dim));
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn read_default(
        &mut self,
        path: &Path,
        node: roxmltree::Node,
        parent: Option<String>,
    ) -> Result<(), Diagnostic> {
        let class = match (node.attribute("class"), &parent) {
            (Some(c), _) => c.to_string(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => return Err(malformed(path, "nested <default> without class")),
        };
        let mut kind = None;
        for child in node.children().filter(|n| n.is_element()) {
            match child.tag_name().name() {
                "joint" => {
                    if let Some(t) = child.attribute("type") {
                        kind =
                            Some(parse_kind(t).ok_or_else(|| {
                                malformed(path, format!("unknown joint type `{t}`"))
                            })?);
                    }
                }
                "default" => self.read_default(path, child, Some(class.clone()))?,
                _ => {}
            }
        }
        self.defaults.insert(class, (parent, kind));
        Ok(())
    }

    fn joint_kind_from_class(&self, class: &str) -> JointKind {
        let mut cur = Some(class.to_string());
        while let Some(c) = cur {
            match self.defaults.get(&c) {
                Some((parent, kind)) => {
                    if let Some(k) = kind {
                        return *k;
                    }
                    cur = parent
                        .clone()
                        .or_else(|| (c != "main").then(|| "main".into()));
                }
                None => cur = (c != "main").then(|| "main".into()),
            }
        }
        JointKind::Hinge
    }

    fn read_body(
        &mut self,
        path: &Path,
        node: roxmltree::Node,
        childclass: Option<&str>,
    ) -> Result<BodyNode, Diagnostic> {
        self.nbody += 1;
        if self.nbody > limits::MAX_BODIES {
            let mut d = limits::too_many_bodies("this <body>");
            if let Some(source) = &self.source {
                let start = node.range().start;
                d = d.at(Location::new(source, start..start + 5));
            }
            return Err(d);
        }
        let childclass = node.attribute("childclass").or(childclass);
        let mut body = BodyNode {
            name: node.attribute("name").unwrap_or("").into(),
            mocap: node.attribute("mocap") == Some("true"),
            joints: vec![],
            sites: vec![],
            geoms: vec![],
            children: vec![],
        };
        self.read_body_content(path, node, childclass, &mut body)?;
        Ok(body)
    }

    /// Children of a body (or of a `<frame>`, whose content belongs to the enclosing body).
    fn read_body_content(
        &mut self,
        path: &Path,
        node: roxmltree::Node,
        childclass: Option<&str>,
        body: &mut BodyNode,
    ) -> Result<(), Diagnostic> {
        for child in node.children().filter(|n| n.is_element()) {
            match child.tag_name().name() {
                "joint" => {
                    let kind = match child.attribute("type") {
                        Some(t) => parse_kind(t)
                            .ok_or_else(|| malformed(path, format!("unknown joint type `{t}`")))?,
                        None => self.joint_kind_from_class(
                            child.attribute("class").or(childclass).unwrap_or("main"),
                        ),
                    };
                    body.joints
                        .push((child.attribute("name").unwrap_or("").into(), kind));
                }
                "freejoint" => body.joints.push((
                    child.attribute("name").unwrap_or("").into(),
                    JointKind::Free,
                )),
                "site" => body
                    .sites
                    .push(child.attribute("name").unwrap_or("").into()),
                "geom" => body
                    .geoms
                    .push(child.attribute("name").unwrap_or("").into()),
                "body" => body.children.push(self.read_body(path, child, childclass)?),
                "include" => {
                    let file = child
                        .attribute_node("file")
                        .ok_or_else(|| malformed(path, "<include> without file"))?;
                    let at = self
                        .source
                        .as_ref()
                        .map(|s| Location::new(s, file.range_value()));
                    let dir = path.parent().unwrap_or(Path::new("."));
                    let inc = dir.join(file.value());
                    self.read_file_into(&inc, at, Dest::Body(body, childclass))?;
                }
                "frame" => {
                    let cc = child.attribute("childclass").or(childclass);
                    self.read_body_content(path, child, cc, body)?;
                }
                tag @ ("replicate" | "attach" | "composite" | "flexcomp") => {
                    return Err(malformed(
                        path,
                        format!("<{tag}> is not supported by the spec resolver yet"),
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Number bodies, joints and sites as MuJoCo does.
    fn build_tree(&mut self) -> Result<(), Diagnostic> {
        let roots = std::mem::take(&mut self.world_children);
        let mut stack: Vec<&BodyNode> = roots.iter().rev().collect();
        while let Some(b) = stack.pop() {
            let id = self.info.bodies.len();
            self.info.bodies.push(b.name.clone());
            if b.mocap {
                self.info.mocap.push(id);
            }
            for (name, kind) in &b.joints {
                self.info.joints.push(Joint {
                    name: name.clone(),
                    kind: *kind,
                    body: id,
                    qposadr: self.info.nq,
                    dofadr: self.info.nv,
                });
                self.info.nq += kind.nq();
                self.info.nv += kind.nv();
            }
            self.info.sites.extend(b.sites.iter().cloned());
            self.info.site_bodies.extend(b.sites.iter().map(|_| id));
            self.info.geoms.extend(b.geoms.iter().cloned());
            stack.extend(b.children.iter().rev());
        }
        Ok(())
    }
}
