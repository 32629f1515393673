//! What one env costs in memory (`Env::footprint`), for vector envs to check before they build.

use std::sync::Arc;

use mujoco_rs::mujoco_c::mjData;
use mujoco_rs::prelude::{MjData, MjModel};

use super::Env;
use crate::mj::log as mujoco_log;
use crate::mj::{self, Call};

/// What one env holds beyond the model it shares, in the two measures a process runs out of:
/// `resident`, the memory it writes (what the machine's available memory must hold), and
/// `mapped`, its address space (what `ulimit -v` counts: MuJoCo maps each env's whole arena,
/// 13 MiB for Hopper, and writes a few hundred KiB of it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// Bytes written: the `mjData` buffer, the arena pages stepping touches, the env's vectors.
    pub resident: u64,
    /// Bytes of address space: as `resident`, with the whole arena.
    pub mapped: u64,
}

/// Per-env bytes beyond the vectors [`Env::footprint`] counts (the struct, small vectors,
/// allocator rounding); measured at about 20 KiB for the Gymnasium suite.
const ENV_OVERHEAD_BYTES: u64 = 32 << 10;
/// Arena bytes counted beyond twice what the probe used (pages, the stack's first frames).
const ARENA_SLACK_BYTES: u64 = 64 << 10;
/// Physics steps the arena probe runs from `qpos0` with zero controls.
const PROBE_STEPS: usize = 50;

/// The most arena and stack bytes `mj_forward` and a few zero-control steps use on a scratch
/// `mjData` of `model` (None when MuJoCo fails: the caller counts the whole arena).
fn arena_in_use(model: &Arc<MjModel>) -> Option<u64> {
    let mut d = mujoco_log::guard(|| MjData::try_new(Arc::clone(model)))
        .ok()?
        .ok()?;
    let probe = (|| {
        mj::call(&mut d, Call::Forward)?;
        for _ in 0..PROBE_STEPS {
            mj::call(&mut d, Call::Step { n: 1, rne: false })?;
        }
        Ok::<(), String>(())
    })();
    // The probe's warnings belong to no env.
    mujoco_log::drain_into(&mut Vec::new());
    probe.ok()?;
    let f = d.ffi();
    Some((f.maxuse_arena as u64).saturating_add(f.maxuse_stack as u64))
}

impl Env {
    /// Bytes of this env's `mjData` as mapped: its buffer and its whole arena.
    pub fn data_bytes(&self) -> u64 {
        let d = self.sim.data.ffi();
        (d.nbuffer as u64).saturating_add(d.narena as u64)
    }
    /// What one more env of this spec holds beyond the shared model (see [`Footprint`]). Runs a
    /// short probe on a scratch `mjData` of the model to see how much of the arena stepping
    /// touches; this env is left as it is.
    pub fn footprint(&self) -> Footprint {
        let d = self.sim.data.ffi();
        let (buffer, arena) = (d.nbuffer as u64, d.narena as u64);
        let rings = self.obs_noise.as_ref().map_or(0, |n| n.bytes())
            + self.latency.as_ref().map_or(0, |l| l.bytes());
        // An env whose events write the model steps its own copy of it.
        let model = if self
            .spec
            .events
            .iter()
            .any(envspec::events::Event::writes_model)
        {
            self.sim.model.ffi().nbuffer as u64
        } else {
            0
        };
        // The vectors sized by the spec: the observation and its two bounds, info values, state
        // copies; plus the allocator's and the struct's own overhead.
        let numbers = 3 * self.spec.obs_dim
            + self.step_info_values.len()
            + self.reset_info_values.len()
            + self.qpos_init.len()
            + self.qvel_init.len()
            + self.sim.ten_j.len()
            + self.sim.action.len()
            + self.term_values.len()
            + self.draw.len();
        let own = (numbers * 8) as u64 + ENV_OVERHEAD_BYTES;
        // MuJoCo maps the arena whole but writes only what the solver and contacts use: the
        // pages a probe touched, twice over for states with more contacts than it met.
        let touched = arena_in_use(&self.sim.model).map_or(arena, |used| {
            used.saturating_mul(2)
                .saturating_add(ARENA_SLACK_BYTES)
                .min(arena)
        });
        // MuJoCo allocates the `mjData` struct itself too: its solver statistics make it
        // about 200 KiB, more than a small model's buffer.
        let header = std::mem::size_of::<mjData>() as u64;
        let common = header + buffer + rings + model + own;
        Footprint {
            resident: common.saturating_add(touched),
            mapped: common.saturating_add(arena),
        }
    }
}
