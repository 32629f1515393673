//! Children (workers and `envc`) run under memory, CPU and wall-clock limits, and judged by how
//! they ended.

use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use super::findings::Finding;
use super::{CHILD_TIMEOUT, MEMORY_LIMIT};

pub(super) struct Exit {
    pub(super) status: Option<std::process::ExitStatus>,
    pub(super) timed_out: bool,
    pub(super) stderr: String,
}

/// Run `cmd` with stdout discarded and stderr in `io_dir`, under RLIMIT_AS, RLIMIT_CPU and a wall timeout.
pub(super) fn run_limited(mut cmd: Command, io_dir: &Path, timeout: Duration) -> Exit {
    let e = io_dir.join(".stderr");
    cmd.stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&e).unwrap());
    let cpu = timeout.as_secs() + 2;
    // SAFETY: only async-signal-safe calls (setrlimit) between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            let lim = |r, v: u64| {
                let l = libc::rlimit {
                    rlim_cur: v as libc::rlim_t,
                    rlim_max: v as libc::rlim_t,
                };
                libc::setrlimit(r, &l);
            };
            lim(libc::RLIMIT_AS, MEMORY_LIMIT);
            lim(libc::RLIMIT_CPU, cpu);
            lim(libc::RLIMIT_CORE, 0);
            Ok(())
        });
    }
    let mut child = cmd.spawn().expect("spawn");
    let t0 = Instant::now();
    let mut timed_out = false;
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Some(s),
            Ok(None) if t0.elapsed() > timeout => {
                timed_out = true;
                let _ = child.kill(); // our own child, by its handle
                break child.wait().ok();
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(_) => break None,
        }
    };
    let read = |p: &Path| {
        let b = std::fs::read(p).unwrap_or_default();
        let _ = std::fs::remove_file(p);
        String::from_utf8_lossy(&b[..b.len().min(20_000)]).into_owned()
    };
    Exit {
        status,
        timed_out,
        stderr: read(&e),
    }
}

/// What is wrong with how `envc` ended, if anything.
pub(super) fn judge(x: &Exit) -> Option<Finding> {
    let detail = format!("stderr:\n{}", x.stderr);
    if x.timed_out {
        return Some(Finding {
            symptom: format!("timeout ({} s wall) or CPU limit", CHILD_TIMEOUT.as_secs()),
            signature: "timeout".into(),
            detail,
        });
    }
    if let Some(p) = x.stderr.find("panicked at") {
        let at: String = x.stderr[p..]
            .lines()
            .next()
            .unwrap_or("")
            .chars()
            .take(120)
            .collect();
        return Some(Finding {
            symptom: "panic".into(),
            signature: at,
            detail,
        });
    }
    let status = x.status?;
    if let Some(sig) = status.signal() {
        let first = x
            .stderr
            .lines()
            .find(|l| l.contains("terminate") || l.contains("what()") || l.contains("fatal"))
            .unwrap_or("");
        return Some(Finding {
            symptom: format!(
                "killed by signal {sig}{}",
                if sig == 24 { " (CPU limit)" } else { "" }
            ),
            signature: format!("signal {sig} {first}"),
            detail,
        });
    }
    match status.code() {
        Some(0..=3) => None,
        c => Some(Finding {
            symptom: format!("exit status {c:?}"),
            signature: format!("exit {c:?}"),
            detail,
        }),
    }
}
