#!/usr/bin/env python3
"""Fail when the two release builds ask for a shared dependency with different features.

scripts/setup.sh builds the Python extension (`-p envc-python`) and scripts/test.sh and
build-wheel.sh the CLI (`-p envc-cli`), in separate cargo runs. Cargo reuses what the first run
built only for crates the second asks for with the same features; one crate that differs (syn, say)
rebuilds everything above it. workspace-hack/Cargo.toml asks for the union; this check says which
crate to add there when a dependency change splits them again.

Features are read from `cargo tree`, per crate and per side: the host side (proc-macros, build
scripts and their dependencies) is resolved apart from the target side, so a crate may be on both
with different features, which is fine as long as both builds agree on each side.
"""

from __future__ import annotations

import re
import subprocess
import sys

BUILDS = ("envc-python", "envc-cli")
FEATURES = "hdf5-static"


def features(package: str) -> dict[tuple[str, str], set[str]]:
    """(crate@version, side) -> the features cargo resolves for it, in `package`'s release build."""
    out = subprocess.run(
        ["cargo", "tree", "-q", "--locked", "-p", package, "--features", f"{package}/{FEATURES}",
         "-e", "normal,build", "-f", "{p}|{f}", "--no-dedupe"],
        check=True, capture_output=True, text=True,
    ).stdout
    found: dict[tuple[str, str], set[str]] = {}
    stack: list[tuple[int, bool]] = []  # (depth, on the host side)
    for line in out.splitlines():
        m = re.match(r"^([ │├└─]*)(.+)$", line)
        if not m:
            continue
        depth, text = len(m.group(1)), m.group(2).strip()
        while stack and stack[-1][0] >= depth:
            stack.pop()
        host = stack[-1][1] if stack else False
        if text.startswith("["):  # "[build-dependencies]" opens the host side
            stack.append((depth, host or text == "[build-dependencies]"))
            continue
        pkg, _, feats = text.removesuffix(" (*)").partition("|")
        host = host or "(proc-macro)" in pkg
        name, version = pkg.split()[:2]
        found.setdefault((f"{name}@{version}", "host" if host else "target"), set()).add(feats)
        stack.append((depth, host))
    return found


def main() -> int:
    a, b = (features(p) for p in BUILDS)
    split = sorted(k for k in a.keys() & b.keys() if a[k] != b[k])
    for crate, side in split:
        print(f"release_features: {crate} ({side}) is built with [{' | '.join(sorted(a[(crate, side)]))}]"
              f" for {BUILDS[0]} but [{' | '.join(sorted(b[(crate, side)]))}] for {BUILDS[1]};"
              " ask for the union in workspace-hack/Cargo.toml", file=sys.stderr)
    if not split:
        print(f"release_features: {BUILDS[0]} and {BUILDS[1]} share every common dependency's build")
    return 1 if split else 0


if __name__ == "__main__":
    sys.exit(main())
