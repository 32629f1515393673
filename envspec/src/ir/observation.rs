//! Observation segments: what each reads and how it is transformed.

use crate::conditions::Indicator;
use crate::selector::Selection;

/// Elementwise function applied to an observation segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Apply {
    /// `sin(x)`.
    Sin,
    /// `cos(x)`.
    Cos,
    /// `1.0 if x > 0 else 0.0` (numpy's `x > 0.0` in a float array: a touch sensor's contact).
    Positive,
}

/// One named observation segment.
#[derive(Clone, Debug)]
pub struct Segment {
    /// The table's name.
    pub name: String,
    /// The `doc` text.
    pub doc: String,
    /// What it reads.
    pub source: Selection,
    /// What is subtracted elementwise, if anything.
    pub minus: Option<Selection>,
    /// The function applied after the subtraction.
    pub apply: Option<Apply>,
    /// Clipped to `[lo, hi]` last.
    pub clip: Option<(f64, f64)>,
    /// `scale`: `source` and `minus` are each multiplied by it before the subtraction
    /// (Gymnasium-Robotics' velocities `× dt`).
    pub scale: Option<f64>,
    /// Each element replaced by one of two values by a comparison (after `apply`, before `clip`).
    pub indicator: Option<Indicator>,
    /// Start index in the observation vector.
    pub offset: usize,
}

impl Segment {
    /// The selections the segment reads: `source`, then `minus`.
    pub fn sources(&self) -> impl Iterator<Item = &Selection> {
        std::iter::once(&self.source).chain(&self.minus)
    }
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.source.len()
    }
    /// Whether it has no elements.
    pub fn is_empty(&self) -> bool {
        self.source.is_empty()
    }
    /// One readable name per element, e.g. `cos(qpos[hinge])`.
    pub fn element_names(&self) -> Vec<String> {
        (0..self.len())
            .map(|i| {
                let mut n = self.source.names[i].clone();
                if let Some(m) = &self.minus {
                    n = format!("{n} - {}", m.names[i]);
                }
                if let Some(s) = self.scale {
                    n = format!("{}·({n})", crate::value::format_float(s));
                }
                match self.apply {
                    Some(Apply::Sin) => format!("sin({n})"),
                    Some(Apply::Cos) => format!("cos({n})"),
                    Some(Apply::Positive) => format!("({n} > 0)"),
                    None => n,
                }
            })
            .collect()
    }
}
