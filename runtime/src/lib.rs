//! envc runtime.
