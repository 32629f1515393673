//! Fuzzing kept in the repository (docs/fuzzing.md): mutated specs, models, maze layouts,
//! factorizations, `.npy` action files and `envc` command lines must never panic, abort, hang or
//! run away with memory.
//!
//! Why a harness of our own rather than cargo-afl or proptest: it runs on the stable toolchain with
//! no instrumentation and no extra dependency, inside `cargo test --workspace` (a bounded pass),
//! and the same binary does the long run. Inputs are structured text (TOML, MJCF, URDF) and argv,
//! where dictionary tokens spliced into a committed seed corpus (`tests/fuzz/corpus/`) reach deep
//! into the readers quickly; coverage guidance would add little for the cost. The generator is a
//! seeded SplitMix64, so input `i` of a target is the same on every machine.
//!
//! Targets, and how each is run:
//! - in-process (`spec`, `resolve`, `maze`, `agents`, `npy`): the pure-Rust readers, each input
//!   under `catch_unwind` with a time bound, in a worker child (this test binary re-executed) under
//!   `setrlimit` and a wall-clock timeout, so a stack overflow, an abort or a hang is also caught;
//! - subprocess (`compile`, `cli`): the `envc` binary per input (MuJoCo compilation and runs of
//!   mutated specs and models, mutated argv), under the same limits.
//!
//! A finding (panic, signal, abort, timeout, exit status outside 0..=3, slow input) is saved under
//! the output directory with its input files. `ENVC_FUZZ_SECONDS` (default 60) is the total wall
//! budget, `ENVC_FUZZ_TARGETS` a comma list of targets, `ENVC_FUZZ_SEED` the generator seed,
//! `ENVC_FUZZ_OUT` where findings go (default: a temporary directory, printed).

use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
/// An in-process input slower than this is a finding (debug build; the seeds take milliseconds).
const SLOW: Duration = Duration::from_secs(5);
/// Wall-clock bound of one `envc` run.
const CHILD_TIMEOUT: Duration = Duration::from_secs(20);
/// Address-space limit of every child (worker or `envc`).
const MEMORY_LIMIT: u64 = 4 << 30;
/// Findings saved per signature (the rest are counted).
const KEEP_PER_SIGNATURE: usize = 3;

/// Known problems whose fix has not landed yet: reported, not failed on, until the fix lands.
/// Each is (text of the symptom, text of the input files, output or argv, what it is); both must
/// occur. Remove an entry when its fix is merged; their inputs are in `tests/fuzz/findings/`.
/// Empty: the first runs' findings (device files read without end, NumpyRng::uniform on an
/// infinite ctrlrange, bad_alloc on huge MuJoCo sizes, unmeetable resample_until, runaway runs)
/// are fixed, with regression tests in `cli/tests/limits.rs` and cases in `tests/catalogue/`.
const KNOWN: &[(&str, &str, &str)] = &[];

#[derive(Clone, Copy, PartialEq)]
enum Run {
    /// A pure reader called in a worker process.
    InProcess,
    /// `envc` run per input.
    Subprocess,
    /// The Python API, by `tests/fuzz/python_api.py` (the same seeding, workers and findings).
    Python,
}

struct Target {
    name: &'static str,
    /// Seed directories under `tests/fuzz/corpus/` (each seed is one directory).
    corpus: &'static str,
    /// Files of a seed the mutator may change.
    mutable: &'static [&'static str],
    run: Run,
    /// Share of the total budget.
    share: f64,
}

const TARGETS: &[Target] = &[
    Target {
        name: "spec",
        corpus: "tasks",
        mutable: &["spec.toml"],
        run: Run::InProcess,
        share: 0.10,
    },
    Target {
        name: "resolve",
        corpus: "tasks",
        mutable: &["spec.toml", "model.xml", "model.urdf"],
        run: Run::InProcess,
        share: 0.15,
    },
    Target {
        name: "maze",
        corpus: "maze",
        mutable: &["maze.toml", "map.toml"],
        run: Run::InProcess,
        share: 0.10,
    },
    Target {
        name: "agents",
        corpus: "agents",
        mutable: &["agents.toml"],
        run: Run::InProcess,
        share: 0.10,
    },
    Target {
        name: "npy",
        corpus: "npy",
        mutable: &["a.npy"],
        run: Run::InProcess,
        share: 0.05,
    },
    Target {
        name: "compile",
        corpus: "tasks",
        mutable: &["spec.toml", "model.xml", "model.urdf"],
        run: Run::Subprocess,
        share: 0.20,
    },
    Target {
        name: "cli",
        corpus: "cli",
        mutable: &[],
        run: Run::Subprocess,
        share: 0.30,
    },
    Target {
        name: "python",
        corpus: "",
        mutable: &[],
        run: Run::Python,
        share: 0.10,
    },
];

