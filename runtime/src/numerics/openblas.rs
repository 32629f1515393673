//! OpenBLAS `ddot` as numpy 2.4.6's bundled OpenBLAS 0.3.31 (scipy-openblas, `DYNAMIC_ARCH`)
//! computes it, and which of its kernels that library picks on a given CPU.
//!
//! Written by hand because the last bit depends on the kernel's summation order and on whether
//! its compiler contracted the tail loop into fused multiply-adds; no Rust BLAS reproduces that.
//! The rules were read from the wheel's own machine code (`ddot_k_*`, `dot_compute`,
//! `gotoblas_dynamic_init`) and OpenBLAS's `driver/others/dynamic.c` and `kernel/x86_64/ddot*`,
//! and are checked against the live library under every `OPENBLAS_CORETYPE`
//! (`tests/numerics.rs`, `tests/reference/record_numerics.py`).

use super::cpu::{Cpu, Vendor};

/// The five x86-64 `ddot` kernels in the wheel's build (its `DYNAMIC_LIST`); every other core
/// type OpenBLAS knows is mapped onto one of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kernel {
    /// SSE2 (`dot_sse2.S`): four 2-lane accumulators, no FMA.
    Prescott,
    /// SSE2 (`ddot_microk_nehalem`): blocks of 16, four 2-lane accumulators; plain tail.
    Nehalem,
    /// AVX: blocks of 16, four 4-lane accumulators, multiply then add; plain tail.
    Sandybridge,
    /// AVX2: as Sandybridge with fused multiply-adds in the blocks; plain tail.
    Haswell,
    /// AVX-512: 32-element ZMM blocks, a 16-element YMM block, all fused; FMA-contracted tail.
    SkylakeX,
}

impl Kernel {
    /// Every kernel, oldest first.
    pub const ALL: [Kernel; 5] = [
        Kernel::Prescott,
        Kernel::Nehalem,
        Kernel::Sandybridge,
        Kernel::Haswell,
        Kernel::SkylakeX,
    ];

    /// The lower-case name used in profile names (`openblas-<name>`).
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Prescott => "prescott",
            Kernel::Nehalem => "nehalem",
            Kernel::Sandybridge => "sandybridge",
            Kernel::Haswell => "haswell",
            Kernel::SkylakeX => "skylakex",
        }
    }

    /// The kernel of a lower-case name (`name`'s inverse).
    pub fn from_name(s: &str) -> Option<Kernel> {
        Kernel::ALL.into_iter().find(|k| k.name() == s)
    }

    /// Whether this CPU can execute the kernel (forcing one it cannot makes numpy die of SIGILL;
    /// envc computes the same numbers in portable code either way).
    pub fn runs_on(self, cpu: &Cpu) -> bool {
        match self {
            Kernel::Prescott | Kernel::Nehalem => cpu.leaf1_eax != 0,
            Kernel::Sandybridge => cpu.os_avx(),
            Kernel::Haswell => cpu.avx2() && cpu.fma(),
            Kernel::SkylakeX => cpu.openblas_avx512(),
        }
    }
}

/// OpenBLAS's core names in its `corename[]` order, 1..=25: the names `OPENBLAS_CORETYPE`
/// accepts (SapphireRapids, index 26, is outside the loop that matches them), each with the kernel
/// the wheel's build maps it to.
const CORE_NAMES: [(&str, Kernel); 25] = [
    ("Katmai", Kernel::Prescott),
    ("Coppermine", Kernel::Prescott),
    ("Northwood", Kernel::Prescott),
    ("Prescott", Kernel::Prescott),
    ("Banias", Kernel::Prescott),
    ("Atom", Kernel::Nehalem),
    ("Core2", Kernel::Prescott),
    ("Penryn", Kernel::Prescott),
    ("Dunnington", Kernel::Prescott),
    ("Nehalem", Kernel::Nehalem),
    ("Athlon", Kernel::Prescott),
    ("Opteron_SSE3", Kernel::Prescott),
    ("Opteron", Kernel::Prescott),
    ("Barcelona", Kernel::Nehalem),
    ("Nano", Kernel::Prescott),
    ("Sandybridge", Kernel::Sandybridge),
    ("Bobcat", Kernel::Nehalem),
    ("Bulldozer", Kernel::Sandybridge),
    ("Piledriver", Kernel::Sandybridge),
    ("Haswell", Kernel::Haswell),
    ("Steamroller", Kernel::Sandybridge),
    ("Excavator", Kernel::Sandybridge),
    ("Zen", Kernel::Haswell),
    ("SkylakeX", Kernel::SkylakeX),
    ("Cooperlake", Kernel::SkylakeX),
];

