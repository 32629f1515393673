//! W0401: `minus` that pairs elements of different joints. `qpos[7:] − default_pose` is only
//! meaningful when actuator k drives the joint at `qpos[7 + k]`; reordered actuator tables make
//! it pair a hip with a shoulder's default without any error.

use crate::diagnostic::{Code, Diagnostic};
use crate::ir::ResolvedSpec;
use crate::mjcf::{JointKind, ModelInfo};
use crate::selector::{Field, Selection};
use crate::syntax::Spec;

/// The joint each element of a selection belongs to, where that is defined: hinge and slide
/// positions and velocities by address, per-actuator fields by the actuator's joint.
fn joints_of(s: &Selection, m: &ModelInfo) -> Vec<Option<String>> {
    let by_adr = |adr: usize, q: bool| {
        m.joints
            .iter()
            .find(|j| {
                matches!(j.kind, JointKind::Hinge | JointKind::Slide)
                    && (if q { j.qposadr } else { j.dofadr }) == adr
            })
            .map(|j| j.name.clone())
    };
    s.indices
        .iter()
        .map(|&i| match s.field {
            Field::Qpos => by_adr(i, true),
            Field::Qvel => by_adr(i, false),
            Field::DefaultPose | Field::LastAction | Field::Ctrl | Field::ActuatorForce => m
                .actuators
                .get(i)
                .and_then(|a| a.target.clone())
                .filter(|t| m.joint(t).is_some()),
            _ => None,
        })
        .collect()
}

pub(super) fn warnings(spec: &Spec, r: &ResolvedSpec) -> Vec<Diagnostic> {
    let mut out = vec![];
    let mut check = |kind: &str, name: &str, a: &Selection, b: &Selection| {
        if a.len() != b.len() {
            return;
        }
        let (x, y) = (joints_of(a, &r.model), joints_of(b, &r.model));
        let pairs: Vec<(usize, &String, &String)> = x
            .iter()
            .zip(&y)
            .enumerate()
            .filter_map(|(k, (p, q))| match (p, q) {
                (Some(p), Some(q)) if p != q => Some((k, p, q)),
                _ => None,
            })
            .collect();
        let Some(&(k, p, q)) = pairs.first() else {
            return;
        };
        let section = match kind {
            "observation" => spec.observation.iter().find(|s| s.name == name),
            _ => spec.reward.iter().find(|s| s.name == name),
        };
        let loc = section.and_then(|s| s.get("minus").map(|v| v.loc.clone()));
        out.push(
            Diagnostic::new(
                Code::W0401,
                format!(
                    "[{kind}.{name}]: `{}` minus `{}` pairs elements of different joints at {} of {} places; the first is element {k}: `{p}` minus the value of `{q}`",
                    a.text,
                    b.text,
                    pairs.len(),
                    a.len()
                ),
            )
            .at_opt(loc)
            .label("the actuators are not in the order of the joints they drive")
            .help("list the [actuators.*] joints in model order (`envc show --model` prints it), or select the joints in actuator order"),
        );
    };
    for s in &r.observation {
        if let Some(m) = &s.minus {
            check("observation", &s.name, &s.source, m);
        }
    }
    for t in &r.reward {
        let v: Vec<&Selection> = t.kind.sources().collect();
        if let [a, b] = v.as_slice()
            && spec
                .reward
                .iter()
                .any(|s| s.name == t.name && s.get("minus").is_some())
        {
            check("reward", &t.name, a, b);
        }
    }
    out
}
