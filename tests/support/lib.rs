//! Shared helpers of envc's integration tests: reading the reference fixtures and replaying them.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use envc::numerics::Profile;
use envc::{Env, Override};
use ndarray::{ArrayD, IxDyn};
use ndarray_npy::NpzReader;
use serde::Deserialize;

/// The v5/v4 suite's recordings for the MuJoCo this build is for (`fixtures_of("parity")`), or
/// `$ENVC_PARITY_DIR` (a live recording made by CI).
pub fn fixtures_dir() -> PathBuf {
    match std::env::var_os("ENVC_PARITY_DIR") {
        Some(d) => PathBuf::from(d),
        None => fixtures_of("parity"),
    }
}

/// The committed recordings of one suite (`parity`, `vector`, `maze`, `mamujoco`, `adroit`) made
/// on the MuJoCo this build of envc is for: `tests/reference/fixtures/<suite>` for 3.17.0 (the v5
/// suite at the top level), `tests/reference/fixtures/mujoco-<version>/<suite>` for the others.
pub fn fixtures_of(suite: &str) -> PathBuf {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/fixtures");
    match (envc::MUJOCO_VERSION, suite) {
        ("3.17.0", "parity") => fixtures,
        ("3.17.0", _) => fixtures.join(suite),
        (version, _) => fixtures.join(format!("mujoco-{version}")).join(suite),
    }
}

#[derive(Deserialize, Debug)]
pub struct Manifest {
    pub gymnasium: String,
    pub mujoco: String,
    /// The numerics profile the reference ran under (`tests/reference/numerics_profile.py`).
    pub numerics: String,
    pub cases: Vec<Case>,
}

impl Manifest {
    /// The recording's numerics profile: replays force it, so a fixture recorded on one CPU
    /// passes on every CPU.
    pub fn profile(&self) -> Profile {
        parse_profile(&self.numerics)
    }
}

/// A recorded profile name, parsed (a fixture without a valid one is a broken fixture).
pub fn parse_profile(name: &str) -> Profile {
    Profile::parse(name)
        .unwrap_or_else(|| panic!("fixture numerics profile `{name}` is not a profile"))
}

/// Little-endian float64s written as hex (the reference recorders' `hexa`).
pub fn unhex(s: &str) -> Vec<f64> {
    (0..s.len() / 16)
        .map(|i| {
            let b: Vec<u8> = (0..8)
                .map(|k| {
                    u8::from_str_radix(&s[16 * i + 2 * k..16 * i + 2 * k + 2], 16)
                        .expect("a fixture's hex")
                })
                .collect();
            f64::from_le_bytes(b.try_into().expect("eight bytes"))
        })
        .collect()
}

/// The `numerics` key of a recording's JSON (a per-file recording or a manifest).
pub fn recorded_profile(v: &serde_json::Value) -> Profile {
    parse_profile(
        v["numerics"]
            .as_str()
            .expect("the recording names its numerics profile (`numerics`)"),
    )
}

#[derive(Deserialize, Debug)]
pub struct Case {
    pub name: String,
    pub env_id: String,
    pub file: String,
    pub overrides: BTreeMap<String, String>,
    pub steps: usize,
    pub step_info_keys: Vec<String>,
    pub reset_info_keys: Vec<String>,
}

impl Case {
    pub fn overrides(&self) -> Vec<Override> {
        self.overrides
            .iter()
            .map(|(k, v)| Override::text(k, v))
            .collect()
    }
}

pub fn manifest(dir: &Path) -> Manifest {
    let text = std::fs::read_to_string(dir.join("manifest.json")).expect("fixture manifest");
    serde_json::from_str(&text).expect("manifest.json format")
}

/// One recorded trajectory.
pub struct Recording {
    pub arrays: BTreeMap<String, ArrayD<f64>>,
    pub bools: BTreeMap<String, ArrayD<bool>>,
    pub reset_step: Vec<i64>,
    pub reset_seed: Vec<i64>,
}

