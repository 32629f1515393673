#!/usr/bin/env python3
"""Measure whether glibc's CPU-dispatched libm variants (FMA/AVX2 vs SSE2) change results.

glibc (x86-64) picks an FMA/AVX2 or an SSE2 build of exp, log, pow, sin, cos, tan, atan2, ... at load
time (IRELATIVE relocations / ifuncs).  A trajectory recorded on an FMA machine may therefore not replay
bit for bit on a machine without FMA.  We emulate "no FMA" on this machine with a glibc tunable and
compare subprocesses that differ ONLY in GLIBC_TUNABLES (see SETTINGS):

  1. libm itself (ctypes on libm.so.6, float64, seeded inputs over physics-relevant ranges):
     number of bit-wise mismatches per function;
  2. with --mujoco: Gymnasium MuJoCo v5 trajectories (obs, reward, qpos, qvel, qacc_warmstart).

Usage:  .venv/bin/python tests/reference/measure_libm.py [--n 500000] [--mujoco] [--steps 1000]

The tunable spelling is glibc >= 2.33's (feature names without "_Usable"; the old
"-AVX2_Usable,-FMA_Usable" spelling is silently ignored there).  `ld.so --list-diagnostics` shows
the effect: the FMA bit (leaf 1 ECX bit 12), AVX2 bit (leaf 7 EBX bit 5) and, for "-AVX", leaf 1
ECX bit 28 leave the "active" set; the impl column below shows the variant the linker bound.
"""

import argparse
import ctypes
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

# "nofma" looks like an AVX-but-no-FMA CPU (Sandy/Ivy Bridge): libm then picks its AVX (VEX, no FMA)
# builds of exp/log/atan2/sin/cos/tan and the SSE2 builds of pow/log1p/expm1/asin/acos; "sse2" also
# hides AVX (a pre-2011 CPU) so every routine takes the SSE2 build.  Hiding AVX from glibc does not stop libmujoco
# (built with -mavx) from executing AVX; it only changes glibc's own selection.
SETTINGS = {"default": None, "nofma": "glibc.cpu.hwcaps=-AVX2,-FMA", "sse2": "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX"}
LIBM = "libm.so.6"
ENVS = ["Ant-v5", "Humanoid-v5", "Hopper-v5", "Reacher-v5", "InvertedDoublePendulum-v5", "Walker2d-v5"]


# ---------------------------------------------------------------------------------------------
# Inputs.  Each case: (label, libm symbol, symbol version or None for the default, arity, generator).
# The GLIBC_2.2.5 versions of exp/log/pow are what libmujoco.so imports (old wrappers); the
# unversioned lookup gives the GLIBC_2.29 ones that new binaries (and ctypes, Rust) bind to.
# ---------------------------------------------------------------------------------------------
def logu(rng, lo, hi, n, signed=False):
    x = 10.0 ** rng.uniform(lo, hi, n)
    return x * rng.choice([-1.0, 1.0], n) if signed else x


