//! Runtime errors. Spec problems keep their envspec diagnostics; everything else has a stable code
//! from the same table (`docs/errors.md`).

use std::path::PathBuf;

use envspec::{Code, Diagnostics};

#[derive(Debug, thiserror::Error)]
pub enum EnvError {
    /// The spec, an override or the model's MJCF did not check out.
    #[error("{0}")]
    Spec(#[from] Diagnostics),
    #[error("{}", crate::model_build::compile_error_text(path, message))]
    Compile { path: PathBuf, message: String },
    #[error("error[E1002]: the compiled model {} disagrees with its MJCF as read by envspec: {}", path.display(), envspec::diagnostic::escape(what))]
    ModelMismatch { path: PathBuf, what: String },
    #[error(
        "error[E1101]: action has {got} entries but {} expects {expected}",
        envspec::diagnostic::escape(env)
    )]
    ActionLength {
        env: String,
        expected: usize,
        got: usize,
    },
    #[error("error[E1102]: action[{index}] is {value}; actions must be finite")]
    NonFiniteAction { index: usize, value: f64 },
    #[error("error[E1103]: step() called before the first reset()")]
    NotReset,
    #[error(
        "error[E1104]: {env}: the reset step [reset.{step}] drew {draws} times without meeting its resample_until condition; reset again with another seed, or widen the condition"
    )]
    ResampleUnmet {
        env: String,
        step: String,
        draws: u32,
    },
    #[error("error[E1004]: {env}: MuJoCo failed {during}: {message}")]
    Mujoco {
        env: String,
        during: &'static str,
        message: String,
    },
    #[error("error[E1003]: {} cannot be run: {what}", path.display())]
    BadModelValues { path: PathBuf, what: String },
    #[error(
        "error[E1110]: {}: {}",
        envspec::diagnostic::escape(env),
        envspec::diagnostic::escape(what)
    )]
    Legged { env: String, what: String },
    #[error(
        "error[E1120]: {}: the compiled model has no {what}, which an [events] entry names (the MJCF reader and MuJoCo disagree)",
        envspec::diagnostic::escape(env)
    )]
    EventElement { env: String, what: String },
    #[error("error[E1403]: {}: {what}", envspec::diagnostic::escape(env))]
    TooLarge { env: String, what: String },
    #[error("{0}")]
    Numerics(#[from] crate::numerics::NumericsError),
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
            EnvError::NonFiniteAction { .. } => Code::E1102,
            EnvError::NotReset => Code::E1103,
            EnvError::ResampleUnmet { .. } => Code::E1104,
            EnvError::BadModelValues { .. } => Code::E1003,
            EnvError::Mujoco { .. } => Code::E1004,
            EnvError::Legged { .. } => Code::E1110,
            EnvError::TooLarge { .. } => Code::E1403,
            EnvError::EventElement { .. } => Code::E1120,
            EnvError::Numerics(e) => e.code(),
            EnvError::Render(e) => e.code(),
        }
    }
}
