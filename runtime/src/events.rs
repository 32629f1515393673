//! `[events.*]` executed (IR: `envspec::events`): domain randomization of the env's own model
//! copy and pushes. Everything is laid out when the env is built; reset and step only read and
//! write preallocated buffers and the model's arrays (no allocation).
//!
//! Values: `startup` events start from the compiled values and compose in spec order; `reset`
//! and `interval` events start from the startup values (so repeated events never drift), a later
//! event on the same value wins. Results are clamped to the field's bounds
//! (`EventField::lower_bound`, `upper_bound`).

use envspec::ResolvedSpec;
use envspec::events::{Event, EventDist, EventField, EventKind, EventMode, Operation};
use mujoco_rs::mujoco_c::{mjModel, mjtObj};
use mujoco_rs::prelude::MjModel;

use crate::mj::model_edit::{ModelArray, ModelValues, NPRM};

use crate::error::EnvError;
use crate::numerics::{self, Profile};
use crate::rng::NumpyRng;

/// A model array an event writes, with MuJoCo's row strides.
type Arr = ModelArray;

/// One value an event writes: `slot`, and for a position servo's kp also `−value` to `neg`.
#[derive(Clone, Copy, Debug)]
struct Write {
    slot: usize,
    neg: Option<usize>,
}

/// A push: the first dof of each free joint, and the x and y ranges.
type Push = (Vec<usize>, (f64, f64), (f64, f64));

struct Runtime {
    mode: EventMode,
    field: Option<EventField>,
    dist: EventDist,
    operation: Operation,
    shared: bool,
    writes: Vec<Write>,
    /// `body_quat_euler.*`: per element, (its entry in `Events::euler`, the angle's axis).
    euler: Vec<(usize, usize)>,
    push: Option<Push>,
    /// Interval events: seconds until the next firing.
    time_left: f64,
}

/// The events of one env.
pub(crate) struct Events {
    events: Vec<Runtime>,
    slots: Vec<(Arr, usize)>,
    /// Per slot: the compiled value and the value after the startup events.
    original: Vec<f64>,
    startup: Vec<f64>,
    /// Bodies whose orientation `body_quat_euler.*` events set: the body and the angles drawn at
    /// this reset (0 where none was).
    euler: Vec<(usize, [f64; 3])>,
    /// Whether MuJoCo's derived constants must be recomputed after startup/reset events.
    pub set_const: bool,
    pub changes_mass: bool,
    pub changes_timestep: bool,
    started: bool,
}

/// The events' reach into the env: its model copy, its data, the RNG and the numerics profile.
pub(crate) struct Target<'a> {
    pub m: ModelValues<'a>,
    pub qvel: &'a mut [f64],
    pub rng: &'a mut NumpyRng,
    pub profile: Profile,
}

/// One draw of `dist` from the env's stream.
fn draw(dist: EventDist, rng: &mut NumpyRng, profile: Profile) -> f64 {
    match dist {
        EventDist::Uniform { low, high } => rng.uniform(low, high),
        // ln by the C library (Python's `math.log`), exp as numpy's `np.exp`.
        EventDist::LogUniform { low, high } => {
            numerics::exp(profile, rng.uniform(low.ln(), high.ln()))
        }
        EventDist::Gaussian { mean, std } => mean + std * rng.standard_normal(),
    }
}

fn clamp(field: EventField, x: f64) -> f64 {
    let x = field.lower_bound().map_or(x, |lo| x.max(lo));
    field.upper_bound().map_or(x, |hi| x.min(hi))
}

/// One model value an event writes: where, the kp's negated bias if any, and a label
/// (`FR`, `trunk.x`, `FR_hip_joint`, `gravity.z`).
struct Value {
    at: (Arr, usize),
    neg: Option<(Arr, usize)>,
    label: String,
}