impl Recording {
    pub fn load(path: &Path, case: &Case) -> Recording {
        let mut npz = NpzReader::new(File::open(path).expect("fixture file")).expect("npz");
        let mut arrays = BTreeMap::new();
        let mut f64s = vec![
            "actions".to_string(),
            "obs".into(),
            "reward".into(),
            "reset_obs".into(),
        ];
        f64s.extend(case.step_info_keys.iter().map(|k| format!("info.{k}")));
        f64s.extend(
            case.reset_info_keys
                .iter()
                .map(|k| format!("reset_info.{k}")),
        );
        for name in f64s {
            let a: ArrayD<f64> = npz
                .by_name(&name)
                .unwrap_or_else(|e| panic!("{}: {name}: {e}", path.display()));
            arrays.insert(name, a);
        }
        let mut bools = BTreeMap::new();
        for name in ["terminated", "truncated"] {
            let a: ArrayD<bool> = npz.by_name(name).expect("bool array");
            bools.insert(name.to_string(), a);
        }
        let ints = |npz: &mut NpzReader<File>, n: &str| -> Vec<i64> {
            let a: ArrayD<i64> = npz.by_name(n).expect("int array");
            a.iter().copied().collect()
        };
        let reset_step = ints(&mut npz, "reset_step");
        let reset_seed = ints(&mut npz, "reset_seed");
        Recording {
            arrays,
            bools,
            reset_step,
            reset_seed,
        }
    }

    /// Row `t` of a recorded array, flattened.
    pub fn row(&self, name: &str, t: usize) -> Vec<f64> {
        let a = &self.arrays[name];
        let row = a.index_axis(ndarray::Axis(0), t);
        row.iter().copied().collect()
    }

    pub fn flag(&self, name: &str, t: usize) -> bool {
        self.bools[name][IxDyn(&[t])]
    }
}

/// Distance in units in the last place between two doubles of the same sign (u64::MAX otherwise).
pub fn ulps(a: f64, b: f64) -> u64 {
    if a.to_bits() == b.to_bits() {
        return 0;
    }
    if a.is_sign_negative() != b.is_sign_negative() || a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    a.to_bits().abs_diff(b.to_bits())
}

/// Collects the first mismatches of a replay.
#[derive(Default)]
pub struct Mismatches {
    pub lines: Vec<String>,
    pub count: usize,
}

impl Mismatches {
    pub fn values(&mut self, what: &str, ours: &[f64], theirs: &[f64]) {
        if ours.len() != theirs.len() {
            self.push(format!(
                "{what}: length {} vs reference {}",
                ours.len(),
                theirs.len()
            ));
            return;
        }
        for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
            if a.to_bits() != b.to_bits() {
                self.push(format!(
                    "{what}[{i}]: {a:?} vs reference {b:?} ({} ulp)",
                    ulps(*a, *b)
                ));
                return;
            }
        }
    }
    pub fn push(&mut self, line: String) {
        self.count += 1;
        if self.lines.len() < 20 {
            self.lines.push(line);
        }
    }
}