// ---------------------------------------------------------------- generator and mutations

/// SplitMix64: small, seedable, the same everywhere.
struct Rng(u64);

impl Rng {
    fn for_input(seed: u64, target: &str, i: u64) -> Rng {
        let h = target.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        Rng(seed ^ h ^ i.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

/// The dictionary (`tests/fuzz/dict.txt`): one token a line, `# ` comments, `\n \t \\ \u{..}`
/// escapes, and generated tokens.
fn dictionary() -> Vec<Vec<u8>> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("tests/fuzz/dict.txt"))
        .expect("tests/fuzz/dict.txt");
    let mut out = vec![];
    for line in text.lines() {
        if line.is_empty() || line == "#" || line.starts_with("# ") {
            continue;
        }
        out.push(match line {
            "@LONG" => "a".repeat(70_000).into_bytes(),
            "@DEEP" => format!("{}{}", "[".repeat(5_000), "]".repeat(5_000)).into_bytes(),
            "@HUGE_INT" => format!("1{}", "0".repeat(400)).into_bytes(),
            _ => unescape(line).into_bytes(),
        });
    }
    out
}

fn unescape(s: &str) -> String {
    let mut out = String::new();
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match it.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('u') => {
                let hex: String = it.by_ref().skip(1).take_while(|&c| c != '}').collect();
                out.push(
                    u32::from_str_radix(&hex, 16)
                        .ok()
                        .and_then(char::from_u32)
                        .unwrap_or('?'),
                );
            }
            Some(c) => out.push(c),
            None => out.push('\\'),
        }
    }
    out
}

/// What a number of a spec or model becomes in the number mutation.
const NUMBERS: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "5e-324",
    "-1",
    "0",
    "-0",
    "999999999",
    "4294967296",
    "9223372036854775807",
    "1e9",
];

const INTERESTING: &[u8] = b"\0\xff\"'[]{}=,.\n<>/#\\:-";

fn is_word(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b"._-+$".contains(&b)
}

