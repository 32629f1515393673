"""The ``envc`` command of the wheel: the command line runs inside the native core built for the
installed MuJoCo (``envc._envc.cli_main``, envc/_mujoco.py), with the bundled specs of the package
(``envc/_bundle``)."""

from __future__ import annotations

import os
import signal
import sys


def main() -> None:
    from . import _envc
    from ._mujoco import installed

    # What `envc info` reports: this script, and why this build of envc was chosen.
    os.environ["ENVC_EXECUTABLE"] = os.path.abspath(sys.argv[0])
    os.environ["ENVC_MUJOCO_REASON"] = f"the installed mujoco is {installed() or '(none)'}"
    # Ctrl-C ends the command as it ends a native program (`envc collect` sets its own handler);
    # Python's handler would only raise once the command returned.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    raise SystemExit(_envc.cli_main(sys.argv))


if __name__ == "__main__":
    main()