/// Replay one recorded case against envc: every reset and step, every value compared bit for bit.
pub fn replay(dir: &Path, profile: Profile, case: &Case) -> Mismatches {
    let rec = Recording::load(&dir.join(&case.file), case);
    let mut mm = Mismatches::default();
    let mut env = match Env::make(&case.env_id, &case.overrides()) {
        Ok(e) => e,
        Err(e) => {
            mm.push(format!("cannot build {}: {e}", case.env_id));
            return mm;
        }
    };
    env.set_numerics(profile);
    // Loading may warn (HalfCheetah's deprecated settotalmass, as in the reference); running must not.
    env.clear_warnings();
    let mut r = 0;
    for t in 0..case.steps {
        if r < rec.reset_step.len() && rec.reset_step[r] as usize == t {
            let seed = (rec.reset_seed[r] >= 0).then(|| rec.reset_seed[r] as u64);
            let (obs, info) = env.reset(seed);
            mm.values(
                &format!("reset {r} (step {t}) obs"),
                obs,
                &rec.row("reset_obs", r),
            );
            let keys: Vec<&str> = info.keys().collect();
            if keys != case.reset_info_keys {
                mm.push(format!(
                    "reset {r} info keys {keys:?} vs reference {:?}",
                    case.reset_info_keys
                ));
            }
            for k in &case.reset_info_keys {
                match info.get(k) {
                    Some(v) => mm.values(
                        &format!("reset {r} info.{k}"),
                        v,
                        &rec.row(&format!("reset_info.{k}"), r),
                    ),
                    None => mm.push(format!("reset {r}: missing info.{k}")),
                }
            }
            r += 1;
        }
        let action = rec.row("actions", t);
        let step = match env.step(&action) {
            Ok(s) => s,
            Err(e) => {
                mm.push(format!("step {t}: {e}"));
                return mm;
            }
        };
        mm.values(&format!("step {t} obs"), step.obs, &rec.row("obs", t));
        mm.values(
            &format!("step {t} reward"),
            &[step.reward],
            &rec.row("reward", t),
        );
        for (name, ours) in [
            ("terminated", step.terminated),
            ("truncated", step.truncated),
        ] {
            if ours != rec.flag(name, t) {
                mm.push(format!(
                    "step {t} {name}: {ours} vs reference {}",
                    rec.flag(name, t)
                ));
            }
        }
        let keys: Vec<&str> = step.info.keys().collect();
        if keys != case.step_info_keys {
            mm.push(format!(
                "step {t} info keys {keys:?} vs reference {:?}",
                case.step_info_keys
            ));
        }
        for k in &case.step_info_keys {
            match step.info.get(k) {
                Some(v) => mm.values(
                    &format!("step {t} info.{k}"),
                    v,
                    &rec.row(&format!("info.{k}"), t),
                ),
                None => mm.push(format!("step {t}: missing info.{k}")),
            }
        }
    }
    if !env.warnings().is_empty() {
        mm.push(format!("unexpected MuJoCo warnings: {:?}", env.warnings()));
    }
    mm
}

/// A per-thread counting allocator, so other test threads do not interfere: a test binary
/// installs it with `#[global_allocator] static A: ThreadCounting = ThreadCounting;` and measures
/// with [`allocations`].
pub struct ThreadCounting;

thread_local! {
    static COUNT: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

// SAFETY: forwards to the system allocator; counting touches only a thread-local integer.
unsafe impl std::alloc::GlobalAlloc for ThreadCounting {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
        // SAFETY: the caller's `GlobalAlloc` contract, passed on unchanged.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: as in `alloc`.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new: usize) -> *mut u8 {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
        // SAFETY: as in `alloc`.
        unsafe { std::alloc::System.realloc(ptr, layout, new) }
    }
}

/// Allocations `f` made on this thread (under [`ThreadCounting`]).
pub fn allocations(f: impl FnOnce()) -> u64 {
    let before = COUNT.with(std::cell::Cell::get);
    f();
    COUNT.with(std::cell::Cell::get) - before
}

/// A file written into a directory of its own under the temporary directory; both are removed
/// when it is dropped (pass it by value to a function that reads it once, e.g.
/// `Env::from_spec_file`), so the tests leave nothing behind.
pub struct ScratchFile {
    dir: PathBuf,
    path: PathBuf,
}

impl ScratchFile {
    /// `text` as `name` in `<tmp>/<label>-<pid>-<name>/`.
    pub fn new(label: &str, name: &str, text: &str) -> ScratchFile {
        let dir = std::env::temp_dir().join(format!("{label}-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create a scratch directory");
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write a scratch file");
        ScratchFile { dir, path }
    }
}

impl AsRef<Path> for ScratchFile {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
