//! Runtime errors. Spec problems keep their envspec diagnostics; everything else has a stable code
//! from the same table (`docs/errors.md`).

use std::path::PathBuf;

use envspec::{Code, Diagnostics};

/// Why building, resetting or stepping an env failed; every variant has a stable code.
#[derive(Debug, thiserror::Error)]
pub enum EnvError {
    /// The spec, an override or the model's MJCF did not check out.
    #[error("{0}")]
    Spec(#[from] Diagnostics),
    /// MuJoCo refused to compile the model (E1001).
    #[error("{}", crate::model_build::compile_error_text(path, message))]
    Compile {
        /// The MJCF or URDF file MuJoCo compiled.
        path: PathBuf,
        /// MuJoCo's own error text.
        message: String,
    },
    /// MuJoCo's compiled model and envspec's reading of the MJCF disagree (E1002).
    #[error("error[E1002]: the compiled model {} disagrees with its MJCF as read by envspec: {}", path.display(), envspec::diagnostic::escape(what))]
    ModelMismatch {
        /// The model file.
        path: PathBuf,
        /// What differs.
        what: String,
    },
    /// The action has the wrong number of entries (E1101).
    #[error(
        "error[E1101]: action has {got} entries but {} expects {expected}",
        envspec::diagnostic::escape(env)
    )]
    ActionLength {
        /// The env's id.
        env: String,
        /// The action space's size.
        expected: usize,
        /// The entries given.
        got: usize,
    },
    /// `Env::set_state` given a `qpos` or `qvel` of another length than the model's (E1105).
    #[error(
        "error[E1105]: {} has {got} entries but {} expects {expected}",
        what,
        envspec::diagnostic::escape(env)
    )]
    StateLength {
        /// The env's id.
        env: String,
        /// `qpos` or `qvel`.
        what: &'static str,
        /// The model's size.
        expected: usize,
        /// The entries given.
        got: usize,
    },
    /// An action entry is NaN or infinite (E1102).
    #[error("error[E1102]: action[{index}] is {value}; actions must be finite")]
    NonFiniteAction {
        /// Which entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// `step` before any `reset` (E1103).
    #[error("error[E1103]: step() called before the first reset()")]
    NotReset,
    /// A reset step's `resample_until` condition was not met within its draw limit (E1104).
    #[error(
        "error[E1104]: {env}: the reset step [reset.{step}] ran {draws} times without meeting its condition (resample_until, or a settle step's watch); reset again with another seed, or widen the condition"
    )]
    ResampleUnmet {
        /// The env's id.
        env: String,
        /// The `[reset.<step>]` name.
        step: String,
        /// How many draws were made.
        draws: u32,
    },
    /// MuJoCo raised an error while running (E1004).
    #[error("error[E1004]: {env}: MuJoCo failed {during}: {message}")]
    Mujoco {
        /// The env's id.
        env: String,
        /// What the env was doing, worded to follow "MuJoCo failed".
        during: &'static str,
        /// MuJoCo's message.
        message: String,
    },
    /// The compiled model has values the env cannot run with (E1003).
    #[error("error[E1003]: {} cannot be run: {what}", path.display())]
    BadModelValues {
        /// The model file.
        path: PathBuf,
        /// Which value, and why.
        what: String,
    },
    /// A legged-task setting does not fit the model (E1110).
    #[error(
        "error[E1110]: {}: {}",
        envspec::diagnostic::escape(env),
        envspec::diagnostic::escape(what)
    )]
    Legged {
        /// The env's id.
        env: String,
        /// What does not fit.
        what: String,
    },
    /// An `[end_effector]` or `[init] mocap` body the compiled model cannot drive (E1111).
    #[error(
        "error[E1111]: {}: {}",
        envspec::diagnostic::escape(env),
        envspec::diagnostic::escape(what)
    )]
    Mocap {
        /// The env's id.
        env: String,
        /// What does not fit.
        what: String,
    },
    /// An `[events]` entry names an element the compiled model lacks (E1120).
    #[error(
        "error[E1120]: {}: the compiled model has no {what}, which an [events] entry names (the MJCF reader and MuJoCo disagree)",
        envspec::diagnostic::escape(env)
    )]
    EventElement {
        /// The env's id.
        env: String,
        /// The missing element.
        what: String,
    },
    /// A size is past one of envc's limits (`envspec::limits`, docs/limits.md) (E1403).
    #[error("error[E1403]: {}: {what}", envspec::diagnostic::escape(env))]
    TooLarge {
        /// The env's id.
        env: String,
        /// What is too large.
        what: String,
    },
    /// The numerics profile could not be chosen.
    #[error("{0}")]
    Numerics(#[from] crate::numerics::NumericsError),
    /// Rendering failed or its settings do not fit the model.
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
}

impl EnvError {
    /// The stable code (the first one for a list of spec diagnostics).
    pub fn code(&self) -> Code {
        match self {
            EnvError::Spec(d) => d.0.first().map(|d| d.code).unwrap_or(Code::E0104),
            EnvError::Compile { .. } => Code::E1001,
            EnvError::ModelMismatch { .. } => Code::E1002,
            EnvError::ActionLength { .. } => Code::E1101,
            EnvError::StateLength { .. } => Code::E1105,
            EnvError::NonFiniteAction { .. } => Code::E1102,
            EnvError::NotReset => Code::E1103,
            EnvError::ResampleUnmet { .. } => Code::E1104,
            EnvError::BadModelValues { .. } => Code::E1003,
            EnvError::Mujoco { .. } => Code::E1004,
            EnvError::Legged { .. } => Code::E1110,
            EnvError::Mocap { .. } => Code::E1111,
            EnvError::TooLarge { .. } => Code::E1403,
            EnvError::EventElement { .. } => Code::E1120,
            EnvError::Numerics(e) => e.code(),
            EnvError::Render(e) => e.code(),
        }
    }
}

/// Why the compiled model cannot serve the spec's `[actions]` or legged terms (E1110).
pub(crate) fn unfit(spec: &envspec::ResolvedSpec, what: String) -> EnvError {
    EnvError::Legged {
        env: spec.id.clone(),
        what,
    }
}
