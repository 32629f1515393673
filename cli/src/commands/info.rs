//! `envc info`: what the machine is, which numerics profile `auto` picks here and why, and what
//! envc matches. The profile rules are in `envc::numerics`; this only prints them.

use anyhow::Result;
use envc::numerics::{self, Profile, cpu::Cpu};

use crate::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Output format.
    #[arg(long, value_enum, default_value = "text")]
    format: Format,
}

#[derive(clap::ValueEnum, Clone, Copy)]
enum Format {
    Text,
    Json,
}

pub fn run(args: Args) -> Result<Outcome> {
    let auto = numerics::auto();
    let default = numerics::default_profile();
    let cpu = auto.as_ref().map(|a| a.cpu).unwrap_or_else(|_| Cpu::this());
    let mujoco = envc::mujoco_version();
    let features: Vec<&str> = [
        ("avx", cpu.os_avx()),
        ("avx2", cpu.avx2()),
        ("fma", cpu.fma()),
        ("avx512vl", cpu.openblas_avx512()),
        ("avx512_bf16", cpu.openblas_avx512_bf16()),
        ("numpy X86_V3", cpu.npy_x86_v3()),
        ("numpy X86_V4", cpu.npy_x86_v4()),
    ]
    .into_iter()
    .filter_map(|(n, on)| on.then_some(n))
    .collect();
    let var = |k: &str| std::env::var(k).ok();
    let vars: Vec<(&str, Option<String>)> = [
        "OPENBLAS_CORETYPE",
        "NPY_ENABLE_CPU_FEATURES",
        "NPY_DISABLE_CPU_FEATURES",
        "ENVC_NUMERICS",
    ]
    .into_iter()
    .map(|k| (k, var(k)))
    .collect();
    // glibc's libm (shared by numpy, MuJoCo and envc) uses its FMA variants when FMA and AVX2 are
    // usable, unless GLIBC_TUNABLES hides them; envc cannot choose this (docs/numerics.md).
    let tunables = var("GLIBC_TUNABLES").unwrap_or_default();
    let libm_fma =
        cpu.fma() && cpu.avx2() && !(tunables.contains("-FMA") || tunables.contains("-AVX2"));
    let libm = if libm_fma { "fma" } else { "sse2/avx" };
    let install = Install::here();
    match args.format {
        Format::Json => {
            let v = serde_json::json!({
                "envc": env!("CARGO_PKG_VERSION"),
                "installation": install.json(),
                "reference": numerics::REFERENCE,
                "mujoco_linked": mujoco,
                "mujoco_built_for": envc::MUJOCO_VERSION,
                "mujoco_reason": mujoco_reason(),
                "cpu": {
                    "brand": cpu.brand(),
                    "vendor": format!("{:?}", cpu.vendor),
                    "family": cpu.display_family(),
                    "model": cpu.display_model(),
                    "features": features,
                },
                "settings": vars.iter().map(|(k, v)| (k.to_string(), serde_json::json!(v))).collect::<serde_json::Map<_, _>>(),
                "auto": match &auto {
                    Ok(a) => serde_json::json!({
                        "profile": a.profile.to_string(),
                        "blas": a.blas_reason,
                        "exp": a.exp_reason,
                    }),
                    Err(e) => serde_json::json!({ "error": e.to_string() }),
                },
                "default": match &default {
                    Ok(p) => serde_json::json!(p.to_string()),
                    Err(e) => serde_json::json!({ "error": e.to_string() }),
                },
                "libm": libm,
                "profiles": Profile::all().iter().map(|p| p.to_string()).collect::<Vec<_>>(),
                "reference_kernels_runnable": numerics::Kernel::ALL.iter().filter(|k| k.runs_on(&cpu)).map(|k| k.name()).collect::<Vec<_>>(),
            });
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
        Format::Text => {
            println!("envc {}", env!("CARGO_PKG_VERSION"));
            install.print();
            println!("matches:   {}", numerics::REFERENCE);
            println!("linked:    MuJoCo {mujoco}");
            println!("  why:     {}", mujoco_reason());
            println!(
                "cpu:       {} ({:?}, family {:#x}, model {:#x})",
                cpu.brand(),
                cpu.vendor,
                cpu.display_family(),
                cpu.display_model()
            );
            println!("features:  {}", features.join(", "));
            for (k, v) in &vars {
                println!("{k:<25}{}", v.as_deref().unwrap_or("(unset)"));
            }
            match &auto {
                Ok(a) => {
                    println!("auto:      {}", a.profile);
                    println!("  ddot:    {}", a.blas_reason);
                    println!("  exp:     {}", a.exp_reason);
                }
                Err(e) => println!("auto:      {e}"),
            }
            match &default {
                Ok(p) => println!("new envs:  {p}"),
                Err(e) => println!("new envs:  {e}"),
            }
            println!(
                "libm:      glibc {libm} variants (shared by numpy, MuJoCo and envc; not part of a profile, see docs/numerics.md)"
            );
            let all: Vec<String> = Profile::all().iter().map(|p| p.to_string()).collect();
            println!(
                "profiles:  {} (envc computes any of them here)",
                all.join(", ")
            );
            let native: Vec<&str> = numerics::Kernel::ALL
                .iter()
                .filter(|k| k.runs_on(&cpu))
                .map(|k| k.name())
                .collect();
            println!(
                "kernels this CPU can run in the reference (OPENBLAS_CORETYPE): {}",
                native.join(", ")
            );
        }
    }
    Ok(Outcome::Ok)
}

/// Where this envc is and where what it runs comes from.
struct Install {
    exe: Option<std::path::PathBuf>,
    bundle: Result<(std::path::PathBuf, envspec::bundle::Origin), String>,
    mujoco: Option<std::path::PathBuf>,
    spec_path: Option<String>,
}

impl Install {
    fn here() -> Install {
        Install {
            // The wheel's console script runs the command inside Python: it names itself.
            exe: std::env::var_os("ENVC_EXECUTABLE")
                .map(std::path::PathBuf::from)
                .or_else(|| std::env::current_exe().ok()),
            bundle: envspec::bundle::root()
                .map(|(p, o)| (p.to_path_buf(), o))
                .map_err(str::to_string),
            mujoco: envc::mujoco_library_path(),
            spec_path: std::env::var("ENVC_SPEC_PATH").ok(),
        }
    }

    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "executable": self.exe,
            "bundle": match &self.bundle {
                Ok((p, o)) => serde_json::json!({"root": p, "origin": o, "hash": envspec::bundle::hash()}),
                Err(e) => serde_json::json!({"error": e}),
            },
            "mujoco_library": self.mujoco,
            "spec_path": self.spec_path,
            "user_ids": envspec::registry::user_entries().iter().map(|e| e.id.clone()).collect::<Vec<_>>(),
        })
    }

    fn print(&self) {
        let or_unknown = |p: &Option<std::path::PathBuf>| {
            p.as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_else(|| "(unknown)".into())
        };
        println!("installed: {}", or_unknown(&self.exe));
        match &self.bundle {
            Ok((p, o)) => {
                println!(
                    "specs:     {} ({})",
                    p.join("specs").display(),
                    o.describe()
                );
                println!("models:    {}", p.join("assets").display());
            }
            Err(e) => println!("specs:     none: {e}"),
        }
        println!("mujoco:    {}", or_unknown(&self.mujoco));
        println!(
            "ENVC_SPEC_PATH           {}",
            self.spec_path.as_deref().unwrap_or("(unset)")
        );
    }
}

/// Why this MuJoCo: the wheel's console script says which installed package chose this build
/// (ENVC_MUJOCO_REASON, envc/_mujoco.py); otherwise it is the version this build is for.
fn mujoco_reason() -> String {
    let built = match envc::MUJOCO_VERSION {
        "3.17.0" => "the default build",
        _ => "built with cargo feature `mujoco-4.0.1`",
    };
    match std::env::var("ENVC_MUJOCO_REASON") {
        Ok(r) if !r.is_empty() => format!(
            "{r}; this build is MuJoCo {}'s ({built})",
            envc::MUJOCO_VERSION
        ),
        _ => format!(
            "this build is for MuJoCo {} ({built})",
            envc::MUJOCO_VERSION
        ),
    }
}
