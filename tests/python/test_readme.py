"""The README's Python quick start runs as written."""

from __future__ import annotations

import os
import re


def test_readme_python_quick_start_runs():
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    readme = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    section = readme[readme.index("## From Python") :]
    block = re.search(r"```python\n(.*?)```", section, re.S)
    assert block, "no python block under 'From Python'"
    scope: dict = {}
    exec(compile(block.group(1), "README.md (From Python)", "exec"), scope)
    assert scope["hopper"].unwrapped.observation_space.shape == (11,)