/// One to four stacked byte-level mutations of `data`; `others` are the same file of other seeds.
fn mutate(rng: &mut Rng, data: &mut Vec<u8>, dict: &[Vec<u8>], others: &[Vec<u8>]) {
    for _ in 0..1 + rng.below(4) {
        let len = data.len();
        let at = rng.below(len + 1);
        match rng.below(14) {
            0 if len > 0 => data[at.min(len - 1)] ^= 1 << rng.below(8),
            1 if len > 0 => data[at.min(len - 1)] = *rng.pick(INTERESTING),
            2 => {
                let end = (at + 1 + rng.below(16)).min(len);
                data.drain(at..end);
            }
            3 => {
                let end = (at + 1 + rng.below(64)).min(len);
                let chunk = data[at..end].to_vec();
                let to = rng.below(len + 1);
                data.splice(to..to, chunk);
            }
            4 => {
                let t = rng.pick(dict).clone();
                data.splice(at..at, t);
            }
            // Replace the word (number, name, key) around `at` with a token: `0.01` → `nan`.
            5 | 6 => {
                let (mut s, mut e) = (at.min(len), at.min(len));
                while s > 0 && is_word(data[s - 1]) {
                    s -= 1;
                }
                while e < len && is_word(data[e]) {
                    e += 1;
                }
                let t = rng.pick(dict).clone();
                data.splice(s..e, t);
            }
            // Structure-aware: a token as an attribute of a random XML element (`<geom` →
            // `<geom size="-1"`), or as the value of a random `key = value` line.
            9 | 11 => {
                let tags: Vec<usize> = (0..len.saturating_sub(1))
                    .filter(|&k| data[k] == b'<' && data[k + 1].is_ascii_alphabetic())
                    .collect();
                let values: Vec<usize> = (0..len.saturating_sub(3))
                    .filter(|&k| &data[k..k + 3] == b" = ")
                    .collect();
                let t = rng.pick(dict).clone();
                if !tags.is_empty() {
                    let mut k = *rng.pick(&tags) + 1;
                    while k < len && is_word(data[k]) {
                        k += 1;
                    }
                    data.splice(k..k, b" ".iter().chain(&t).copied());
                } else if !values.is_empty() {
                    let k = *rng.pick(&values) + 3;
                    let e = data[k..]
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(len, |p| k + p);
                    data.splice(k..e, t);
                }
            }
            // A number of the input (a gain, a range bound, a size, a count) made extreme.
            12 | 13 => {
                let starts: Vec<usize> = (0..len)
                    .filter(|&k| {
                        data[k].is_ascii_digit() && (k == 0 || !is_word(data[k - 1]))
                            || data[k] == b'-' && data.get(k + 1).is_some_and(u8::is_ascii_digit)
                    })
                    .collect();
                if !starts.is_empty() {
                    let a = *rng.pick(&starts);
                    let mut e = a + 1;
                    while e < len && is_word(data[e]) {
                        e += 1;
                    }
                    data.splice(a..e, rng.pick(NUMBERS).bytes());
                }
            }
            // A random line copied elsewhere (a key or table twice, a row of a maze).
            10 => {
                let starts: Vec<usize> = std::iter::once(0)
                    .chain((0..len).filter(|&k| data[k] == b'\n').map(|k| k + 1))
                    .collect();
                let a = *rng.pick(&starts);
                let e = data[a..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(len, |p| a + p + 1);
                let line = data[a..e].to_vec();
                let to = *rng.pick(&starts);
                data.splice(to..to, line);
            }
            7 if !others.is_empty() => {
                let o = rng.pick(others);
                let s = rng.below(o.len() + 1);
                let e = (s + rng.below(256)).min(o.len());
                data.splice(at..at, o[s..e].iter().copied());
            }
            _ => data.truncate(at),
        }
    }
}

/// Argv-level mutations: replace, insert, remove, byte-mutate an argument, or splice seeds.
fn mutate_args(rng: &mut Rng, args: &mut Vec<Vec<u8>>, dict: &[Vec<u8>], others: &[Vec<Vec<u8>>]) {
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(args.len() + 1);
        match rng.below(6) {
            0 if at < args.len() => args[at] = rng.pick(dict).clone(),
            1 => args.insert(at, rng.pick(dict).clone()),
            2 if at < args.len() => {
                args.remove(at);
            }
            3 if at < args.len() => {
                let mut a = std::mem::take(&mut args[at]);
                mutate(rng, &mut a, dict, &[]);
                args[at] = a;
            }
            4 if !others.is_empty() => {
                let o = rng.pick(others);
                let from = rng.below(o.len() + 1);
                args.truncate(at);
                args.extend(o[from..].iter().cloned());
            }
            _ => {
                let t = rng.pick(dict).clone();
                args.insert(at, b"--set".to_vec());
                args.insert(at + 1, t);
            }
        }
    }
    // argv cannot carry NUL bytes.
    for a in args.iter_mut() {
        a.retain(|&b| b != 0);
    }
}

// ---------------------------------------------------------------- corpus and files

struct Seed {
    dir: PathBuf,
    name: String,
}

fn seeds(t: &Target) -> Vec<Seed> {
    let dir = Path::new(ROOT).join("tests/fuzz/corpus").join(t.corpus);
    let mut out: Vec<Seed> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.file_name().is_some_and(|n| n != "world"))
        .map(|p| Seed {
            name: p.file_name().unwrap().to_string_lossy().into_owned(),
            dir: p,
        })
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        if e.path().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

fn fresh_dir(p: &Path) {
    let _ = std::fs::remove_dir_all(p);
    std::fs::create_dir_all(p).unwrap();
}

