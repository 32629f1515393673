#!/usr/bin/env python3
"""Record what the reference's CPU-dependent float64 primitives return: `np.linalg.norm(v)` and
`np.dot(a, b)` (OpenBLAS ddot, kernel chosen by CPU / OPENBLAS_CORETYPE) and `np.exp(x)` (SVML or
glibc, chosen by numpy's CPU dispatch / NPY_*_CPU_FEATURES), with the numerics profile they ran under
(numerics_profile.py).

    .venv/bin/python tests/reference/record_numerics.py --out DIR [--name NAME] [--quick] [--seed N]
        # this process's environment: DIR/inputs.json and DIR/NAME.json
    .venv/bin/python tests/reference/record_numerics.py --matrix DIR [--quick] [--seed N]
        # every setting this CPU can run (OPENBLAS_CORETYPE x numpy mask), one child process each:
        # DIR/inputs.json, DIR/<setting>.json, DIR/matrix.json
    .venv/bin/python tests/reference/record_numerics.py --matrix tests/reference/fixtures/numerics
        # the committed set

Files (all hex is the little-endian bytes of float64 values, concatenated: 16 hex digits a value,
like `np.asarray(v, "<f8").tobytes().hex()`):

* inputs.json, shared by all settings: {"seed", "quick", "norm": [{"n", "v": hex}] (for each n of N_SET
  in order, `count` vectors), "dot": [{"n", "a": i, "b": j}] (i, j index "norm"), "exp": hex}.
* <setting>.json: {"numerics", "settings", "openblas_corename", "exp_target", "numpy", "openblas", "cpu",
  "inputs": "inputs.json", "inputs_sha256", "exp_array_matches_scalar", "norm": hex, "dot": hex,
  "exp": hex}; value i of "norm" / "dot" / "exp" belongs to entry i of the same key of inputs.json:
  np.linalg.norm(fresh copy of v), np.dot(fresh copy of a, fresh copy of b),
  np.exp(np.float64(x)) element by element.
* matrix.json (--matrix): the settings run, their files and profiles, the CPU.

--matrix children get exactly the setting's OPENBLAS_CORETYPE / NPY_DISABLE_CPU_FEATURES (the parent's
values of those and of NPY_ENABLE_CPU_FEATURES are dropped); everything else, GLIBC_TUNABLES included,
is inherited and recorded in "settings".
"""

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import numerics_profile  # noqa: E402

SEED = 20260822
N_SET = list(range(1, 49)) + [63, 64, 65, 100, 127, 128, 129, 1000, 4097]


def counts(n, quick):
    """Vectors recorded for length n (dot pairs: min(10, count // 2))."""
    if n <= 48:
        return 4 if quick else 40
    if n <= 129:
        return 2 if quick else 16
    if n <= 1000:
        return 2 if quick else 4
    return 2


EXP_RANDOM = {False: 20000, True: 2000}
# exp's edges: zeros, tiny, +-ln2, the overflow / subnormal / underflow thresholds, inf, nan.
EXP_SPECIAL = [
    "0x0.0p+0", "-0x0.0p+0", "0x1.0p+0", "-0x1.0p+0", "0x1.0p-1", "-0x1.0p-1", "0x1.0p+1", "-0x1.0p+1",
    "-0x1.4p+4", "0x1.8p+1", "-0x1.8p+1", "0x1.4p+3", "-0x1.4p+3", "-0x1.3ffffffffffffp+4",
    "0x1.fffffffffffffp-1", "0x1.0p-28", "-0x1.0p-28", "0x1.0p-54", "-0x1.0p-54", "0x1.0p-1022",
    "0x0.0000000000001p-1022", "-0x0.0000000000001p-1022", "0x1.62e42fefa39efp-1", "-0x1.62e42fefa39efp-1",
    "0x1.62e42fefa39efp+9", "0x1.62e42fefa39f0p+9", "0x1.63p+9", "-0x1.6232bdd7abcd2p+9",
    "-0x1.6232bdd7abcd3p+9", "-0x1.62p+9", "-0x1.74385446d71c3p+9", "-0x1.74385446d71c4p+9",
    "-0x1.74910d52d3051p+9", "-0x1.74910d52d3052p+9", "-0x1.75p+9", "-0x1.f4p+9", "inf", "-inf", "nan",
]


def hexa(x):
    import numpy as np

    return np.ascontiguousarray(np.asarray(x, dtype=np.float64)).astype("<f8").tobytes().hex()


