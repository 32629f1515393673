#!/usr/bin/env python3
"""Independent reproduction of envc's `[events]` model randomization at `reset(seed)`.

Written from docs/spec-reference.md ("Domain randomization", "Draw order"), not from envc's code:
MuJoCo's Python bindings compile the model, numpy's `default_rng(seed)` (envc's stream) draws.
Prints the randomized model arrays as JSON (f64 as 16-hex-digit IEEE bit patterns); tests/events.rs
compares them bit for bit with the env's model copy after `reset(seed)`.

    .venv/bin/python tests/reference/check_events.py SPEC.toml SEED [XML]
"""

import fnmatch
import json
import math
import os
import struct
import sys
import tomllib

import mujoco
import numpy as np

ARRAYS = [
    "geom_friction",
    "body_mass",
    "body_ipos",
    "dof_damping",
    "dof_armature",
    "actuator_gainprm",
    "actuator_biasprm",
]
NONNEG = {"geom_friction", "body_mass", "dof_damping", "dof_armature", "kp"}


def hexf(x):
    return struct.pack(">d", float(x)).hex()


def names(m, obj, n):
    return [mujoco.mj_id2name(m, obj, i) or "" for i in range(n)]


def matched(patterns, all_names):
    if isinstance(patterns, str):
        patterns = [patterns]
    return [i for i, n in enumerate(all_names) if n and any(fnmatch.fnmatchcase(n, p) for p in patterns)]


def writes(m, e):
    """(array, flat index, negated-kp index or None) per value, in draw order."""
    f, els = e["field"], e.get("elements", [])
    out = []
    if f.startswith("geom_friction."):
        k = ["sliding", "torsional", "rolling"].index(f.split(".")[1])
        for g in matched(els, names(m, mujoco.mjtObj.mjOBJ_GEOM, m.ngeom)):
            out.append(("geom_friction", 3 * g + k, None))
    elif f == "body_mass":
        out += [("body_mass", b, None) for b in matched(els, names(m, mujoco.mjtObj.mjOBJ_BODY, m.nbody))]
    elif f == "body_ipos":
        for b in matched(els, names(m, mujoco.mjtObj.mjOBJ_BODY, m.nbody)):
            out += [("body_ipos", 3 * b + c, None) for c in range(3)]
    elif f in ("joint_damping", "joint_armature"):
        arr = "dof_" + f.split("_")[1]
        ndof = {0: 6, 1: 3, 2: 1, 3: 1}
        for j in matched(els, names(m, mujoco.mjtObj.mjOBJ_JOINT, m.njnt)):
            a = m.jnt_dofadr[j]
            out += [(arr, a + c, None) for c in range(ndof[int(m.jnt_type[j])])]
    elif f.startswith("actuator_"):
        for a in matched(els, names(m, mujoco.mjtObj.mjOBJ_ACTUATOR, m.nu)):
            if f == "actuator_gain":
                out.append(("actuator_gainprm", 10 * a, None))
            elif f == "actuator_bias":
                out += [("actuator_biasprm", 10 * a + c, None) for c in range(3)]
            else:  # actuator_kp
                out.append(("actuator_gainprm", 10 * a, ("actuator_biasprm", 10 * a + 1)))
    elif f == "gravity":
        out += [("gravity", c, None) for c in range(3)]
    elif f == "timestep":
        out.append(("timestep", 0, None))
    return out


def draw(rng, e):
    d = e["distribution"]
    if d == "uniform":
        return rng.uniform(*e["range"])
    if d == "log_uniform":
        lo, hi = e["range"]
        return np.exp(rng.uniform(math.log(lo), math.log(hi)))
    return rng.normal(e["mean"], e["std"])


def main():
    spec_path, seed = sys.argv[1], int(sys.argv[2])
    with open(spec_path, "rb") as f:
        spec = tomllib.load(f)
    xml = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(spec_path), spec["params"]["xml_file"])
    m = mujoco.MjModel.from_xml_path(xml)
    flat = {a: getattr(m, a).reshape(-1) for a in ARRAYS}  # views: writes change the model
    flat["gravity"] = m.opt.gravity

    def get(a, i):
        return m.opt.timestep if a == "timestep" else flat[a][i]

    def put(a, i, v):
        if a == "timestep":
            m.opt.timestep = v
        else:
            flat[a][i] = v

    def apply(e, base):
        field = e["field"]
        shared = None
        for a, i, neg in writes(m, e):
            d = shared if shared is not None else draw(rng, e)
            if e.get("shared", False):
                shared = d
            b = base(a, i)
            op = e.get("operation", "abs")
            v = b + d if op == "add" else b * d if op == "scale" else d
            key = "kp" if field == "actuator_kp" else a
            if key in NONNEG:
                v = max(v, 0.0)
            if a == "timestep":
                v = min(max(v, 1e-6), 1.0)
            put(a, i, v)
            if neg:
                put(neg[0], neg[1], -v)

    rng = np.random.default_rng(seed)
    events = list(spec.get("events", {}).values())
    model = [e for e in events if e.get("kind", "model") == "model"]
    # 1. startup events in spec order, each on the current values.
    for e in model:
        if e["mode"] == "startup":
            apply(e, get)
    startup = {a: flat[a].copy() for a in flat}
    startup_ts = m.opt.timestep
    # 2. reset events in spec order, each on the startup values.
    for e in model:
        if e["mode"] == "reset":
            apply(e, lambda a, i: startup_ts if a == "timestep" else startup[a][i])
    out = {a: [hexf(x) for x in flat[a]] for a in flat}
    out["timestep"] = [hexf(m.opt.timestep)]
    json.dump(out, sys.stdout)


main()
