"""Minari datasets from Python: ``envc.collect`` writes what ``envc collect`` writes."""

from __future__ import annotations

import os
from typing import Any, Callable

import numpy as np

from . import _envc, _errors
from ._gym import _id, overrides_to_toml


def collect(
    id_or_path: str,
    dataset_id: str,
    episodes: int = 10,
    *,
    policy: str | Callable[[np.ndarray, np.random.Generator], Any] = "random",
    seed: int | None = None,
    format: str = "arrow",
    root: str | os.PathLike | None = None,
    actions: Any = None,
    author: str | None = None,
    description: str | None = None,
    env_spec: str = "reference",
    **overrides: Any,
) -> str:
    """Record a Minari dataset of a task or maze spec; returns the dataset's directory.

    The same recording as ``envc collect``: ``policy`` is ``"zero"``, ``"random"`` (uniform
    float32 in the action bounds, episode ``i`` drawing from ``numpy.random.default_rng([seed,
    i])``), ``"replay"`` (rows of ``actions``, an array ``[T, act_dim]``, from row 0 in every
    episode) or a callable ``policy(obs, rng) -> action`` (task envs), whose ``rng`` is episode
    ``i``'s ``default_rng([seed, i])``. Episode ``i`` is reset with ``seed + i``; without a seed
    one is drawn from OS entropy (episode 0's stored seed). Episode ``i`` depends on ``(seed,
    i)`` only, so ``envc.ray.collect`` writes the same dataset on any number of machines.
    ``root`` defaults to ``$MINARI_DATASETS_PATH``, else ``~/.minari/datasets``; ``format`` is
    ``"arrow"`` or ``"hdf5"``. Keyword arguments are the spec's parameters, stored as the
    dataset's env kwargs. The dataset appears only once every episode is written.

    ``env_spec`` is the env ``dataset.recover_environment()`` rebuilds: ``"reference"`` (the
    default) names the reference's class (Gymnasium's ``AntEnv``, ...), ``"envc"`` names envc's
    own registration (``envc/<id>``), so that recovering needs only ``import envc``.
    """
    rows = _replay_rows(actions)
    policy_fn = None
    if callable(policy):
        policy_fn, policy = policy, "callable"
    if env_spec not in ("reference", "envc"):
        raise _errors.coded(
            f"error[E1105]: env_spec={env_spec!r}: expected 'reference' or 'envc'", "E1105"
        )
    spec_json = _envc_spec_json(id_or_path, overrides) if env_spec == "envc" else None
    episodes = _errors.integer(episodes, "episodes", 1, 2**64)
    seed = _errors.seed(seed)
    directory, _steps, _seed = _envc.collect(
        _id(id_or_path),
        dataset_id,
        episodes,
        policy,
        seed,
        format,
        None if root is None else os.fspath(root),
        overrides_to_toml(overrides),
        rows,
        author,
        description,
        spec_json,
        policy_fn,
    )
    return directory


def _replay_rows(actions: Any) -> list[float] | None:
    if actions is None:
        return None
    try:
        a = np.asarray(actions, dtype=np.float32)
    except (TypeError, ValueError) as e:
        raise _errors.coded(f"error[E1105]: actions must be numbers ({e})", "E1105") from None
    if a.ndim != 2:
        raise _errors.coded(
            f"error[E1105]: actions must be a 2-D array [T, act_dim], got shape {a.shape}",
            "E1105",
        )
    return a.ravel().tolist()


def _envc_spec_json(id_or_path: str, overrides: dict[str, Any]) -> str:
    """Gymnasium's ``EnvSpec.to_json()`` of the envc registration, with the overrides as kwargs."""
    import gymnasium as gym

    from ._registry import env_id_for, spec_of

    import dataclasses

    base = spec_of(env_id_for(os.fspath(id_or_path)))
    rest = dict(overrides)
    max_steps = rest.pop("max_episode_steps", base.max_episode_steps)
    kwargs = {**base.kwargs, **rest}
    return dataclasses.replace(base, kwargs=kwargs, max_episode_steps=max_steps).to_json()
