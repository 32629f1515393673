//! How a goal distance sums its squares (a leaf: the IR and the manipulation tables both use it).

/// How a goal distance adds the squared differences (numpy's two ways to spell the same norm,
/// which differ in the last bit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoalNorm {
    /// `np.linalg.norm(a − b, axis=-1)`: `sqrt` of numpy's pairwise sum of the squares (spec
    /// `norm = "pairwise"`; the default of the reward kinds).
    Pairwise,
    /// `np.linalg.norm(a − b)`: OpenBLAS `ddot` as the env's numerics profile sums it, then
    /// `sqrt` (spec `norm = "blas"`; the default of `goal_reached`).
    Blas,
    /// The angle between two quaternions (w first): `2 · arccos(clip(w(a ⊗ conj(b)), −1, 1))`,
    /// numpy's `arccos` under the numerics profile (spec `norm = "angle"`; 4 elements).
    Angle,
    /// As `Angle`, after the achieved orientation's Z Euler angle is replaced by the desired
    /// one's (`quat2euler`, then `euler2quat`; spec `norm = "angle_ignoring_z"`, Gymnasium-Robotics'
    /// `ignore_z_target_rotation`, the pen's).
    AngleIgnoringZ,
}

impl GoalNorm {
    /// The `norm` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["pairwise", "blas", "angle", "angle_ignoring_z"];
    /// The norm a spec's `norm = "..."` names, if any.
    pub fn parse(s: &str) -> Option<GoalNorm> {
        match s {
            "pairwise" => Some(GoalNorm::Pairwise),
            "blas" => Some(GoalNorm::Blas),
            "angle" => Some(GoalNorm::Angle),
            "angle_ignoring_z" => Some(GoalNorm::AngleIgnoringZ),
            _ => None,
        }
    }
    /// The `norm` a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            GoalNorm::Pairwise => "pairwise",
            GoalNorm::Blas => "blas",
            GoalNorm::Angle => "angle",
            GoalNorm::AngleIgnoringZ => "angle_ignoring_z",
        }
    }
}
