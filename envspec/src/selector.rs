//! Selectors: how a spec names numbers in the simulation, e.g. `qpos[2:]`, `cfrc_ext[1:]`,
//! `xpos[$main_body][0:2]`, `site_xpos[tip][0,2]`, `qvel[hip_1]`.
//!
//! ```text
//! selector := field ( "[" index "]" )?  ( "[" index "]" )?     -- rows, then columns
//! index    := int | int? ":" int? | int ("," int)+ | name | "$" param
//! ```
//! Integers may be negative (counted from the end, as in Python). A name selects the rows of the
//! named model element (a joint's qpos or dof entries for joint-indexed fields). `$param` takes the
//! index or name from a spec parameter.

use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::mjcf::ModelInfo;

/// A mjData / mjModel array (or a derived quantity) that specs can read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// `qpos`: joint positions.
    Qpos,
    /// `qvel`: joint velocities.
    Qvel,
    /// The model's reference configuration `qpos0` (what Gymnasium calls `init_qpos`).
    Qpos0,
    /// The action passed to `step`, as given (before MuJoCo clamps it to ctrlrange).
    Action,
    /// `ctrl`: the control MuJoCo applies (the action clamped to ctrlrange).
    Ctrl,
    /// `qfrc_actuator`: actuator forces in joint space.
    QfrcActuator,
    /// `qfrc_constraint`: constraint forces in joint space.
    QfrcConstraint,
    /// `cfrc_ext`: external (contact) wrench on each body, 6 per body.
    CfrcExt,
    /// `cfrc_int`: internal wrench on each body, 6 per body.
    CfrcInt,
    /// `cacc`: body acceleration (rotational, then linear), 6 per body.
    Cacc,
    /// `cinert`: body inertia in the centre-of-mass frame, 10 per body.
    Cinert,
    /// `cvel`: body velocity (rotational, then linear), 6 per body.
    Cvel,
    /// `xpos`: body frame positions.
    Xpos,
    /// `xipos`: body centre-of-mass positions.
    Xipos,
    /// `site_xpos`: site positions.
    SiteXpos,
    /// `subtree_linvel`: linear velocity of each body's subtree centre of mass (world frame;
    /// MuJoCo's `mj_subtreeVel` over the lagged quantities, as a `subtreelinvel` sensor).
    SubtreeLinvel,
    /// `subtree_angmom`: angular momentum of each body's subtree about its centre of mass
    /// (world frame; `mj_subtreeVel`, as a `subtreeangmom` sensor).
    SubtreeAngmom,
    /// `ten_length`: tendon lengths.
    TenLength,
    /// `ten_velocity`: tendon velocities.
    TenVelocity,
    /// The tendon Jacobian as a dense ntendon × nv matrix (MuJoCo ≥ 3.6 stores it sparse; envc
    /// expands it, as `mju_sparse2dense`). Rows are `tendon:dof` pairs, e.g. `ten_J[0:2]`.
    TenJ,
    /// Mass-weighted mean of `xipos` over all bodies, summed sequentially (numpy's einsum order)
    /// and divided by the pairwise sum of `body_mass`.
    MassCenter,
    /// Velocities and frame axes of sites (MuJoCo's `mj_objectVelocity`, lagged like `cvel`):
    /// linear / angular velocity in the world frame, the same in the site's own frame (a
    /// velocimeter, a gyro), the site's z axis in the world frame (an up-vector), and the world's
    /// gravity direction `(0, 0, −1)` in the site's frame (projected gravity).
    SiteLinvel,
    /// Angular velocity of a site in the world frame.
    SiteAngvel,
    /// Linear velocity of a site in its own frame (a velocimeter).
    SiteLocalLinvel,
    /// Angular velocity of a site in its own frame (a gyro).
    SiteLocalAngvel,
    /// A site's z axis in the world frame (an up-vector).
    SiteZaxis,
    /// Gravity's direction in a site's frame (projected gravity).
    SiteGravity,
    /// `actuator_force`: the force (torque) each actuator applies.
    ActuatorForce,
    /// The previous step's action (zeros after a reset); updated after the observation.
    LastAction,
    /// The PD default pose of each actuator's joint (`[actions]`).
    DefaultPose,
    /// The current command vectors (`[commands.*]`), written `command[NAME]`.
    Command,
    /// `xquat`: body orientations as quaternions (w, x, y, z).
    Xquat,
    /// `site_xmat`: site orientations as row-major 3 × 3 matrices.
    SiteXmat,
    /// Site orientations as Euler angles, Gymnasium-Robotics' `rotations.mat2euler(site_xmat)`.
    SiteEuler,
    /// Body orientations as Euler angles, Gymnasium-Robotics' `rotations.quat2euler(xquat)`
    /// (numpy's `quat2mat`, then `mat2euler`).
    BodyEuler,
    /// Site linear velocity `jacp @ qvel` (`mj_jacSite`, then numpy's matmul: OpenBLAS `dgemv`
    /// as the numerics profile sums it), Gymnasium-Robotics' `get_site_xvelp`.
    SiteXvelp,
    /// Site angular velocity `jacr @ qvel`, as `SiteXvelp` (`get_site_xvelr`).
    SiteXvelr,
    /// The env-held goal vector (`[goal]`), written `goal` or `goal[0:2]`.
    Goal,
    /// The `[derived.*]` values, written `derived[NAME]` or `derived[NAME][k]`.
    Derived,
    /// `sensordata`: the model's `<sensor>` values (a name selects all of a sensor's values).
    SensorData,
    /// `mocap_pos`: mocap bodies' positions, selected by body name.
    MocapPos,
    /// `mocap_quat`: mocap bodies' orientations (w, x, y, z), selected by body name.
    MocapQuat,
}

