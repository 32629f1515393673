//! `[physics]` options: the solver options and integrators a spec may set.

/// A numeric `mjOption` field `[physics]` may set (MJCF's `<option>` attribute of that name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverOption {
    /// `cone`: 0 pyramidal (MuJoCo's default), 1 elliptic.
    Cone,
    /// `iterations`: main solver iterations.
    Iterations,
    /// `ls_iterations`: line-search iterations.
    LsIterations,
    /// `noslip_iterations`: no-slip solver iterations.
    NoslipIterations,
    /// `ccd_iterations`: convex collision iterations.
    CcdIterations,
    /// `tolerance`: main solver tolerance.
    Tolerance,
    /// `ls_tolerance`: line-search tolerance.
    LsTolerance,
    /// `impratio`: frictional-to-normal impedance ratio.
    Impratio,
}

/// The `[physics]` solver options: (key, option, whole number, smallest value). `cone` is read as
/// a name (`"pyramidal"`, `"elliptic"`); the others as numbers.
pub const SOLVER_OPTIONS: &[(&str, SolverOption, bool, f64)] = &[
    ("cone", SolverOption::Cone, true, 0.0),
    ("iterations", SolverOption::Iterations, true, 1.0),
    ("ls_iterations", SolverOption::LsIterations, true, 1.0),
    (
        "noslip_iterations",
        SolverOption::NoslipIterations,
        true,
        0.0,
    ),
    ("ccd_iterations", SolverOption::CcdIterations, true, 1.0),
    ("tolerance", SolverOption::Tolerance, false, 0.0),
    ("ls_tolerance", SolverOption::LsTolerance, false, 0.0),
    ("impratio", SolverOption::Impratio, false, f64::MIN_POSITIVE),
];

/// MuJoCo's integrators, spelt as in MJCF's `<option integrator>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// `Euler` (MuJoCo's default): semi-implicit Euler.
    Euler,
    /// `RK4`: fourth-order Runge-Kutta.
    Rk4,
    /// `implicit`: implicit in velocity.
    Implicit,
    /// `implicitfast`: implicit in velocity, without the Coriolis terms.
    ImplicitFast,
}

impl Integrator {
    /// The `integrator` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["Euler", "RK4", "implicit", "implicitfast"];
    /// The integrator a spec's `integrator = "..."` names, if any.
    pub fn parse(s: &str) -> Option<Integrator> {
        match s {
            "Euler" => Some(Integrator::Euler),
            "RK4" => Some(Integrator::Rk4),
            "implicit" => Some(Integrator::Implicit),
            "implicitfast" => Some(Integrator::ImplicitFast),
            _ => None,
        }
    }
    /// The name as MJCF and specs write it.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "Euler",
            Integrator::Rk4 => "RK4",
            Integrator::Implicit => "implicit",
            Integrator::ImplicitFast => "implicitfast",
        }
    }
}
