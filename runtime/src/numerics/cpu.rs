//! The x86-64 CPU facts that OpenBLAS and numpy dispatch on, read with CPUID and XGETBV. Kept as
//! raw register values so that every rule below reads like the source it follows and tests can
//! feed in other CPUs' values.

/// CPU vendor, from CPUID leaf 0's vendor string.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vendor {
    /// `GenuineIntel`.
    Intel,
    /// `AuthenticAMD`.
    Amd,
    /// `HygonGenuine`.
    Hygon,
    /// `CentaurHauls`.
    Centaur,
    /// `  Shanghai  `.
    Zhaoxin,
    /// Any other vendor string.
    Other,
}

/// The CPUID leaves and XCR0 bits the dispatch rules read. All zero on non-x86-64 targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cpu {
    /// Who made the CPU (OpenBLAS's core tables are per vendor).
    pub vendor: Vendor,
    /// Leaf 1 EAX (family, model, stepping).
    pub leaf1_eax: u32,
    /// Leaf 1 ECX (SSE3 to AVX, OSXSAVE, F16C, FMA).
    pub leaf1_ecx: u32,
    /// Leaf 7 sub-leaf 0 EBX (AVX2, BMI, AVX-512 subsets).
    pub leaf7_ebx: u32,
    /// Leaf 7 sub-leaf 0 EDX (AMX; read by no rule now, kept with the other raw values).
    pub leaf7_edx: u32,
    /// Leaf 7 sub-leaf 1 EAX (AVX512_BF16).
    pub leaf7_1_eax: u32,
    /// Leaf 0xD sub-leaf 0 EAX (which state components the CPU supports; AMX tiles; read by no
    /// rule now).
    pub leafd_eax: u32,
    /// Leaf 0x8000_0001 ECX (LZCNT).
    pub ext1_ecx: u32,
    /// XCR0: which register states the OS saves (0 when OSXSAVE is off).
    pub xcr0: u64,
    /// The brand string (for `envc info` only).
    pub brand: [u8; 48],
}

fn bit(reg: u32, n: u32) -> bool {
    reg >> n & 1 == 1
}

impl Cpu {
    /// The CPU this process runs on.
    pub fn this() -> Cpu {
        #[cfg(target_arch = "x86_64")]
        {
            read_x86_64()
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            Cpu::none()
        }
    }

    /// No CPUID at all (other architectures).
    pub fn none() -> Cpu {
        Cpu {
            vendor: Vendor::Other,
            leaf1_eax: 0,
            leaf1_ecx: 0,
            leaf7_ebx: 0,
            leaf7_edx: 0,
            leaf7_1_eax: 0,
            leafd_eax: 0,
            ext1_ecx: 0,
            xcr0: 0,
            brand: [0; 48],
        }
    }

    /// Leaf 1's base family field.
    pub fn family(&self) -> u32 {
        self.leaf1_eax >> 8 & 0xf
    }
    /// Leaf 1's extended family field.
    pub fn exfamily(&self) -> u32 {
        self.leaf1_eax >> 20 & 0xff
    }
    /// Leaf 1's base model field.
    pub fn model(&self) -> u32 {
        self.leaf1_eax >> 4 & 0xf
    }
    /// Leaf 1's extended model field.
    pub fn exmodel(&self) -> u32 {
        self.leaf1_eax >> 16 & 0xf
    }
    /// Leaf 1's stepping.
    pub fn stepping(&self) -> u32 {
        self.leaf1_eax & 0xf
    }
    /// The family as Linux prints it (family + extended family).
    pub fn display_family(&self) -> u32 {
        self.family()
            + if self.family() == 0xf {
                self.exfamily()
            } else {
                0
            }
    }
    /// The model as Linux prints it.
    pub fn display_model(&self) -> u32 {
        self.model() | self.exmodel() << 4
    }