def unhex(h):
    import numpy as np

    return np.frombuffer(bytes.fromhex(h), dtype="<f8")


def vector(rng, n, k):
    """Length-n vector number k: ten patterns of scales (uniform, exponents spread over +-8, +-40,
    +-300, mostly small with a few large, positive, squares in the subnormal range, squares near
    overflow, integers, one scale per vector). Only exact operations: the same bits on any CPU."""
    import numpy as np

    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    m = rng.uniform(1.0, 2.0, n)
    p = k % 10
    if p == 0:
        return rng.uniform(-1.0, 1.0, n)
    if p in (1, 2, 3, 6, 7):
        lo, hi = {1: (-8, 8), 2: (-40, 40), 3: (-300, 300), 6: (-545, -495), 7: (480, 509)}[p]
        return sign * np.ldexp(m, rng.integers(lo, hi + 1, n))
    if p == 4:
        big = rng.random(n) < 0.15
        return sign * np.ldexp(m, np.where(big, rng.integers(5, 25, n), rng.integers(-30, -10, n)))
    if p == 5:
        return rng.uniform(0.0, 1000.0, n)
    if p == 8:
        return rng.integers(-1000, 1001, n).astype(np.float64)
    return rng.uniform(-1.0, 1.0, n) * np.ldexp(1.0, int(rng.integers(-60, 61)))


