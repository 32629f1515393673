"""Dataset specs read through envc's one reader (``envc.datasets.read_spec``, envspec in Rust):
the same data as ``tomllib`` for every bundled spec, a mistake is E1801 at its line and column,
and the reference-score rewrite changes that table only, comments and layout kept."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path
from typing import Any

import pytest

import envc
import envc.datasets

ROOT = Path(__file__).resolve().parents[2]
SUITE = ROOT / "specs" / "datasets"
SPECS = sorted(SUITE.rglob("*.toml"))

SPEC = """[dataset]
id = "t/x-v0"
tier = "x"
env = "Hopper-v5"
steps = 10
seed = 1
[policy]
file = "p.npz"
mode = "deterministic"
[metadata]
algorithm_name = "a"
author = []
description = "d"
"""


def _typed(v: Any) -> Any:
    """The value with every leaf's type beside it: `1 == 1.0` must not pass."""
    if isinstance(v, dict):
        return {k: _typed(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_typed(x) for x in v]
    return (type(v).__name__, v)


def test_every_bundled_spec_reads_as_tomllib_reads_it():
    assert len(SPECS) == 28
    for path in SPECS:
        want = tomllib.loads(path.read_text())
        got = envc.datasets.read_spec(path)
        assert _typed(got) == _typed(want), path
        # Key order as written, as tomllib keeps it.
        assert list(got) == list(want), path
        assert list(got["dataset"]) == list(want["dataset"]), path
    # A bundled id reads its file.
    hopper = SUITE / "mujoco" / "hopper" / "simple-v0.toml"
    assert envc.datasets.read_spec("mujoco/hopper/simple-v0") == tomllib.loads(hopper.read_text())


def test_a_mistake_is_e1801_at_its_line_and_column(tmp_path):
    bad = tmp_path / "d.toml"
    bad.write_text(SPEC.replace("seed = 1\n", "episodes = 2\nseed = 1\n"))
    with pytest.raises(envc.DatasetError) as e:
        envc.datasets.read_spec(bad)
    assert e.value.code == "E1801"
    assert str(e.value) == f"error[E1801]: {bad}:6:1: give `steps` or `episodes`, not both"
    # An unknown key is refused where it is written.
    bad.write_text(SPEC.replace("mode = ", "mood = "))
    with pytest.raises(envc.DatasetError) as e:
        envc.datasets.read_spec(bad)
    assert e.value.code == "E1801"
    assert str(e.value).startswith(f"error[E1801]: {bad}:9:1: unknown field `mood`, expected")
    # Not TOML at all.
    bad.write_text(SPEC.replace('tier = "x"', 'tier = "x'))
    with pytest.raises(envc.DatasetError) as e:
        envc.datasets.read_spec(bad)
    assert e.value.code == "E1801"
    assert str(e.value).startswith(f"error[E1801]: {bad}:3:")
    # Neither a file nor a bundled id.
    with pytest.raises(envc.Error) as e:
        envc.datasets.read_spec("mujoco/hopper/none-v0")
    assert "neither a dataset spec file nor a bundled dataset id" in str(e.value)


def test_the_reference_score_rewrite_changes_that_table_only(tmp_path):
    """Every tier of an env gets the scores: where the table is, its values are replaced in
    place; where it is not, a table comes before [train]; every other line is as written."""
    env = tmp_path / "invertedpendulum"
    shutil.copytree(SUITE / "mujoco" / "invertedpendulum", env)
    # One tier without the table, the other with a comment in it.
    expert, medium = env / "expert-v0.toml", env / "medium-v0.toml"
    table = expert.read_text().split("[reference_scores]\n", 1)[1].split("\n\n", 1)[0] + "\n"
    medium.write_text(medium.read_text().replace("[reference_scores]\n" + table + "\n", ""))
    comment = "[reference_scores]\n# measured by Minari\n"
    expert.write_text(expert.read_text().replace("[reference_scores]\n", comment))
    before = {p.name: p.read_text() for p in sorted(env.glob("*.toml"))}
    assert "[reference_scores]" not in before["medium-v0.toml"]
    scores = {"ref_min_score": -12.5, "ref_max_score": 3000.25, "num_episodes_average_score": 100}
    written = envc.datasets.write_reference_scores(expert, scores)
    assert [Path(p).name for p in written] == ["expert-v0.toml", "medium-v0.toml"]
    new = "ref_min_score = -12.5\nref_max_score = 3000.25\nnum_episodes_average_score = 100\n"
    after = {p.name: p.read_text() for p in sorted(env.glob("*.toml"))}
    for name, text in after.items():
        assert tomllib.loads(text)["reference_scores"] == scores, name
    assert after["expert-v0.toml"] == before["expert-v0.toml"].replace(comment + table, comment + new)
    assert after["medium-v0.toml"] == before["medium-v0.toml"].replace(
        "\n[train]\n", "\n[reference_scores]\n" + new + "\n[train]\n", 1
    )
