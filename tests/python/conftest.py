"""What the Python tests share."""

import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def envc_cli() -> str:
    """The `envc` command of this checkout: the release build scripts/test.sh and the wheel use
    (so this is no rebuild there; a different feature set would rebuild the whole dependency tree)."""
    subprocess.run(
        ["cargo", "build", "-q", "--release", "--locked", "-p", "envc-cli", "--features", "hdf5-static"],
        cwd=ROOT,
        check=True,
    )
    return str(ROOT / "target" / "release" / "envc")