/// The kernel OpenBLAS uses, and why (for `envc info`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// The kernel chosen.
    pub kernel: Kernel,
    /// Chosen by a recognised `OPENBLAS_CORETYPE` (the same on every CPU), not by the CPU.
    pub by_name: bool,
    /// Why, in words.
    pub reason: String,
}

/// What `gotoblas_dynamic_init` picks: a recognised `OPENBLAS_CORETYPE` (matched case-insensitively
/// and exactly, as `strncasecmp(.., 20)` against names shorter than 20), else the CPU model table,
/// else the feature fallback. An unrecognised core type also ends in the feature fallback.
pub fn select(cpu: &Cpu, coretype: Option<&str>) -> Selection {
    if let Some(name) = coretype {
        if let Some((core, kernel)) = CORE_NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
        {
            return Selection {
                kernel: *kernel,
                by_name: true,
                reason: format!("OPENBLAS_CORETYPE={name} names core {core}"),
            };
        }
        let kernel = fallback(cpu);
        return Selection {
            kernel,
            by_name: false,
            reason: format!(
                "OPENBLAS_CORETYPE={name:?} is not a core OpenBLAS knows; its CPU-feature fallback picks {}",
                kernel.name()
            ),
        };
    }
    match by_model(cpu) {
        Some(kernel) => Selection {
            kernel,
            by_name: false,
            reason: format!(
                "OpenBLAS's CPU table: {:?} family {:#x} model {:#x}",
                cpu.vendor,
                cpu.display_family(),
                cpu.display_model()
            ),
        },
        None => {
            let kernel = fallback(cpu);
            Selection {
                kernel,
                by_name: false,
                reason: format!(
                    "{:?} family {:#x} model {:#x} is not in OpenBLAS's CPU table; its CPU-feature fallback picks {}",
                    cpu.vendor,
                    cpu.display_family(),
                    cpu.display_model(),
                    kernel.name()
                ),
            }
        }
    }
}

/// `gotoblas_dynamic_init`'s fallback when no core was identified.
fn fallback(cpu: &Cpu) -> Kernel {
    if cpu.openblas_avx512() {
        Kernel::SkylakeX
    } else if cpu.avx2() {
        Kernel::Haswell
    } else if cpu.os_avx() {
        Kernel::Sandybridge
    } else {
        Kernel::Prescott
    }
}

/// The table's common answer: the best of SkylakeX / Haswell / Sandybridge / Nehalem the CPU and
/// OS allow, capped at `top`.
fn capped(cpu: &Cpu, top: Kernel) -> Kernel {
    if top >= Kernel::SkylakeX && cpu.openblas_avx512() {
        Kernel::SkylakeX
    } else if top >= Kernel::Haswell && cpu.avx2() {
        Kernel::Haswell
    } else if top >= Kernel::Sandybridge && cpu.os_avx() {
        Kernel::Sandybridge
    } else {
        Kernel::Nehalem
    }
}

