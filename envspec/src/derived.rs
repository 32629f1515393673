//! Derived values (`[derived.<name>]`): quantities computed from the state, in document order,
//! after every reset and after every step's physics (or once per episode with `at = "reset"`),
//! read anywhere a selector is read as `derived[name]`. Gymnasium-Robotics' Adroit pen divides
//! its orientation vectors by lengths measured at reset and compares them with a dot product.
//! Resolved in `resolve/derived.rs`, computed in `runtime/src/derived.rs`;
//! docs/spec-reference.md §23.

use crate::selector::Selection;

/// What a derived value computes.
#[derive(Clone, Debug, PartialEq)]
pub enum DerivedKind {
    /// `(source − minus) / divide_by`, elementwise (numpy's `(a - b) / d`).
    Difference {
        /// The elements.
        source: Selection,
        /// Subtracted, if given.
        minus: Option<Selection>,
        /// One number every element is divided by, if given.
        divide_by: Option<Selection>,
    },
    /// `‖source − minus‖₂`, as `np.linalg.norm` (OpenBLAS `ddot` of the numerics profile).
    Norm {
        /// The elements.
        source: Selection,
        /// Subtracted, if given.
        minus: Option<Selection>,
    },
    /// `Σ sourceₖ · withₖ`, as `np.dot` of two float64 vectors (OpenBLAS `ddot`).
    Dot {
        /// The first vector.
        source: Selection,
        /// The second, of the same length.
        with: Selection,
    },
    /// Contacts of the last forward pass between two elements (or one and anything): whether
    /// they touch, how many contacts, the summed normal force, or the net force on the first.
    Contact {
        /// The first element.
        a: ContactSide,
        /// The second (`None`: any geom).
        b: Option<ContactSide>,
        /// What is reported.
        value: ContactValue,
    },
}

/// One side of a contact pair: a geom, or every geom of a body (`world`: the world's geoms).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSide {
    /// The geom's or the body's name.
    pub name: String,
    /// The name is a body's (a geom of that name is preferred).
    pub body: bool,
}

/// What a `contact` derived value reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactValue {
    /// `1.0` if any contact pairs the two, else `0.0`.
    Touching,
    /// The number of contacts between them.
    Count,
    /// `Σ` of the contacts' normal forces (`mj_contactForce`'s first component, N).
    NormalForce,
    /// The net contact force on the first element, in the world frame (3 values, N).
    Force,
}

/// `value` names of a `contact` derived value, as a spec writes them.
pub const CONTACT_VALUES: &[(&str, ContactValue)] = &[
    ("touching", ContactValue::Touching),
    ("count", ContactValue::Count),
    ("normal_force", ContactValue::NormalForce),
    ("force", ContactValue::Force),
];

/// One `[derived.<name>]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Derived {
    /// The table's name: `derived[name]` reads it.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// What it computes.
    pub kind: DerivedKind,
    /// `at = "reset"`: computed after each reset only, and held through the episode.
    pub at_reset: bool,
    /// Its first index in the derived buffer.
    pub offset: usize,
    /// Its number of values.
    pub len: usize,
}

impl Derived {
    /// The selections it reads.
    pub fn sources(&self) -> Vec<&Selection> {
        match &self.kind {
            DerivedKind::Difference {
                source,
                minus,
                divide_by,
            } => std::iter::once(source)
                .chain(minus)
                .chain(divide_by)
                .collect(),
            DerivedKind::Norm { source, minus } => std::iter::once(source).chain(minus).collect(),
            DerivedKind::Dot { source, with } => vec![source, with],
            DerivedKind::Contact { .. } => vec![],
        }
    }
    /// The `kind` a spec writes for it.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            DerivedKind::Difference { .. } => "difference",
            DerivedKind::Norm { .. } => "norm",
            DerivedKind::Dot { .. } => "dot",
            DerivedKind::Contact { .. } => "contact",
        }
    }
}
