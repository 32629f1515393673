//! Observation noise and delay per `[observation.*]` segment, and action latency (`[latency]`):
//! the IR of what corrupts the env's signals in time and value (sim-to-real training terms).
//! Resolved by `resolve/noise.rs`, executed by the runtime's `obs_noise` and `latency` modules.
//! A spec that declares none of them has an empty [`Corruption`] and draws nothing new.

use std::fmt;

/// The distribution of one segment's noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoiseKind {
    /// `(2·u − 1) · level · scale`, `u = U[0, 1)` (MuJoCo Playground's noise): uniform on
    /// `[−level·scale, level·scale)`.
    Uniform,
    /// `z · level · scale`, `z` a standard normal: Gaussian with standard deviation `level·scale`.
    Gaussian,
}

impl NoiseKind {
    /// The `kind` values a spec may write (for suggestions).
    pub const NAMES: &'static [&'static str] = &["uniform", "gaussian"];
    /// The kind a spec's `kind = "..."` names, if any.
    pub fn parse(s: &str) -> Option<NoiseKind> {
        match s {
            "uniform" => Some(NoiseKind::Uniform),
            "gaussian" => Some(NoiseKind::Gaussian),
            _ => None,
        }
    }
    /// The name a spec writes for it.
    pub fn name(self) -> &'static str {
        match self {
            NoiseKind::Uniform => "uniform",
            NoiseKind::Gaussian => "gaussian",
        }
    }
}

/// Additive noise on every element of a segment, one draw per element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// The distribution drawn.
    pub kind: NoiseKind,
    /// The segment's amplitude (`scale`), before `level`.
    pub scale: f64,
    /// A multiplier shared by segments (Playground's `noise_config.level`), 1 by default.
    pub level: f64,
    /// `order = "level_scale_draw"`: `(level · scale) · draw` (Gymnasium-Robotics' and D4RL's
    /// `ratio * amp * uniform(-1, 1)`), where the default multiplies left to right from the
    /// draw, `draw · level · scale` (Playground's). The two round differently.
    pub scale_first: bool,
}

impl Noise {
    /// The `order` values a spec may write.
    pub const ORDERS: &'static [&'static str] = &["draw_level_scale", "level_scale_draw"];
}

impl Noise {
    /// The noise's standard deviation (for reports): `level·scale` (Gaussian) or `level·scale/√3`.
    pub fn std(&self) -> f64 {
        let a = self.level * self.scale;
        match self.kind {
            NoiseKind::Gaussian => a,
            NoiseKind::Uniform => a / 3f64.sqrt(),
        }
    }
}

impl fmt::Display for Noise {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.level * self.scale;
        match self.kind {
            NoiseKind::Uniform => write!(f, "uniform ±{a}")?,
            NoiseKind::Gaussian => write!(f, "gaussian std {a}")?,
        }
        if self.level != 1.0 {
            write!(f, " (level {} × scale {})", self.level, self.scale)?;
        }
        if self.scale_first {
            f.write_str(", (level · scale) · draw")?;
        }
        Ok(())
    }
}

/// What corrupts one resolved observation segment.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentCorruption {
    /// The segment's name and index in `ResolvedSpec::observation` (enabled segments only).
    pub name: String,
    /// Its index in `ResolvedSpec::observation` (the name is above).
    pub segment: usize,
    /// Added before the segment's `clip` (Isaac Lab's order: noise, then clip).
    pub noise: Option<Noise>,
    /// The segment reports its value from this many env steps ago (0: none).
    pub delay: usize,
}

/// Observation noise and delay (segments that declare either, in observation order) and the
/// action latency, in env steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Corruption {
    /// The segments with noise or delay, in observation order.
    pub segments: Vec<SegmentCorruption>,
    /// `[latency] action`: the env applies the action given this many steps earlier (0: none).
    pub action_latency: usize,
}

impl Corruption {
    /// Whether the spec declares none of these terms (the env then draws nothing new).
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty() && self.action_latency == 0
    }
    /// The corruption of the segment named `name`, if it has one.
    pub fn segment(&self, name: &str) -> Option<&SegmentCorruption> {
        self.segments.iter().find(|s| s.name == name)
    }
}
