#!/usr/bin/env python3
"""No import circle between the files of a crate: a file's `crate::a::b` and `super::x` paths
and the names the crate root re-exports (`crate::Name`), outside comments, are edges to the files
of those modules, and no set of files may reach itself
through them. A module and its own submodules are one family (a parent re-exporting its children
is not a circle). Run by scripts/test.sh's hygiene check; exit status 1 names each circle.

Rust compiles circles between modules; they are forbidden here because a circle makes files that
cannot be read, tested or moved one at a time.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys

# The crates' source roots, by crate.
CRATES = {
    "envspec": "envspec/src",
    "envc": "runtime/src",
    "envc-datasets": "datasets/src",
    "envc-cli": "cli/src",
    "envc-python": "python/src",
    "envc-codegen": "codegen/src",
}
PATH = re.compile(r"crate::([a-z_][a-z0-9_]*(?:::[a-z_][a-z0-9_]*)*)")
SUPER = re.compile(r"super::([a-z_][a-z0-9_]*)")
ROOT_NAME = re.compile(r"crate::([A-Za-z_][A-Za-z0-9_]*)\b(?!::)")


def module(root: str, path: str) -> str:
    parts = os.path.relpath(path, root)[:-3].split("/")
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return "::".join(parts)


def related(a: str, b: str) -> bool:
    """One is the other's ancestor (or they are the same module)."""
    return a == b or a.startswith(b + "::") or b.startswith(a + "::") or not a or not b


def reexports(root: str, mods: dict[str, str]) -> dict[str, str]:
    """Names the crate root re-exports (`pub use module::{A, B}`), by the module they come from:
    `crate::A` reaches that module's file."""
    out: dict[str, str] = {}
    for name in ("lib.rs", "main.rs"):
        path = os.path.join(root, name)
        if not os.path.exists(path):
            continue
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        for m, names in re.findall(r"pub use ([a-z_][a-z0-9_:]*)::\{([^}]*)\}", text):
            for n in names.split(","):
                n = n.strip().split(" as ")[-1].strip()
                if n and m in mods:
                    out[n] = m
        for m, n in re.findall(r"pub use ([a-z_][a-z0-9_:]*)::([A-Za-z_][A-Za-z0-9_]*)\s*;", text):
            if m in mods:
                out[n] = m
    return out


def edges(root: str) -> dict[str, set[str]]:
    files = subprocess.check_output(["git", "ls-files", f"{root}/*.rs"], text=True).split()
    mods = {module(root, f): f for f in files}
    names = reexports(root, mods)
    out: dict[str, set[str]] = {m: set() for m in mods}
    for m, f in mods.items():
        with open(f, encoding="utf-8") as fh:
            text = "\n".join(
                line for line in fh.read().split("\n") if not line.lstrip().startswith("//")
            )
        for n in ROOT_NAME.findall(text):
            target = names.get(n)
            if target is not None and not related(m, target):
                out[m].add(target)
        for p in PATH.findall(text):
            parts = p.split("::")
            for k in range(len(parts), 0, -1):
                target = "::".join(parts[:k])
                if target in mods:
                    if not related(m, target):
                        out[m].add(target)
                    break
        parent = "::".join(m.split("::")[:-1])
        for name in SUPER.findall(text):
            target = f"{parent}::{name}" if parent else name
            if target in mods and not related(m, target):
                out[m].add(target)
    return out


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected sets of more than one file (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []
    counter = 0
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    found.append(sorted(comp))
    return found


def main() -> int:
    bad = 0
    for crate, root in CRATES.items():
        for c in circles(edges(root)):
            bad += 1
            print(f"{crate}: an import circle between {', '.join(c)}")
    if bad:
        print(f"scripts/import_circles.py: {bad} circle(s); move what both sides need to one place")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
