"""The ``envc`` command of the wheel: runs the native ``envc`` binary shipped in the package
(``envc/_bin/envc``, which finds MuJoCo in the ``mujoco`` package beside it and the bundled specs
in ``envc/_bundle``)."""

from __future__ import annotations

import os
import sys


def main() -> None:
    exe = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_bin", "envc")
    if not os.access(exe, os.X_OK):
        sys.stderr.write(
            "envc: this installation has no envc binary (an editable install from a checkout: "
            "run `cargo run --release --bin envc --` there, or build the wheel with "
            "scripts/build-wheel.sh)\n"
        )
        raise SystemExit(2)
    os.execv(exe, [exe, *sys.argv[1:]])


if __name__ == "__main__":
    main()
