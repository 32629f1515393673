//! MuJoCo's process-wide timer callback, cleared while envc steps (every core uses this).

use std::sync::{Mutex, MutexGuard};

/// Run `f` with MuJoCo's process-wide timer callback `mjcb_time` cleared, and put it back after.
///
/// `import mujoco` (MuJoCo's Python bindings, which Gymnasium's MuJoCo envs import) installs a
/// clock there, and every `mj_step` then reads it for each of its profiling timers (`mjData.timer`):
/// about 2.5 µs per `mj_step` on the benchmark machine, +60 % on InvertedPendulum's physics
/// (docs/PERFORMANCE.md). envc never reads `mjData.timer`, and timers do not change the physics.
/// Safe to nest and to call from threads that released the GIL: the first caller in clears the
/// callback, the last one out puts it back. Meanwhile a `mujoco.mj_step` on another thread runs
/// without the clock (its timer statistics miss those steps, nothing else).
pub fn without_mujoco_timer<T>(f: impl FnOnce() -> T) -> T {
    type Clock = Option<unsafe extern "C" fn() -> f64>;
    // Callers inside, and the callback they found.
    static INSIDE: Mutex<(usize, Clock)> = Mutex::new((0, None));
    fn lock() -> MutexGuard<'static, (usize, Clock)> {
        INSIDE.lock().unwrap_or_else(|e| e.into_inner())
    }
    struct Leave;
    impl Drop for Leave {
        fn drop(&mut self) {
            let mut inside = lock();
            inside.0 -= 1;
            if inside.0 == 0 {
                // SAFETY: a pointer-sized global of libmujoco, written back as the first caller
                // found it; every writer from envc holds the lock.
                unsafe { mjcb_time = inside.1 };
            }
        }
    }
    {
        let mut inside = lock();
        if inside.0 == 0 {
            // SAFETY: as above; MuJoCo calls the callback only when it is non-null.
            inside.1 = unsafe {
                let found = mjcb_time;
                mjcb_time = None;
                found
            };
        }
        inside.0 += 1;
    }
    let _leave = Leave;
    f()
}

unsafe extern "C" {
    /// `mjfTime mjcb_time` (mujoco.h): the clock MuJoCo's profiling timers read, or null.
    static mut mjcb_time: Option<unsafe extern "C" fn() -> f64>;
}
