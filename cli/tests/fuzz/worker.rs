//! The worker child of an in-process target: the pure readers called under `catch_unwind`.

use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::corpus::{make_input, seeds};
use super::findings::{Finding, Findings};
use super::mutate::{Rng, dictionary};
use super::{SLOW, Target};

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
pub(super) fn worker(target: &Target, out: &Path, seed: u64, start: u64, seconds: f64) {
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