/// What the rows of a field are indexed by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rows {
    /// Position coordinates (`nq`): joints by name, free and ball joints by component.
    Qpos,
    /// Degrees of freedom (`nv`).
    Dof,
    /// Bodies (`nbody`, `world` included).
    Body,
    /// Sites.
    Site,
    /// Tendons.
    Tendon,
    /// One row per (tendon, dof) pair, tendon-major.
    TendonDof,
    /// Actuators (`nu`).
    Actuator,
    /// The three coordinates `x`, `y`, `z` (a vector field with no model rows).
    Xyz,
    /// Command components (`[commands.*]`); selected by the resolver, not by name here.
    Command,
    /// Sensor values (`sensordata`): a sensor's name selects its values.
    Sensor,
    /// Mocap bodies (`nmocap`), by body name.
    Mocap,
}

/// Every field by the name a selector writes, e.g. `qpos`.
pub const FIELDS: &[(&str, Field)] = &[
    ("qpos", Field::Qpos),
    ("qvel", Field::Qvel),
    ("qpos0", Field::Qpos0),
    ("action", Field::Action),
    ("ctrl", Field::Ctrl),
    ("qfrc_actuator", Field::QfrcActuator),
    ("qfrc_constraint", Field::QfrcConstraint),
    ("cfrc_ext", Field::CfrcExt),
    ("cfrc_int", Field::CfrcInt),
    ("cacc", Field::Cacc),
    ("cinert", Field::Cinert),
    ("cvel", Field::Cvel),
    ("xpos", Field::Xpos),
    ("xipos", Field::Xipos),
    ("site_xpos", Field::SiteXpos),
    ("subtree_linvel", Field::SubtreeLinvel),
    ("subtree_angmom", Field::SubtreeAngmom),
    ("ten_length", Field::TenLength),
    ("ten_velocity", Field::TenVelocity),
    ("ten_J", Field::TenJ),
    ("mass_center", Field::MassCenter),
    ("site_linvel", Field::SiteLinvel),
    ("site_angvel", Field::SiteAngvel),
    ("site_local_linvel", Field::SiteLocalLinvel),
    ("site_local_angvel", Field::SiteLocalAngvel),
    ("site_zaxis", Field::SiteZaxis),
    ("site_gravity", Field::SiteGravity),
    ("actuator_force", Field::ActuatorForce),
    ("last_action", Field::LastAction),
    ("default_pose", Field::DefaultPose),
    ("command", Field::Command),
    ("xquat", Field::Xquat),
    ("site_xmat", Field::SiteXmat),
    ("site_euler", Field::SiteEuler),
    ("body_euler", Field::BodyEuler),
    ("site_xvelp", Field::SiteXvelp),
    ("site_xvelr", Field::SiteXvelr),
    ("goal", Field::Goal),
    ("derived", Field::Derived),
    ("sensordata", Field::SensorData),
    ("mocap_pos", Field::MocapPos),
    ("mocap_quat", Field::MocapQuat),
];

