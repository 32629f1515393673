"""Minari datasets from Python: ``envc.collect`` writes what ``envc collect`` writes."""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import gymnasium as gym
import numpy as np
import numpy.typing as npt

from . import _envc, _errors
from ._gym import _id, overrides_to_toml

if TYPE_CHECKING:
    from ._envc import _Policy, _PolicyFn


def collect(
    id_or_path: str,
    dataset_id: str,
    episodes: int = 10,
    *,
    policy: Literal["zero", "random", "replay"]
    | Callable[[npt.NDArray[np.float64], np.random.Generator], npt.ArrayLike] = "random",
    seed: int | None = None,
    format: Literal["arrow", "hdf5"] = "arrow",
    root: str | os.PathLike[str] | None = None,
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
    policy_fn: _PolicyFn | None = None
    policy_name: _Policy
    if callable(policy):
        policy_fn, policy_name = policy, "callable"
    else:
        policy_name = policy
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
        policy_name,
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
    rows: list[float] = a.ravel().tolist()
    return rows


def _envc_spec_json(id_or_path: str, overrides: dict[str, Any]) -> str:
    """Gymnasium's ``EnvSpec.to_json()`` of the envc registration, with the overrides as kwargs."""

    import dataclasses

    from ._registry import env_id_for, spec_of

    base = spec_of(env_id_for(os.fspath(id_or_path)))
    rest = dict(overrides)
    max_steps = rest.pop("max_episode_steps", base.max_episode_steps)
    kwargs = {**base.kwargs, **rest}
    return dataclasses.replace(base, kwargs=kwargs, max_episode_steps=max_steps).to_json()


_ENTRY = {"task": "envc._gym:EnvcEnv", "maze": "envc._maze:EnvcMazeEnv"}


def recover_environment(
    dataset: Any,
    *,
    accept_changed_spec: bool = False,
    refuse_other_mujoco: bool = False,
    use_recorded_spec: bool = False,
    **kwargs: Any,
) -> gym.Env[Any, Any]:
    """The envc env that made a dataset, from what the dataset carries (``envc_provenance``).

    ``dataset`` is a ``minari.MinariDataset``, a dataset directory, or a dataset id under
    ``$MINARI_DATASETS_PATH`` (else ``~/.minari/datasets``). The spec is the one recorded: found
    at its recorded id or path and unchanged, or rebuilt from the dataset's copy when it is no
    longer there. A spec found there but changed is ``envc.DatasetError`` E1212, unless
    ``accept_changed_spec`` (then ``envc.DatasetWarning`` W1212) or ``use_recorded_spec`` (the
    dataset's own copy, wherever a spec is found); another MuJoCo version than the
    dataset's warns W1214, or is E1214 with ``refuse_other_mujoco``. The stored parameters and
    time limit apply; ``kwargs`` (parameters, ``render_mode``) are added. Unlike Minari's
    ``recover_environment``, this gives envc's env also for datasets naming the reference class.
    Datasets without a record (older ones) open the spec their env spec names.
    """
    meta = _metadata(dataset)
    text = meta.get("env_spec")
    stored = json.loads(text) if isinstance(text, str) else {}
    prov = meta.get("envc_provenance")
    params = {
        k: v
        for k, v in stored.get("kwargs", {}).items()
        if k not in ("spec_id", "envc_provenance")
    }
    entry = stored.get("entry_point", "")
    if prov is not None:
        spec_id, entry = prov.get("spec"), _ENTRY.get(prov.get("kind"), "envc._gym:EnvcEnv")
    else:
        # An older dataset: the spec its env spec names, checked against nothing.
        spec_id = stored.get("kwargs", {}).get("spec_id") or str(stored.get("id", ""))
        spec_id = spec_id.removeprefix("envc/")
        if not entry.startswith("envc."):
            entry = "envc._gym:EnvcEnv"
        _warn_other_mujoco(meta, refuse_other_mujoco)
    if not spec_id:
        raise _errors.coded(
            "error[E1213]: the dataset stores neither envc_provenance nor an env spec; "
            "nothing names the env that made it",
            "E1213",
        )
    env_spec = gym.envs.registration.EnvSpec(
        id=f"envc/{str(stored.get('id', spec_id)).removeprefix('envc/')}",
        entry_point=entry,
        max_episode_steps=stored.get("max_episode_steps"),
        kwargs={"spec_id": spec_id, "envc_provenance": prov, **params},
    )
    return gym.make(
        env_spec,
        accept_changed_spec=accept_changed_spec,
        refuse_other_mujoco=refuse_other_mujoco,
        use_recorded_spec=use_recorded_spec,
        **kwargs,
    )


def _warn_other_mujoco(meta: dict[str, Any], refuse: bool) -> None:
    recorded = meta.get("mujoco_version")
    running = _envc.__mujoco_version__
    if recorded is None or recorded == running:
        return
    msg = (
        f"dataset `{meta.get('dataset_id')}` was made with MuJoCo {recorded}; this process runs "
        f"MuJoCo {running}"
    )
    if refuse:
        raise _errors.coded(f"error[E1214]: {msg} (refused: `refuse_other_mujoco`)", "E1214")
    import warnings

    from ._gym import DatasetWarning

    warnings.warn(
        DatasetWarning(f"warning[W1214]: {msg}, so replayed episodes may differ", "W1214"),
        stacklevel=3,
    )


def _metadata(dataset: Any) -> dict[str, Any]:
    """A dataset's ``metadata.json``: of a ``MinariDataset``, a directory or an id."""
    storage = getattr(dataset, "storage", None)
    if storage is not None:
        return dict(storage.metadata)
    p = Path(os.fspath(dataset))
    if not p.is_dir():
        root = os.environ.get("MINARI_DATASETS_PATH") or Path.home() / ".minari" / "datasets"
        p = Path(root) / p
    for f in (p / "data" / "metadata.json", p / "metadata.json"):
        if f.is_file():
            meta: dict[str, Any] = json.loads(f.read_text())
            return meta
    raise _errors.coded(
        f"error[E1204]: {p}: not a readable Minari dataset: no metadata.json", "E1204"
    )