/// The values a model event writes, in draw order: element by element, component by component.
fn layout(env: &str, e: &Event, m: &mjModel) -> Result<Vec<Value>, EnvError> {
    let EventKind::Model {
        field, elements, ..
    } = &e.kind
    else {
        return Ok(vec![]);
    };
    let xyz = ["x", "y", "z"];
    let one = |at: (Arr, usize), label: String| Value {
        at,
        neg: None,
        label,
    };
    let mut out = vec![];
    match field {
        EventField::Gravity => {
            for (k, c) in xyz.iter().enumerate() {
                out.push(one((Arr::Gravity, k), format!("gravity.{c}")));
            }
        }
        EventField::Timestep => out.push(one((Arr::Timestep, 0), "timestep".into())),
        _ => {}
    }
    for el in elements {
        let name = &el.name;
        match *field {
            EventField::GeomFriction(k) => {
                let g = geom_id(env, m, name)?;
                out.push(one((Arr::GeomFriction, 3 * g + k), name.clone()));
            }
            EventField::BodyMass => out.push(one((Arr::BodyMass, el.index), name.clone())),
            EventField::BodyIposAxis(k) => out.push(one(
                (Arr::BodyIpos, 3 * el.index + k),
                format!("{name}.{}", xyz[k]),
            )),
            EventField::BodyIpos => {
                for (k, c) in xyz.iter().enumerate() {
                    out.push(one(
                        (Arr::BodyIpos, 3 * el.index + k),
                        format!("{name}.{c}"),
                    ));
                }
            }
            EventField::BodyQuatEuler(k) => out.push(one(
                (Arr::BodyQuat, 4 * el.index),
                format!("{name}.euler_{}", xyz[k]),
            )),
            EventField::BodyPosAxis(k) => out.push(one(
                (Arr::BodyPos, 3 * el.index + k),
                format!("{name}.{}", xyz[k]),
            )),
            EventField::SitePosAxis(k) => out.push(one(
                (Arr::SitePos, 3 * el.index + k),
                format!("{name}.{}", xyz[k]),
            )),
            EventField::BodyPos | EventField::SitePos => {
                let arr = if *field == EventField::BodyPos {
                    Arr::BodyPos
                } else {
                    Arr::SitePos
                };
                for (k, c) in xyz.iter().enumerate() {
                    out.push(one((arr, 3 * el.index + k), format!("{name}.{c}")));
                }
            }
            EventField::JointDamping | EventField::JointArmature => {
                let arr = if *field == EventField::JointDamping {
                    Arr::DofDamping
                } else {
                    Arr::DofArmature
                };
                for k in 0..el.dofs.1 {
                    let label = if el.dofs.1 == 1 {
                        name.clone()
                    } else {
                        format!("{name}.{k}")
                    };
                    out.push(one((arr, el.dofs.0 + k), label));
                }
            }
            EventField::ActuatorGain => {
                out.push(one((Arr::GainPrm, NPRM * el.index), name.clone()))
            }
            EventField::ActuatorBias => {
                for k in 0..3 {
                    out.push(one(
                        (Arr::BiasPrm, NPRM * el.index + k),
                        format!("{name}.bias{k}"),
                    ));
                }
            }
            EventField::ActuatorKp => out.push(Value {
                at: (Arr::GainPrm, NPRM * el.index),
                neg: Some((Arr::BiasPrm, NPRM * el.index + 1)),
                label: name.clone(),
            }),
            EventField::Gravity | EventField::Timestep => {}
        }
    }
    Ok(out)
}

