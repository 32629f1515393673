"""What envc's env classes share over their native core (``self._core``): the numerics profile
and, for the single-process envs, closing. A closed env's core is ``_Closed``, which refuses every
call with E1103."""

from __future__ import annotations

from typing import Any, NoReturn

from . import _errors


class _Closed:
    """What a closed env steps with: every call raises, and so does setting anything (the
    numerics profile of a closed env, say)."""

    def __getattr__(self, name: str) -> NoReturn:
        raise _errors.coded("error[E1103]: the env is closed", "E1103")

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise _errors.coded("error[E1103]: the env is closed", "E1103")


class WithNumerics:
    """The numerics profile of the env's core."""

    _core: Any

    @property
    def numerics(self) -> str:
        """The numerics profile (docs/numerics.md), e.g. ``openblas-haswell+svml``."""
        return str(self._core.numerics)

    @numerics.setter
    def numerics(self, name: str) -> None:
        self._core.numerics = name


class CoreEnv(WithNumerics):
    """An env over one native core: ``close`` releases it, and any later use raises E1103."""

    def close(self) -> None:
        """Release the env; any later use raises ``RuntimeError`` (E1103)."""
        core = self._core
        if not isinstance(core, _Closed):
            core.close()
        self._core = _Closed()