impl Field {
    /// The name a selector writes, e.g. `site_xpos`.
    pub fn name(self) -> &'static str {
        FIELDS
            .iter()
            .find(|(_, f)| *f == self)
            .map(|(n, _)| *n)
            .unwrap_or("?")
    }
    /// What the field's rows are indexed by.
    pub fn rows(self) -> Rows {
        match self {
            Field::Qpos | Field::Qpos0 => Rows::Qpos,
            Field::Qvel | Field::QfrcActuator | Field::QfrcConstraint => Rows::Dof,
            Field::Action
            | Field::Ctrl
            | Field::ActuatorForce
            | Field::LastAction
            | Field::DefaultPose => Rows::Actuator,
            Field::Command | Field::Goal | Field::Derived => Rows::Command,
            Field::SensorData => Rows::Sensor,
            Field::MocapPos | Field::MocapQuat => Rows::Mocap,
            Field::CfrcExt
            | Field::CfrcInt
            | Field::Cacc
            | Field::Cinert
            | Field::Cvel
            | Field::Xpos
            | Field::Xipos
            | Field::SubtreeLinvel
            | Field::SubtreeAngmom
            | Field::Xquat
            | Field::BodyEuler => Rows::Body,
            Field::SiteXpos | Field::SiteLinvel | Field::SiteAngvel => Rows::Site,
            Field::SiteXmat | Field::SiteEuler | Field::SiteXvelp | Field::SiteXvelr => Rows::Site,
            Field::SiteLocalLinvel
            | Field::SiteLocalAngvel
            | Field::SiteZaxis
            | Field::SiteGravity => Rows::Site,
            Field::TenLength | Field::TenVelocity => Rows::Tendon,
            Field::TenJ => Rows::TendonDof,
            Field::MassCenter => Rows::Xyz,
        }
    }
    /// Entries per row (1 for vector fields).
    pub fn cols(self) -> usize {
        match self {
            Field::CfrcExt | Field::CfrcInt | Field::Cacc | Field::Cvel => 6,
            Field::Cinert => 10,
            Field::Xpos | Field::Xipos | Field::SiteXpos | Field::MocapPos => 3,
            Field::SubtreeLinvel | Field::SubtreeAngmom => 3,
            f if f.is_site_frame() => 3,
            Field::Xquat | Field::MocapQuat => 4,
            Field::SiteXmat => 9,
            Field::SiteEuler | Field::SiteXvelp | Field::SiteXvelr | Field::BodyEuler => 3,
            _ => 1,
        }
    }
    /// The derived site fields (velocities and frame axes), computed when a spec reads them.
    pub fn is_site_frame(self) -> bool {
        matches!(
            self,
            Field::SiteLinvel
                | Field::SiteAngvel
                | Field::SiteLocalLinvel
                | Field::SiteLocalAngvel
                | Field::SiteZaxis
                | Field::SiteGravity
        )
    }
    /// Whether reading the field needs `mj_subtreeVel` after the physics steps.
    pub fn needs_subtree_vel(self) -> bool {
        matches!(self, Field::SubtreeLinvel | Field::SubtreeAngmom)
    }
    /// Whether reading the field needs `mj_rnePostConstraint` after the physics steps.
    pub fn needs_rne_post_constraint(self) -> bool {
        matches!(self, Field::CfrcExt | Field::CfrcInt | Field::Cacc)
    }
    fn col_names(self) -> &'static [&'static str] {
        match self {
            Field::CfrcExt | Field::CfrcInt | Field::Cacc | Field::Cvel => {
                &["rx", "ry", "rz", "tx", "ty", "tz"]
            }
            Field::Cinert => &["i0", "i1", "i2", "i3", "i4", "i5", "mx", "my", "mz", "m"],
            Field::Xpos | Field::Xipos | Field::SiteXpos | Field::MocapPos => &["x", "y", "z"],
            Field::SubtreeLinvel | Field::SubtreeAngmom => &["x", "y", "z"],
            f if f.is_site_frame() => &["x", "y", "z"],
            Field::SiteEuler | Field::SiteXvelp | Field::SiteXvelr | Field::BodyEuler => {
                &["x", "y", "z"]
            }
            Field::Xquat | Field::MocapQuat => &["w", "x", "y", "z"],
            Field::SiteXmat => &["xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"],
            _ => &[""],
        }
    }
}

