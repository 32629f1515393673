"""Which build of envc's native core this process uses: the one for the MuJoCo installed beside it.
A wheel carries one build per supported MuJoCo (``_envc`` for 3.17.0, ``_mujoco_4_0_1/_envc`` for
4.0.1; each also runs the ``envc`` command); envc never installs, upgrades or downgrades MuJoCo."""

from __future__ import annotations

import importlib
import importlib.metadata
import os
import sys
from types import ModuleType

#: The MuJoCo versions envc is bit-identical to the reference on.
SUPPORTED = ("3.17.0", "4.0.1")
_HERE = os.path.dirname(os.path.abspath(__file__))


def installed() -> str | None:
    """The installed MuJoCo's version: ``mujoco-core`` (4.0 on, which the ``mujoco`` metapackage
    requires), else ``mujoco``; ``None`` when neither is installed."""
    for dist in ("mujoco-core", "mujoco"):
        try:
            return importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            continue
    return None


def _build_dir(version: str) -> str | None:
    """The folder of the build for ``version`` other than the package's own, if this wheel has
    it."""
    d = os.path.join(_HERE, "_mujoco_" + version.replace(".", "_"))
    return d if os.path.isdir(d) else None


def load_core() -> ModuleType:
    """The native core built for the installed MuJoCo, registered as ``envc._envc``. Another
    installed version is an ``ImportError`` naming the supported ones, never a silent mix."""
    version = installed()
    supported = " and ".join(SUPPORTED)
    if version is not None and version not in SUPPORTED:
        raise ImportError(
            f"envc: the installed MuJoCo is {version}; envc supports MuJoCo {supported} "
            f"(pip install 'mujoco=={SUPPORTED[-1]}' or 'mujoco=={SUPPORTED[0]}')"
        )
    if version is None or version == SUPPORTED[0]:
        try:
            from . import _envc
        except ImportError as e:
            raise ImportError(f"envc: MuJoCo {SUPPORTED[0]}'s library was not found: {e}") from e
        return _envc
    build = _build_dir(version)
    if build is None:
        raise ImportError(
            f"envc: this installation has no build for MuJoCo {version} (a wheel has one for "
            f"each of {supported}; a build from source is {SUPPORTED[0]}'s only)"
        )
    core = importlib.import_module(f"envc.{os.path.basename(build)}._envc")
    sys.modules["envc._envc"] = core
    return core
