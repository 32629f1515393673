//! envc runtime: executes resolved envc specs over MuJoCo with Gymnasium semantics.
//!
//! MuJoCo 3.17.0 by default; feature `mujoco-4.0.1` builds against 4.0.1 (docs/mujoco-versions.md).
//!
//! ```no_run
//! use envc::Env;
//! let mut env = Env::from_spec_file("specs/gymnasium/hopper.toml", &[])?;
//! let (obs, _info) = env.reset(Some(0));
//! assert_eq!(obs.len(), 11);
//! let step = env.step(&[0.1, -0.2, 0.3])?;
//! println!("reward {} terminated {}", step.reward, step.terminated);
//! # Ok::<(), envc::EnvError>(())
//! ```

#![warn(missing_docs)]

// Generated code names `::envc::…`; this makes those paths work inside envc itself.
extern crate self as envc;

// The bindings of the MuJoCo this build is for, under one name (`mujoco_rs`) for every module;
// re-exported as `envc::mujoco_rs` for code that reads MuJoCo's structs beside envc.
#[cfg(not(feature = "mujoco-4.0.1"))]
pub extern crate mujoco_rs_3_17_0 as mujoco_rs;
#[cfg(feature = "mujoco-4.0.1")]
pub extern crate mujoco_rs_4_0_1 as mujoco_rs;

/// The MuJoCo version this build of envc is for (its bindings; the library it loads must match).
#[cfg(not(feature = "mujoco-4.0.1"))]
pub const MUJOCO_VERSION: &str = "3.17.0";
/// The MuJoCo version this build of envc is for (its bindings; the library it loads must match).
#[cfg(feature = "mujoco-4.0.1")]
pub const MUJOCO_VERSION: &str = "4.0.1";

mod any_env;
pub mod bench;
mod derived;
pub mod describe;
pub mod env;
pub mod environment;
pub mod error;
pub mod events;
pub mod goal;
mod goal_parts;
pub mod gymnasium;
pub mod joint_env;
mod landings;
mod latency;
mod legged;
mod manipulation;
pub mod maze;
pub mod memory;
mod mj;
mod model_build;
mod model_values;
pub mod multi_agent;
pub mod npy;
pub mod numerics;
mod obs_noise;
mod observe;
pub mod os;
pub mod registry;
pub mod render;
pub mod rng;
pub mod terrain;
pub mod typed;
pub mod vector;

pub use any_env::{AnyEnv, open};
pub use env::{BoxSpace, Env, Footprint, Info, Step, Unhealthy};
/// A typed env from a spec, checked at compile time: `envc::env!("specs/my_robot.toml")`.
pub use envc_codegen::env;
/// Typed per-agent types for one conf of a multi-agent spec: `envc::multi_agent_env!(pub Name = "specs/mamujoco/ant.toml", agent_conf = "2x4")`.
pub use envc_codegen::multi_agent_env;
pub use environment::Environment;
pub use envspec;
pub use envspec::{AnySpec, Kind, Override, ParamValue, ResolvedSpec};
pub use error::EnvError;
pub use joint_env::{JointAction, JointEnv, JointStep};
pub use mj::log::mujoco_error_message;
pub use mj::without_mujoco_timer;
pub use vector::{Autoreset, Stepped, VecEnv};

/// The file of the MuJoCo library this process loaded, from the process's memory map (Linux).
pub fn mujoco_library_path() -> Option<std::path::PathBuf> {
    mujoco_version();
    let maps = std::fs::read_to_string("/proc/self/maps").ok()?;
    maps.lines()
        .filter_map(|l| l.split_whitespace().nth(5))
        .find(|p| {
            std::path::Path::new(p)
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("libmujoco.so"))
        })
        .map(std::path::PathBuf::from)
}

/// The version of the MuJoCo library this process linked (`mj_versionString`).
pub fn mujoco_version() -> String {
    mj::version()
}