/// A resolved selector: flat indices into the field, one name per element.
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// The field it reads.
    pub field: Field,
    /// Indices into the field's row-major flattened array.
    pub indices: Vec<usize>,
    /// One readable name per selected element, e.g. `qpos[hip_1]`, `cfrc_ext[torso].rx`.
    pub names: Vec<String>,
    /// The selector as written.
    pub text: String,
}

impl Selection {
    /// Number of selected elements.
    pub fn len(&self) -> usize {
        self.indices.len()
    }
    /// Whether it selects nothing.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }
    /// Drop the first `n` elements (e.g. Gymnasium's excluded x/y positions).
    pub fn drop_first(&mut self, n: usize) {
        let n = n.min(self.indices.len());
        self.indices.drain(..n);
        self.names.drain(..n);
    }
}

/// How `$param` indices are looked up.
pub enum ParamIndex {
    /// An index, used as written.
    Int(i64),
    /// A name, looked up in the model.
    Name(String),
}

#[derive(Debug)]
enum Index {
    Int(i64),
    Slice(Option<i64>, Option<i64>),
    List(Vec<i64>),
    /// Names (or integers) listed in order.
    Names(Vec<String>),
    Name(String),
    Param(String),
}

fn syntax_error(loc: &Location, msg: &str) -> Diagnostic {
    Diagnostic::new(Code::E0401, format!("cannot read selector: {msg}"))
        .at(loc.clone())
        .label("expected field[rows][cols], e.g. `qpos[2:]` or `xpos[torso][0:2]`")
}