/// `get_coretype` mapped to the build's kernels; `None` where OpenBLAS returns NULL.
fn by_model(cpu: &Cpu) -> Option<Kernel> {
    use Kernel::*;
    let (family, exfamily, model, exmodel) =
        (cpu.family(), cpu.exfamily(), cpu.model(), cpu.exmodel());
    match cpu.vendor {
        Vendor::Intel => match family {
            0x6 => match (exmodel, model) {
                (0, 0..=15) if model != 12 => Some(Prescott), // Katmai .. Core2
                (1, 6 | 7 | 13) => Some(Prescott),            // Core2, Penryn, Dunnington
                (1, 10 | 11 | 14 | 15) | (1, 12) => Some(Nehalem), // Nehalem, Atom
                (2, 5 | 12 | 14 | 15) => Some(Nehalem),
                (2, 10 | 13) | (3, 10 | 14) => Some(capped(cpu, Sandybridge)),
                (3, 12 | 15 | 13) => Some(capped(cpu, Haswell)),
                (3, 7) => Some(Nehalem), // Bay Trail
                (4, 5 | 6 | 7 | 15 | 14) => Some(capped(cpu, Haswell)),
                (4, 12 | 13) => Some(Nehalem),
                (5, 6 | 14 | 7) => Some(capped(cpu, Haswell)),
                (5, 5) => Some(capped(cpu, SkylakeX)),
                (5, 12 | 15) => Some(Nehalem),
                (6, 6) => Some(capped(cpu, Haswell)), // Cannon Lake: no AVX-512 kernels
                (6, 10 | 12) => Some(capped(cpu, SkylakeX)),
                (7, 10) => Some(Nehalem),
                (7, 13 | 14) => Some(capped(cpu, SkylakeX)),
                (8, 12 | 13 | 15) => Some(capped(cpu, SkylakeX)),
                (8, 14) => Some(capped(cpu, Haswell)),
                (9, 7 | 10) => Some(capped(cpu, SkylakeX)),
                (9, 14) => Some(capped(cpu, Haswell)),
                (10, 5 | 6) => Some(capped(cpu, Haswell)),
                (10, 7) => Some(capped(cpu, SkylakeX)),
                _ => None,
            },
            0xf => Some(Prescott), // Northwood, Prescott
            _ => None,
        },
        Vendor::Amd | Vendor::Hygon => match family {
            0..=0xe => None, // Athlon-era (32-bit cores; 64-bit builds never get here usefully)
            0xf => match exfamily {
                0 | 2 => Some(Prescott), // Opteron
                5 | 7 => Some(Nehalem),  // Bobcat
                6 => match (model, cpu.exmodel()) {
                    (1 | 2 | 3 | 5, _) | (0 | 8, 1 | 3 | 6) => Some(if cpu.os_avx() {
                        Sandybridge // Bulldozer .. Excavator
                    } else {
                        Nehalem // Barcelona
                    }),
                    _ => None,
                },
                8 | 9 => Some(if cpu.os_avx() { Haswell } else { Nehalem }), // Zen 1-3
                10 => Some(if cpu.openblas_avx512() {
                    SkylakeX // Zen 4: Cooperlake / SkylakeX
                } else if cpu.os_avx() {
                    Haswell
                } else {
                    Nehalem
                }),
                _ => None, // Zen 5 and later: the feature fallback
            },
            _ => None,
        },
        // Centaur / Zhaoxin: OpenBLAS's table is not followed here; the feature fallback answers.
        _ => None,
    }
}

/// `cblas_ddot(n, x, 1, y, 1)` computed as `kernel` does, for contiguous, 16-byte-aligned arrays
/// (numpy's own allocations) of at most 10 000 elements (beyond, OpenBLAS splits the sum over
/// threads).
pub fn ddot(kernel: Kernel, n: usize, x: &dyn Fn(usize) -> f64, y: &dyn Fn(usize) -> f64) -> f64 {
    match kernel {
        Kernel::Prescott => ddot_prescott(n, x, y),
        Kernel::Nehalem => {
            let n1 = n & !15;
            let mut acc = [[0.0f64; 2]; 4];
            for i in (0..n1).step_by(8) {
                for (k, a) in acc.iter_mut().enumerate() {
                    for (l, a) in a.iter_mut().enumerate() {
                        *a += x(i + 2 * k + l) * y(i + 2 * k + l);
                    }
                }
            }
            let r = add2(add2(acc[0], acc[1]), add2(acc[2], acc[3]));
            plain_tail(if n1 > 0 { r[0] + r[1] } else { 0.0 }, n1, n, x, y)
        }
        Kernel::Sandybridge | Kernel::Haswell => {
            let fused = kernel == Kernel::Haswell;
            let n1 = n & !15;
            let mut acc = [[0.0f64; 4]; 4];
            for i in (0..n1).step_by(16) {
                for (k, a) in acc.iter_mut().enumerate() {
                    for (l, a) in a.iter_mut().enumerate() {
                        let j = i + 4 * k + l;
                        *a = if fused {
                            x(j).mul_add(y(j), *a)
                        } else {
                            *a + x(j) * y(j)
                        };
                    }
                }
            }
            // Each YMM accumulator folds its high half onto its low half, then pairs, then lanes.
            let h = acc.map(|a| [a[0] + a[2], a[1] + a[3]]);
            let r = add2(add2(h[0], h[1]), add2(h[2], h[3]));
            plain_tail(if n1 > 0 { r[0] + r[1] } else { 0.0 }, n1, n, x, y)
        }
        Kernel::SkylakeX => ddot_skylakex(n, x, y),
    }
}

fn add2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

/// `dot += y[i] * x[i]` for the leftover elements, multiply and add rounded separately.
fn plain_tail(
    mut dot: f64,
    from: usize,
    n: usize,
    x: &dyn Fn(usize) -> f64,
    y: &dyn Fn(usize) -> f64,
) -> f64 {
    for i in from..n {
        dot += y(i) * x(i);
    }
    dot
}

