//! What std does not wrap, behind safe functions: the Linux calls envc makes (clocks, limits,
//! file systems, signals) and glibc's `pow`. The one user of `libc` apart from MuJoCo's bindings,
//! the renderer and the vector pool.

use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};
use std::time::Duration;

/// CPU time of the calling thread (`CLOCK_THREAD_CPUTIME_ID`).
pub(crate) fn thread_cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid clock id and a valid out-pointer; cannot fail on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// The soft address-space limit (`ulimit -v`) in bytes; None when unlimited or unreadable.
pub(crate) fn address_space_limit() -> Option<u64> {
    let mut lim = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the struct we pass.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut lim) } == 0;
    (ok && lim.rlim_cur != libc::RLIM_INFINITY).then_some(lim.rlim_cur)
}

/// Flush everything under `dir`'s file system to stable storage (`syncfs`): a published
/// dataset is on the disk before it is reported written.
pub fn sync_fs(dir: &std::path::Path) -> std::io::Result<()> {
    use std::os::fd::AsRawFd;
    let f = std::fs::File::open(dir)?;
    // SAFETY: syncfs on a descriptor we own, open for the whole call.
    if unsafe { libc::syncfs(f.as_raw_fd()) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}

/// Bytes an unprivileged user may still write on the file system holding `dir` (`statvfs`).
pub fn free_bytes(dir: &std::path::Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    // SAFETY: `st` is a plain C struct that statvfs fills; `c` is a valid NUL-terminated path.
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: as above; the pointers live for the call.
    if unsafe { libc::statvfs(c.as_ptr(), &mut st) } != 0 {
        return None;
    }
    Some((st.f_bavail as u64).saturating_mul(st.f_frsize as u64))
}

/// Die quietly when the reader of stdout goes away (`envc list | head`), as Unix tools do, instead
/// of failing in `println!`: SIGPIPE's default action. Call before starting threads.
pub fn default_sigpipe() {
    // SAFETY: setting a signal disposition; no handler of ours runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// The flag `stop_on_signals` raises.
static STOP_FLAG: AtomicPtr<AtomicBool> = AtomicPtr::new(std::ptr::null_mut());

/// On SIGINT, SIGTERM or SIGHUP, set `flag` (a long command then stops at its next check and
/// cleans up); a second signal of a kind has the default action, ending the process at once.
pub fn stop_on_signals(flag: &'static AtomicBool) {
    extern "C" fn raise(sig: libc::c_int) {
        let flag = STOP_FLAG.load(Ordering::Relaxed);
        // SAFETY: STOP_FLAG only ever holds a `&'static AtomicBool` (set below, before the
        // handler is installed); storing to an atomic is async-signal-safe.
        if let Some(flag) = unsafe { flag.as_ref() } {
            flag.store(true, Ordering::Relaxed);
        }
        // SAFETY: `signal` is async-signal-safe; the next signal of this kind takes its default.
        unsafe {
            libc::signal(sig, libc::SIG_DFL);
        }
    }
    STOP_FLAG.store(std::ptr::from_ref(flag).cast_mut(), Ordering::Relaxed);
    for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: the handler only stores to an atomic and resets its own disposition, both
        // async-signal-safe.
        unsafe {
            libc::signal(sig, raise as *const () as libc::sighandler_t);
        }
    }
}

unsafe extern "C" {
    /// glibc's `pow`. Called directly because the compiler rewrites `powf(x, 2.0)` into `x * x`,
    /// which differs from `pow` in the last bit (reference trap T5: numpy's `x**2` on a float64
    /// scalar is libm `pow`).
    #[link_name = "pow"]
    fn libm_pow(x: f64, y: f64) -> f64;
}

/// glibc's `pow(x, y)`, as numpy's float64 scalar `**` calls it.
pub(crate) fn pow(x: f64, y: f64) -> f64 {
    // SAFETY: `pow` is a pure libm function.
    unsafe { libm_pow(x, y) }
}
