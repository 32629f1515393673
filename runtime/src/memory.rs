//! How much memory this process may still allocate, so that commands sized by their input (a
//! vector env's envs, a rollout's trajectory) refuse up front instead of aborting when an
//! allocation fails part-way (Rust aborts on a failed allocation; MuJoCo raises an error).

/// Bytes this process may still allocate: the smaller of the machine's available memory and what
/// the address-space limit (`ulimit -v`) leaves. None when neither can be read.
pub fn available() -> Option<u64> {
    let b = budget();
    match (b.memory, b.address_space) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The limits a process runs into, apart: memory that can still be written (resident), address
/// space that can still be mapped, and how much mapped-but-unwritten memory envc bets on.
/// Mapped but untouched memory (MuJoCo's arenas) counts against the last two only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// The machine's available memory (`MemAvailable`); None when unreadable.
    pub memory: Option<u64>,
    /// What `ulimit -v` leaves of this process's address space, or what the kernel still
    /// commits under strict overcommit (`vm.overcommit_memory = 2`); None when neither applies.
    pub address_space: Option<u64>,
    /// [`MAPPED_PER_MEMORY`] times the machine's memory and swap: the most one request may map.
    pub mapped_cap: Option<u64>,
}

/// How many times the machine's memory (and swap) one request (a vector env's envs) may map.
/// Linux maps memory lazily, so MuJoCo's arenas, sized for a model's worst state and mostly
/// untouched, cost only the pages written (Hopper: 13 MiB mapped, about 20 KiB written); past
/// this the bet that most envs never fill theirs is too large.
pub const MAPPED_PER_MEMORY: u64 = 8;

fn meminfo_bytes(text: &str, key: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map(|kb| kb * 1024)
}

/// The machine's available memory, the address space left, and the mapping cap.
pub fn budget() -> Budget {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let info = |key: &str| meminfo.as_deref().and_then(|t| meminfo_bytes(t, key));
    let memory = info("MemAvailable:");
    let limit = crate::os::address_space_limit().map(|cur| {
        let used = std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|t| meminfo_bytes(&t, "VmSize:"));
        cur.saturating_sub(used.unwrap_or(0))
    });
    let strict =
        std::fs::read_to_string("/proc/sys/vm/overcommit_memory").is_ok_and(|m| m.trim() == "2");
    let commit = match (strict, info("CommitLimit:"), info("Committed_AS:")) {
        (true, Some(limit), Some(used)) => Some(limit.saturating_sub(used)),
        _ => None,
    };
    let address_space = match (limit, commit) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let mapped_cap = info("MemTotal:").map(|total| {
        total
            .saturating_add(info("SwapTotal:").unwrap_or(0))
            .saturating_mul(MAPPED_PER_MEMORY)
    });
    Budget {
        memory,
        address_space,
        mapped_cap,
    }
}
