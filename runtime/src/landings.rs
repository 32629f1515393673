//! Contacts tracked at every physics substep, as mjlab's contact sensors are updated
//! (`ManagerBasedRlEnv.step` calls `scene.update` after each `sim.step`): feet landings for
//! `feet_swing_height` and `soft_landing`, and self contacts for `self_collisions`.
//!
//! A foot *lands* in an env step when it is on the floor at the last substep and has been for at
//! most `frame_skip` substeps (mjlab's `compute_first_contact`: contact time in `(0, dt]`). The
//! contact time restarts at reset, as the sensor's, and so does a swing's peak height: mjlab's
//! `feet_swing_height` keeps it across resets (the term has no reset), which would make an
//! episode depend on the one before and break `reset(seed)`'s promise of the same trajectory.

use envspec::ir::{LeggedTerm, ResolvedSpec, TermKind};
use mujoco_rs::mujoco_c::mjtObj;
use mujoco_rs::prelude::MjData;
use mujoco_rs::wrappers::mj_model::traits::ModelType;

use crate::EnvError;
use crate::error::unfit;

/// Which geoms a foot or a floor is: one geom, or every geom of one body.
#[derive(Clone, Copy, Debug)]
struct Part {
    id: i32,
    body: bool,
}

impl Part {
    fn holds(self, geom: i32, geom_bodyid: &[i32]) -> bool {
        if self.body {
            // `geom` is a geom id from the contact list.
            geom >= 0 && geom_bodyid[geom as usize] == self.id
        } else {
            geom == self.id
        }
    }
}

/// The landing state of one `feet_swing_height` or `soft_landing` term.
#[derive(Clone, Debug)]
struct Feet {
    feet: Vec<Part>,
    floor: Part,
    /// Site of each foot (its height), for `feet_swing_height`.
    sites: Vec<usize>,
    max_height: f64,
    target: f64,
    swing: bool,
    /// Consecutive substeps each foot has been on the floor (0: in the air).
    contact_substeps: Vec<u32>,
    /// Highest height seen while in the air since the last landing.
    peak: Vec<f64>,
    /// Per foot, this step: the landing's cost (`(peak / target − 1)²` or the force norm), 0
    /// when it did not land.
    value: Vec<f64>,
}

/// What the substep tracking holds for each reward term (None: a term without it).
#[derive(Clone, Debug, Default)]
pub(crate) struct Landings {
    terms: Vec<Option<Tracked>>,
    frame_skip: u32,
}

#[derive(Clone, Debug)]
enum Tracked {
    Feet(Feet),
    /// Bodies of the subtree, then the substeps of this env step that counted.
    SelfContacts {
        inside: Vec<bool>,
        threshold: f64,
        hits: u32,
    },
}

fn part(
    spec: &ResolvedSpec,
    m: &mujoco_rs::prelude::MjModel,
    name: &str,
    body: bool,
) -> Result<Part, EnvError> {
    let (obj, what) = if body {
        (mjtObj::mjOBJ_BODY, "body")
    } else {
        (mjtObj::mjOBJ_GEOM, "geom")
    };
    let id = crate::mj::names::id(m.ffi(), obj, name)
        .ok_or_else(|| unfit(spec, format!("the compiled model has no {what} `{name}`")))?;
    Ok(Part {
        id: id as i32,
        body,
    })
}

impl Landings {
    pub fn new(spec: &ResolvedSpec, m: &mujoco_rs::prelude::MjModel) -> Result<Landings, EnvError> {
        let mut terms = vec![];
        for t in &spec.reward {
            let TermKind::Legged(l) = &t.kind else {
                terms.push(None);
                continue;
            };
            terms.push(match l {
                LeggedTerm::FeetSwingHeight { feet: f, .. }
                | LeggedTerm::SoftLanding { feet: f, .. } => {
                    let n = f.geoms.len();
                    let feet = (0..n)
                        .map(|i| part(spec, m, &f.geoms[i], f.bodies[i]))
                        .collect::<Result<Vec<_>, _>>()?;
                    let (sites, target, max_height, swing) = match l {
                        LeggedTerm::FeetSwingHeight {
                            height,
                            target,
                            max_height,
                            ..
                        } => (
                            // site_xpos z: index 3·site + 2.
                            height.indices.iter().map(|&k| k / 3).collect(),
                            *target,
                            *max_height,
                            true,
                        ),
                        _ => (vec![], 1.0, 0.0, false),
                    };
                    Some(Tracked::Feet(Feet {
                        feet,
                        floor: part(spec, m, &f.floor, f.floor_is_body)?,
                        sites,
                        max_height,
                        target,
                        swing,
                        contact_substeps: vec![0; n],
                        peak: vec![0.0; n],
                        value: vec![0.0; n],
                    }))
                }
                LeggedTerm::SelfCollisions { subtree, threshold } => {
                    let root = part(spec, m, subtree, true)?.id;
                    let parent = m.body_parentid();
                    let inside = (0..parent.len())
                        .map(|b| {
                            let mut b = b as i32;
                            while b != root && b > 0 {
                                b = parent[b as usize];
                            }
                            b == root
                        })
                        .collect();
                    Some(Tracked::SelfContacts {
                        inside,
                        threshold: *threshold,
                        hits: 0,
                    })
                }
                _ => None,
            });
        }
        Ok(Landings {
            terms,
            frame_skip: spec.frame_skip,
        })
    }

    /// Whether any term needs the contacts of every physics substep.
    pub fn active(&self) -> bool {
        self.terms.iter().any(Option::is_some)
    }

