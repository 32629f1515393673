"""envc's exceptions: one hierarchy under ``envc.Error``, each with the stable error code
(``.code``, e.g. ``"E0201"``; docs/errors.md) and picklable with it, so an error raised in a
``multiprocessing`` worker or an ``AsyncVectorEnv`` subprocess arrives whole.

Each class also derives from the builtin exception envc raised before the hierarchy existed
(``SpecError`` is a ``ValueError``, an unknown parameter a ``TypeError``, a step before reset a
``RuntimeError``), so existing ``except`` clauses keep working.
"""

from __future__ import annotations

from typing import Any


class Error(Exception):
    """Every error envc raises; ``code`` is its stable code (docs/errors.md)."""

    def __init__(self, message: str = "", code: str | None = None):
        super().__init__(message)
        if code is None:
            # Rebuilt from its text alone (Gymnasium's `make` re-raises `type(e)(f"{e} ...")`).
            import re

            m = re.search(r"error\[(E\d{4})\]", str(message))
            code = m.group(1) if m else None
        self.code = code

    def __reduce__(self) -> tuple[type[Error], tuple[Any, str | None], dict[str, Any]]:
        message = self.args[0] if self.args else ""
        return (type(self), (message, self.code), self.__dict__)


class SpecError(Error, ValueError):
    """A spec, parameter, override or setting that does not check out (E0xxx, E13xx,
    E1503–E1505)."""


class UnknownParameterError(SpecError, TypeError):
    """An override of a parameter the spec does not have (E0202), as an unknown keyword is a
    ``TypeError`` in Python."""


class KindError(SpecError, TypeError):
    """A spec of a kind the call does not serve (E0602): a multi-agent spec for ``collect``."""


class ModelError(Error, ValueError):
    """A model MuJoCo cannot compile or envc cannot run (E1001–E1003, E1110, E1120)."""


class ActionError(Error, ValueError):
    """An action of the wrong length or with a NaN or infinite entry (E1101, E1102)."""


class NotResetError(Error, RuntimeError):
    """``step`` before ``reset``, or after a failure that needs a reset (E1103)."""


class SimulationError(Error, RuntimeError, ValueError):
    """MuJoCo or envc failed while running: MuJoCo's own error (E1004), a reset condition never
    met (E1104), memory (E1402, E1403), rendering (E1501, E1502, E1506, E1507)."""


class DatasetError(Error, ValueError):
    """A Minari dataset that cannot be read or written, a collection that failed, or a dataset
    spec that cannot be used (E12xx, E1600–E1602, E1801–E1802)."""


class ArgumentError(Error, TypeError, ValueError):
    """An argument of a Python call of the wrong type or out of range (E1105): a seed, reset
    options, ``num_envs``, ``episodes``."""


class InternalError(Error, RuntimeError):
    """A bug in envc (E1900): an internal failure caught at the Python boundary. The env that
    raised it must be reset before it steps again. Please report it with the message."""


_ALL = (
    Error,
    SpecError,
    UnknownParameterError,
    KindError,
    ModelError,
    ActionError,
    NotResetError,
    SimulationError,
    DatasetError,
    ArgumentError,
    InternalError,
)
# Pickled by their public name (`envc.SpecError`), which is where users meet them.
for _cls in _ALL:
    _cls.__module__ = "envc"


def class_for(code: str) -> type[Error]:
    """The exception class of a code."""
    if code == "E0202":
        return UnknownParameterError
    if code == "E1105":
        return ArgumentError
    if code == "E0602":
        return KindError
    if code == "E1900":
        return InternalError
    if code == "E1103":
        return NotResetError
    if code in ("E1101", "E1102"):
        return ActionError
    if code in ("E1001", "E1002", "E1003", "E1110", "E1111", "E1120"):
        return ModelError
    if code.startswith(("E12", "E16", "E18")):
        return DatasetError
    if code < "E1000" or code.startswith("E13") or code in ("E1503", "E1504", "E1505"):
        return SpecError
    return SimulationError


def coded(message: str, code: str) -> Error:
    """The exception for an error of ``code`` (what the native core raises)."""
    return class_for(code)(message, code)


def integer(value: object, name: str, low: int = 0, high: int | None = None) -> int:
    """``value`` as an int in ``[low, high)`` (``high`` None: no upper bound), or
    ``ArgumentError`` (E1105). Only integers count: a float, a string or a bool is refused, not
    truncated or parsed (``seed=1.5`` must not become 1)."""
    import numbers

    if getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        value = value.item()  # a 0-d numpy array
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise coded(
            f"error[E1105]: {name} must be an integer, got {type(value).__name__} {value!r}",
            "E1105",
        )
    v = int(value)
    if v < low or (high is not None and v >= high):
        bound = f"[{low}, {high})" if high is not None else f"at least {low}"
        raise coded(f"error[E1105]: {name} must be in {bound}, got {v}", "E1105")
    return v


def seed(value: object) -> int | None:
    """A reset seed: None, or an integer in [0, 2**64)."""
    return None if value is None else integer(value, "seed", 0, 2**64)


def options(value: object) -> dict[str, Any]:
    """Reset options: None or a dict."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise coded(
            f"error[E1105]: options must be a dict or None, got {type(value).__name__}", "E1105"
        )
    return value
