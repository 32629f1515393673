//! Which float64 `np.exp` numpy 2.4.6 runs: its X86_V4 loop calls Intel SVML (`svml_exp`), its
//! X86_V3 and baseline loops call glibc's `exp`. numpy's other ufuncs that envc mirrors (`sin`,
//! `cos`, `sqrt`, `square`, `clip`, sums, scalar `x**2`) give the same bits on every dispatch
//! target (measured by `tests/reference/probe_numpy_dispatch.py`), so `exp` is the only choice.
//!
//! The overrides follow numpy's `npy_cpu_features.c`: `NPY_ENABLE_CPU_FEATURES` (only these
//! dispatched features) or `NPY_DISABLE_CPU_FEATURES` (all but these), names separated by any of
//! `", \t\v\r\n\f"`, case-sensitive, unknown names ignored. A loop runs only if every feature it
//! implies is on, so the X86_V4 loop needs both X86_V3 and X86_V4.

use super::cpu::Cpu;

/// numpy 2.4's x86-64 dispatch names (X86_V2 is the wheel's baseline).
const KNOWN: [&str; 5] = ["X86_V2", "X86_V3", "X86_V4", "AVX512_ICL", "AVX512_SPR"];

/// The two override variables as read from the environment (`None` or blank: unset).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Overrides {
    /// `NPY_ENABLE_CPU_FEATURES`.
    pub enable: Option<String>,
    /// `NPY_DISABLE_CPU_FEATURES`.
    pub disable: Option<String>,
}

impl Overrides {
    /// Read both variables from this process's environment.
    pub fn from_env() -> Overrides {
        let get = |k: &str| std::env::var(k).ok();
        Overrides {
            enable: get("NPY_ENABLE_CPU_FEATURES"),
            disable: get("NPY_DISABLE_CPU_FEATURES"),
        }
    }
}

fn names(s: &str) -> Vec<&str> {
    s.split([',', ' ', '\t', '\u{b}', '\r', '\n', '\u{c}'])
        .filter(|n| !n.is_empty())
        .collect()
}

fn set(v: &Option<String>) -> Option<Vec<&str>> {
    v.as_deref().map(names).filter(|n| !n.is_empty())
}

/// Whether numpy uses SVML for float64 `exp`, and why; `Err` for settings numpy refuses to
/// import with.
pub fn svml_exp(cpu: &Cpu, ov: &Overrides) -> Result<(bool, String), String> {
    // AVX512_ICL / AVX512_SPR select no loop envc mirrors and are not detected here, so enabling
    // one the CPU lacks (an import error in numpy) goes unnoticed; KNOWN lists them for that reason.
    let lacks = |f: &str| match f {
        "X86_V3" => !cpu.npy_x86_v3(),
        "X86_V4" => !cpu.npy_x86_v4(),
        _ => false,
    };
    type Enabled = Box<dyn Fn(&str) -> bool>;
    let (on, why): (Enabled, String) = match (set(&ov.enable), set(&ov.disable)) {
        (Some(_), Some(_)) => {
            return Err(
                "both NPY_ENABLE_CPU_FEATURES and NPY_DISABLE_CPU_FEATURES are set; numpy refuses to import"
                    .into(),
            );
        }
        (Some(en), None) => {
            if let Some(f) = en.iter().find(|f| KNOWN.contains(f) && lacks(f)) {
                return Err(format!(
                    "NPY_ENABLE_CPU_FEATURES names {f}, which this CPU lacks; numpy refuses to import"
                ));
            }
            let list: Vec<String> = en.iter().map(|s| s.to_string()).collect();
            let why = format!("NPY_ENABLE_CPU_FEATURES={}", list.join(","));
            (Box::new(move |f: &str| list.iter().any(|n| n == f)), why)
        }
        (None, Some(dis)) => {
            if dis.contains(&"X86_V2") {
                return Err(
                    "NPY_DISABLE_CPU_FEATURES names the baseline X86_V2; numpy refuses to import"
                        .into(),
                );
            }
            let list: Vec<String> = dis.iter().map(|s| s.to_string()).collect();
            let why = format!("NPY_DISABLE_CPU_FEATURES={}", list.join(","));
            (Box::new(move |f: &str| !list.iter().any(|n| n == f)), why)
        }
        (None, None) => (
            Box::new(|_: &str| true),
            "no NPY_*_CPU_FEATURES override".into(),
        ),
    };
    let svml = cpu.npy_x86_v4() && on("X86_V3") && on("X86_V4");
    let what = if svml {
        "numpy's X86_V4 loop: float64 exp is SVML".to_string()
    } else if !cpu.npy_x86_v4() {
        "the CPU lacks X86_V4 (AVX-512 F/CD/BW/DQ/VL): float64 exp is glibc's".to_string()
    } else {
        "X86_V4 switched off: float64 exp is glibc's".to_string()
    };
    Ok((svml, format!("{what} ({why})")))
}