/// Build input `i` of a file target in `work`: a seed copied and one of its files mutated.
/// Returns a one-line description (seed, file).
fn make_input(t: &Target, seeds: &[Seed], dict: &[Vec<u8>], rng: &mut Rng, work: &Path) -> String {
    let seed = rng.pick(seeds);
    fresh_dir(work);
    copy_dir(&seed.dir, work);
    let present: Vec<&str> = t
        .mutable
        .iter()
        .copied()
        .filter(|f| work.join(f).is_file())
        .collect();
    let file = *rng.pick(&present);
    let others: Vec<Vec<u8>> = seeds
        .iter()
        .filter_map(|s| std::fs::read(s.dir.join(file)).ok())
        .collect();
    let mut data = std::fs::read(work.join(file)).unwrap();
    mutate(rng, &mut data, dict, &others);
    std::fs::write(work.join(file), &data).unwrap();
    format!("seed {} file {file}", seed.name)
}

// ---------------------------------------------------------------- findings

struct Finding {
    symptom: String,
    /// What groups findings of one cause: the panic location, the signal, "timeout".
    signature: String,
    detail: String,
}

struct Findings {
    dir: PathBuf,
    saved: std::collections::BTreeMap<String, usize>,
    known: usize,
    new: Vec<String>,
}

impl Findings {
    fn new(dir: PathBuf) -> Findings {
        Findings {
            dir,
            saved: Default::default(),
            known: 0,
            new: vec![],
        }
    }
    /// Record a finding; its input files are copied from `work`.
    fn add(&mut self, target: &str, i: u64, what: &str, work: &Path, f: Finding) {
        // Known problems are recognised by the symptom, the output and the input files' text.
        let mut text = format!("{}\n{}\n{}", f.symptom, f.detail, what);
        for e in std::fs::read_dir(work).into_iter().flatten().flatten() {
            let b = std::fs::read(e.path()).unwrap_or_default();
            text += &String::from_utf8_lossy(&b[..b.len().min(100_000)]);
        }
        let symptom = format!("{} {}", f.symptom, f.signature);
        let known = KNOWN
            .iter()
            .find(|(s, k, _)| symptom.contains(s) && text.contains(k));
        if let Some((_, _, why)) = known {
            self.known += 1;
            eprintln!("fuzz {target} #{i}: known ({why}): {}", f.symptom);
        }
        let n = self.saved.entry(f.signature.clone()).or_default();
        *n += 1;
        if known.is_none() && *n == 1 {
            self.new
                .push(format!("{target} #{i}: {} [{}]", f.symptom, f.signature));
        }
        if *n > KEEP_PER_SIGNATURE {
            return;
        }
        let dir = self.dir.join(format!("{target}-{i}"));
        fresh_dir(&dir);
        copy_dir(work, &dir);
        std::fs::write(
            dir.join("finding.txt"),
            format!(
                "target: {target}\ninput: {i}\n{what}\nsymptom: {}\nsignature: {}\n\n{}\n",
                f.symptom, f.signature, f.detail
            ),
        )
        .unwrap();
    }
}

// ---------------------------------------------------------------- in-process targets (worker)

static PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Call the target's reader on the input in `work`; an error is rendered as users see it (the
/// renderer slices the source text at the diagnostic's span, so it is fuzzed too).
fn run_reader(target: &str, work: &Path) -> Result<String, String> {
    match target {
        "spec" => envspec::Spec::load(&work.join("spec.toml"))
            .map(|s| format!("{}", s.path().display()))
            .map_err(|d| d.to_string()),
        "resolve" => {
            let spec = work.join("spec.toml");
            let overrides = match std::fs::read_to_string(work.join("override.txt")) {
                Ok(o) => vec![envspec::Override::parse(&o).map_err(|d| d.to_string())?],
                Err(_) => vec![],
            };
            envspec::open_file(&spec, &overrides)
                .map(|s| s.id().to_string())
                .map_err(|d| d.to_string())
        }
        "maze" => envspec::open_file(&work.join("maze.toml"), &[])
            .map(|s| s.id().to_string())
            .map_err(|d| d.to_string()),
        "agents" => envspec::open_file(&work.join("agents.toml"), &[])
            .map(|s| s.id().to_string())
            .map_err(|d| d.to_string()),
        "npy" => envc::npy::read_matrix(&work.join("a.npy"))
            .map(|m| format!("{:?}", m.dim()))
            .map_err(|e| e.to_string()),
        _ => unreachable!("{target}"),
    }
}

