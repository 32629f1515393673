//! The envc spec language.
//!
//! A spec is a TOML file describing one environment: its MuJoCo model, parameters with defaults,
//! observation segments, reward terms, health checks, reset distributions and info entries. This
//! crate reads it with locations ([`Spec`]), checks it, and resolves it against the model's MJCF
//! into the IR ([`ResolvedSpec`]) that the runtime executes and the code generator describes.
//! It links no MuJoCo and has no proc-macro dependency.
//!
//! The language reference is `docs/spec-reference.md`; error codes are in `docs/errors.md`.
//!
//! ```no_run
//! use envspec::{load, Override};
//! let spec = load("specs/gymnasium/ant.toml".as_ref(), &[Override::text("ctrl_cost_weight", "0.1")])?;
//! assert_eq!(spec.obs_dim, 105);
//! # Ok::<(), envspec::Diagnostics>(())
//! ```

// Every public item says what it is or why it exists; CI denies warnings.
#![warn(missing_docs)]

pub mod bundle;
pub mod camera;
pub mod commands;
pub mod conditions;
pub mod dataset_spec;
pub mod derived;
pub mod describe;
pub mod diagnostic;
pub mod diff;
pub mod events;
pub mod goal;
pub mod goal_norm;
pub mod ir;
pub mod kind;
pub mod limits;
pub mod manipulation;
pub mod maze;
pub mod mjcf;
pub mod multi_agent;
pub mod noise;
pub mod open;
pub mod params;
pub mod path;
pub mod registry;
pub mod resolve;
pub mod selector;
pub mod source;
pub mod syntax;
pub mod urdf;
pub mod value;

pub use diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile};
pub use ir::ResolvedSpec;
pub use kind::Kind;
pub use mjcf::ModelInfo;
pub use open::{AnySpec, open, open_file};
pub use params::{Override, OverrideValue, Param, ParamType, ParamValue};
pub use resolve::{load, resolve};
pub use selector::{Field, Selection};
pub use syntax::Spec;
