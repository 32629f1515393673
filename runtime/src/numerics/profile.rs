//! Numerics profiles: a name for "how the reference computes on some machine", and `auto`, the
//! profile of the machine envc runs on.

use std::fmt;
use std::sync::{OnceLock, RwLock};

use envspec::Code;

use super::cpu::Cpu;
use super::npy;
use super::openblas::{self, Kernel};

/// One machine's reference arithmetic: the OpenBLAS `ddot` kernel and whether numpy's float64
/// `exp` is SVML. Written `openblas-<kernel>[+svml]`, e.g. `openblas-skylakex+svml`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Profile {
    /// The OpenBLAS `ddot` kernel behind `np.linalg.norm`.
    pub blas: Kernel,
    /// Whether numpy's float64 `exp` is the AVX-512 SVML one.
    pub svml_exp: bool,
}

impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "openblas-{}", self.blas.name())?;
        if self.svml_exp {
            f.write_str("+svml")?;
        }
        Ok(())
    }
}

/// A profile choice that cannot be honoured.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NumericsError {
    /// A profile name that is neither `auto` nor a known kernel (E1301).
    #[error(
        "error[E1301]: unknown numerics profile `{given}` (from {source_}); expected `auto` or openblas-<kernel>[+svml] with kernel one of prescott, nehalem, sandybridge, haswell, skylakex"
    )]
    UnknownProfile {
        /// The name given.
        given: String,
        /// Where it came from (an env variable, an argument).
        source_: String,
    },
    /// `auto` on a machine whose numpy envc cannot follow (E1302).
    #[error("error[E1302]: `auto` cannot follow numpy here: {0}")]
    NumpyRefuses(String),
}

impl NumericsError {
    /// The stable code (docs/errors.md).
    pub fn code(&self) -> Code {
        match self {
            NumericsError::UnknownProfile { .. } => Code::E1301,
            NumericsError::NumpyRefuses(_) => Code::E1302,
        }
    }
}

impl Profile {
    /// Every profile (5 kernels × exp choice), in name order of kernels.
    pub fn all() -> Vec<Profile> {
        Kernel::ALL
            .into_iter()
            .flat_map(|blas| [false, true].map(|svml_exp| Profile { blas, svml_exp }))
            .collect()
    }

    /// Parse a profile name (not `auto`; see [`resolve`](Profile::resolve)).
    pub fn parse(s: &str) -> Option<Profile> {
        let rest = s.trim().strip_prefix("openblas-")?;
        let (kernel, svml_exp) = match rest.strip_suffix("+svml") {
            Some(k) => (k, true),
            None => (rest, false),
        };
        Some(Profile {
            blas: Kernel::from_name(kernel)?,
            svml_exp,
        })
    }

    /// A profile name or `auto`; `source` says where the text came from, for the error.
    pub fn resolve(s: &str, source: &str) -> Result<Profile, NumericsError> {
        if s.trim() == "auto" {
            return auto().map(|a| a.profile);
        }
        Profile::parse(s).ok_or_else(|| NumericsError::UnknownProfile {
            given: s.to_string(),
            source_: source.to_string(),
        })
    }
}

/// What `auto` found on this machine.
#[derive(Clone, Debug)]
pub struct Auto {
    /// The profile `auto` chose.
    pub profile: Profile,
    /// The CPU facts it chose from.
    pub cpu: Cpu,
    /// Why that BLAS kernel, in words.
    pub blas_reason: String,
    /// Why SVML `exp` or not, in words.
    pub exp_reason: String,
    /// `OPENBLAS_CORETYPE` as read at start-up.
    pub coretype: Option<String>,
    /// numpy's CPU-feature overrides as read at start-up.
    pub npy: npy::Overrides,
}

/// The profile numpy 2.4.6 and its OpenBLAS would use in this process, from the CPU and the
/// override variables (read once, as numpy and OpenBLAS read them once at load time).
pub fn auto() -> Result<Auto, NumericsError> {
    static AUTO: OnceLock<Result<Auto, NumericsError>> = OnceLock::new();
    AUTO.get_or_init(|| {
        auto_for(
            Cpu::this(),
            std::env::var("OPENBLAS_CORETYPE").ok(),
            npy::Overrides::from_env(),
        )
    })
    .clone()
}

/// `auto` for a given CPU and given settings (tests replay recorded settings through this).
pub fn auto_for(
    cpu: Cpu,
    coretype: Option<String>,
    npy_overrides: npy::Overrides,
) -> Result<Auto, NumericsError> {
    let sel = openblas::select(&cpu, coretype.as_deref());
    let (svml_exp, exp_reason) =
        npy::svml_exp(&cpu, &npy_overrides).map_err(NumericsError::NumpyRefuses)?;
    Ok(Auto {
        profile: Profile {
            blas: sel.kernel,
            svml_exp,
        },
        cpu,
        blas_reason: sel.reason,
        exp_reason,
        coretype,
        npy: npy_overrides,
    })
}

pub use npy::Overrides as NpyOverrides;

static DEFAULT: RwLock<Option<Profile>> = RwLock::new(None);

/// Make `profile` the default of every env built from now on in this process (the CLI's
/// `--numerics`); envs built earlier keep theirs.
pub fn set_default_profile(profile: Profile) {
    let mut d = DEFAULT.write().unwrap_or_else(|e| e.into_inner());
    *d = Some(profile);
}

/// The profile a new env starts with: the process default if one was set, else
/// `ENVC_NUMERICS` (a profile name or `auto`), else `auto`.
pub fn default_profile() -> Result<Profile, NumericsError> {
    if let Some(p) = *DEFAULT.read().unwrap_or_else(|e| e.into_inner()) {
        return Ok(p);
    }
    match std::env::var("ENVC_NUMERICS") {
        Ok(v) if !v.trim().is_empty() => Profile::resolve(&v, "ENVC_NUMERICS"),
        _ => auto().map(|a| a.profile),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for p in Profile::all() {
            assert_eq!(Profile::parse(&p.to_string()), Some(p));
        }
        assert_eq!(
            Profile::parse("openblas-skylakex+svml"),
            Some(Profile {
                blas: Kernel::SkylakeX,
                svml_exp: true
            })
        );
        assert_eq!(Profile::parse("openblas-zen"), None);
        assert_eq!(Profile::parse("haswell"), None);
        let e = Profile::resolve("openblas-haswel", "--numerics").unwrap_err();
        assert_eq!(e.code(), Code::E1301);
    }
}
