//! What a vector env costs in memory, checked before any env is built: E1403 when the envs
//! would not fit.

use envspec::ResolvedSpec;

use super::VecEnv;
use crate::env::{Env, Footprint};
use crate::error::EnvError;

/// Observation rows per env a caller may hold beyond the vector's own two (see `VecEnv::per_env`):
/// the Python binding returns fresh arrays (the last two alive at once, and the next step's made
/// ahead while the workers step), and Gymnasium's batched observation space holds low and high
/// bounds and two masks over the whole batch.
const CALLER_OBS_ROWS: usize = 6;

/// Address space a worker thread maps (its stack, guard page and thread-local data).
const THREAD_MAPPED_BYTES: u64 = 8 << 20;

impl VecEnv {
    /// E1403: more envs than envc's limit.
    pub(super) fn check_count(spec: &ResolvedSpec, num_envs: usize) -> Result<(), EnvError> {
        if num_envs > envspec::limits::MAX_VEC_ENVS {
            return Err(EnvError::TooLarge {
                env: spec.id.clone(),
                what: format!(
                    "{num_envs} envs are beyond envc's limit of {} per vector env",
                    envspec::limits::MAX_VEC_ENVS
                ),
            });
        }
        Ok(())
    }

    /// What each env costs: its own footprint and its rows of the batch buffers (observations
    /// and goals twice here, and [`CALLER_OBS_ROWS`] times more for a caller that copies the
    /// batch out).
    pub(super) fn per_env(first: &Env) -> Footprint {
        let spec = first.spec();
        let row = spec.obs_dim + 2 * super::goal_dim(spec);
        let rows = ((2 + CALLER_OBS_ROWS) * row * 8 + spec.act_dim() * 12 + 64) as u64;
        let f = first.footprint();
        Footprint {
            resident: f.resident.saturating_add(rows),
            mapped: f.mapped.saturating_add(rows),
        }
    }

    /// E1403: `num_envs` envs of `per_env` each do not fit in the memory left, or in the
    /// address space `ulimit -v` leaves.
    pub(super) fn check_memory(
        id: &str,
        num_envs: usize,
        threads: usize,
        per_env: Footprint,
    ) -> Result<(), EnvError> {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        let budget = crate::memory::budget();
        let n = num_envs as u64;
        let resident = per_env.resident.saturating_mul(n);
        // Each worker thread maps its stack.
        let mapped = per_env
            .mapped
            .saturating_mul(n)
            .saturating_add(threads.min(num_envs) as u64 * THREAD_MAPPED_BYTES);
        let refuse = |need: u64, each: u64, free: u64, what: &str| EnvError::TooLarge {
            env: id.to_string(),
            what: format!(
                "{num_envs} envs need about {:.1} GiB of {what} ({:.2} MiB each), and {:.1} GiB is available; use fewer envs",
                gib(need),
                mib(each),
                gib(free)
            ),
        };
        if let Some(free) = budget.memory
            && resident > free
        {
            return Err(refuse(resident, per_env.resident, free, "memory"));
        }
        if let Some(free) = budget.address_space
            && mapped > free
        {
            return Err(refuse(
                mapped,
                per_env.mapped,
                free,
                "address space under this process's limit (ulimit -v or the kernel's commit limit)",
            ));
        }
        if let Some(cap) = budget.mapped_cap
            && mapped > cap
        {
            return Err(refuse(
                mapped,
                per_env.mapped,
                cap,
                "address space, mostly MuJoCo arenas (at most 8 times the machine's memory and swap may be mapped)",
            ));
        }
        Ok(())
    }

    /// What each env of this vector costs in memory, as [`VecEnv::make`] checked it before
    /// making them (resident and mapped bytes).
    pub fn footprint_per_env(&self) -> Footprint {
        self.per_env
    }
}
