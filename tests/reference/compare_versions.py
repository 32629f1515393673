"""Which envs' trajectories change between two MuJoCo versions: recordings of the same cases and
seeds made under each, compared step by step. Prints a Markdown table: per env, the cases that are
bit-identical over the recording, where the others first differ, and how far apart they end up.
docs/mujoco-versions.md holds its output.

usage: compare_versions.py {suite,maze,mamujoco} DIR_A DIR_B
  suite     record.py's v5/v4 recordings (manifest.json, one .npz per case)
  maze      record_maze.py's (one .json per case, hex-encoded events)
  mamujoco  record_mamujoco.py's (manifest.json, one .npz per case with the global state)
"""

from __future__ import annotations

import json
import os
import sys
from collections import defaultdict

import numpy as np

# Per case: (env, first differing step or None; 0 = the reset, max |difference|, steps compared).
Row = tuple[str, "int | None", float, int]


def first_row(a: np.ndarray, b: np.ndarray) -> int | None:
    n = min(len(a), len(b))
    diff = np.flatnonzero((a[:n] != b[:n]).reshape(n, -1).any(axis=1))
    return int(diff[0]) if len(diff) else None


def common(a: np.ndarray, b: np.ndarray) -> int:
    """How many leading rows two action sequences share."""
    f = first_row(a, b)
    return min(len(a), len(b)) if f is None else f


def suite(a_dir: str, b_dir: str) -> list[Row]:
    b_cases = {c["name"]: c for c in json.load(open(os.path.join(b_dir, "manifest.json")))["cases"]}
    rows = []
    for case in json.load(open(os.path.join(a_dir, "manifest.json")))["cases"]:
        if case["name"] not in b_cases:
            continue
        a = np.load(os.path.join(a_dir, case["file"]))
        b = np.load(os.path.join(b_dir, b_cases[case["name"]]["file"]))
        # Episodes that end at other steps draw other reset seeds and then other actions: compare
        # up to the first action that differs (always after the first observation that does).
        t = common(a["actions"], b["actions"])
        if a["reset_obs"][0].tobytes() != b["reset_obs"][0].tobytes():
            first = 0
        else:
            f = first_row(a["obs"][:t], b["obs"][:t])
            first = None if f is None else f + 1
        rows.append((case["env_id"], first, float(np.max(np.abs(a["obs"][:t] - b["obs"][:t]))), t))
    return rows


def maze(a_dir: str, b_dir: str) -> list[Row]:
    rows = []
    for name in sorted(f for f in os.listdir(a_dir) if f.endswith(".json") and f != "manifest.json"):
        if not os.path.exists(os.path.join(b_dir, name)):
            continue
        a, b = (json.load(open(os.path.join(d, name))) for d in (a_dir, b_dir))
        if "events" not in a or "events" not in b:
            continue
        first, gap, t = None, 0.0, 0
        for i, (ea, eb) in enumerate(zip(a["events"], b["events"])):
            if ea.get("action") != eb.get("action"):
                break
            oa = np.concatenate([np.frombuffer(bytes.fromhex(v), "<f8") for v in ea["obs"].values()])
            ob = np.concatenate([np.frombuffer(bytes.fromhex(v), "<f8") for v in eb["obs"].values()])
            if first is None and oa.tobytes() != ob.tobytes():
                first = i
            gap, t = max(gap, float(np.max(np.abs(oa - ob)))), i
        rows.append((a["id"], first, gap, t))
    return rows


def mamujoco(a_dir: str, b_dir: str) -> list[Row]:
    rows = []
    for case in json.load(open(os.path.join(a_dir, "manifest.json")))["cases"]:
        file = case["name"] + ".npz"
        if not os.path.exists(os.path.join(b_dir, file)):
            continue
        a, b = np.load(os.path.join(a_dir, file)), np.load(os.path.join(b_dir, file))
        t = common(a["actions"], b["actions"])
        first = first_row(a["state"][: t + 1], b["state"][: t + 1])
        gap = float(np.max(np.abs(a["state"][: t + 1] - b["state"][: t + 1])))
        rows.append((f"{case['scenario']} {case['agent_conf'] or 'single'}", first, gap, t))
    return rows


def main() -> None:
    kind, a_dir, b_dir = sys.argv[1:4]
    rows = {"suite": suite, "maze": maze, "mamujoco": mamujoco}[kind](a_dir, b_dir)
    per_env: dict[str, list[Row]] = defaultdict(list)
    for row in rows:
        per_env[row[0]].append(row)
    horizon = max(r[3] for r in rows)
    print(f"| env | cases identical (of) | first difference (step; 0 = the reset) | max \\|Δ\\| (up to {horizon} steps) |")
    print("|---|---:|---|---:|")
    for env in sorted(per_env):
        cases = per_env[env]
        same = sum(1 for r in cases if r[1] is None)
        firsts = sorted({r[1] for r in cases if r[1] is not None})
        first = ", ".join(str(f) for f in firsts[:3]) if firsts else "none"
        name = env.replace("|", "\\|")
        print(f"| {name} | {same} of {len(cases)} | {first} | {max(r[2] for r in cases):.3g} |")


if __name__ == "__main__":
    main()