def make_inputs(seed, quick):
    import numpy as np

    rng = np.random.default_rng(seed)
    norm, dot = [], []
    for n in N_SET:
        c = counts(n, quick)
        first = len(norm)
        for k in range(c):
            norm.append({"n": n, "v": hexa(vector(rng, n, k))})
        for k in range(min(10, c // 2)):
            dot.append({"n": n, "a": first + k, "b": first + k + c // 2})
    xs = np.concatenate([rng.uniform(-20.0, 1.0, EXP_RANDOM[quick]), [float.fromhex(s) for s in EXP_SPECIAL]])
    return {"seed": seed, "quick": quick, "norm": norm, "dot": dot, "exp": hexa(xs)}


def dumps(doc):
    return json.dumps(doc, indent=1) + "\n"


def cpu_info():
    """The first processor of /proc/cpuinfo: vendor, family/model/stepping, name, the SIMD flags."""
    info = {}
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if not line.strip():
                    break
                k, _, v = line.partition(":")
                info[k.strip()] = v.strip()
    except OSError:
        pass
    keep = re.compile(r"^(sse\d?|ssse3|sse4_[12]|avx.*|fma|f16c|bmi[12]|abm|movbe|amx.*)$")
    return {"vendor_id": info.get("vendor_id"), "cpu_family": info.get("cpu family"), "model": info.get("model"),
            "stepping": info.get("stepping"), "model_name": info.get("model name"),
            "flags": sorted(f for f in info.get("flags", "").split() if keep.match(f))}


def record_results(inputs_path):
    """Run the primitives on inputs.json under this process's environment."""
    import numpy as np

    with open(inputs_path, "rb") as f:
        raw = f.read()
    inp = json.loads(raw)
    vecs = [unhex(c["v"]) for c in inp["norm"]]

    def fresh(v):
        a = v.copy()  # a new numpy allocation (16-byte aligned), as the reference's temporaries are
        assert a.flags.c_contiguous and a.ctypes.data % 16 == 0, "fresh array not 16-byte aligned"
        return a

    with np.errstate(all="ignore"):  # overflow to inf, underflow, nan are cases, not errors
        norms = [np.linalg.norm(fresh(v)) for v in vecs]
        dots = [np.dot(fresh(vecs[c["a"]]), fresh(vecs[c["b"]])) for c in inp["dot"]]
        xs = unhex(inp["exp"])
        exps = np.array([np.exp(np.float64(x)) for x in xs], dtype=np.float64)
        vector_exp = np.exp(xs.copy())
    d = numerics_profile.details()
    return {
        "numerics": d["numerics"], "settings": d["settings"], "openblas_corename": d["openblas_corename"],
        "exp_target": d["exp_target"], "numpy": d["numpy"], "openblas": d["openblas"], "cpu": cpu_info(),
        "inputs": os.path.basename(inputs_path), "inputs_sha256": hashlib.sha256(raw).hexdigest(),
        "exp_array_matches_scalar": bool(vector_exp.tobytes() == exps.tobytes()),
        "norm": hexa(norms), "dot": hexa(dots), "exp": hexa(exps),
    }


def write_inputs(out, seed, quick, force):
    path = os.path.join(out, "inputs.json")
    text = json.dumps(make_inputs(seed, quick), separators=(",", ":")) + "\n"
    if os.path.exists(path) and not force:
        with open(path) as f:
            if f.read() != text:
                sys.exit(f"record_numerics: {path} holds other inputs (seed/--quick); use another --out")
    os.makedirs(out, exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    return path


def default_name(s):
    def slug(v):
        return re.sub(r"[^a-z0-9]+", "-", v.lower()).strip("-")

    name = slug(s["OPENBLAS_CORETYPE"]) if s["OPENBLAS_CORETYPE"] is not None else "unset"
    if s["NPY_DISABLE_CPU_FEATURES"] == "X86_V4 AVX512_ICL" and s["NPY_ENABLE_CPU_FEATURES"] is None:
        name += "_novx4"
    else:
        for k, tag in (("NPY_DISABLE_CPU_FEATURES", "npydisable"), ("NPY_ENABLE_CPU_FEATURES", "npyenable")):
            if s[k] is not None:
                name += f"_{tag}-{slug(s[k])}"
    if s["GLIBC_TUNABLES"] is not None:
        name += f"_glibc-{slug(s['GLIBC_TUNABLES'])}"
    return name


# --matrix: OPENBLAS_CORETYPE values (None: unset) and the CPU flags each needs to run at all.
CORETYPES = [
    ("Prescott", ()), ("Nehalem", ()), ("Sandybridge", ("avx",)), ("Haswell", ("avx2", "fma")),
    ("SkylakeX", ("avx512f", "avx512vl")), ("Zen", ("avx2", "fma")), ("Cooperlake", ("avx512f", "avx512vl")),
    ("bogus-name", ()), (None, ()),
]
X86_V4 = ("avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl")
NOVX4 = "X86_V4 AVX512_ICL"


def matrix_settings(flags):
    out = []
    for core, needs in CORETYPES:
        if not all(f in flags for f in needs):
            continue
        for mask in ([None, NOVX4] if all(f in flags for f in X86_V4) else [None]):
            name = (core.lower() if core else "unset") + ("_novx4" if mask else "")
            out.append((name, core, mask))
    return out


# Every core name OpenBLAS knows (its corename[] table, SapphireRapids included), in other cases, and
# near misses: which kernel does OPENBLAS_CORETYPE=<name> give? Unknown names fall back to the
# CPU's features. A name whose kernel this CPU cannot run is recorded with kernel null if the
# reference process dies for it.
CORETYPE_NAMES = [
    "Katmai", "Coppermine", "Northwood", "Prescott", "Banias", "Atom", "Core2", "Penryn", "Dunnington",
    "Nehalem", "Athlon", "Opteron_SSE3", "Opteron", "Barcelona", "Nano", "Sandybridge", "Bobcat", "Bulldozer",
    "Piledriver", "Haswell", "Steamroller", "Excavator", "Zen", "SkylakeX", "Cooperlake", "SapphireRapids",
    "haswell", "SKYLAKEX", "zen", "opteron_sse3", "Haswell ", " Haswell", "Zen5", "", "unknown",
]


def coretype_names():
    """[{"name", "kernel"}] for CORETYPE_NAMES, each read off a fresh reference process."""
    out = []
    for name in CORETYPE_NAMES:
        env = dict(os.environ, OPENBLAS_CORETYPE=name)
        run = subprocess.run([sys.executable, os.path.join(HERE, "numerics_profile.py"), "--json"], env=env,
                             capture_output=True, text=True)
        if run.returncode != 0:
            # A kernel this CPU lacks may already fault while OpenBLAS initialises it: not asked here.
            out.append({"name": name, "kernel": None, "failed": run.returncode})
            continue
        out.append({"name": name, "kernel": json.loads(run.stdout)["numerics"].split("+")[0].removeprefix("openblas-")})
    return out


def run_matrix(out, seed, quick):
    t0 = time.time()
    if sys.platform != "linux" or os.uname().machine != "x86_64":
        sys.exit("record_numerics --matrix: x86-64 Linux only (reads /proc/cpuinfo)")
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    inputs = write_inputs(out, seed, quick, force=True)
    cpu = cpu_info()
    flags = set(cpu["flags"])
    entries, results = [], {}
    for name, core, mask in matrix_settings(flags):
        env = dict(os.environ)
        for k in ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES", "NPY_ENABLE_CPU_FEATURES"):
            env.pop(k, None)
        if core is not None:
            env["OPENBLAS_CORETYPE"] = core
        if mask is not None:
            env["NPY_DISABLE_CPU_FEATURES"] = mask
        run = subprocess.run([sys.executable, os.path.abspath(__file__), "--results-only", inputs, "--out", out,
                              "--name", name], env=env, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"record_numerics: setting {name} failed ({run.returncode}):\n{run.stderr}")
        with open(os.path.join(out, name + ".json")) as f:
            r = json.load(f)
        results[name] = r
        entries.append({"file": name + ".json", "numerics": r["numerics"], "settings": r["settings"],
                        "openblas_corename": r["openblas_corename"], "exp_target": r["exp_target"]})
        note = "" if not run.stderr.strip() else f"  stderr: {run.stderr.strip()[:120]}"
        print(f"{name:20s} {r['numerics']:28s} corename {r['openblas_corename']:12s} exp {r['exp_target']}{note}")
    names = coretype_names()
    with open(os.path.join(out, "matrix.json"), "w") as f:
        first = next(iter(results.values()))
        f.write(dumps({"numpy": first["numpy"], "openblas": first["openblas"], "cpu": cpu, "inputs": "inputs.json",
                       "seed": seed, "quick": quick, "settings": entries, "coretype_names": names}))
    # Same profile <=> same results: the name must say everything that changes a bit.
    problems = []
    by_profile = {}
    for name, r in results.items():
        by_profile.setdefault(r["numerics"], []).append(name)
    for prof, names in by_profile.items():
        for k in ("norm", "dot", "exp"):
            if len({results[n][k] for n in names}) > 1:
                problems.append(f"{prof}: {k} differs between {', '.join(names)}")
    for name, r in results.items():
        if not r["exp_array_matches_scalar"]:
            problems.append(f"{name}: np.exp on the array differs from np.exp on each scalar")
    profs = sorted(by_profile)
    for i, a in enumerate(profs):
        for b in profs[i + 1:]:
            ra, rb = results[by_profile[a][0]], results[by_profile[b][0]]
            blas_same = ra["norm"] == rb["norm"] and ra["dot"] == rb["dot"]
            if a.split("+")[0] != b.split("+")[0] and blas_same:
                problems.append(f"{a} and {b}: same norm/dot results for different kernels")
            if a.endswith("+svml") != b.endswith("+svml") and ra["exp"] == rb["exp"]:
                problems.append(f"{a} and {b}: same exp results with and without SVML")
    stray = sorted(set(f for f in os.listdir(out) if f.endswith(".json"))
                   - {"inputs.json", "matrix.json"} - {e["file"] for e in entries})
    if stray:
        print(f"warning: {out} holds files not in this matrix: {', '.join(stray)}")
    size = sum(os.path.getsize(os.path.join(out, f)) for f in ["inputs.json", "matrix.json"] + [e["file"] for e in entries])
    print(f"record_numerics: {len(entries)} settings, {len(by_profile)} profiles "
          f"({', '.join(f'{p}: {len(by_profile[p])}' for p in profs)}), {size / 1e6:.2f} MB in {out}, "
          f"{time.time() - t0:.1f} s")
    if problems:
        print("PROBLEMS:\n  " + "\n  ".join(problems))
        sys.exit(1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--out", help="record this process's setting into DIR")
    mode.add_argument("--matrix", metavar="DIR", help="record every setting this CPU can run into DIR")
    ap.add_argument("--name", default=None, help="results file stem (default: from the settings, e.g. haswell_novx4)")
    ap.add_argument("--quick", action="store_true", help="fewer vectors and exp inputs (live checks)")
    ap.add_argument("--seed", type=int, default=SEED, help=f"input seed (default {SEED})")
    ap.add_argument("--results-only", metavar="INPUTS", default=None, help=argparse.SUPPRESS)  # --matrix child
    args = ap.parse_args()
    if args.matrix:
        return run_matrix(args.matrix, args.seed, args.quick)
    out = os.path.abspath(args.out)
    inputs = args.results_only or write_inputs(out, args.seed, args.quick, force=False)
    res = record_results(inputs)
    name = args.name or default_name(res["settings"])
    with open(os.path.join(out, name + ".json"), "w") as f:
        f.write(dumps(res))
    if not args.results_only:
        print(f"record_numerics: {res['numerics']} ({res['openblas_corename']}, exp {res['exp_target']}) "
              f"-> {os.path.join(out, name + '.json')}")


if __name__ == "__main__":
    main()
