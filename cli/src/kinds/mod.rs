//! What the commands do for the kinds beyond tasks: `rollout`, `show`, `list` and `check` of a
//! maze (`[maze]`) and of a multi-agent spec (`[agents]`). Each command matches on the kind once
//! and calls in here.
pub mod maze;
pub mod multi_agent;