    /// Reset: contact times and swing peaks restart.
    pub fn reset(&mut self) {
        for t in self.terms.iter_mut().flatten() {
            match t {
                Tracked::Feet(f) => {
                    f.contact_substeps.fill(0);
                    f.peak.fill(0.0);
                    f.value.fill(0.0);
                }
                Tracked::SelfContacts { hits, .. } => *hits = 0,
            }
        }
    }

    /// Before the physics substeps of an env step.
    pub fn begin_step(&mut self) {
        for t in self.terms.iter_mut().flatten() {
            if let Tracked::SelfContacts { hits, .. } = t {
                *hits = 0;
            }
        }
    }

    /// After one physics substep: which feet touch the floor, and whether this substep's first
    /// self contact pushes harder than the threshold.
    pub fn substep<M: ModelType>(&mut self, d: &MjData<M>) {
        let (geom_bodyid, contacts) = (d.model().geom_bodyid(), d.contact());
        for t in self.terms.iter_mut().flatten() {
            match t {
                Tracked::Feet(f) => {
                    for (i, &foot) in f.feet.iter().enumerate() {
                        let touching = contacts
                            .iter()
                            .any(|c| pairs(foot, f.floor, c.geom, geom_bodyid).is_some());
                        f.contact_substeps[i] = if touching {
                            f.contact_substeps[i].saturating_add(1)
                        } else {
                            0
                        };
                    }
                }
                Tracked::SelfContacts {
                    inside,
                    threshold,
                    hits,
                } => {
                    let within = |g: i32| g >= 0 && inside[geom_bodyid[g as usize] as usize];
                    let first = contacts
                        .iter()
                        .position(|c| within(c.geom[0]) && within(c.geom[1]));
                    if let Some(k) = first {
                        // k < ncon.
                        let f = d.try_contact_force(k).unwrap_or_default();
                        if (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt() > *threshold {
                            *hits += 1;
                        }
                    }
                }
            }
        }
    }

    /// After the physics, before the reward: each foot's landing value this step, from the last
    /// substep's contacts and the sites' heights.
    pub fn before_reward<M: ModelType>(&mut self, d: &MjData<M>) {
        let (geom_bodyid, contacts, site_xpos) =
            (d.model().geom_bodyid(), d.contact(), d.site_xpos());
        let frame_skip = self.frame_skip;
        for t in self.terms.iter_mut().flatten() {
            let Tracked::Feet(f) = t else { continue };
            for i in 0..f.feet.len() {
                let n = f.contact_substeps[i];
                let landed = n > 0 && n <= frame_skip;
                f.value[i] = if f.swing {
                    if n == 0 {
                        let h = site_xpos[f.sites[i]][2].clamp(0.0, f.max_height);
                        f.peak[i] = f.peak[i].max(h);
                    }
                    let cost = if landed {
                        let e = f.peak[i] / f.target - 1.0;
                        e * e
                    } else {
                        0.0
                    };
                    if landed {
                        f.peak[i] = 0.0;
                    }
                    cost
                } else if landed {
                    net_force(d, f.feet[i], f.floor, contacts, geom_bodyid)
                } else {
                    0.0
                };
            }
        }
    }

    /// The kernel of reward term `i` before its gate: the sum over feet, or the substeps counted.
    pub fn kernel(&self, i: usize) -> f64 {
        match self.terms.get(i).and_then(Option::as_ref) {
            Some(Tracked::Feet(f)) => crate::numerics::pairwise_sum(f.value.len(), &|k| f.value[k]),
            Some(Tracked::SelfContacts { hits, .. }) => f64::from(*hits),
            None => 0.0,
        }
    }
}

/// `Some(true)` when the contact pairs the foot (as its second geom) with the floor,
/// `Some(false)` when the foot is its first geom, None when it does not pair them.
fn pairs(foot: Part, floor: Part, g: [i32; 2], geom_bodyid: &[i32]) -> Option<bool> {
    if foot.holds(g[1], geom_bodyid) && floor.holds(g[0], geom_bodyid) {
        Some(true)
    } else if foot.holds(g[0], geom_bodyid) && floor.holds(g[1], geom_bodyid) {
        Some(false)
    } else {
        None
    }
}

/// ‖Σ F‖ over the foot's contacts with the floor: each contact's force (`mj_contactForce`, in
/// its frame) turned to the world frame and to the force on the foot.
fn net_force<M: ModelType>(
    d: &MjData<M>,
    foot: Part,
    floor: Part,
    contacts: &[mujoco_rs::mujoco_c::mjContact],
    geom_bodyid: &[i32],
) -> f64 {
    let mut total = [0.0f64; 3];
    for (k, c) in contacts.iter().enumerate() {
        let Some(second) = pairs(foot, floor, c.geom, geom_bodyid) else {
            continue;
        };
        // k < ncon.
        let f = d.try_contact_force(k).unwrap_or_default();
        // The frame's rows are the normal (from the first geom to the second) and the two
        // tangents; every contact of one foot with the floor is oriented the same way (on the
        // foot), so the norm of the sum is the contact sensor's netforce.
        let sign = if second { 1.0 } else { -1.0 };
        for (j, t) in total.iter_mut().enumerate() {
            *t += sign * (f[0] * c.frame[j] + f[1] * c.frame[3 + j] + f[2] * c.frame[6 + j]);
        }
    }
    (total[0] * total[0] + total[1] * total[1] + total[2] * total[2]).sqrt()
}