fn parse(text: &str, loc: &Location) -> Result<(String, Vec<Index>), Diagnostic> {
    let text = text.trim();
    let (field, mut rest) = match text.find('[') {
        Some(i) => (&text[..i], &text[i..]),
        None => (text, ""),
    };
    let mut indices = vec![];
    while !rest.is_empty() {
        // `.x`, `.tz`: a column by name, as `envc show` prints element names (`xpos[torso].x`).
        if let Some(col) = rest.strip_prefix('.') {
            let col = col.trim();
            if col.is_empty() || !col.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(syntax_error(loc, &format!("`.{col}` is not a column name")));
            }
            if indices.len() != 1 {
                return Err(syntax_error(
                    loc,
                    "a `.column` follows exactly one `[rows]`, as in `xpos[torso].x`",
                ));
            }
            indices.push(Index::Name(col.to_string()));
            break;
        }
        let close = rest
            .find(']')
            .ok_or_else(|| syntax_error(loc, "missing `]`"))?;
        if !rest.starts_with('[') {
            return Err(syntax_error(loc, "expected `[` after `]`"));
        }
        let inner = rest[1..close].trim();
        rest = rest[close + 1..].trim_start();
        let int = |s: &str| -> Result<i64, Diagnostic> {
            s.trim()
                .parse::<i64>()
                .map_err(|_| syntax_error(loc, &format!("`{s}` is not an integer")))
        };
        // `joint:part` (`qpos[root:z]`, as `envc show` prints a free joint's elements) is a name,
        // not a slice: a slice's ends are integers or empty.
        let slice_end = |x: &str| x.trim().is_empty() || x.trim().parse::<i64>().is_ok();
        let idx = if let Some(p) = inner.strip_prefix('$') {
            Index::Param(p.trim().to_string())
        } else if let Some((a, b)) = inner
            .split_once(':')
            .filter(|(a, b)| slice_end(a) && slice_end(b))
        {
            let a = if a.trim().is_empty() {
                None
            } else {
                Some(int(a)?)
            };
            let b = if b.trim().is_empty() {
                None
            } else {
                Some(int(b)?)
            };
            Index::Slice(a, b)
        } else if inner.contains(',') && inner.split(',').all(|x| x.trim().parse::<i64>().is_ok()) {
            Index::List(inner.split(',').map(int).collect::<Result<_, _>>()?)
        } else if inner.contains(',') {
            // Names (or indices) listed in order: `qpos[goal_x,goal_y,goal_z]`.
            let parts: Vec<String> = inner.split(',').map(|x| x.trim().to_string()).collect();
            if parts.iter().any(String::is_empty) {
                return Err(syntax_error(loc, "an empty entry in a `,` list"));
            }
            Index::Names(parts)
        } else if let Ok(i) = inner.parse::<i64>() {
            Index::Int(i)
        } else if inner.is_empty() {
            return Err(syntax_error(loc, "empty `[]`"));
        } else {
            Index::Name(inner.to_string())
        };
        indices.push(idx);
    }
    if indices.len() > 2 {
        return Err(syntax_error(
            loc,
            "at most two indices (rows, then columns)",
        ));
    }
    Ok((field.trim().to_string(), indices))
}

