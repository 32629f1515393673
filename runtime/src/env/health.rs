//! Health checks: whether the current state is healthy, and which check and element fail it.

use envspec::ir::*;

use super::Env;

impl Env {
    /// Why the current state is unhealthy: the first health check that fails, with the first
    /// element that fails it (None when every check holds). For explaining endings (`envc run`);
    /// not on the step path.
    pub fn unhealthy(&self) -> Option<Unhealthy> {
        let c = self.spec.health.iter().find(|c| !self.check(c))?;
        let (element, value) = c
            .sources
            .iter()
            .flat_map(|s| {
                let f = self.sim.field(s.field);
                s.indices
                    .iter()
                    .zip(&s.names)
                    .map(move |(&i, n)| (n.clone(), f[i]))
            })
            .find(|(_, x)| !check_value(&c.kind, *x))
            .unwrap_or_default();
        Some(Unhealthy {
            check: c.name.clone(),
            rule: envspec::describe::check(c),
            element,
            value,
        })
    }

    /// Whether every element the check reads passes it.
    pub(super) fn check(&self, c: &HealthCheck) -> bool {
        c.sources.iter().all(|s| {
            let f = self.sim.field(s.field);
            s.indices.iter().all(|&i| check_value(&c.kind, f[i]))
        })
    }
}

/// Whether one element passes a health check.
fn check_value(kind: &CheckKind, x: f64) -> bool {
    match *kind {
        CheckKind::Finite => x.is_finite(),
        CheckKind::InRange {
            lo,
            hi,
            closed: true,
        } => lo <= x && x <= hi,
        CheckKind::InRange {
            lo,
            hi,
            closed: false,
        } => lo < x && x < hi,
        CheckKind::FailsIf { op, value } => !match op {
            CmpOp::Lt => x < value,
            CmpOp::Le => x <= value,
            CmpOp::Gt => x > value,
            CmpOp::Ge => x >= value,
        },
    }
}

/// A failed health check, as [`Env::unhealthy`] reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct Unhealthy {
    /// The check's name in the spec (`[health.<name>]`).
    pub check: String,
    /// What the check requires, in words.
    pub rule: String,
    /// The first element that fails it, e.g. `qpos[1] (rootz)`, and its value.
    pub element: String,
    /// That element's value.
    pub value: f64,
}