/// `dot_sse2.S` on aligned data: pairs of elements go round-robin into four 2-lane accumulators
/// (16 per round), then 8, 4, 2 leftovers into the first ones and a last single element into
/// lane 0 of the first.
fn ddot_prescott(n: usize, x: &dyn Fn(usize) -> f64, y: &dyn Fn(usize) -> f64) -> f64 {
    let mut acc = [[0.0f64; 2]; 4];
    let pair = |acc: &mut [[f64; 2]; 4], k: usize, i: usize| {
        for (l, a) in acc[k].iter_mut().enumerate() {
            *a += x(i + l) * y(i + l);
        }
    };
    let mut i = 0;
    while i + 16 <= n {
        for p in 0..8 {
            pair(&mut acc, p % 4, i + 2 * p);
        }
        i += 16;
    }
    let rest = n - i;
    if rest & 8 != 0 {
        for p in 0..4 {
            pair(&mut acc, p, i + 2 * p);
        }
        i += 8;
    }
    if rest & 4 != 0 {
        for p in 0..2 {
            pair(&mut acc, p, i + 2 * p);
        }
        i += 4;
    }
    if rest & 2 != 0 {
        pair(&mut acc, 0, i);
        i += 2;
    }
    if rest & 1 != 0 {
        acc[0][0] += x(i) * y(i);
    }
    let r = add2(add2(acc[0], acc[1]), add2(acc[2], acc[3]));
    r[0] + r[1]
}

/// The SkylakeX build of `ddot.c`: 32-element blocks in four 8-lane accumulators (folded to four
/// lanes), one more 16-element block in four 4-lane accumulators, and the tail contracted to FMA.
fn ddot_skylakex(n: usize, x: &dyn Fn(usize) -> f64, y: &dyn Fn(usize) -> f64) -> f64 {
    let n1 = n & !15;
    let mut dot = 0.0f64;
    if n1 > 0 {
        let n32 = if n1 >= 32 { n & !31 } else { 0 };
        let mut z = [[0.0f64; 8]; 4];
        for i in (0..n32).step_by(32) {
            for (k, a) in z.iter_mut().enumerate() {
                for (l, a) in a.iter_mut().enumerate() {
                    let j = i + 8 * k + l;
                    *a = x(j).mul_add(y(j), *a);
                }
            }
        }
        let mut acc = z.map(|a| [a[0] + a[4], a[1] + a[5], a[2] + a[6], a[3] + a[7]]);
        for i in (n32..n1).step_by(16) {
            for (k, a) in acc.iter_mut().enumerate() {
                for (l, a) in a.iter_mut().enumerate() {
                    let j = i + 4 * k + l;
                    *a = x(j).mul_add(y(j), *a);
                }
            }
        }
        let t: [f64; 4] =
            std::array::from_fn(|l| ((acc[0][l] + acc[1][l]) + acc[2][l]) + acc[3][l]);
        dot = (t[0] + t[2]) + (t[1] + t[3]);
    }
    for i in n1..n {
        dot = y(i).mul_add(x(i), dot);
    }
    dot
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coretype_names_match_exactly_and_case_insensitively() {
        let cpu = Cpu::none();
        assert_eq!(select(&cpu, Some("haswell")).kernel, Kernel::Haswell);
        assert_eq!(select(&cpu, Some("ZEN")).kernel, Kernel::Haswell);
        assert_eq!(select(&cpu, Some("Cooperlake")).kernel, Kernel::SkylakeX);
        // Not a name: the feature fallback (no features here: Prescott).
        assert_eq!(select(&cpu, Some("Haswell ")).kernel, Kernel::Prescott);
        assert_eq!(
            select(&cpu, Some("SapphireRapids")).kernel,
            Kernel::Prescott
        );
        assert_eq!(select(&cpu, Some("")).kernel, Kernel::Prescott);
    }

    #[test]
    fn short_vectors() {
        let v = [0.1f64, 0.7];
        let f = |i: usize| v[i];
        assert_eq!(ddot(Kernel::Haswell, 2, &f, &f), 0.1 * 0.1 + 0.7 * 0.7);
        assert_eq!(
            ddot(Kernel::SkylakeX, 2, &f, &f),
            0.7f64.mul_add(0.7, 0.1f64.mul_add(0.1, 0.0))
        );
        assert_eq!(ddot(Kernel::Prescott, 0, &f, &f), 0.0);
    }
}