impl Events {
    /// Lay out the writes of `events` on model `m` (geoms are looked up by name).
    pub fn new(env: &str, events: &[Event], m: &mjModel) -> Result<Events, EnvError> {
        let mut slots: Vec<(Arr, usize)> = vec![];
        let mut slot = |at: (Arr, usize)| match slots.iter().position(|&s| s == at) {
            Some(k) => k,
            None => {
                slots.push(at);
                slots.len() - 1
            }
        };
        let mut out = vec![];
        let mut euler: Vec<(usize, [f64; 3])> = vec![];
        let (mut set_const, mut changes_mass, mut changes_timestep) = (false, false, false);
        for e in events {
            let mut rt = Runtime {
                mode: e.mode,
                field: None,
                dist: EventDist::Uniform {
                    low: 0.0,
                    high: 0.0,
                },
                operation: Operation::Add,
                shared: false,
                writes: vec![],
                euler: vec![],
                push: None,
                time_left: 0.0,
            };
            match &e.kind {
                EventKind::Push { joints, x, y } => {
                    rt.push = Some((joints.iter().map(|j| j.dofs.0).collect(), *x, *y));
                }
                EventKind::Model {
                    field,
                    elements,
                    dist,
                    operation,
                    shared,
                } => {
                    set_const |= field.needs_set_const();
                    changes_mass |= *field == EventField::BodyMass;
                    changes_timestep |= *field == EventField::Timestep;
                    rt.writes = layout(env, e, m)?
                        .into_iter()
                        .map(|v| Write {
                            slot: slot(v.at),
                            neg: v.neg.map(&mut slot),
                        })
                        .collect();
                    // Euler angles go to a per-body buffer, made a quaternion after the resets'
                    // events; their slot only shows in the table.
                    if let EventField::BodyQuatEuler(axis) = field {
                        rt.writes.clear();
                        for el in elements {
                            let k = match euler.iter().position(|&(b, _)| b == el.index) {
                                Some(k) => k,
                                None => {
                                    euler.push((el.index, [0.0; 3]));
                                    euler.len() - 1
                                }
                            };
                            rt.euler.push((k, *axis));
                        }
                    }
                    rt.field = Some(*field);
                    rt.dist = *dist;
                    rt.operation = *operation;
                    rt.shared = *shared;
                }
            }
            out.push(rt);
        }
        // Every slot's index is within its array: element indices come from the resolver, checked
        // against the compiled model's numbering (`check_model`), and geom ids from MuJoCo itself.
        let original: Vec<f64> = slots.iter().map(|&(a, i)| a.get(m, i)).collect();
        Ok(Events {
            events: out,
            startup: original.clone(),
            original,
            slots,
            euler,
            set_const,
            changes_mass,
            changes_timestep,
            started: false,
        })
    }

    /// Reset steps 1 and 2 of the draw order: on a seeded (or the first) reset restore the
    /// compiled values and apply the startup events; else restore the startup values. Then the
    /// reset events, then the first interval of each interval event with a range.
    pub fn reset(&mut self, t: &mut Target, reseed: bool) {
        if reseed || !self.started {
            self.restore(&mut t.m, false);
            for k in 0..self.events.len() {
                if self.events[k].mode == EventMode::Startup {
                    self.apply(k, t, true);
                }
            }
            for (s, &(a, i)) in self.slots.iter().enumerate() {
                self.startup[s] = t.m.get(a, i);
            }
            self.started = true;
        } else {
            self.restore(&mut t.m, true);
        }
        for k in 0..self.events.len() {
            if self.events[k].mode == EventMode::Reset {
                self.apply(k, t, false);
            }
        }
        for (b, angles) in &mut self.euler {
            let q = crate::manipulation::euler2quat(*angles);
            for (j, &x) in q.iter().enumerate() {
                t.m.set(Arr::BodyQuat, 4 * *b + j, x);
            }
            *angles = [0.0; 3];
        }
        for e in &mut self.events {
            if let EventMode::Interval { low, high } = e.mode {
                e.time_left = if low == high {
                    low
                } else {
                    t.rng.uniform(low, high)
                };
            }
        }
    }

    /// Step 5 of the draw order: the interval events that are due after `dt` seconds, in spec
    /// order. Returns whether any fired.
    pub fn step(&mut self, t: &mut Target, dt: f64) -> bool {
        let mut fired = false;
        for k in 0..self.events.len() {
            let EventMode::Interval { low, high } = self.events[k].mode else {
                continue;
            };
            self.events[k].time_left -= dt;
            // A tolerance for the rounding of repeated subtraction (an interval of 1 s at
            // dt = 0.02 fires on the 50th step).
            if self.events[k].time_left > 1e-9 {
                continue;
            }
            self.apply(k, t, false);
            fired = true;
            self.events[k].time_left = if low == high {
                low
            } else {
                t.rng.uniform(low, high)
            };
        }
        fired
    }

    fn restore(&self, m: &mut ModelValues, to_startup: bool) {
        let values = if to_startup {
            &self.startup
        } else {
            &self.original
        };
        for (s, &(a, i)) in self.slots.iter().enumerate() {
            m.set(a, i, values[s]);
        }
    }

