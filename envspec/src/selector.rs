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

mod parse;
mod rows;
#[cfg(test)]
mod tests;

use crate::diagnostic::{Code, Diagnostic, Location, suggest};
use crate::mjcf::ModelInfo;
use parse::{Index, parse, syntax_error};
use rows::{row_names, select_ints, select_rows};

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
