//! One module per subcommand.
pub mod bench;
pub mod check;
pub mod collect;
pub mod dataset;
pub mod diff;
pub mod info;
pub mod list;
pub mod new;
pub mod render;
pub mod rollout;
pub mod run;
pub mod show;