/// `name=value`: a parameter declared in the spec's `[params]`, a dictionary token as value.
fn random_override(rng: &mut Rng, spec: &Path, dict: &[Vec<u8>]) -> String {
    let text = String::from_utf8_lossy(&std::fs::read(spec).unwrap_or_default()).into_owned();
    let params: Vec<&str> = text
        .lines()
        .skip_while(|l| l.trim() != "[params]")
        .skip(1)
        .take_while(|l| !l.starts_with('['))
        .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.trim()))
        .collect();
    let name = if params.is_empty() {
        "frame_skip"
    } else {
        rng.pick(&params)
    };
    let value: &Vec<u8> = rng.pick(dict);
    format!("{name}={}", String::from_utf8_lossy(value))
}

/// The worker: runs inputs `start..` of one in-process target until its deadline.
fn worker(target: &Target, out: &Path, seed: u64, start: u64, seconds: f64) {
    let deadline = Instant::now() + Duration::from_secs_f64(seconds);
    let seeds = seeds(target);
    let dict = dictionary();
    let work = out.join("work");
    // `out` is the target's directory; findings of every target go to one directory beside it.
    let mut findings = Findings::new(out.parent().unwrap().join("findings"));
    std::panic::set_hook(Box::new(|info| {
        *PANIC.lock().unwrap_or_else(|e| e.into_inner()) = Some(info.to_string());
    }));
    let (mut i, mut accepted) = (start, 0u64);
    while Instant::now() < deadline {
        let mut rng = Rng::for_input(seed, target.name, i);
        let mut what = make_input(target, &seeds, &dict, &mut rng, &work);
        if target.name == "resolve" && rng.below(4) == 0 {
            let o = random_override(&mut rng, &work.join("spec.toml"), &dict);
            what += &format!(" override {o:?}");
            std::fs::write(work.join("override.txt"), o).unwrap();
        }
        std::fs::write(out.join("iter"), format!("{i}\n{what}")).unwrap();
        let t0 = Instant::now();
        let r = std::panic::catch_unwind(|| run_reader(target.name, &work));
        let took = t0.elapsed();
        accepted += u64::from(matches!(r, Ok(Ok(_))));
        if r.is_err() {
            let msg = PANIC
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .take()
                .unwrap_or_default();
            let at = msg
                .lines()
                .next()
                .unwrap_or("")
                .split(':')
                .take(2)
                .collect::<Vec<_>>()
                .join(":");
            findings.add(
                target.name,
                i,
                &what,
                &work,
                Finding {
                    symptom: "panic".into(),
                    signature: format!("panic {at}"),
                    detail: msg,
                },
            );
        } else if took > SLOW {
            findings.add(
                target.name,
                i,
                &what,
                &work,
                Finding {
                    symptom: format!("slow: {:.1} s", took.as_secs_f64()),
                    signature: "slow".into(),
                    detail: String::new(),
                },
            );
        }
        i += 1;
    }
    std::fs::write(
        out.join("done"),
        format!(
            "{}\n{accepted}\n{}\n{}",
            i - start,
            findings.known,
            findings.new.join("\n")
        ),
    )
    .unwrap();
}

#[test]
fn fuzz_worker() {
    let Ok(name) = std::env::var("ENVC_FUZZ_WORKER") else {
        return; // only a worker child does something
    };
    let var = |k: &str| std::env::var(k).unwrap();
    let target = TARGETS.iter().find(|t| t.name == name).unwrap();
    let out = PathBuf::from(var("ENVC_FUZZ_WORKER_OUT"));
    let (seed, start): (u64, u64) = (
        var("ENVC_FUZZ_SEED").parse().unwrap(),
        var("ENVC_FUZZ_START").parse().unwrap(),
    );
    let seconds: f64 = var("ENVC_FUZZ_WORKER_SECONDS").parse().unwrap();
    // The CLI runs readers on the main thread's 8 MB stack, not a test thread's 2 MB.
    std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(move || worker(target, &out, seed, start, seconds))
        .unwrap()
        .join()
        .unwrap();
}

// ---------------------------------------------------------------- children under limits

struct Exit {
    status: Option<std::process::ExitStatus>,
    timed_out: bool,
    stderr: String,
}

