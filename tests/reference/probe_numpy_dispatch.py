#!/usr/bin/env python3
"""Which float kernels numpy 2.4.6 runs on this x86-64 machine, under each CPU-feature mask.

numpy picks a ufunc inner loop per CPU "target" (baseline X86_V2, dispatched X86_V3 / X86_V4 /
AVX512_ICL / AVX512_SPR) once, at import, from CPUID and the env variables NPY_DISABLE_CPU_FEATURES /
NPY_ENABLE_CPU_FEATURES.  envc must pick the same arithmetic, so this probe measures, in subprocesses:

  1. targets: the loop numpy bound for each ufunc we use (numpy.lib.introspect.opt_func_info) and
     how the two env variables are parsed (errors, warnings, implications);
  2. values: every float op the Gymnasium MuJoCo / maze / MaMuJoCo envs use, on ~1e6 seeded inputs,
     compared across masks (diff counts against the default mask) and against plain references
     (glibc via ctypes/math, x*x, a Python port of numpy's pairwise sum, a port of
     runtime/src/maze/npexp.rs with exact FMA emulated by fractions.Fraction);
  3. BLAS: np.linalg.norm(v) without axis is sqrt(ddot(v, v)) for len(v) >= 2, and OpenBLAS picks
     its ddot kernel from CPUID (override OPENBLAS_CORETYPE), independently of numpy's masks.

Usage:  .venv/bin/python tests/reference/probe_numpy_dispatch.py     (about 1 minute, < 4 GB)
"""

import json
import math
import os
import resource
import subprocess
import sys
import tempfile
from fractions import Fraction

import numpy as np