/// Resolve a selector against a model. `param` looks up `$name` indices.
pub fn resolve(
    text: &str,
    loc: &Location,
    model: &ModelInfo,
    param: &dyn Fn(&str) -> Result<ParamIndex, Diagnostic>,
) -> Result<Selection, Diagnostic> {
    let (field_name, idx) = parse(text, loc)?;
    let field = FIELDS
        .iter()
        .find(|(n, _)| *n == field_name)
        .map(|(_, f)| *f)
        .ok_or_else(|| {
            Diagnostic::new(
                Code::E0402,
                format!("unknown field `{field_name}` in selector `{text}`"),
            )
            .at(loc.clone())
            .label(format!(
                "expected one of: {}",
                FIELDS
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
            .help_opt(suggest(&field_name, FIELDS.iter().map(|(n, _)| *n)))
        })?;
    let cols = field.cols();
    if cols == 1 && idx.len() > 1 {
        return Err(syntax_error(
            loc,
            &format!("`{field_name}` is a vector: one index only"),
        ));
    }
    let row_names = row_names(field, model);
    let nrows = row_names.len();

    let rows: Vec<usize> = match idx.first() {
        None => (0..nrows).collect(),
        Some(i) => select_rows(i, field, model, nrows, loc, param)?,
    };
    let col_ids: Vec<usize> = match idx.get(1) {
        None => (0..cols).collect(),
        // A column by name (`xpos[torso][x]`, `xpos[torso].x`, `cfrc_ext[foot].tz`).
        Some(Index::Name(n)) if field.col_names().contains(&n.as_str()) => {
            vec![field.col_names().iter().position(|c| c == n).unwrap_or(0)]
        }
        Some(Index::Names(l)) => {
            let mut out = vec![];
            for n in l {
                match (
                    n.parse::<i64>(),
                    field.col_names().iter().position(|c| c == n),
                ) {
                    (Ok(i), _) => out.extend(select_ints(&Index::Int(i), cols, loc)?),
                    (_, Some(c)) => out.push(c),
                    _ => {
                        return Err(Diagnostic::new(
                            Code::E0401,
                            format!("`{n}` is not a column of `{field_name}`"),
                        )
                        .at(loc.clone())
                        .label(format!(
                            "expected column indices or names ({})",
                            field.col_names().join(", ")
                        ))
                        .help_opt(suggest(n, field.col_names().iter().copied())));
                    }
                }
            }
            out
        }
        Some(Index::Name(n)) | Some(Index::Param(n)) => {
            let names = field.col_names().join(", ");
            return Err(Diagnostic::new(
                Code::E0401,
                format!("`{n}` is not a column of `{field_name}`"),
            )
            .at(loc.clone())
            .label(format!(
                "expected a column index below {cols}{}",
                if names.is_empty() {
                    String::new()
                } else {
                    format!(" or one of: {names}")
                }
            ))
            .help_opt(suggest(n, field.col_names().iter().copied())));
        }
        Some(i) => select_ints(i, cols, loc)?,
    };
    let mut indices = vec![];
    let mut names = vec![];
    for &r in &rows {
        for &c in &col_ids {
            indices.push(r * cols + c);
            let col = field.col_names()[c];
            names.push(if col.is_empty() {
                format!("{}[{}]", field.name(), row_names[r])
            } else {
                format!("{}[{}].{col}", field.name(), row_names[r])
            });
        }
    }
    Ok(Selection {
        field,
        indices,
        names,
        text: text.to_string(),
    })
}

/// Readable names of a field's rows.
fn row_names(field: Field, model: &ModelInfo) -> Vec<String> {
    let or_id = |name: &str, prefix: &str, i: usize| {
        if name.is_empty() {
            format!("{prefix}{i}")
        } else {
            name.to_string()
        }
    };
    match field.rows() {
        Rows::Qpos | Rows::Dof => {
            let mut out = vec![];
            for (j, joint) in model.joints.iter().enumerate() {
                let parts = if field.rows() == Rows::Qpos {
                    joint.kind.qpos_parts()
                } else {
                    joint.kind.dof_parts()
                };
                let base = or_id(&joint.name, "joint", j);
                for p in parts {
                    out.push(if p.is_empty() {
                        base.clone()
                    } else {
                        format!("{base}:{p}")
                    });
                }
            }
            out
        }
        Rows::Body => model
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| or_id(b, "body", i))
            .collect(),
        Rows::Site => model
            .sites
            .iter()
            .enumerate()
            .map(|(i, s)| or_id(s, "site", i))
            .collect(),
        Rows::Mocap => model
            .mocap
            .iter()
            .enumerate()
            .map(|(i, &b)| or_id(&model.bodies[b], "mocap", i))
            .collect(),
        Rows::Tendon => model
            .tendons
            .iter()
            .enumerate()
            .map(|(i, s)| or_id(s, "tendon", i))
            .collect(),
        Rows::Actuator => model
            .actuators
            .iter()
            .enumerate()
            .map(|(i, a)| or_id(&a.name, "actuator", i))
            .collect(),
        Rows::Xyz => vec!["x".into(), "y".into(), "z".into()],
        Rows::Command => vec![],
        // One row per value: `touch` (one value), `accel:0` … `accel:2`.
        Rows::Sensor => {
            let mut out = vec![];
            for (i, (name, dim)) in model.sensors.iter().enumerate() {
                let base = or_id(name, "sensor", i);
                match dim {
                    Some(1) => out.push(base),
                    Some(n) => out.extend((0..*n).map(|k| format!("{base}:{k}"))),
                    // (a sensor of unknown size ends what can be numbered)
                    None => break,
                }
            }
            out
        }
        Rows::TendonDof => {
            let dofs = row_names(Field::Qvel, model);
            let mut out = vec![];
            for (i, t) in model.tendons.iter().enumerate() {
                for d in &dofs {
                    out.push(format!("{}:{d}", or_id(t, "tendon", i)));
                }
            }
            out
        }
    }
}

fn select_rows(
    idx: &Index,
    field: Field,
    model: &ModelInfo,
    nrows: usize,
    loc: &Location,
    param: &dyn Fn(&str) -> Result<ParamIndex, Diagnostic>,
) -> Result<Vec<usize>, Diagnostic> {
    let by_name = |name: &str| -> Result<Vec<usize>, Diagnostic> {
        // A row by the name envc prints: one element of a multi-element joint (`root:z`), or
        // an unnamed element by its generated name (`actuator0`). A joint's own name still
        // selects all its elements (`qpos[root]`: 7).
        if let Some(i) = row_names(field, model).iter().position(|r| r == name) {
            return Ok(vec![i]);
        }
        match rows_by_name(name, field, model, loc) {
            Ok(rows) => Ok(rows),
            Err(e) => name_range(name, field, model, loc).unwrap_or(Err(e)),
        }
    };
    match idx {
        Index::Name(n) => by_name(n),
        Index::Names(l) => {
            let mut out = vec![];
            for n in l {
                match n.parse::<i64>() {
                    Ok(i) => out.extend(select_ints(&Index::Int(i), nrows, loc)?),
                    Err(_) => out.extend(by_name(n)?),
                }
            }
            Ok(out)
        }
        Index::Param(p) => match param(p)? {
            ParamIndex::Name(n) => by_name(&n),
            ParamIndex::Int(i) => select_ints(&Index::Int(i), nrows, loc),
        },
        other => select_ints(other, nrows, loc),
    }
}

/// `first:last`, two names (names may hold `:` themselves, as `root:z`): every row from the
/// first's first to the last's last, both included (`qpos[shoulder:wrist]`). `None` when no split
/// of the text names two elements; an error when the two are out of order or several splits do.
fn name_range(
    text: &str,
    field: Field,
    model: &ModelInfo,
    loc: &Location,
) -> Option<Result<Vec<usize>, Diagnostic>> {
    let names = row_names(field, model);
    let rows = |n: &str| -> Option<Vec<usize>> {
        match names.iter().position(|r| r == n) {
            Some(i) => Some(vec![i]),
            None => rows_by_name(n, field, model, loc)
                .ok()
                .filter(|r| !r.is_empty()),
        }
    };
    let ranges: Vec<(usize, usize)> = text
        .match_indices(':')
        .filter_map(|(k, _)| {
            let (a, b) = (rows(text[..k].trim())?, rows(text[k + 1..].trim())?);
            Some((*a.first()?, *b.last()?))
        })
        .collect();
    let err = |label: String| {
        Some(Err(Diagnostic::new(
            Code::E0401,
            format!("cannot read the name range `{text}`"),
        )
        .at(loc.clone())
        .label(label)))
    };
    match ranges.as_slice() {
        [] => None,
        [(a, b)] if a <= b => Some(Ok((*a..=*b).collect())),
        [(a, b)] => err(format!(
            "expected the first name before the last: `{}` comes after `{}`",
            names[*a], names[*b]
        )),
        _ => err("expected one way to split it into two names; list the names with `,`".into()),
    }
}

fn rows_by_name(
    name: &str,
    field: Field,
    model: &ModelInfo,
    loc: &Location,
) -> Result<Vec<usize>, Diagnostic> {
    let (what, candidates, found): (&str, Vec<&str>, Option<Vec<usize>>) = match field.rows() {
        Rows::Qpos | Rows::Dof => {
            let found = model.joint(name).map(|j| {
                if field.rows() == Rows::Qpos {
                    (j.qposadr..j.qposadr + j.kind.nq()).collect()
                } else {
                    (j.dofadr..j.dofadr + j.kind.nv()).collect()
                }
            });
            (
                "joint",
                model.joints.iter().map(|j| j.name.as_str()).collect(),
                found,
            )
        }
        Rows::Body => (
            "body",
            model.bodies.iter().map(String::as_str).collect(),
            model.body_id(name).map(|i| vec![i]),
        ),
        Rows::Site => (
            "site",
            model.sites.iter().map(String::as_str).collect(),
            model.sites.iter().position(|s| s == name).map(|i| vec![i]),
        ),
        Rows::Mocap => (
            "mocap body",
            model
                .mocap
                .iter()
                .map(|&b| model.bodies[b].as_str())
                .collect(),
            model
                .mocap
                .iter()
                .position(|&b| model.bodies[b] == name)
                .map(|i| vec![i]),
        ),
        Rows::Tendon => (
            "tendon",
            model.tendons.iter().map(String::as_str).collect(),
            model
                .tendons
                .iter()
                .position(|s| s == name)
                .map(|i| vec![i]),
        ),
        Rows::Actuator => (
            "actuator",
            model.actuators.iter().map(|a| a.name.as_str()).collect(),
            model
                .actuators
                .iter()
                .position(|a| a.name == name)
                .map(|i| vec![i]),
        ),
        Rows::TendonDof => ("tendon:dof pair", vec![], None),
        Rows::Sensor => {
            let mut adr = 0;
            let mut found = None;
            for (n, dim) in &model.sensors {
                let Some(dim) = dim else { break };
                if n == name {
                    found = Some((adr..adr + dim).collect());
                    break;
                }
                adr += dim;
            }
            (
                "sensor",
                model.sensors.iter().map(|s| s.0.as_str()).collect(),
                found,
            )
        }
        Rows::Command => ("command", vec![], None),
        Rows::Xyz => (
            "component",
            vec!["x", "y", "z"],
            ["x", "y", "z"]
                .iter()
                .position(|c| *c == name)
                .map(|i| vec![i]),
        ),
    };
    found.ok_or_else(|| {
        let named: Vec<&str> = candidates
            .iter()
            .copied()
            .filter(|c| !c.is_empty())
            .collect();
        Diagnostic::new(
            Code::E0303,
            format!(
                "the model {} has no {what} named `{name}`",
                model.path.display()
            ),
        )
        .at(loc.clone())
        .label(format!(
            "expected the name of a {what} of the model ({} named)",
            named.len()
        ))
        .help_opt(
            // No such site but a body of that name (URDF models have no sites): its position is
            // `xpos[name]`.
            (field == Field::SiteXpos && model.body_id(name).is_some())
                .then(|| {
                    format!(
                        "`{name}` is a body of this model, not a site: its position is `xpos[{name}]`"
                    )
                })
                .or_else(|| suggest(name, named.iter().copied())),
        )
    })
}

fn select_ints(idx: &Index, n: usize, loc: &Location) -> Result<Vec<usize>, Diagnostic> {
    let n_i = n as i64;
    let one = |i: i64| -> Result<usize, Diagnostic> {
        let j = if i < 0 { i + n_i } else { i };
        if j < 0 || j >= n_i {
            Err(Diagnostic::new(
                Code::E0304,
                format!("index {i} is out of range for {n} entries"),
            )
            .at(loc.clone())
            .label(format!("expected an index in -{n}..{n}")))
        } else {
            Ok(j as usize)
        }
    };
    match idx {
        Index::Int(i) => Ok(vec![one(*i)?]),
        Index::List(l) => l.iter().map(|&i| one(i)).collect(),
        Index::Slice(a, b) => {
            // Python slice semantics: clamp, negative counts from the end.
            let clamp = |v: i64| -> i64 { if v < 0 { (v + n_i).max(0) } else { v.min(n_i) } };
            let a = a.map(clamp).unwrap_or(0);
            let b = b.map(clamp).unwrap_or(n_i);
            Ok((a..b.max(a)).map(|i| i as usize).collect())
        }
        Index::Name(_) | Index::Names(_) | Index::Param(_) => {
            unreachable!("names are resolved by the caller")
        }
    }
}

/// Whether `name` matches `pattern` (`*`: any run of characters, `?`: one character).
pub fn glob(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    // Iterative matching with backtracking to the last `*`: linear memory, no recursion.
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}
