"""The ``envc/`` namespace in Gymnasium's registry: every bundled id, and spec files on demand."""

from __future__ import annotations

import os
import warnings
from collections.abc import Iterable
from typing import Any

import gymnasium as gym

from . import _envc

# Entry points by kind; multi-agent specs are PettingZoo envs (envc.parallel_env), not registered.
_ENTRY = {
    "task": "envc._gym:EnvcEnv",
    "maze": "envc._maze:EnvcMazeEnv",
}


def bundled_ids(kind: str | None = None) -> list[str]:
    """The bundled ids (``"task"``, ``"maze"`` or ``"agents"``; all kinds by default), sorted."""
    return [e[0] for e in _envc.registry() if kind is None or e[1] == kind]


def _register(
    env_id: str, kind: str, spec_id: str, max_steps: int | None, threshold: float | None = None
) -> None:
    # What `gym.register` stores, without its per-call scan of the whole registry for other
    # versions of the name (quadratic: 10,000 user specs took 4.3 s of `import envc`). envc's
    # ids are checked as Gymnasium's grammar requires (E0111) and unique (E0603) already.
    gym.registry[env_id] = gym.envs.registration.EnvSpec(
        id=env_id,
        entry_point=_ENTRY[kind],
        kwargs={"spec_id": spec_id},
        max_episode_steps=max_steps or None,
        reward_threshold=threshold,
        vector_entry_point="envc._vector:EnvcVectorEnv" if kind == "task" else None,
    )


def _register_rows(rows: Iterable[tuple[str, str, int | None, bool, float | None]]) -> None:
    for spec_id, kind, max_steps, _example, threshold in rows:
        if kind in _ENTRY and f"envc/{spec_id}" not in gym.registry:
            _register(f"envc/{spec_id}", kind, spec_id, max_steps, threshold)


def register_all() -> None:
    """Register every known single-agent id as ``envc/<id>`` (idempotent): the bundled ones and
    the user's (``ENVC_SPEC_PATH``, :func:`register`). A user's spec that cannot be registered
    is left out with a warning (``envc list`` names it too); it never breaks ``import envc``."""
    try:
        rows = _envc.registry()
    except Exception as e:  # noqa: BLE001 - a broken user spec must not break the import
        warnings.warn(f"envc: the registry could not be read: {e}", stacklevel=2)
        return
    for row in rows:
        try:
            _register_rows([row])
        except Exception as e:  # noqa: BLE001
            warnings.warn(f"envc: `{row[0]}` is not registered: {e}", stacklevel=2)
    try:
        problems = _envc.spec_path_problems()
    except Exception:  # noqa: BLE001
        problems = []
    for p in problems:
        warnings.warn(f"envc: ENVC_SPEC_PATH: {p} (left out)", stacklevel=2)


def register(path: str | os.PathLike[str]) -> list[str]:
    """Register the ids of a spec file, or of every spec file under a directory, so that
    ``gymnasium.make("envc/<id>")``, ``envc.make("<id>")`` and ``envc.parallel_env`` open them.

    Returns the ids. Registering the same file again changes nothing. An id that is bundled with
    envc, or registered from another file, raises :class:`envc.SpecError` (E0603) and registers
    nothing. ``ENVC_SPEC_PATH`` (directories or files, ``:``-separated) registers at import.
    """
    ids = _envc.register(os.fspath(path))
    # Only the new ids are read: registering file after file stays linear.
    _register_rows(_envc.registry([i for i in ids if f"envc/{i}" not in gym.registry]))
    return ids


def spec_of(env_id: str | gym.envs.registration.EnvSpec) -> gym.envs.registration.EnvSpec:
    """The ``EnvSpec`` of what :func:`env_id_for` returned."""
    return env_id if isinstance(env_id, gym.envs.registration.EnvSpec) else gym.spec(env_id)


# Keyword arguments `gym.make` takes for itself; the rest are the spec's parameters.
_GYM_MAKE_KEYS = (
    "max_episode_steps",
    "disable_env_checker",
    "autoreset",
    "apply_api_compatibility",
)


def env_id_for(
    id_or_path: str, overrides: dict[str, Any] | None = None
) -> str | gym.envs.registration.EnvSpec:
    """The Gymnasium id of a bundled id or a spec file (registered as ``envc/<its id>``), or, for
    a file whose id belongs to another spec, an unregistered ``EnvSpec`` of that name.
    ``overrides`` are the keyword arguments the env will be made with: a spec file whose default
    model is elsewhere (``xml_file``) resolves only with them."""
    name = id_or_path[5:] if id_or_path.startswith("envc/") else id_or_path
    if f"envc/{name}" in gym.registry and not os.path.isfile(name):
        return f"envc/{name}"
    params = {k: v for k, v in (overrides or {}).items() if k not in _GYM_MAKE_KEYS}
    try:
        kind, spec_id, max_steps = _envc.describe(os.fspath(name))
    except _envc.SpecError:
        if not params:
            raise
        from ._gym import overrides_to_toml

        kind, spec_id, max_steps = _envc.describe(os.fspath(name), overrides_to_toml(params))
    if kind not in _ENTRY:
        from ._errors import coded

        raise coded(
            f"error[E0602]: `{id_or_path}` is a multi-agent spec: open it with envc.parallel_env",
            "E0602",
        )
    env_id = f"envc/{spec_id}"
    path = os.path.abspath(name) if os.path.isfile(name) else name
    if env_id in gym.registry and gym.registry[env_id].kwargs.get("spec_id") == path:
        # The same file again (perhaps edited): its registration is refreshed.
        del gym.registry[env_id]
    if env_id in gym.registry or _envc.registry([spec_id]):
        # A file whose id is bundled, registered, or made from another file never takes that id
        # over: the env is made from an unregistered spec of the same name.
        return gym.envs.registration.EnvSpec(
            id=env_id,
            entry_point=_ENTRY[kind],
            kwargs={"spec_id": path},
            max_episode_steps=max_steps or None,
            vector_entry_point="envc._vector:EnvcVectorEnv" if kind == "task" else None,
        )
    _register(env_id, kind, path, max_steps)
    return env_id
