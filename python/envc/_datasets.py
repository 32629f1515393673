"""Minari datasets from Python: ``envc.collect`` writes what ``envc collect`` writes."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from . import _envc
from ._gym import overrides_to_toml


def collect(
    id_or_path: str,
    dataset_id: str,
    episodes: int = 10,
    *,
    policy: str = "random",
    seed: int | None = None,
    format: str = "arrow",
    root: str | os.PathLike | None = None,
    actions: Any = None,
    author: str | None = None,
    description: str | None = None,
    **overrides: Any,
) -> str:
    """Record a Minari dataset of a task or maze spec; returns the dataset's directory.

    The same recording as ``envc collect``: ``policy`` is ``"zero"``, ``"random"`` (uniform
    float32 in the action bounds) or ``"replay"`` (rows of ``actions``, an array
    ``[T, act_dim]``); episode ``i`` is reset with ``seed + i`` (OS entropy without a seed).
    ``root`` defaults to ``$MINARI_DATASETS_PATH``, else ``~/.minari/datasets``; ``format`` is
    ``"arrow"`` or ``"hdf5"``. Keyword arguments are the spec's parameters, stored as the
    dataset's env kwargs. The dataset appears only once every episode is written.
    """
    rows = None
    if actions is not None:
        a = np.asarray(actions, dtype=np.float32)
        if a.ndim != 2:
            raise ValueError(f"actions must be a 2-D array [T, act_dim], got shape {a.shape}")
        rows = a.ravel().tolist()
    directory, _steps = _envc.collect(
        os.fspath(id_or_path),
        dataset_id,
        int(episodes),
        policy,
        seed,
        format,
        None if root is None else os.fspath(root),
        overrides_to_toml(overrides),
        rows,
        author,
        description,
    )
    return directory
