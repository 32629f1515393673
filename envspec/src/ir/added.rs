//! Model elements and actuators a spec adds (`[bodies]`, `[sites]`, `[geoms]`, `[cameras]`,
//! `[lights]`, `[actuators]`).

/// A model element a spec adds. Bodies hang from the world, after the model's own bodies, so
/// every existing index stays; sites, geoms and cameras attach to any body (`world` by default).
#[derive(Clone, Debug, PartialEq)]
pub enum AddedElement {
    /// `[bodies]`: a body child of the world, with its joints and an optional marker geom.
    Body {
        /// Its name.
        name: String,
        /// Position in the world frame.
        pos: [f64; 3],
        /// (name, kind, axis): slide or hinge joints along or about a world axis, or a free or
        /// ball joint (axis unused), in order.
        joints: Vec<(String, crate::mjcf::JointKind, [f64; 3])>,
        /// A marker geom (no contacts): type, size, rgba.
        geom: Option<(AddedGeomType, [f64; 3], [f32; 4])>,
        /// A mocap body: placed by `mocap_pos` / `mocap_quat`, never moved by the physics.
        mocap: bool,
        /// Gravity compensation (0: none, 1: the body floats).
        gravcomp: f64,
        /// The marker geom's mass (None: MuJoCo's default density).
        mass: Option<f64>,
        /// A mocap body's weld partner: a weld equality ties that body to this one.
        weld: Option<String>,
    },
    /// `[sites]`: a site on a body.
    Site {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Radius of its sphere.
        size: f64,
        /// Colour.
        rgba: [f32; 4],
    },
    /// `[geoms]`: a geom on a body.
    Geom {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Its shape.
        kind: AddedGeomType,
        /// Position in the body frame.
        pos: [f64; 3],
        /// MuJoCo's `size` for the shape.
        size: [f64; 3],
        /// Colour.
        rgba: [f32; 4],
        /// Whether it collides (false: `contype = conaffinity = 0`).
        contact: bool,
        /// Its mass (None: from the density).
        mass: Option<f64>,
        /// Its density (None: MuJoCo's 1000).
        density: Option<f64>,
    },
    /// `[cameras]`: a camera on a body.
    Camera {
        /// Its name (render with it by `camera_name`).
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Orientation as MJCF's `xyaxes`, if given.
        xyaxes: Option<[f64; 6]>,
        /// Vertical field of view in degrees, if given.
        fovy: Option<f64>,
    },
    /// `[lights]`: a light on a body.
    Light {
        /// Its name.
        name: String,
        /// The body it is attached to.
        body: String,
        /// Position in the body frame.
        pos: [f64; 3],
        /// Direction it shines in.
        dir: [f64; 3],
    },
}

/// The shapes an added geom may have (MuJoCo's geom types).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AddedGeomType {
    /// A sphere.
    Sphere,
    /// A box.
    Box,
    /// A capsule.
    Capsule,
    /// A cylinder.
    Cylinder,
    /// An infinite collision plane (size: half-lengths drawn, 0 = infinite, and grid spacing);
    /// MuJoCo takes planes on static bodies only (the world or a body without joints).
    Plane,
}

impl AddedGeomType {
    /// The `type` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["sphere", "box", "capsule", "cylinder", "plane"];
    /// The shape a spec's `type = "..."` names, if any.
    pub fn parse(s: &str) -> Option<AddedGeomType> {
        Some(match s {
            "sphere" => AddedGeomType::Sphere,
            "box" => AddedGeomType::Box,
            "capsule" => AddedGeomType::Capsule,
            "cylinder" => AddedGeomType::Cylinder,
            "plane" => AddedGeomType::Plane,
            _ => return None,
        })
    }
}

/// An actuator on one hinge or slide joint (MuJoCo's `<motor>`, `<position>`, `<velocity>`).
#[derive(Clone, Debug, PartialEq)]
pub struct AddedActuator {
    /// Its name in the model.
    pub name: String,
    /// The `[actuators.<section>]` table that added it.
    pub section: String,
    /// The joint it drives.
    pub joint: String,
    /// Motor or servo.
    pub kind: ActuatorKind,
    /// Transmission gear.
    pub gear: f64,
    /// Always limited: the action space is the control range.
    pub ctrlrange: (f64, f64),
    /// Limits of the force it applies, if limited.
    pub forcerange: Option<(f64, f64)>,
}

/// How an added actuator turns `ctrl` into force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActuatorKind {
    /// Force (torque) = gear × ctrl.
    Motor,
    /// Position servo: force = kp × (ctrl − q) − kv × q̇.
    Position {
        /// Position gain.
        kp: f64,
        /// Velocity damping of the servo, if any.
        kv: Option<f64>,
    },
    /// Velocity servo: force = kv × (ctrl − q̇).
    Velocity {
        /// Velocity gain.
        kv: f64,
    },
}
