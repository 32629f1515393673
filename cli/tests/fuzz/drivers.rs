//! The drivers: each target run for its share of the budget, its findings gathered.

use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use super::child::{judge, run_limited};
use super::corpus::{Seed, copy_dir, fresh_dir, make_input, seeds};
use super::findings::{Finding, Findings};
use super::mutate::{Rng, dictionary, mutate_args};
use super::{CHILD_TIMEOUT, KEEP_PER_SIGNATURE, ROOT, SLOW, Target, envc_bin};

pub(super) struct Stats {
    pub(super) target: &'static str,
    pub(super) inputs: u64,
    /// Inputs the reader accepted (in-process: `Ok`; `envc`: exit status 0).
    pub(super) accepted: u64,
    pub(super) findings: usize,
    pub(super) known: usize,
    pub(super) new: Vec<String>,
}

/// An in-process target: worker children until the budget is spent; a worker that dies is a
/// finding for the input it was on, and the next worker resumes after it.
pub(super) fn drive_in_process(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
    let dir = out.join(t.name);
    fresh_dir(&dir);
    let deadline = Instant::now() + Duration::from_secs_f64(seconds);
    let mut findings = Findings::new(out.join("findings"));
    let (mut start, mut inputs, mut accepted, mut known, mut new) =
        (0u64, 0u64, 0u64, 0usize, vec![]);
    while Instant::now() < deadline {
        let left = (deadline - Instant::now()).as_secs_f64();
        let _ = std::fs::remove_file(dir.join("done"));
        let mut cmd = Command::new(std::env::current_exe().unwrap());
        cmd.args([
            "fuzz::fuzz_worker",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("ENVC_FUZZ_WORKER", t.name)
        .env("ENVC_FUZZ_WORKER_OUT", &dir)
        .env("ENVC_FUZZ_SEED", seed.to_string())
        .env("ENVC_FUZZ_START", start.to_string())
        .env("ENVC_FUZZ_WORKER_SECONDS", left.to_string());
        let x = run_limited(cmd, &dir, Duration::from_secs_f64(left) + SLOW * 6);
        if let Ok(done) = std::fs::read_to_string(dir.join("done")) {
            let mut l = done.lines();
            inputs += l.next().unwrap().parse::<u64>().unwrap();
            accepted += l.next().unwrap().parse::<u64>().unwrap();
            known += l.next().unwrap().parse::<usize>().unwrap();
            new.extend(l.map(str::to_string));
            break;
        }
        // The worker died on the input it was on.
        let iter = std::fs::read_to_string(dir.join("iter")).unwrap_or_default();
        let i: u64 = iter
            .lines()
            .next()
            .and_then(|l| l.parse().ok())
            .unwrap_or(start);
        let what = iter.lines().nth(1).unwrap_or("").to_string();
        let f = judge(&x).unwrap_or(Finding {
            symptom: format!("worker ended without a report: {:?}", x.status),
            signature: "worker".into(),
            detail: x.stderr.clone(),
        });
        findings.add(t.name, i, &what, &dir.join("work"), f);
        inputs += i + 1 - start;
        start = i + 1;
    }
    let saved = std::fs::read_dir(out.join("findings"))
        .map(|d| {
            d.flatten()
                .filter(|e| {
                    e.file_name()
                        .to_string_lossy()
                        .starts_with(&format!("{}-", t.name))
                })
                .count()
        })
        .unwrap_or(0);
    new.extend(findings.new);
    Stats {
        target: t.name,
        inputs,
        accepted,
        findings: saved,
        known: known + findings.known,
        new,
    }
}

/// The argv of input `i` of a subprocess target, after building its files in `work`.
fn subprocess_input(
    t: &Target,
    seeds: &[Seed],
    dict: &[Vec<u8>],
    rng: &mut Rng,
    work: &Path,
    i: u64,
) -> (Vec<Vec<u8>>, String) {
    if t.name == "compile" {
        let what = make_input(t, seeds, dict, rng, work);
        let args: &[&str] = if i.is_multiple_of(2) {
            &["check", "--compile", "spec.toml"]
        } else {
            &[
                "run",
                "spec.toml",
                "--episodes",
                "1",
                "--max-steps",
                "20",
                "--seed",
                "1",
            ]
        };
        return (args.iter().map(|a| a.as_bytes().to_vec()).collect(), what);
    }
    fresh_dir(work);
    copy_dir(&Path::new(ROOT).join("tests/fuzz/corpus/cli/world"), work);
    let read = |s: &Seed| -> Vec<Vec<u8>> {
        std::fs::read_to_string(&s.dir)
            .unwrap()
            .lines()
            .map(|l| l.as_bytes().to_vec())
            .collect()
    };
    let seed = rng.pick(seeds);
    let others: Vec<_> = seeds.iter().map(read).collect();
    let mut args = read(seed);
    mutate_args(rng, &mut args, dict, &others);
    (args, format!("seed {}", seed.name))
}

/// An argv asking for more than 10 000 episodes or steps.
fn asks_for_much(args: &[Vec<u8>]) -> bool {
    args.windows(2).any(|w| {
        matches!(&w[0][..], b"--episodes" | b"--steps")
            && std::str::from_utf8(&w[1])
                .ok()
                .and_then(|n| n.parse::<u64>().ok())
                .is_some_and(|n| n > 10_000)
    })
}

/// The Python API target: `tests/fuzz/python_api.py` in the project's venv (scripts/setup.sh
/// installs the package there); skipped, and said so, where the package does not import.
pub(super) fn drive_python(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
    let mut stats = Stats {
        target: t.name,
        inputs: 0,
        accepted: 0,
        findings: 0,
        known: 0,
        new: vec![],
    };
    let py = Path::new(ROOT).join(".venv/bin/python");
    let imports = Command::new(&py)
        .args(["-c", "import envc"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !imports {
        eprintln!("fuzz: python target skipped: the envc package does not import from .venv");
        return stats;
    }
    let o = Command::new(&py)
        .arg(Path::new(ROOT).join("tests/fuzz/python_api.py"))
        .args([
            "--seed",
            &seed.to_string(),
            "--seconds",
            &format!("{seconds:.1}"),
        ])
        .arg("--out")
        .arg(out.join("findings"))
        .output()
        .expect("run the python fuzz target");
    let text = String::from_utf8_lossy(&o.stdout);
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        if let ["python", n, "inputs", ok, "fine", k, "findings", ..] = w.as_slice() {
            stats.inputs = n.parse().unwrap_or(0);
            stats.accepted = ok.parse().unwrap_or(0);
            stats.findings = k.parse().unwrap_or(0);
        } else if let Some(rest) = line.strip_prefix("NEW: ") {
            stats.new.push(rest.to_string());
        }
    }
    if !o.status.success() && stats.new.is_empty() {
        stats.new.push(format!(
            "python: the fuzz script failed: {}",
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    stats
}

pub(super) fn drive_subprocess(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
    let deadline = Instant::now() + Duration::from_secs_f64(seconds);
    let seeds = seeds(t);
    let dict = dictionary();
    let work = out.join(t.name).join("work");
    let mut findings = Findings::new(out.join("findings"));
    let (mut i, mut accepted) = (0u64, 0u64);
    while Instant::now() < deadline {
        let mut rng = Rng::for_input(seed, t.name, i);
        let (args, what) = subprocess_input(t, &seeds, &dict, &mut rng, &work, i);
        // Linux refuses an argument over 128 KiB (E2BIG) before envc runs: no user can type it.
        if args.iter().any(|a| a.len() >= 128 * 1024)
            || args.iter().map(Vec::len).sum::<usize>() >= 1 << 20
        {
            i += 1;
            continue;
        }
        let mut cmd = Command::new(envc_bin());
        cmd.args(args.iter().map(|a| OsString::from_vec(a.clone())))
            .current_dir(&work)
            .env("HOME", &work)
            .env("MINARI_DATASETS_PATH", work.join("datasets"))
            .env_remove("ENVC_NUMERICS");
        let x = run_limited(cmd, &work, CHILD_TIMEOUT);
        accepted += u64::from(x.status.is_some_and(|s| s.success()));
        if x.timed_out && asks_for_much(&args) {
            // `--episodes 999999999` is work the user asked for, not a hang.
        } else if let Some(f) = judge(&x) {
            let argv: Vec<String> = args
                .iter()
                .map(|a| format!("{:?}", String::from_utf8_lossy(a)))
                .collect();
            std::fs::write(work.join("argv.txt"), argv.join("\n")).unwrap();
            let what = format!("{what}\nargv: envc {}", argv.join(" "));
            findings.add(t.name, i, &what, &work, f);
        }
        i += 1;
    }
    let saved: usize = findings
        .saved
        .values()
        .map(|&n| n.min(KEEP_PER_SIGNATURE))
        .sum();
    Stats {
        target: t.name,
        inputs: i,
        accepted,
        findings: saved,
        known: findings.known,
        new: findings.new,
    }
}
