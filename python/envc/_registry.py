"""The ``envc/`` namespace in Gymnasium's registry: every bundled id, and spec files on demand."""

from __future__ import annotations

import os

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
    gym.register(
        id=env_id,
        entry_point=_ENTRY[kind],
        kwargs={"spec_id": spec_id},
        max_episode_steps=max_steps or None,
        reward_threshold=threshold,
        vector_entry_point="envc._vector:EnvcVectorEnv" if kind == "task" else None,
    )


def register_all() -> None:
    """Register every known single-agent id as ``envc/<id>`` (idempotent): the bundled ones and
    the user's (``ENVC_SPEC_PATH``, :func:`register`)."""
    for spec_id, kind, max_steps, _example, threshold in _envc.registry():
        if kind in _ENTRY and f"envc/{spec_id}" not in gym.registry:
            _register(f"envc/{spec_id}", kind, spec_id, max_steps, threshold)


def register(path: str | os.PathLike) -> list[str]:
    """Register the ids of a spec file, or of every spec file under a directory, so that
    ``gymnasium.make("envc/<id>")``, ``envc.make("<id>")`` and ``envc.parallel_env`` open them.

    Returns the ids. Registering the same file again changes nothing. An id that is bundled with
    envc, or registered from another file, raises :class:`envc.SpecError` (E0603) and registers
    nothing. ``ENVC_SPEC_PATH`` (directories or files, ``:``-separated) registers at import.
    """
    ids = _envc.register(os.fspath(path))
    register_all()
    return ids


def spec_of(env_id) -> "gym.envs.registration.EnvSpec":
    """The ``EnvSpec`` of what :func:`env_id_for` returned."""
    return env_id if isinstance(env_id, gym.envs.registration.EnvSpec) else gym.spec(env_id)


# Keyword arguments `gym.make` takes for itself; the rest are the spec's parameters.
_GYM_MAKE_KEYS = ("max_episode_steps", "disable_env_checker", "autoreset", "apply_api_compatibility")


def env_id_for(id_or_path: str, overrides: dict | None = None) -> "str | gym.envs.registration.EnvSpec":
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
        raise TypeError(
            f"`{id_or_path}` is a multi-agent spec: open it with envc.parallel_env"
        )
    env_id = f"envc/{spec_id}"
    path = os.path.abspath(name) if os.path.isfile(name) else name
    if any(row[0] == spec_id for row in _envc.registry()):
        # A file whose id is bundled or registered from another file never takes that id over:
        # the env is made from an unregistered spec of the same name.
        return gym.envs.registration.EnvSpec(
            id=env_id,
            entry_point=_ENTRY[kind],
            kwargs={"spec_id": path},
            max_episode_steps=max_steps or None,
            vector_entry_point="envc._vector:EnvcVectorEnv" if kind == "task" else None,
        )
    if env_id in gym.registry:
        del gym.registry[env_id]
    _register(env_id, kind, path, max_steps)
    return env_id
