#!/usr/bin/env python3
"""The size rules of the Rust sources, as data: no function over MAX_FN_LINES lines and no file
over MAX_FILE_LINES lines (every line counted: code, comments and blank lines), outside the
exceptions below, each with its reason. Run by scripts/test.sh's hygiene check; exit status 1
lists what breaks a rule.

Functions are found by a brace-matching scan (strings, characters and line comments skipped),
which is all the rule needs: clippy's `too_many_lines` counts code lines only, so a function
with long doc comments or tables passes it and not this.
"""
from __future__ import annotations

import re
import subprocess
import sys

MAX_FN_LINES = 120
MAX_FILE_LINES = 800
# Paths (or `path::function`) kept over a limit, with why. Empty: none is needed today.
EXCEPTIONS: dict[str, str] = {}
# Data, not code: recorded inputs and compile-fail cases.
SKIP = ("tests/fixtures/", "codegen/tests/ui/")

FN = re.compile(
    r'\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?(extern\s+"[^"]*"\s+)?fn\s+(\w+)'
)


def code(line: str) -> str:
    """The line without string and character literals and without a `//` comment."""
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])'", "''", line)
    return line.split("//")[0]


def functions(lines: list[str]):
    """(name, first line index, line count) of every function with a body."""
    i = 0
    while i < len(lines):
        m = FN.match(lines[i])
        if not m:
            i += 1
            continue
        depth, started, j = 0, False, i
        while j < len(lines):
            s = code(lines[j])
            if not started and ";" in s and "{" not in s:
                break  # a declaration without a body
            for ch in s:
                if ch == "{":
                    depth, started = depth + 1, True
                elif ch == "}":
                    depth -= 1
            if started and depth == 0:
                break
            j += 1
        if started:
            yield m.group(7), i, j - i + 1
            i = j + 1
        else:
            i += 1


def main() -> int:
    files = subprocess.check_output(["git", "ls-files", "*.rs"], text=True).split()
    problems = []
    for path in files:
        if path.startswith(SKIP):
            continue
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        if len(lines) - 1 > MAX_FILE_LINES and path not in EXCEPTIONS:
            problems.append(f"{path}: {len(lines) - 1} lines (at most {MAX_FILE_LINES})")
        for name, start, n in functions(lines):
            if n > MAX_FN_LINES and f"{path}::{name}" not in EXCEPTIONS:
                problems.append(
                    f"{path}:{start + 1}: fn {name} is {n} lines (at most {MAX_FN_LINES})"
                )
    for p in problems:
        print(p)
    if problems:
        print(
            f"scripts/sizes.py: {len(problems)} over the size rules"
            " (split them, or add an exception with its reason)"
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
