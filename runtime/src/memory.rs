//! How much memory this process may still allocate, so that commands sized by their input (a
//! vector env's envs, a rollout's trajectory) refuse up front instead of aborting when an
//! allocation fails part-way (Rust aborts on a failed allocation; MuJoCo raises an error).

/// Bytes this process may still allocate: the smaller of the machine's available memory and what
/// the address-space limit (`ulimit -v`) leaves. None when neither can be read.
pub fn available() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines()
            .find_map(|l| l.strip_prefix("MemAvailable:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            .map(|kb| kb * 1024)
    });
    let limit = crate::os::address_space_limit().map(|cur| {
        let used = std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|t| {
                t.lines()
                    .find_map(|l| l.strip_prefix("VmSize:"))
                    .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
                    .map(|kb| kb * 1024)
            });
        cur.saturating_sub(used.unwrap_or(0))
    });
    match (meminfo, limit) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}
