#!/usr/bin/env python3
"""Prove that envc's own MJCF models compile to the same mjModel as Gymnasium's.

For each model in MODELS, compile envc's file (assets/gymnasium/<file>) and the
reference file shipped in the installed gymnasium package
(gymnasium/envs/mujoco/assets/<file>) with mujoco.MjModel.from_xml_path and
compare the two compiled models:

  * every int attribute of MjModel (the sizes nq, nv, ..., and signature) and
    every bool attribute (flg_*), enumerated with dir();
  * every numpy array attribute of MjModel, enumerated with dir(): dtype, shape
    and contents compared bit for bit (so NaN payloads and the sign of zero
    count; -0.0 != 0.0 here);
  * the bytes buffers names, paths and text_data;
  * all fields of the opt, vis (with its nested sub-structs) and stat structs,
    enumerated recursively with dir(), floats compared bit for bit;
  * as a cross-check, the complete binary model image written by mj_saveModel
    (this covers the C structs whole, including fields the bindings expose
    oddly, see NOTES below);
  * the warnings MuJoCo emits while compiling each file.

Nothing is skipped silently: an attribute that fits none of the categories
above makes the script fail ("unclassified"), and the attributes that are
deliberately not compared are listed in SKIPPED with the reason.

Usage (from any working directory):
    .venv/bin/python tests/reference/check_models.py            # compare all
    .venv/bin/python tests/reference/check_models.py --self-test

--self-test perturbs envc's ant.xml in memory in several small ways and checks
that each perturbation is detected, after first checking that the unperturbed
text (loaded the same way) compares identical.

MuJoCo writes warnings (HalfCheetah's deprecated settotalmass) to
MUJOCO_LOG.TXT in the current directory. The script installs its own warning
handler while compiling (so nothing is logged) and additionally compiles with a
temporary directory as cwd, which it removes; no MUJOCO_LOG.TXT is left behind.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import importlib.util
import os
import struct
import sys
import tempfile
from pathlib import Path

import mujoco
import numpy as np

MODELS = [
    "ant.xml",
    "half_cheetah.xml",
    "hopper.xml",
    "humanoid.xml",
    "humanoidstandup.xml",
    "inverted_pendulum.xml",
    "inverted_double_pendulum.xml",
    "pusher_v5.xml",
    "reacher.xml",
    "swimmer.xml",
    "walker2d_v5.xml",
    # v4 variants, kept for comparisons against the v4 environments
    "pusher.xml",
    "walker2d.xml",
]

EXPECTED_MUJOCO = "3.17.0"

# md5 of the reference files as shipped in gymnasium 1.4.0 (the 11 v5 ones are
# also listed in trap T11 of the v5 reference notes). A mismatch means the
# installed reference is not the pinned one, so a comparison would prove little.
REFERENCE_MD5 = {
    "ant.xml": "c4a95818ed05a3358c1d948c5fbd6f34",
    "half_cheetah.xml": "6bf6419903e906a511ad88260f424d22",
    "hopper.xml": "8e62795f2527d2582f337665936cd119",
    "humanoid.xml": "ff243fbe3261fe66c495544d0538df87",
    "humanoidstandup.xml": "ef43f503eb41e911990ff91eb4c91838",
    "inverted_pendulum.xml": "106cb6da4a0a67bdb23b4e8748308a43",
    "inverted_double_pendulum.xml": "5af13d946db50e48d3fda82ef389ddef",
    "pusher_v5.xml": "8d7505ba15cd154ef2cd5b7fae8beedd",
    "reacher.xml": "411f9f3bbc62faa25033cb4fd7e34616",
    "swimmer.xml": "ed2b88e40b9519007fa9bebbdcddc952",
    "walker2d_v5.xml": "182c7dadbc3f28f08919a0701d7c748b",
    "pusher.xml": "045a5ba465632663df903081c0ccf048",
    "walker2d.xml": "7fb5491cd0097896df56653c3d0f18a0",
}

HERE = Path(__file__).resolve().parent
OURS_DIR = HERE.parent.parent / "assets" / "gymnasium"

# MjModel attributes that are deliberately not compared, with the reason.
SKIPPED = {
    "_address": "address of the C mjModel in this process; differs per instance by construction",
    "_all_fields": "binding metadata (tuple of field names), identical for every model",
    "_size_fields": "binding metadata (tuple of size names), identical for every model",
    "_setconst_fields": "binding metadata (dict), identical for every model",
    "_setconst_groups": "binding metadata (tuple), identical for every model",
    "_setconst_inputs": "binding metadata (tuple), identical for every model",
    "_setconst_outputs": "binding metadata (tuple), identical for every model",
    "_setconst_scalars": "binding metadata (tuple), identical for every model",
}
# Callables (methods such as body()/geom()/bind(), constructors such as
# from_xml_path, and nested type objects in vis such as vis.Global) are
# accessors/types, not model data; they are skipped by that rule and counted.

NOTES = [
    "vis.rgba.bv and vis.rgba.bvactive are exposed by the bindings as empty "
    "arrays; their C values are covered by the mj_saveModel image comparison.",
]


# --------------------------------------------------------------------------
# locating and loading


def reference_dir() -> Path:
    """gymnasium/envs/mujoco/assets of the installed gymnasium.

    This is the directory of gymnasium.envs.mujoco.__file__. The module's spec
    is used rather than importing it: importing gymnasium.envs.mujoco pulls in
    its renderer (imageio, OpenGL), which the comparison does not need.
    """
    spec = importlib.util.find_spec("gymnasium.envs.mujoco")
    if spec is None or spec.origin is None:
        sys.exit("error: gymnasium.envs.mujoco not found; use the project venv (.venv/bin/python)")
    return Path(spec.origin).resolve().parent / "assets"


@contextlib.contextmanager
def quiet_compile_env():
    """cwd = fresh temp dir, MuJoCo warnings captured instead of logged."""
    captured: list[str] = []
    old_cwd = os.getcwd()
    old_handler = mujoco.get_mju_user_warning()
    with tempfile.TemporaryDirectory(prefix="envc_check_models_") as tmp:
        os.chdir(tmp)
        mujoco.set_mju_user_warning(captured.append)
        try:
            yield Path(tmp), captured
        finally:
            mujoco.set_mju_user_warning(old_handler)
            os.chdir(old_cwd)
            leftover = Path(tmp) / "MUJOCO_LOG.TXT"
            if leftover.exists():  # should not happen with the handler installed
                print(f"note: MuJoCo wrote {leftover.name}:\n{leftover.read_text()}", file=sys.stderr)


def load(path: Path) -> tuple[mujoco.MjModel, list[str]]:
    """Compile one file; return the model and the warnings emitted."""
    with quiet_compile_env() as (_tmp, warnings):
        model = mujoco.MjModel.from_xml_path(str(path))
    return model, list(warnings)


def load_text(text: str, name: str) -> tuple[mujoco.MjModel, list[str]]:
    """Compile XML text, written to a temp file and loaded by path like load()."""
    with quiet_compile_env() as (tmp, warnings):
        path = tmp / name
        path.write_text(text)
        model = mujoco.MjModel.from_xml_path(str(path))
    return model, list(warnings)


# --------------------------------------------------------------------------
# comparison


class Diff:
    def __init__(self) -> None:
        self.items: list[str] = []

    def add(self, what: str, detail: str) -> None:
        self.items.append(f"{what}: {detail}")

    def __bool__(self) -> bool:
        return bool(self.items)


def float_bits(x: float) -> bytes:
    return struct.pack("<d", x)


def compare_arrays(name: str, a: np.ndarray, b: np.ndarray, diff: Diff) -> None:
    """Bitwise comparison (a = ours, b = reference)."""
    if a.dtype != b.dtype:
        diff.add(name, f"dtype ours={a.dtype} ref={b.dtype}")
        return
    if a.shape != b.shape:
        diff.add(name, f"shape ours={a.shape} ref={b.shape}")
        return
    if a.size == 0:
        return
    ab = np.ascontiguousarray(a)
    bb = np.ascontiguousarray(b)
    if ab.tobytes() == bb.tobytes():
        return
    # locate the first element whose bytes differ
    item = a.dtype.itemsize
    raw_a = ab.view(np.uint8).reshape(-1, item)
    raw_b = bb.view(np.uint8).reshape(-1, item)
    bad = np.flatnonzero((raw_a != raw_b).any(axis=1))
    first = np.unravel_index(bad[0], a.shape)
    idx = tuple(int(i) for i in first)
    va, vb = ab[idx].item(), bb[idx].item()
    kind = ""
    if a.dtype.kind == "f" and np.array_equal(a, b, equal_nan=True):
        kind = " (equal as numbers: differs only in sign of zero or NaN payload)"
    diff.add(
        name,
        f"{bad.size} of {a.size} elements differ; first at index {idx}: "
        f"ours={va!r} ref={vb!r}{kind}",
    )


def compare_value(name: str, a, b, diff: Diff) -> str:
    """Compare two attribute values of the same category; return the category."""
    if isinstance(a, np.ndarray):
        if not isinstance(b, np.ndarray):
            diff.add(name, f"type ours=ndarray ref={type(b).__name__}")
        else:
            compare_arrays(name, a, b, diff)
        return "array"
    if isinstance(a, bool):
        if a is not b:
            diff.add(name, f"ours={a!r} ref={b!r}")
        return "flag"
    if isinstance(a, int):
        if type(a) is not type(b) or a != b:
            diff.add(name, f"ours={a!r} ref={b!r}")
        return "int"
    if isinstance(a, float):
        if not isinstance(b, float) or float_bits(a) != float_bits(b):
            diff.add(name, f"ours={a!r} ref={b!r}")
        return "float"
    if isinstance(a, bytes):
        if a != b:
            n = min(len(a), len(b))
            off = next((i for i in range(n) if a[i] != b[i]), n)
            diff.add(
                name,
                f"lengths ours={len(a)} ref={len(b)}; first difference at byte {off}: "
                f"ours={a[off:off + 24]!r} ref={b[off:off + 24]!r}",
            )
        return "bytes"
    return ""


def is_struct(v) -> bool:
    """A nested MuJoCo binding struct (MjOption, MjVisual, MjVisual.Global, ...)."""
    return type(v).__module__.startswith("mujoco") and not callable(v)


def compare_struct(prefix: str, a, b, diff: Diff, counts: dict) -> None:
    """Recursively compare all data fields of a binding struct (opt, vis, stat)."""
    for field in sorted(dir(a)):
        if field.startswith("_"):
            continue
        va, vb = getattr(a, field), getattr(b, field)
        name = f"{prefix}.{field}"
        if callable(va):
            counts["skipped_callables"] += 1
            continue
        if is_struct(va):
            compare_struct(name, va, vb, diff, counts)
            continue
        if not compare_value(name, va, vb, diff):
            diff.add(name, f"unclassified struct field of type {type(va).__name__}; extend the checker")
            continue
        counts["struct_fields"] += 1


def model_image(m: mujoco.MjModel) -> bytes:
    buf = np.zeros(mujoco.mj_sizeModel(m), dtype=np.uint8)
    mujoco.mj_saveModel(m, None, buf)
    return buf.tobytes()


def compare_models(ours: mujoco.MjModel, ref: mujoco.MjModel) -> tuple[Diff, dict]:
    diff = Diff()
    counts = {
        "arrays": 0, "sizes": 0, "signature": 0, "flags": 0, "buffers": 0, "struct_fields": 0,
        "skipped_callables": 0, "skipped_listed": 0,
    }
    seen = set()
    for attr in sorted(dir(ref)):
        if attr.startswith("__"):
            continue
        seen.add(attr)
        if attr in SKIPPED:
            counts["skipped_listed"] += 1
            continue
        va, vb = getattr(ours, attr), getattr(ref, attr)
        if callable(vb):
            counts["skipped_callables"] += 1
            continue
        if attr in ("opt", "vis", "stat"):
            compare_struct(attr, va, vb, diff, counts)
            continue
        cat = compare_value(attr, va, vb, diff)
        if cat == "array":
            counts["arrays"] += 1
        elif cat == "int":
            counts["signature" if attr == "signature" else "sizes"] += 1
        elif cat == "flag":
            counts["flags"] += 1
        elif cat == "bytes":
            counts["buffers"] += 1
        else:
            diff.add(attr, f"unclassified MjModel attribute of type {type(vb).__name__}; extend the checker")
    # every field the bindings declare must have been visited
    declared = set(getattr(ref, "_all_fields", ())) | set(getattr(ref, "_size_fields", ()))
    missing = sorted(declared - seen)
    if missing:
        diff.add("coverage", f"fields declared by the bindings but not visited: {missing}")
    if model_image(ours) != model_image(ref):
        a, b = model_image(ours), model_image(ref)
        n = min(len(a), len(b))
        off = next((i for i in range(n) if a[i] != b[i]), n)
        diff.add("mj_saveModel image", f"lengths ours={len(a)} ref={len(b)}; first difference at byte {off}")
    return diff, counts


# --------------------------------------------------------------------------
# driver


def check_all(ref_dir: Path) -> int:
    failures = 0
    all_warnings: list[str] = []
    counts = {}
    for fname in MODELS:
        ours_path, ref_path = OURS_DIR / fname, ref_dir / fname
        if not ours_path.is_file():
            print(f"FAIL {fname}: envc model missing at {ours_path}")
            failures += 1
            continue
        if not ref_path.is_file():
            print(f"FAIL {fname}: reference missing at {ref_path}")
            failures += 1
            continue
        md5 = hashlib.md5(ref_path.read_bytes()).hexdigest()
        if md5 != REFERENCE_MD5[fname]:
            print(f"FAIL {fname}: reference {ref_path} has md5 {md5}, expected the gymnasium 1.4.0 "
                  f"file {REFERENCE_MD5[fname]}")
            failures += 1
            continue
        ours, w_ours = load(ours_path)
        ref, w_ref = load(ref_path)
        diff, counts = compare_models(ours, ref)
        if w_ours != w_ref:
            diff.add("compile warnings", f"ours={w_ours} ref={w_ref}")
        if diff:
            failures += 1
            print(f"FAIL {fname}: {len(diff.items)} differences")
            for item in diff.items:
                print(f"    {item}")
        else:
            extra = f"; both emit {len(w_ours)} compile warning(s): {w_ours!r}" if w_ours else ""
            print(
                f"ok {fname}: {counts['arrays']} arrays, {counts['sizes']} sizes identical "
                f"(+ signature, {counts['flags']} flags, {counts['buffers']} byte buffers, "
                f"{counts['struct_fields']} opt/vis/stat fields, mj_saveModel image){extra}"
            )
        all_warnings += w_ours
    if counts:
        skipped = ", ".join(sorted(SKIPPED))
        print(
            f"not compared: {counts['skipped_listed']} listed attributes ({skipped}; reasons in SKIPPED) "
            f"and {counts['skipped_callables']} callables (accessor methods / nested type objects)"
        )
        for note in NOTES:
            print(f"note: {note}")
    if failures:
        print(f"FAILED: {failures} of {len(MODELS)} models differ from the reference")
        return 1
    print(f"all {len(MODELS)} models compile identically to the reference (MuJoCo {mujoco.__version__})")
    return 0


# Perturbations of envc's ant.xml for --self-test: (description, old, new,
# attribute expected to be reported). Each old string must occur exactly once.
PERTURBATIONS = [
    ("torso sphere radius +1 ulp", 'name="torso_geom" type="sphere" pos="0 0 0" size="0.25"',
     'name="torso_geom" type="sphere" pos="0 0 0" size="0.25000000000000006"', "geom_size"),
    ("light dir -0 -> 0 (sign of zero only)", 'dir="-0 0 -1.3"', 'dir="0 0 -1.3"', "light_dir"),
    ("timestep 0.01 -> 0.011", 'timestep="0.01"', 'timestep="0.011"', "opt.timestep"),
    ("geom renamed", 'name="third_ankle_geom"', 'name="third_ankle_gem"', "names"),
    ("texture colour", 'rgb1="0 0 0" rgb2="0.8 0.8 0.8"', 'rgb1="0 0 0" rgb2="0.8 0.8 0.7"', "tex_data"),
]


def self_test(ref_dir: Path) -> int:
    fname = "ant.xml"
    text = (OURS_DIR / fname).read_text()
    ref, _ = load(ref_dir / fname)
    ok = True

    control, _ = load_text(text, fname)
    diff, _ = compare_models(control, ref)
    if diff:
        print(f"self-test FAIL: unperturbed {fname} loaded from text already differs:")
        for item in diff.items:
            print(f"    {item}")
        return 1
    print(f"self-test control: unperturbed {fname} compares identical")

    for desc, old, new, expect in PERTURBATIONS:
        if text.count(old) != 1:
            print(f"self-test FAIL: perturbation '{desc}': pattern occurs {text.count(old)} times in {fname}")
            ok = False
            continue
        model, _ = load_text(text.replace(old, new), fname)
        diff, _ = compare_models(model, ref)
        hit = [d for d in diff.items if d.startswith(expect + ":")]
        if hit:
            print(f"self-test detected '{desc}': {len(diff.items)} differences, e.g.\n    {hit[0]}")
        else:
            ok = False
            print(f"self-test FAIL: '{desc}' not detected in {expect} (differences: {diff.items})")
    print("self-test passed: the checker detects every perturbation" if ok else "self-test FAILED")
    return 0 if ok else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--self-test", action="store_true",
                        help="check that perturbed models are reported as different")
    args = parser.parse_args()
    if mujoco.__version__ != EXPECTED_MUJOCO:
        print(f"warning: mujoco {mujoco.__version__}, the reference is pinned to {EXPECTED_MUJOCO}")
    ref_dir = reference_dir()
    return self_test(ref_dir) if args.self_test else check_all(ref_dir)


if __name__ == "__main__":
    sys.exit(main())
