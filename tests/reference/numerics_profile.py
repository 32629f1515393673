#!/usr/bin/env python3
"""The numerics profile the running Python reference computes under, in envc's naming.

    .venv/bin/python tests/reference/numerics_profile.py          # prints e.g. openblas-skylakex+svml
    .venv/bin/python tests/reference/numerics_profile.py --json   # the name, the settings and the raw facts
    .venv/bin/python tests/reference/numerics_profile.py --can-run OPENBLAS_CORETYPE=SkylakeX  # exit 0 if this CPU can

The reference's float64 results depend on the CPU (and a few environment variables) in two places:

* `np.linalg.norm(v)` (1-D, no axis) is `sqrt(ddot(v, v))`, and numpy's bundled OpenBLAS
  (`scipy_openblas64_`, DYNAMIC_ARCH) picks its ddot kernel at load time from CPUID, or from
  OPENBLAS_CORETYPE. `np.dot(a, b)` of two 1-D float64 arrays is the same ddot.
  -> the kernel OpenBLAS reports through `scipy_openblas_get_corename64_()`. The numpy 2.4.6 wheel
  holds 5 x86-64 kernels; "Katmai" is what the library calls its Prescott (SSE2) kernel.
* numpy's float64 `np.exp` is Intel SVML when numpy dispatched its X86_V4 loop (an AVX-512 CPU,
  X86_V4 not disabled by NPY_DISABLE_CPU_FEATURES / NPY_ENABLE_CPU_FEATURES), else glibc's exp.
  -> `numpy.lib.introspect.opt_func_info`: the target numpy bound for exp's `dd` loop.

The profile is `openblas-<kernel>` plus `+svml` when exp is SVML, kernel one of prescott, nehalem,
sandybridge, haswell, skylakex. Both facts are read from the running process (numpy and OpenBLAS
read their variables once, when numpy is imported), so changing os.environ afterwards changes
`settings()` but not the profile.
"""

import ctypes
import glob
import json
import os
import sys

# The variables that change the profile (or, GLIBC_TUNABLES, glibc's exp variant; see README).
SETTING_VARS = ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES", "GLIBC_TUNABLES")

# OpenBLAS core names that denote its generic SSE2 x86-64 kernel set (the DYNAMIC_ARCH table maps
# the cores it was not built for onto the ones it was; this build reports that kernel as "Katmai").
_PRESCOTT = {"katmai", "coppermine", "northwood", "prescott", "banias"}
KERNELS = ("prescott", "nehalem", "sandybridge", "haswell", "skylakex")

# numpy dispatch targets of the float64 exp loop: X86_V4 is the AVX-512 SVML loop. (The other two
# names are what numpy < 2.4 called the same targets.)
_SVML_TARGETS = {"X86_V4", "AVX512_SKX", "AVX512F"}
_LIBM_TARGETS = {"X86_V3", "AVX2", "FMA3__AVX2", "AVX512F_AVX2"}

_openblas = None


def openblas_library():
    """ctypes handle of the OpenBLAS numpy loaded (the same mapping: dlopen returns the loaded one)."""
    global _openblas
    if _openblas is None:
        import numpy as np  # noqa: F401  (loads and initialises OpenBLAS under this process's env)

        libs = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(np.__file__))), "numpy.libs")
        found = sorted(glob.glob(os.path.join(libs, "libscipy_openblas64_*.so*")))
        if not found:
            raise RuntimeError(f"no libscipy_openblas64_*.so in {libs}: not the pinned numpy wheel?")
        _openblas = ctypes.CDLL(found[0])
    return _openblas


def openblas_corename():
    """The core OpenBLAS selected, as the library names it ("Katmai", "Haswell", "SkylakeX", ...)."""
    f = openblas_library().scipy_openblas_get_corename64_
    f.restype = ctypes.c_char_p
    return f().decode()


def openblas_config():
    f = openblas_library().scipy_openblas_get_config64_
    f.restype = ctypes.c_char_p
    return f().decode().strip()


def kernel():
    name = openblas_corename().strip().lower()
    return "prescott" if name in _PRESCOTT else name


def exp_target():
    """The target numpy bound for float64 exp (e.g. 'X86_V4', 'X86_V3', 'baseline(X86_V2)')."""
    from numpy.lib.introspect import opt_func_info

    info = opt_func_info(func_name="^exp$", signature="^float64$")
    return info["exp"]["dd"]["current"]


def svml_exp():
    t = exp_target()
    if t in _SVML_TARGETS:
        return True
    if t in _LIBM_TARGETS or t.startswith("baseline"):
        return False
    raise RuntimeError(f"numpy's float64 exp runs an unknown target {t!r}: cannot name the profile")


def profile_name():
    """e.g. 'openblas-skylakex+svml', 'openblas-haswell'."""
    return f"openblas-{kernel()}" + ("+svml" if svml_exp() else "")


def settings():
    """The environment variables that select the profile, each its value or None (unset)."""
    return {k: os.environ.get(k) for k in SETTING_VARS}


def details():
    import numpy as np

    return {"numerics": profile_name(), "settings": settings(), "openblas_corename": openblas_corename(),
            "exp_target": exp_target(), "numpy": np.__version__, "openblas": openblas_config()}


# What a forced setting needs from the CPU to run at all (a kernel the CPU lacks dies of SIGILL).
NEEDS = {"Sandybridge": ("avx",), "Haswell": ("avx2", "fma"), "Zen": ("avx2", "fma"),
         "SkylakeX": ("avx512f", "avx512vl"), "Cooperlake": ("avx512f", "avx512vl")}


def can_run(assignments):
    """Whether this CPU can run the reference under `KEY=VALUE` settings (x86-64 Linux only)."""
    try:
        with open("/proc/cpuinfo") as f:
            flags = set(next((l for l in f if l.startswith("flags")), ":").split(":", 1)[1].split())
    except OSError:
        return False
    for a in assignments:
        k, _, v = a.partition("=")
        if k == "OPENBLAS_CORETYPE" and not all(x in flags for x in NEEDS.get(v, ())):
            return False
    return True


def main():
    if sys.argv[1:2] == ["--can-run"]:
        sys.exit(0 if can_run(sys.argv[2:]) else 1)
    if sys.argv[1:] == ["--json"]:
        print(json.dumps(details(), indent=1))
    elif sys.argv[1:]:
        sys.exit(__doc__)
    else:
        print(profile_name())


if __name__ == "__main__":
    main()
