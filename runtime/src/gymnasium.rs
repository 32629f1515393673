//! The Gymnasium MuJoCo v5 suite as typed envs, generated from `specs/gymnasium/` by
//! [`env!`](macro@crate::env). Each type wraps the same core as the dynamic [`Env`](crate::Env), so
//! `AntV5::make()` and `Env::make("Ant-v5", &[])` give the same trajectories.
//!
//! ```no_run
//! use envc::gymnasium::{AntV5, AntV5Action, AntV5Config};
//! let mut env = AntV5::new(&AntV5Config::default().ctrl_cost_weight(0.1))?;
//! let (obs, info) = env.reset(Some(0));
//! assert_eq!(obs.cfrc_ext().len(), 78);
//! println!("x = {}", info.x_position);
//! let step = env.step(&AntV5Action::zeros())?;
//! println!("{} {}", step.reward, step.info.reward_forward);
//! # Ok::<(), envc::EnvError>(())
//! ```

crate::env!("../specs/gymnasium/ant.toml");
crate::env!("../specs/gymnasium/half_cheetah.toml");
crate::env!("../specs/gymnasium/hopper.toml");
crate::env!("../specs/gymnasium/humanoid.toml");
crate::env!("../specs/gymnasium/humanoidstandup.toml");
crate::env!("../specs/gymnasium/inverted_double_pendulum.toml");
crate::env!("../specs/gymnasium/inverted_pendulum.toml");
crate::env!("../specs/gymnasium/pusher.toml");
crate::env!("../specs/gymnasium/reacher.toml");
crate::env!("../specs/gymnasium/swimmer.toml");
crate::env!("../specs/gymnasium/walker2d.toml");
