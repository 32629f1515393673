//! What `envc show` and `envc diff` print about a spec's compiled model, apart from running it:
//! the model's inventory with pasteable selectors, the per-joint actuator table, and the
//! differences between two compiled models.

pub mod inventory;
pub mod joint_table;
pub mod model_diff;