SEED = 20260821
N = 1_000_000
# Child runs: (label, env changes); None removes a variable.  OPENBLAS_CORETYPE is inherited.
MASKS = [
    ("default", {}),
    ("D=X86_V4 AVX512_ICL", {"NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL"}),
    ("D=X86_V3 X86_V4 AVX512_ICL", {"NPY_DISABLE_CPU_FEATURES": "X86_V3 X86_V4 AVX512_ICL"}),
    ("D=X86_V3 (only)", {"NPY_DISABLE_CPU_FEATURES": "X86_V3"}),
    ("glibc -AVX2,-FMA", {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"}),
    ("glibc -AVX2,-FMA + D=X86_V4", {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA",
                                     "NPY_DISABLE_CPU_FEATURES": "X86_V4"}),
]
# Env-parsing cases (question 3): only import + introspection.
PARSE_CASES = [
    ("(none)", {}),
    ("D='X86_V4'", {"NPY_DISABLE_CPU_FEATURES": "X86_V4"}),
    ("D='X86_V3'", {"NPY_DISABLE_CPU_FEATURES": "X86_V3"}),
    ("D='X86_V3,X86_V4\\tAVX512_ICL'", {"NPY_DISABLE_CPU_FEATURES": "X86_V3,X86_V4\tAVX512_ICL"}),
    ("D='x86_v4' (case)", {"NPY_DISABLE_CPU_FEATURES": "x86_v4"}),
    ("D='AVX512_SKX' (old)", {"NPY_DISABLE_CPU_FEATURES": "AVX512_SKX"}),
    ("D='AVX512F' (old)", {"NPY_DISABLE_CPU_FEATURES": "AVX512F"}),
    ("D='AVX2 FMA3' (old)", {"NPY_DISABLE_CPU_FEATURES": "AVX2 FMA3"}),
    ("D='BOGUS' (no -W)", {"NPY_DISABLE_CPU_FEATURES": "BOGUS", "_NO_W": "1"}),
    ("D='X86_V2' (baseline)", {"NPY_DISABLE_CPU_FEATURES": "X86_V2"}),
    ("D='AVX512_SPR' (cpu lacks)", {"NPY_DISABLE_CPU_FEATURES": "AVX512_SPR"}),
    ("D=' ' (blank)", {"NPY_DISABLE_CPU_FEATURES": " "}),
    ("E='AVX512_SPR' (cpu lacks)", {"NPY_ENABLE_CPU_FEATURES": "AVX512_SPR"}),
    ("E='X86_V3'", {"NPY_ENABLE_CPU_FEATURES": "X86_V3"}),
    ("E='X86_V4'", {"NPY_ENABLE_CPU_FEATURES": "X86_V4"}),
    ("E='X86_V3 X86_V4'", {"NPY_ENABLE_CPU_FEATURES": "X86_V3 X86_V4"}),
    ("E='X86_V2' (baseline)", {"NPY_ENABLE_CPU_FEATURES": "X86_V2"}),
    ("D and E both set", {"NPY_DISABLE_CPU_FEATURES": "X86_V4", "NPY_ENABLE_CPU_FEATURES": "X86_V3"}),
]
BLAS_CORES = ["(inherited)", "(unset)", "Haswell", "SkylakeX", "Sandybridge", "Prescott"]
NORM_LENS = [2, 3, 4, 7, 8, 15, 16, 17, 33, 100]
ROW_LENS = [1, 2, 3, 7, 8, 9, 15, 16, 17, 100, 127, 128, 129, 255, 256, 1000, 4099]


# ---------------------------------------------------------------------------------------------
# References (pure Python; the point is to pin the *order* of operations, not speed).

def fma(a, b, c):
    """Exact a*b+c rounded once (Python 3.11 has no math.fma; int/int true division rounds right)."""
    return float(Fraction(a) * Fraction(b) + Fraction(c))


def pairwise(a, lo, n, zero):
    """numpy/_core/src/umath/loops_utils.h.src @TYPE@_pairwise_sum (v2.4.6 lines 81-145)."""
    if n < 8:
        res = -zero
        for i in range(lo, lo + n):
            res += a[i]
        return res
    if n <= 128:
        r = list(a[lo:lo + 8])
        i = 8
        while i < n - (n % 8):
            for k in range(8):
                r[k] += a[lo + i + k]
            i += 8
        res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
        while i < n:
            res += a[lo + i]
            i += 1
        return res
    n2 = n // 2
    n2 -= n2 % 8
    return pairwise(a, lo, n2, zero) + pairwise(a, lo + n2, n - n2, zero)


def np_sum_model(row, zero=0.0):
    """add.reduce = identity (+0) + pairwise over the whole reduced axis (reduction.c, 2.4.6)."""
    return zero + pairwise(row, 0, len(row), zero)


def _b(h):
    return float(np.frombuffer(bytes.fromhex(h)[::-1], dtype=np.float64)[0])


# runtime/src/maze/npexp.rs, ported 1:1 (SVML __svml_exp8_ha model).
TH = [_b(h) for h in (
    "3ff0000000000000 3ff0b5586cf9890f 3ff172b83c7d517b 3ff2387a6e756238 3ff306fe0a31b715 "
    "3ff3dea64c123422 3ff4bfdad5362a27 3ff5ab07dd485429 3ff6a09e667f3bcd 3ff7a11473eb0187 "
    "3ff8ace5422aa0db 3ff9c49182a3f090 3ffae89f995ad3ad 3ffc199bdd85529c 3ffd5818dcfba487 "
    "3ffea4afa2a490da").split()]
TLR = [_b(h) for h in (
    "0000000000000000 3c979aa65d837b6d bc801b15eaa59348 3c968efde3a8a894 3c834d754db0abb6 "
    "3c859f48a72a4c6d 3c7690cebb7aafb0 3c9063e1e21c5409 bc93b3efbf5e2228 bc7b32dcb94da51d "
    "3c8db72fc1f0eab4 3c71affc2b91ce27 3c8c1a7792cb3387 3c736eae30af0cb3 3c74a385a63d07a7 "
    "bc8ff7128fd391f0").split()]
(LOG2E, LN2_HI, LN2_LO, C1, C2, C3, C4, C5, C6, SLOW) = (_b(h) for h in (
    "3ff71547652b82fe 3fe62e42fefa39ef 3c7abc9e3b39803f 3fefffffffffff70 3fe000000000d008 "
    "3fc5555553939732 3fa55557242d68fe 3f81101cbbc265c0 3f57411836940c04 40861da04cbafe44").split())


def npexp_model(x):
    if math.isnan(x) or abs(x) >= SLOW:
        return math.exp(x)
    p = x * LOG2E
    e = fma(x, LOG2E, -p)
    n = math.floor(p * 16.0) / 16.0
    if n == p and e < 0.0:
        n -= 1.0 / 16.0
    j = int(n * 16.0) % 16
    r = fma(-n, LN2_HI, x)
    r = fma(-n, LN2_LO, r)
    r2 = r * r
    p56, p34, p12 = fma(C6, r, C5), fma(C4, r, C3), fma(C2, r, C1)
    p16 = fma(r2, fma(r2, p56, p34), p12)
    q = fma(p16, r, TLR[j])
    return fma(TH[j], q, TH[j]) * 2.0 ** math.floor(n)


# ---------------------------------------------------------------------------------------------
# Child modes.

def targets():
    import numpy._core._multiarray_umath as mu
    from numpy.lib.introspect import opt_func_info
    want = {"exp": "dd", "sin": "dd", "cos": "dd", "sqrt": "dd", "square": "dd", "absolute": "dd",
            "add": "ddd", "multiply": "ddd", "subtract": "ddd", "power": "ddd", "minimum": "ddd",
            "maximum": "ddd", "isfinite": "d?"}
    info = opt_func_info(func_name="^(" + "|".join(want) + ")$")
    cur = {f: info.get(f, {}).get(s, {}).get("current", "-") for f, s in want.items()}
    feats = {k: bool(mu.__cpu_features__[k]) for k in
             ("X86_V3", "X86_V4", "AVX512_SKX", "AVX512F", "AVX512_ICL", "AVX512_SPR")}
    return cur, feats


def openblas_core():
    import ctypes
    import glob
    libs = glob.glob(os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs",
                                  "libscipy_openblas*.so"))
    try:
        f = ctypes.CDLL(libs[0]).scipy_openblas_get_corename64_
        f.restype = ctypes.c_char_p
        return f().decode()
    except (IndexError, OSError, AttributeError):
        return "?"


def child_info():
    cur, feats = targets()
    print(json.dumps({"cur": cur, "feats": feats}))


def child_values(out_path):
    import ctypes
    libm = ctypes.CDLL("libm.so.6")
    c_exp = libm.exp
    c_exp.restype, c_exp.argtypes = ctypes.c_double, [ctypes.c_double]
    rng = np.random.default_rng(SEED)
    x = rng.uniform(-20.0, 1.0, N)          # exp inputs (maze: exp(-distance))
    y = rng.uniform(-10.0, 10.0, N)         # angles / velocities / actions
    w = rng.uniform(-3.0, 3.0, N)
    res, st = {}, {}
    cur, _ = targets()
    st["targets"] = cur
    st["openblas"] = openblas_core()

    # --- exp: all call shapes must hit the same loop.
    e = np.exp(x)
    res["exp"] = e
    xl = x.tolist()
    glibc = np.array([math.exp(v) for v in xl])
    st["math.exp==ctypes exp (1e5)"] = int(sum(math.exp(v) == c_exp(v) for v in xl[:100_000]))
    st["exp!=glibc"] = int((e != glibc).sum())
    m = 20_000
    st["scalar np.float64 !=array"] = int(sum(np.exp(np.float64(v)) != e[i] for i, v in enumerate(xl[:m])))
    st["python float !=array"] = int(sum(np.exp(v) != e[i] for i, v in enumerate(xl[:m])))
    st["0-d array !=array"] = int(sum(np.exp(np.array(v)) != e[i] for i, v in enumerate(xl[:m])))
    st["len-1 !=array"] = int(sum(np.exp(x[i:i + 1])[0] != e[i] for i in range(m)))
    st["len-2 !=array"] = int(sum((np.exp(x[i:i + 2]) != e[i:i + 2]).sum() for i in range(0, m, 2)))
    st["len-7 !=array"] = int(sum((np.exp(x[i:i + 7]) != e[i:i + 7]).sum() for i in range(0, m, 7)))
    st["stride-3 !=array"] = int((np.exp(x[::3]) != e[::3]).sum())
    st["reversed !=array"] = int((np.exp(x[::-1]) != e[::-1]).sum())
    a = x.copy()
    np.exp(a, out=a)
    st["in-place !=array"] = int((a != e).sum())
    a = x.copy()
    np.exp(a[:-1], out=a[1:])              # partial overlap: numpy copies the input first
    st["overlap out !=array"] = int((a[1:] != e[:-1]).sum())
    buf = np.zeros(8 * 100_000 + 1, np.uint8)
    ua = buf[1:].view(np.float64)
    ua[:] = x[:100_000]
    st["unaligned !=array"] = int((np.exp(ua) != e[:100_000]).sum())
    st["-(np.float64) !=array"] = int(sum(np.exp(-np.float64(-v)) != e[i] for i, v in enumerate(xl[:m])))

    # --- other unary / binary ufuncs.
    res["sin"], res["cos"] = np.sin(y), np.cos(y)
    yl = y.tolist()
    st["sin!=glibc"] = int((res["sin"] != np.array([math.sin(v) for v in yl])).sum())
    st["cos!=glibc"] = int((res["cos"] != np.array([math.cos(v) for v in yl])).sum())
    res["sqrt"] = np.sqrt(np.abs(y))
    res["square"] = np.square(y)
    st["square!=y*y"] = int((res["square"] != y * y).sum())
    res["abs"] = np.abs(y)
    res["clip"] = np.clip(y, -1.0, 1.0)
    z = y.copy()
    z[::97], z[::89], z[::83] = np.nan, np.inf, -np.inf
    res["isfinite"] = np.isfinite(z)
    res["add"], res["sub"], res["mul"] = y + w, y - w, y * w
    res["arr**2"] = y ** 2
    res["power(arr,2.0)"] = np.power(y, 2.0)             # stride-0 exponent: in1*in1 fast path
    res["power(arr,arr2)"] = np.power(y, np.full(N, 2.0))  # full exponent array: SVML pow on X86_V4
    for k in ("arr**2", "power(arr,2.0)", "power(arr,arr2)"):
        st[k + "!=y*y"] = int((res[k] != y * y).sum())
    # float64 scalar ** 2: scalarmath -> npy_pow -> glibc pow (never the ufunc loop).
    s2 = np.array([np.float64(v) ** 2 for v in yl[:200_000]])
    res["np.float64**2"] = s2
    st["np.float64**2!=y*y"] = int((s2 != y[:200_000] ** 2).sum())
    st["np.float64**2!=glibc pow"] = int((s2 != np.array([math.pow(v, 2.0) for v in yl[:200_000]])).sum())
    st["python float**2!=glibc pow"] = int(sum(v ** 2 != math.pow(v, 2.0) for v in yl[:200_000]))

    # --- reductions: add.reduce over rows of each length, whole-array sum; model = pairwise port.
    bad = 0
    for k in ROW_LENS:
        rows = max(1, min(2000, 200_000 // k))
        Y = y[:rows * k].reshape(rows, k)
        s = np.sum(Y, axis=1)
        res[f"sum_rows{k}"] = s
        res[f"sum_cols{k}"] = np.sum(Y, axis=0)
        bad += sum(np_sum_model(Y[i].tolist()) != s[i] for i in range(min(rows, 200)))
    res["sum_all"] = np.array([np.sum(y)])
    bad += np_sum_model(yl) != np.sum(y)
    st["sum!=pairwise model"] = int(bad)
    y32 = y.astype(np.float32)
    res["f32 square"] = np.square(y32)
    bad = 0
    for k in (3, 8, 17, 128, 300):
        Y = y32[:500 * k].reshape(500, k)
        s = np.sum(np.square(Y), axis=1)
        res[f"f32 sum_sq{k}"] = s
        sq = np.square(Y)
        bad += sum(np_sum_model(list(sq[i]), np.float32(0.0)) != s[i] for i in range(100))
    res["f32 sum_all"] = np.array([np.sum(y32)])
    st["f32 sum!=pairwise model"] = int(bad)

    # --- norms: axis=-1 (sqrt(add.reduce(x*x))) and 1-D without axis (BLAS ddot for n >= 2).
    bad = 0
    for k in (1, 2, 3, 8, 17):
        Y = y[:(N // k) * k].reshape(N // k, k)
        nm = np.linalg.norm(Y, axis=-1)
        res[f"norm_axis{k}"] = nm
        bad += sum(math.sqrt(np_sum_model((Y[i] * Y[i]).tolist())) != nm[i] for i in range(500))
    st["norm(axis=-1)!=sqrt(pairwise)"] = int(bad)
    for k in NORM_LENS:
        Y = y[:2000 * k].reshape(2000, k)
        res[f"norm1d_{k}"] = np.array([np.linalg.norm(r) for r in Y])

    # --- einsum as humanoid's mass_center uses it ("b,bj->j"), and a row-dot.
    M = rng.uniform(0.1, 10.0, (5000, 14))
    P = rng.uniform(-5.0, 5.0, (5000, 14, 3))
    ein = np.array([np.einsum("b,bj->j", M[t], P[t]) for t in range(5000)])
    res["einsum b,bj->j"] = ein
    seq = np.zeros((5000, 3))
    for b in range(14):
        seq = seq + M[:, b:b + 1] * P[:, b, :]
    st["einsum b,bj->j != sequential"] = int((ein != seq).sum())
    A = y[:300_000].reshape(100_000, 3)
    res["einsum ij,ij->i"] = np.einsum("ij,ij->i", A, A)
    np.savez(out_path, **res)
    print(json.dumps(st))


def child_blas(out_path):
    rng = np.random.default_rng(SEED + 1)
    st, res = {"core": openblas_core()}, {}
    for k in NORM_LENS:
        Y = rng.uniform(-5.0, 5.0, (20_000, k))
        nm = np.array([np.linalg.norm(r) for r in Y])
        res[f"n{k}"] = nm
        seq = np.zeros(len(Y))
        for j in range(k):
            seq = seq + Y[:, j] * Y[:, j]
        row = {"!=seq": int((nm != np.sqrt(seq)).sum())}
        if k < 16:
            chain = []
            for r in Y[:2000].tolist():    # x0*x0, then fma(xi, xi, acc): ddot's scalar tail with FMA
                acc = r[0] * r[0]
                for v in r[1:]:
                    acc = fma(v, v, acc)
                chain.append(math.sqrt(acc))
            row["!=fma chain (2000)"] = int((nm[:2000] != np.array(chain)).sum())
        st[k] = row
    v = rng.uniform(-1.0, 1.0, (20, 200_000))       # > 10000 elements: OpenBLAS may thread ddot
    res["n200000"] = np.array([np.linalg.norm(r) for r in v])
    np.savez(out_path, **res)
    print(json.dumps(st))


# ---------------------------------------------------------------------------------------------
# Parent.

def run(args, env_changes, timeout=300):
    env = dict(os.environ)
    for k in ("NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES", "GLIBC_TUNABLES"):
        env.pop(k, None)
    warn = [] if env_changes.get("_NO_W") else ["-W", "always::ImportWarning"]
    for k, v in env_changes.items():
        if k == "_NO_W":
            continue
        if v is None:
            env.pop(k, None)
        else:
            env[k] = v

    def cap():
        resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    p = subprocess.run([sys.executable, *warn, __file__, *args], env=env, capture_output=True,
                       text=True, timeout=timeout, preexec_fn=cap)
    return p.returncode, p.stdout.strip(), p.stderr.strip()


def short_err(err):
    lines = [ln.strip() for ln in err.splitlines() if ln.strip()]
    hit = [ln for ln in lines if "Error" in ln or "Warning" in ln]
    msg = (hit[-1] if hit else (lines[-1] if lines else ""))
    for ln in lines:        # the reason follows a "During parsing ..." header or "Original error"
        if ln.startswith("You cannot"):
            kinds = [k for k in ("ImportWarning", "RuntimeError") if k in msg]
            msg = (kinds[0] if kinds else msg.split(":")[0]) + ": " + ln
            break
        if ln.startswith("Original error was:"):
            msg = "ImportError: " + ln[len("Original error was:"):].strip()
            break
    return msg[:150]


def main():
    print(f"numpy {np.__version__}; python {sys.version.split()[0]}; "
          f"OPENBLAS_CORETYPE={os.environ.get('OPENBLAS_CORETYPE')!r} (inherited by the mask runs)")

    print("\n== 3. env parsing: exit code, loop bound for exp/add/power (float64), __cpu_features__ "
          "flags after the env is applied (SKX is the same enum id as X86_V4), stderr message "
          "(children run with -W always::ImportWarning unless marked 'no -W')")
    print(f"{'case':32} rc {'exp':8} {'add':8} {'power':8} {'V3 V4 SKX ICL':14} message")
    for label, env in PARSE_CASES:
        rc, out, err = run(["--info"], env)
        if rc == 0:
            d = json.loads(out.splitlines()[-1])
            c, f = d["cur"], d["feats"]
            cols = [c["exp"], c["add"], c["power"]]
            fl = " ".join("1" if f[k] else "0" for k in ("X86_V3", "X86_V4", "AVX512_SKX", "AVX512_ICL"))
        else:
            cols, fl = ["-", "-", "-"], "-"
        cols = [s.replace("baseline(X86_V2)", "baseline") for s in cols]
        print(f"{label:32} {rc:2} {cols[0]:8} {cols[1]:8} {cols[2]:8} {fl:14} {short_err(err)}")

    tmp = tempfile.mkdtemp(prefix="npdispatch.")
    print("\n== 1+2. values per mask (diff counts vs the default mask; stats vs in-process references)")
    base, stats = None, {}
    for label, env in MASKS:
        path = os.path.join(tmp, "m.npz")
        rc, out, err = run(["--values", path], env)
        if rc != 0:
            print(f"{label}: FAILED rc={rc}\n{err[-2000:]}")
            continue
        st = json.loads(out.splitlines()[-1])
        stats[label] = st
        d = dict(np.load(path))
        os.remove(path)
        if base is None:
            base = d
        tg = {k: v.replace("baseline(X86_V2)", "base") for k, v in st.pop("targets").items()}
        print(f"\n-- {label}  [openblas {st.pop('openblas')}]  exp:{tg['exp']} sin:{tg['sin']} "
              f"add:{tg['add']} power:{tg['power']} min/max:{tg['minimum']} sqrt/square/abs:{tg['sqrt']}")
        diffs = {k: int((np.asarray(d[k]) != np.asarray(base[k])).sum()) for k in base}
        nz = {k: v for k, v in diffs.items() if v}
        print(f"   arrays differing from default: {nz if nz else 'none'} "
              f"(of {len(diffs)} arrays, {sum(v.size for v in base.values())} values)")
        print("   " + "; ".join(f"{k}={v}" for k, v in st.items()))
        if label == "default":
            model = [npexp_model(v) for v in np.random.default_rng(SEED).uniform(-20.0, 1.0, 20_000).tolist()]
            base_model = np.array(model)
        st_model = int((d["exp"][:20_000] != base_model).sum())
        print(f"   exp != npexp.rs port (first 20000 inputs) = {st_model}")

    print("\n== 4. np.linalg.norm(1-D) = sqrt(ddot) for n >= 2: OpenBLAS kernel per OPENBLAS_CORETYPE")
    ref = None
    for core in BLAS_CORES:
        env = {} if core == "(inherited)" else {"OPENBLAS_CORETYPE": None if core == "(unset)" else core}
        path = os.path.join(tmp, "b.npz")
        rc, out, err = run(["--blas", path], env)
        if rc != 0:
            print(f"{core}: FAILED rc={rc}\n{err[-2000:]}")
            continue
        st = json.loads(out.splitlines()[-1])
        d = dict(np.load(path))
        os.remove(path)
        if ref is None:
            ref = d
        vs = {k: int((d[k] != ref[k]).sum()) for k in ref}
        print(f"-- OPENBLAS_CORETYPE {core} -> kernel {st.pop('core')}; diffs vs (inherited): "
              + " ".join(f"{k}:{v}" for k, v in vs.items()))
        print("   n: " + "; ".join(f"{k} {' '.join(f'{a}={b}' for a, b in v.items())}" for k, v in st.items()))
    rc, out, err = run(["--blas", os.path.join(tmp, "t.npz")], {"OPENBLAS_NUM_THREADS": "1"})
    d = dict(np.load(os.path.join(tmp, "t.npz")))
    os.remove(os.path.join(tmp, "t.npz"))
    print(f"-- OPENBLAS_NUM_THREADS=1 vs inherited ({os.cpu_count()} cpus): n200000 diffs "
          f"{int((d['n200000'] != ref['n200000']).sum())} of 20; n<=100 diffs "
          f"{sum(int((d[k] != ref[k]).sum()) for k in ref if k != 'n200000')}")
    os.rmdir(tmp)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--info":
        child_info()
    elif len(sys.argv) > 2 and sys.argv[1] == "--values":
        child_values(sys.argv[2])
    elif len(sys.argv) > 2 and sys.argv[1] == "--blas":
        child_blas(sys.argv[2])
    else:
        main()