def cases(n, seed):
    rng = np.random.default_rng(seed)
    ints = np.array([-3.0, -2.0, -1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    # Generate all inputs up front, in a fixed order, so both subprocesses see the same bits.
    return [
        ("exp [-50,50]", "exp", None, 1, (rng.uniform(-50, 50, n),)),
        ("exp [-1,1]", "exp", None, 1, (rng.uniform(-1, 1, n),)),
        ("exp@2.2.5 [-50,50]", "exp", "GLIBC_2.2.5", 1, (rng.uniform(-50, 50, n),)),
        ("log 1e-10..1e10", "log", None, 1, (logu(rng, -10, 10, n),)),
        ("log [0.5,2]", "log", None, 1, (rng.uniform(0.5, 2, n),)),
        ("log@2.2.5 1e-10..1e10", "log", "GLIBC_2.2.5", 1, (logu(rng, -10, 10, n),)),
        ("pow ±1e-3..1e3 ^ int", "pow", None, 2, (logu(rng, -3, 3, n, True), rng.choice(ints, n))),
        ("pow 1e-3..1e3 ^ [-4,4]", "pow", None, 2, (logu(rng, -3, 3, n), rng.uniform(-4, 4, n))),
        ("pow@2.2.5 1e-3..1e3 ^ [-4,4]", "pow", "GLIBC_2.2.5", 2, (logu(rng, -3, 3, n), rng.uniform(-4, 4, n))),
        ("sin [-100,100]", "sin", None, 1, (rng.uniform(-100, 100, n),)),
        ("sin [-pi,pi]", "sin", None, 1, (rng.uniform(-np.pi, np.pi, n),)),
        ("cos [-100,100]", "cos", None, 1, (rng.uniform(-100, 100, n),)),
        ("cos [-pi,pi]", "cos", None, 1, (rng.uniform(-np.pi, np.pi, n),)),
        ("tan [-100,100]", "tan", None, 1, (rng.uniform(-100, 100, n),)),
        ("atan2 N(0,1)*1e±3", "atan2", None, 2, (rng.standard_normal(n) * logu(rng, -3, 3, n),
                                                 rng.standard_normal(n) * logu(rng, -3, 3, n))),
        ("log1p [-0.999,10]", "log1p", None, 1, (rng.uniform(-0.999, 10, n),)),
        ("log1p ±1e-10..1", "log1p", None, 1, (logu(rng, -10, 0, n, True) * 0.999,)),
        ("expm1 [-10,10]", "expm1", None, 1, (rng.uniform(-10, 10, n),)),
        ("expm1 ±1e-10..1", "expm1", None, 1, (logu(rng, -10, 0, n, True),)),
        ("sqrt 1e-10..1e10", "sqrt", None, 1, (logu(rng, -10, 10, n),)),
        # Also imported by libmujoco.so:
        ("asin [-1,1]", "asin", None, 1, (rng.uniform(-1, 1, n),)),
        ("acos [-1,1]", "acos", None, 1, (rng.uniform(-1, 1, n),)),
        ("cbrt ±1e-6..1e6", "cbrt", None, 1, (logu(rng, -6, 6, n, True),)),
    ]


# ---------------------------------------------------------------------------------------------
# Which implementation did the dynamic linker pick?  Exported entry points such as sin/cos/tan
# are ifuncs themselves (their address changes); exp/log/pow/atan2/log1p are small wrappers that
# call the real routine through an internal PLT slot filled by an IRELATIVE relocation, so read
# that slot.  The static part (which slot a wrapper uses) comes from readelf/objdump.
# ---------------------------------------------------------------------------------------------
def libm_base_and_path():
    for line in open("/proc/self/maps"):
        f = line.split()
        if len(f) >= 6 and f[5].endswith("/" + LIBM) and int(f[2], 16) == 0:
            return int(f[0].split("-")[0], 16), f[5]
    raise RuntimeError("libm.so.6 not mapped")


def resolve(libm, name, version):
    if version is None:
        return ctypes.cast(getattr(libm, name), ctypes.c_void_p).value
    libc = ctypes.CDLL("libc.so.6")  # dlvsym lives in libc since glibc 2.34
    libc.dlvsym.restype = ctypes.c_void_p
    libc.dlvsym.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_char_p]
    addr = libc.dlvsym(libm._handle, name.encode(), version.encode())
    if not addr:
        raise RuntimeError(f"{name}@{version} not found")
    return addr


def static_slots(path, entries):
    """entry offset -> IRELATIVE GOT slot its wrapper calls through (None: entry is itself the
    selected code, i.e. the resolved address of an IFUNC symbol, or a plain function, or no tools)."""
    out = {off: None for off in entries}
    try:
        run = lambda *c: subprocess.run(c, capture_output=True, text=True, check=True).stdout
        slot_of = {int(m.group(2), 16): int(m.group(1), 16) for m in re.finditer(
            r"^([0-9a-f]+)\s+\S+\s+R_X86_64_IRELATIVE\s+([0-9a-f]+)", run("readelf", "-rW", path), re.M)}
        size = {int(m.group(1), 16): int(m.group(2)) for m in re.finditer(
            r"^\s*\d+: ([0-9a-f]+)\s+(\d+) FUNC ", run("readelf", "--dyn-syms", "-W", path), re.M)}
        for off in entries:
            if off in size:  # a plain exported function: follow its first call into an ifunc PLT slot
                dis = run("objdump", "-d", f"--start-address={off}", f"--stop-address={off + size[off]}", path)
                m = re.search(r"<\*ABS\*\+0x([0-9a-f]+)@plt>", dis)
                out[off] = slot_of.get(int(m.group(1), 16)) if m else None
    except (OSError, subprocess.CalledProcessError):
        pass
    return out


# ---------------------------------------------------------------------------------------------
# Child processes.
# ---------------------------------------------------------------------------------------------
def numpy_features():
    from numpy._core._multiarray_umath import __cpu_features__
    return sorted(k for k, v in __cpu_features__.items() if v)


def child_libm(out, n, seed):
    libm = ctypes.CDLL(LIBM)
    base, path = libm_base_and_path()
    res, impl = {}, {}
    entries = {}
    for i, (label, name, ver, arity, args) in enumerate(cases(n, seed)):
        addr = resolve(libm, name, ver)
        f = ctypes.CFUNCTYPE(ctypes.c_double, *[ctypes.c_double] * arity)(addr)
        lists = [a.tolist() for a in args]
        res[f"r{i}"] = np.fromiter(map(f, *lists), dtype=np.float64, count=n)
        entries[label] = addr - base
    slots = static_slots(path, set(entries.values()))
    for label, off in entries.items():
        s = slots[off]
        target = ctypes.c_uint64.from_address(base + s).value - base if s is not None else off
        impl[label] = f"{off:#x}->{target:#x}" if s is not None else f"{off:#x}"
    np.savez(out, **res, impl=np.array([impl[c[0]] for c in cases(1, 0)]),
             npfeat=np.array(numpy_features()))


def child_mujoco(out, steps, seed):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from record import install_render_shims  # renderer-only imports; physics unaffected
    install_render_shims()
    import gymnasium as gym
    os.chdir(tempfile.mkdtemp(prefix="envc-measure-"))  # keep MUJOCO_LOG.TXT out of the tree
    data = {}
    for k, env_id in enumerate(ENVS):
        env = gym.make(env_id)
        rng = np.random.default_rng(seed + k)
        lo, hi = env.action_space.low, env.action_space.high
        obs, _ = env.reset(seed=seed + k)
        rec = {f: [] for f in ("obs", "reward", "qpos", "qvel", "qacc_warmstart")}
        for _ in range(steps):
            obs, r, term, trunc, _ = env.step(rng.uniform(lo, hi))
            d = env.unwrapped.data
            for f, v in (("obs", obs), ("reward", r), ("qpos", d.qpos), ("qvel", d.qvel),
                         ("qacc_warmstart", d.qacc_warmstart)):
                rec[f].append(np.array(v, dtype=np.float64).copy())
            if term or trunc:
                env.reset()  # unseeded: continues the env's own seeded RNG, same in both runs
        env.close()
        for f, v in rec.items():
            data[f"{env_id}/{f}"] = np.array(v)
    np.savez(out, **data, npfeat=np.array(numpy_features()))


# ---------------------------------------------------------------------------------------------
# Parent: run both settings, compare bits.
# ---------------------------------------------------------------------------------------------
def run_children(mode, tmp, extra):
    out = {}
    for name, tun in SETTINGS.items():
        env = dict(os.environ)
        env.pop("GLIBC_TUNABLES", None)  # the only difference between the runs
        if tun:
            env["GLIBC_TUNABLES"] = tun
        path = os.path.join(tmp, f"{mode}-{name}.npz")
        subprocess.run([sys.executable, os.path.abspath(__file__), f"--child-{mode}", path, *extra],
                       env=env, check=True)
        out[name] = np.load(path)
    if len({tuple(r["npfeat"]) for r in out.values()}) != 1:
        print("WARNING: numpy's enabled CPU features differ between the runs")
    return out


def ulps(x, y):
    """max bit distance over mismatching pairs (inf if a sign or finiteness differs)."""
    if not len(x):
        return 0
    xi, yi = x.view(np.int64), y.view(np.int64)
    if np.any((xi < 0) != (yi < 0)) or not (np.isfinite(x).all() and np.isfinite(y).all()):
        return float("inf")
    return int(np.max(np.abs(xi - yi)))


PAIRS = [("default", "nofma"), ("default", "sse2"), ("nofma", "sse2")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=500_000, help="inputs per case (default 500000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--mujoco", action="store_true", help="also compare Gymnasium MuJoCo trajectories")
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--child-libm", metavar="OUT")
    ap.add_argument("--child-mujoco", metavar="OUT")
    a = ap.parse_args()
    if a.child_libm:
        return child_libm(a.child_libm, a.n, a.seed)
    if a.child_mujoco:
        return child_mujoco(a.child_mujoco, a.steps, a.seed)

    for k, v in SETTINGS.items():
        print(f"{k:8} GLIBC_TUNABLES={v or '(unset)'}")
    with tempfile.TemporaryDirectory(prefix="envc-measure-") as tmp:
        r = run_children("libm", tmp, ["--n", str(a.n), "--seed", str(a.seed)])
        print(f"\nlibm: bit mismatches out of {a.n} per case [max ulp]; "
              "impl = entry offset [-> internal target] in libm.so.6")
        print(f"{'case':30}" + "".join(f"{x + '/' + y:>19}" for x, y in PAIRS) + "   impl " + " | ".join(SETTINGS))
        for i, c in enumerate(cases(1, 0)):
            line = f"{c[0]:30}"
            for x, y in PAIRS:
                p, q = r[x][f"r{i}"], r[y][f"r{i}"]
                bad = p.view(np.uint64) != q.view(np.uint64)
                line += f"{f'{int(bad.sum())} [{ulps(p[bad], q[bad])}]':>19}"
            print(line + "   " + " | ".join(str(r[k]["impl"][i]) for k in SETTINGS))

        if a.mujoco:
            r = run_children("mujoco", tmp, ["--steps", str(a.steps), "--seed", str(a.seed)])
            fields = {"obs": "o", "reward": "r", "qpos": "p", "qvel": "v", "qacc_warmstart": "w"}
            print(f"\nGymnasium MuJoCo, {a.steps} steps, seeded uniform actions: first differing step "
                  "(0-based)/number of differing steps [fields differing there: o=obs r=reward p=qpos v=qvel w=qacc_warmstart], "
                  "max|d obs| over the run; or 'identical'")
            print(f"{'env':27}" + "".join(f"{x + '/' + y:>26}" for x, y in PAIRS))
            for env_id in ENVS:
                line = f"{env_id:27}"
                for x, y in PAIRS:
                    firsts, anyrow = {}, 0
                    for fl in fields:
                        A, B = r[x][f"{env_id}/{fl}"], r[y][f"{env_id}/{fl}"]
                        bad = (A.view(np.uint64) != B.view(np.uint64)).reshape(len(A), -1).any(1)
                        anyrow, rows = anyrow | bad, np.flatnonzero(bad)
                        if len(rows):
                            firsts[fl] = int(rows[0])
                    if not firsts:
                        line += f"{'identical':>26}"
                        continue
                    s0 = min(firsts.values())
                    mx = float(np.max(np.abs(r[x][f"{env_id}/obs"] - r[y][f"{env_id}/obs"])))
                    which = "".join(fields[fl] for fl, v in firsts.items() if v == s0)
                    line += f"{f'{s0}/{int(np.sum(anyrow))} [{which}] {mx:.2g}':>26}"
                print(line)


if __name__ == "__main__":
    main()
