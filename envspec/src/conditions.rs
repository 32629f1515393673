//! State conditions: a comparison of one number read from the simulation with a constant. They
//! gate reward terms (`only_if`: Gymnasium-Robotics' `if goal_distance > 0.2: reward += 2`), make
//! boolean info entries (`kind = "condition"`: `info["success"]`), and turn an observation
//! element into one of two values (`indicator`: Adroit's door `1.0 if open else -1.0`). Resolved
//! in `resolve/conditions.rs`; docs/spec-reference.md §7 ("Conditions").

use crate::selector::Selection;

/// A comparison: a condition's `op`, a health check's `fails_if`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CmpOp {
    /// `<`.
    Lt,
    /// `≤`.
    Le,
    /// `>`.
    Gt,
    /// `≥`.
    Ge,
}

/// The number a condition compares.
#[derive(Clone, Debug, PartialEq)]
pub enum Quantity {
    /// `source − minus` of one element (or `source` alone).
    Value {
        /// The element.
        source: Selection,
        /// Subtracted, if given.
        minus: Option<Selection>,
    },
    /// `‖source − minus‖₂`, summed as `np.linalg.norm` (OpenBLAS `ddot` of the numerics profile).
    Norm {
        /// The elements.
        source: Selection,
        /// Subtracted elementwise, if given.
        minus: Option<Selection>,
    },
}

impl Quantity {
    /// The selections it reads.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        let (Quantity::Value { source, minus } | Quantity::Norm { source, minus }) = self;
        std::iter::once(source).chain(minus)
    }
}

/// `quantity op value`: false for a NaN quantity, whatever the comparison (numpy's `>`).
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    /// What is compared.
    pub quantity: Quantity,
    /// The comparison.
    pub op: CmpOp,
    /// The constant compared with.
    pub value: f64,
}

impl Condition {
    /// Whether `x op value` holds.
    pub fn holds_for(&self, x: f64) -> bool {
        compare(self.op, x, self.value)
    }
}

/// `x op value` (false when either is NaN).
pub fn compare(op: CmpOp, x: f64, value: f64) -> bool {
    match op {
        CmpOp::Lt => x < value,
        CmpOp::Le => x <= value,
        CmpOp::Gt => x > value,
        CmpOp::Ge => x >= value,
    }
}

/// The spelling of a comparison (`<`, `<=`, `>`, `>=`).
pub fn op_text(op: CmpOp) -> &'static str {
    match op {
        CmpOp::Lt => "<",
        CmpOp::Le => "<=",
        CmpOp::Gt => ">",
        CmpOp::Ge => ">=",
    }
}

/// An observation segment's `indicator`: each element becomes `then` where `x op value`, else
/// `otherwise`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Indicator {
    /// The comparison.
    pub op: CmpOp,
    /// The constant compared with.
    pub value: f64,
    /// The element's value where the comparison holds.
    pub then: f64,
    /// The element's value where it does not (NaN included).
    pub otherwise: f64,
}

impl Indicator {
    /// The element's value for `x`.
    pub fn apply(&self, x: f64) -> f64 {
        if compare(self.op, x, self.value) {
            self.then
        } else {
            self.otherwise
        }
    }
}
