"""docs/pick-and-place.md's Python runs as written: its ``xml``/``toml`` file blocks are written
into a fresh directory (``append`` appends) and its ``python`` blocks run there in page order;
blocks marked ``no-test`` (training with Stable-Baselines3, not a dependency) are skipped. The
``sh`` blocks run in cli/tests/tutorial.rs. The scripted pick asserts its own success rate, and
that ``compute_reward`` gives each step's reward."""

from __future__ import annotations

import os
import re

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def test_the_guides_python_runs(tmp_path, monkeypatch):
    page = open(os.path.join(ROOT, "docs", "pick-and-place.md"), encoding="utf-8").read()
    monkeypatch.chdir(tmp_path)
    ran = 0
    for info, body in re.findall(r"```([^\n]*)\n(.*?)```", page, re.S):
        words = info.split()
        if len(words) >= 2 and words[1].startswith("file="):
            name = words[1][len("file=") :]
            with open(tmp_path / name, "a" if "append" in words else "w", encoding="utf-8") as f:
                f.write(body)
        elif words == ["python"]:
            scope: dict = {}
            exec(compile(body, "docs/pick-and-place.md", "exec"), scope)
            ran += 1
    assert ran == 1
    assert (tmp_path / "pick.toml").is_file()