    /// Draw and write event `k`. `current`: the base is the model's current value (startup
    /// events), else the startup value.
    fn apply(&mut self, k: usize, t: &mut Target, current: bool) {
        let e = &self.events[k];
        if !e.euler.is_empty() {
            // `body_quat_euler.*` (abs, reset only): the angle itself, made a quaternion after
            // every reset event has drawn.
            for &(entry, axis) in &e.euler {
                self.euler[entry].1[axis] = draw(e.dist, t.rng, t.profile);
            }
            return;
        }
        if let Some((dofs, x, y)) = &e.push {
            for &dof in dofs {
                let (dx, dy) = (t.rng.uniform(x.0, x.1), t.rng.uniform(y.0, y.1));
                // A free joint has 6 dofs from `dof`.
                t.qvel[dof] += dx;
                t.qvel[dof + 1] += dy;
            }
            return;
        }
        let Some(field) = e.field else { return };
        let mut shared = None;
        for w in &e.writes {
            let d = match shared {
                Some(d) => d,
                None => {
                    let d = draw(e.dist, t.rng, t.profile);
                    if e.shared {
                        shared = Some(d);
                    }
                    d
                }
            };
            let (a, i) = self.slots[w.slot];
            let base = if current {
                t.m.get(a, i)
            } else {
                self.startup[w.slot]
            };
            let v = clamp(field, e.operation.apply(base, d));
            t.m.set(a, i, v);
            if let Some(n) = w.neg {
                let (a, i) = self.slots[n];
                t.m.set(a, i, -v);
            }
        }
    }
}

/// The id of geom `name` in the compiled model (E1120 if MuJoCo has none of that name).
fn geom_id(env: &str, m: &mjModel, name: &str) -> Result<usize, EnvError> {
    crate::mj::names::id(m, mjtObj::mjOBJ_GEOM, name).ok_or_else(|| EnvError::EventElement {
        env: env.to_string(),
        what: format!("geom `{name}`"),
    })
}

/// One row of the randomization table (`envc show`): a value an event writes.
#[derive(Clone, Debug)]
pub struct Row {
    /// The `[events.<name>]` entry.
    pub event: String,
    /// `startup`, `reset`, `interval 5–10 s`.
    pub mode: String,
    /// The model field written (`push` for a velocity push).
    pub field: &'static str,
    /// The element it writes, e.g. a body or a joint's axis.
    pub element: String,
    /// `uniform[0.9, 1.1]`, `gaussian(mean 0, std 0.1)`; pushes: the x and y ranges.
    pub distribution: String,
    /// How the draw combines with the compiled value (`add`, `scale`, `abs`).
    pub operation: &'static str,
    /// The compiled value (pushes: none, they add to the velocity).
    pub compiled: Option<f64>,
    /// The values it can take (a Gaussian: mean ± 3 std), clamped to the field's bounds.
    pub range: (f64, f64),
}

/// The randomization table of an env's spec over its compiled model values (the env's model
/// before its first reset).
pub fn table(spec: &ResolvedSpec, model: &MjModel) -> Result<Vec<Row>, EnvError> {
    let m: &mjModel = model.ffi();
    let mut rows = vec![];
    for e in &spec.events {
        let mode = match e.mode {
            EventMode::Interval { low, high } if low == high => format!("interval {low} s"),
            EventMode::Interval { low, high } => format!("interval {low}–{high} s"),
            _ => e.mode.name().to_string(),
        };
        match &e.kind {
            EventKind::Push { joints, x, y } => {
                for j in joints {
                    for (c, r) in [("vx", x), ("vy", y)] {
                        rows.push(Row {
                            event: e.name.clone(),
                            mode: mode.clone(),
                            field: "push",
                            element: format!("{}.{c}", j.name),
                            distribution: format!("uniform[{}, {}]", r.0, r.1),
                            operation: "add",
                            compiled: None,
                            range: *r,
                        });
                    }
                }
            }
            EventKind::Model {
                field,
                dist,
                operation,
                shared,
                ..
            } => {
                for v in layout(&spec.id, e, m)? {
                    let base = v.at.0.get(m, v.at.1);
                    let (lo, hi) = operation.apply_range(base, dist.support());
                    rows.push(Row {
                        event: e.name.clone(),
                        mode: mode.clone(),
                        field: field.name(),
                        element: v.label,
                        distribution: if *shared {
                            format!("{} (shared)", dist.describe())
                        } else {
                            dist.describe()
                        },
                        operation: operation.name(),
                        // An Euler angle has no compiled value (the whole quaternion is set).
                        compiled: (!matches!(field, EventField::BodyQuatEuler(_))).then_some(base),
                        range: (clamp(*field, lo), clamp(*field, hi)),
                    });
                }
            }
        }
    }
    Ok(rows)
}