/// Run `cmd` with stdout discarded and stderr in `io_dir`, under RLIMIT_AS, RLIMIT_CPU and a wall timeout.
fn run_limited(mut cmd: Command, io_dir: &Path, timeout: Duration) -> Exit {
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
fn judge(x: &Exit) -> Option<Finding> {
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

// ---------------------------------------------------------------- drivers

struct Stats {
    target: &'static str,
    inputs: u64,
    /// Inputs the reader accepted (in-process: `Ok`; `envc`: exit status 0).
    accepted: u64,
    findings: usize,
    known: usize,
    new: Vec<String>,
}

/// An in-process target: worker children until the budget is spent; a worker that dies is a
/// finding for the input it was on, and the next worker resumes after it.
fn drive_in_process(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
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
fn drive_python(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
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

fn drive_subprocess(t: &Target, out: &Path, seed: u64, seconds: f64) -> Stats {
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

/// The bounded pass of `cargo test` (ENVC_FUZZ_SECONDS, default 60), and the long run.
#[test]
fn fuzz() {
    if std::env::var_os("ENVC_FUZZ_WORKER").is_some() {
        return;
    }
    let seconds: f64 = std::env::var("ENVC_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60.0);
    let seed: u64 = std::env::var("ENVC_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    let only = std::env::var("ENVC_FUZZ_TARGETS").ok();
    let out = std::env::var_os("ENVC_FUZZ_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join(format!("envc-fuzz-{}", std::process::id())));
    fresh_dir(&out);
    let chosen: Vec<&Target> = TARGETS
        .iter()
        .filter(|t| {
            only.as_deref()
                .is_none_or(|o| o.split(',').any(|n| n == t.name))
        })
        .collect();
    let total: f64 = chosen.iter().map(|t| t.share).sum();
    let mut report = vec![];
    for t in chosen {
        let s = seconds * t.share / total;
        let stats = match t.run {
            Run::InProcess => drive_in_process(t, &out, seed, s),
            Run::Subprocess => drive_subprocess(t, &out, seed, s),
            Run::Python => drive_python(t, &out, seed, s),
        };
        report.push(stats);
    }
    let mut summary = format!(
        "envc fuzz: seed {seed}, {seconds} s, findings in {}\n",
        out.display()
    );
    for s in &report {
        summary += &format!(
            "{:8} {:7} inputs {:7} accepted  {:3} findings saved  {:3} known\n",
            s.target, s.inputs, s.accepted, s.findings, s.known
        );
    }
    let new: Vec<&String> = report.iter().flat_map(|s| &s.new).collect();
    for n in &new {
        summary += &format!("NEW: {n}\n");
    }
    std::fs::write(out.join("summary.txt"), &summary).unwrap();
    println!("{summary}");
    assert!(
        new.is_empty(),
        "the fuzzer found problems (inputs under {}):\n{summary}",
        out.display()
    );
    if new.is_empty() && std::env::var_os("ENVC_FUZZ_OUT").is_none() {
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// The harness itself sees what it must: a signal, a timeout, a panic message, a bad status.
#[test]
fn the_judge_sees_crashes_hangs_and_panics() {
    let dir = std::env::temp_dir().join(format!("envc-fuzz-judge-{}", std::process::id()));
    fresh_dir(&dir);
    let sh = |script: &str, secs: u64| {
        let mut c = Command::new("sh");
        c.args(["-c", script]);
        judge(&run_limited(c, &dir, Duration::from_secs(secs)))
    };
    let f = sh("kill -ABRT $$", 5).expect("abort");
    assert_eq!(f.symptom, "killed by signal 6");
    let t0 = Instant::now();
    assert_eq!(sh("exec sleep 30", 1).expect("hang").signature, "timeout");
    assert!(t0.elapsed() < Duration::from_secs(10));
    let f = sh(
        "echo \"thread 'main' panicked at src/x.rs:1:2:\" >&2; exit 101",
        5,
    );
    assert!(
        f.expect("panic")
            .signature
            .starts_with("panicked at src/x.rs")
    );
    assert_eq!(
        sh("exit 7", 5).expect("status").symptom,
        "exit status Some(7)"
    );
    assert!(sh("exit 2", 5).is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The `envc` under test: this build's, or `ENVC_BIN` (scripts/test.sh runs the release binary
/// too, where undefined behaviour the optimizer exposes would show).
fn envc_bin() -> String {
    std::env::var("ENVC_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_envc").to_string())
}
