//! The CPU-dependent primitives against the reference, one recorded file per dispatch setting
//! (tests/reference/record_numerics.py): `np.linalg.norm` and `np.dot` (OpenBLAS ddot, every
//! kernel of the wheel) and float64 `np.exp` (SVML or glibc), bit for bit under the recorded
//! profile. With `$ENVC_NUMERICS_DIR` (a live matrix recorded on this machine) `auto` must also
//! pick the recorded profile from the recorded settings, as numpy and OpenBLAS did.

use std::path::{Path, PathBuf};

use envc::numerics::{self, NpyOverrides, Profile, cpu::Cpu};
use serde_json::Value;

fn dir() -> (PathBuf, bool) {
    match std::env::var_os("ENVC_NUMERICS_DIR") {
        Some(d) => (PathBuf::from(d), true),
        None => (
            Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/fixtures/numerics"),
            false,
        ),
    }
}

fn read(p: &Path) -> Value {
    serde_json::from_str(
        &std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())),
    )
    .unwrap()
}

fn unhex(h: &str) -> Vec<f64> {
    (0..h.len() / 16)
        .map(|i| {
            let mut b = [0u8; 8];
            for (k, byte) in b.iter_mut().enumerate() {
                *byte = u8::from_str_radix(&h[16 * i + 2 * k..16 * i + 2 * k + 2], 16).unwrap();
            }
            f64::from_le_bytes(b)
        })
        .collect()
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn setting(s: &Value, k: &str) -> Option<String> {
    s[k].as_str().map(str::to_string)
}

#[test]
fn primitives_match_the_reference_under_every_recorded_setting() {
    let (dir, live) = dir();
    let inputs = read(&dir.join("inputs.json"));
    let vecs: Vec<Vec<f64>> = inputs["norm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| unhex(c["v"].as_str().unwrap()))
        .collect();
    let xs = unhex(inputs["exp"].as_str().unwrap());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.extension().is_some_and(|x| x == "json")
                && !p.ends_with("inputs.json")
                && !p.ends_with("matrix.json")
        })
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "no recorded settings in {}",
        dir.display()
    );
    let mut errors = vec![];
    let mut kernels = std::collections::BTreeSet::new();
    for f in &files {
        let rec = read(f);
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let profile = Profile::parse(rec["numerics"].as_str().unwrap()).unwrap();
        kernels.insert((profile.blas, profile.svml_exp));
        let norms = unhex(rec["norm"].as_str().unwrap());
        let dots = unhex(rec["dot"].as_str().unwrap());
        let exps = unhex(rec["exp"].as_str().unwrap());
        assert_eq!(norms.len(), vecs.len(), "{name}: norm count");
        let mut bad = 0;
        // Counts every differing value, keeps the first three as messages.
        let mut check = |what: String, got: f64, want: f64| {
            if !same(got, want) {
                if bad < 3 {
                    errors.push(format!(
                        "{name} ({profile}): {what} gave {got:e}, numpy {want:e}"
                    ));
                }
                bad += 1;
            }
        };
        for (v, want) in vecs.iter().zip(&norms) {
            let got = numerics::norm(profile, v.len(), &|i| v[i]);
            check(format!("norm of n={}", v.len()), got, *want);
        }
        for (c, want) in inputs["dot"].as_array().unwrap().iter().zip(&dots) {
            let a = &vecs[c["a"].as_u64().unwrap() as usize];
            let b = &vecs[c["b"].as_u64().unwrap() as usize];
            let got = numerics::dot(profile, a.len(), &|i| a[i], &|i| b[i]);
            check(format!("dot of n={}", a.len()), got, *want);
        }
        for (x, want) in xs.iter().zip(&exps) {
            check(format!("exp({x:e})"), numerics::exp(profile, *x), *want);
        }
        if bad > 0 {
            errors.push(format!("{name}: {bad} values differ"));
        }
        if live {
            let s = &rec["settings"];
            let auto = numerics::auto_for(
                Cpu::this(),
                setting(s, "OPENBLAS_CORETYPE"),
                NpyOverrides {
                    enable: setting(s, "NPY_ENABLE_CPU_FEATURES"),
                    disable: setting(s, "NPY_DISABLE_CPU_FEATURES"),
                },
            )
            .map(|a| a.profile.to_string())
            .unwrap_or_else(|e| e.to_string());
            if auto != profile.to_string() {
                errors.push(format!(
                    "{name}: auto picks {auto}, numpy and OpenBLAS ran {profile}"
                ));
            }
        }
    }
    eprintln!(
        "numerics: {} settings from {} ({} profiles), {} norms, {} dots, {} exps each",
        files.len(),
        dir.display(),
        kernels.len(),
        vecs.len(),
        inputs["dot"].as_array().unwrap().len(),
        xs.len()
    );
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    if !live {
        // The committed set covers every kernel of the wheel and both exp paths.
        assert!(
            kernels.len() >= 6,
            "committed numerics fixtures cover only {kernels:?}"
        );
    }
}

/// `OPENBLAS_CORETYPE=<name>` for every core name OpenBLAS knows, other cases and near misses,
/// against the kernel the reference's OpenBLAS reported (`coretype_names` in matrix.json). Names
/// OpenBLAS does not recognise fall back to the recording CPU's features, so those are checked
/// only live (on the CPU that recorded them).
#[test]
fn coretype_names_pick_the_reference_kernel() {
    use envc::numerics::openblas::select;
    let (dir, live) = dir();
    let m = read(&dir.join("matrix.json"));
    let names = m["coretype_names"]
        .as_array()
        .expect("matrix.json has coretype_names");
    assert!(names.len() >= 26);
    let cpu = Cpu::this();
    let mut checked = 0;
    for n in names {
        let name = n["name"].as_str().unwrap();
        if n["kernel"].is_null() {
            continue; // the reference could not run that kernel on the recording CPU
        }
        let sel = select(&cpu, Some(name));
        if !sel.by_name && !live {
            continue;
        }
        assert_eq!(
            sel.kernel.name(),
            n["kernel"],
            "OPENBLAS_CORETYPE={name:?}: {}",
            sel.reason
        );
        checked += 1;
    }
    assert!(checked >= 25, "only {checked} names checked");
}
