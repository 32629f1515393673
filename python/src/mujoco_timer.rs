//! MuJoCo's process-wide timer callback, cleared while envc steps (every core uses this): the
//! runtime's, where MuJoCo's FFI lives.

pub use envc::without_mujoco_timer;