    /// AVX usable: the CPU has XSAVE, OSXSAVE and AVX, and the OS saves XMM and YMM state.
    pub fn os_avx(&self) -> bool {
        bit(self.leaf1_ecx, 26)
            && bit(self.leaf1_ecx, 27)
            && bit(self.leaf1_ecx, 28)
            && self.xcr0 & 6 == 6
    }
    /// AVX2, with the OS saving AVX state.
    pub fn avx2(&self) -> bool {
        self.os_avx() && bit(self.leaf7_ebx, 5)
    }
    /// OpenBLAS's `support_avx512`: AVX512VL and the OS saves opmask/ZMM state (it does not look
    /// at AVX512F itself).
    pub fn openblas_avx512(&self) -> bool {
        self.os_avx() && bit(self.leaf7_ebx, 31) && self.xcr0 & 0xe0 == 0xe0
    }
    /// OpenBLAS's `support_avx512_bf16`.
    pub fn openblas_avx512_bf16(&self) -> bool {
        self.openblas_avx512() && bit(self.leaf7_1_eax, 5)
    }
    /// numpy's X86_V3: AVX, AVX2, F16C, FMA3, BMI1, BMI2, LZCNT and MOVBE (on top of the X86_V2
    /// baseline every numpy 2.4 wheel already requires).
    pub fn npy_x86_v3(&self) -> bool {
        self.os_avx()
            && bit(self.leaf7_ebx, 5)
            && bit(self.leaf1_ecx, 29)
            && bit(self.leaf1_ecx, 12)
            && bit(self.leaf7_ebx, 3)
            && bit(self.leaf7_ebx, 8)
            && bit(self.ext1_ecx, 5)
            && bit(self.leaf1_ecx, 22)
    }
    /// numpy's X86_V4: X86_V3 plus AVX512 F, CD, BW, DQ and VL, with ZMM state saved by the OS.
    pub fn npy_x86_v4(&self) -> bool {
        self.npy_x86_v3()
            && self.xcr0 & 0xe6 == 0xe6
            && [16, 28, 30, 17, 31].iter().all(|&b| bit(self.leaf7_ebx, b))
    }
    /// FMA3 (glibc's libm picks its FMA variants of exp, sin, cos, pow, ... when FMA and AVX2
    /// are usable).
    pub fn fma(&self) -> bool {
        self.os_avx() && bit(self.leaf1_ecx, 12)
    }

    /// The brand string, trimmed (`envc info` prints it).
    pub fn brand(&self) -> String {
        String::from_utf8_lossy(&self.brand)
            .trim_matches(char::from(0))
            .trim()
            .to_string()
    }
}

#[cfg(target_arch = "x86_64")]
fn read_x86_64() -> Cpu {
    use std::arch::x86_64::__cpuid_count;
    // CPUID exists on every x86-64 CPU (the intrinsic is safe); leaves above the reported maximum
    // are not read.
    let l0 = __cpuid_count(0, 0);
    let mut vendor_bytes = [0u8; 12];
    vendor_bytes[0..4].copy_from_slice(&l0.ebx.to_le_bytes());
    vendor_bytes[4..8].copy_from_slice(&l0.edx.to_le_bytes());
    vendor_bytes[8..12].copy_from_slice(&l0.ecx.to_le_bytes());
    let vendor = match &vendor_bytes {
        b"GenuineIntel" => Vendor::Intel,
        b"AuthenticAMD" => Vendor::Amd,
        b"HygonGenuine" => Vendor::Hygon,
        b"CentaurHauls" => Vendor::Centaur,
        b"  Shanghai  " => Vendor::Zhaoxin,
        _ => Vendor::Other,
    };
    let max = l0.eax;
    let leaf = |l: u32, s: u32| {
        if l <= max {
            Some(__cpuid_count(l, s))
        } else {
            None
        }
    };
    let l1 = leaf(1, 0);
    let l7 = leaf(7, 0);
    let l71 = leaf(7, 1);
    let ld = leaf(0xd, 0);
    let ext_max = __cpuid_count(0x8000_0000, 0).eax;
    let ext = |l: u32| (l <= ext_max).then(|| __cpuid_count(l, 0));
    let mut brand = [0u8; 48];
    for (k, l) in (0x8000_0002u32..=0x8000_0004).enumerate() {
        if let Some(r) = ext(l) {
            for (j, v) in [r.eax, r.ebx, r.ecx, r.edx].iter().enumerate() {
                brand[k * 16 + j * 4..k * 16 + j * 4 + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
    }
    let leaf1_ecx = l1.map_or(0, |r| r.ecx);
    let xcr0 = if bit(leaf1_ecx, 27) {
        // SAFETY: OSXSAVE is set, so XGETBV is enabled.
        unsafe { xgetbv0() }
    } else {
        0
    };
    Cpu {
        vendor,
        leaf1_eax: l1.map_or(0, |r| r.eax),
        leaf1_ecx,
        leaf7_ebx: l7.map_or(0, |r| r.ebx),
        leaf7_edx: l7.map_or(0, |r| r.edx),
        leaf7_1_eax: l71.map_or(0, |r| r.eax),
        leafd_eax: ld.map_or(0, |r| r.eax),
        ext1_ecx: ext(0x8000_0001).map_or(0, |r| r.ecx),
        xcr0,
        brand,
    }
}

/// XCR0 (the `xsave` target feature is not needed for the instruction's encoding).
#[cfg(target_arch = "x86_64")]
unsafe fn xgetbv0() -> u64 {
    let (lo, hi): (u32, u32);
    // SAFETY: the caller checked OSXSAVE; XGETBV with ECX = 0 reads XCR0 and has no side effects.
    unsafe {
        std::arch::asm!("xgetbv", in("ecx") 0u32, out("eax") lo, out("edx") hi, options(nomem, nostack, preserves_flags));
    }
    (hi as u64) << 32 | lo as u64
}
