"""What the Python tests share."""

import signal
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# A shell ignores SIGINT in what it starts in the background (`cmd &` without job control), and
# the ignoring is inherited: Python then installs no KeyboardInterrupt handler, in pytest or in
# the processes the Ctrl-C tests start. Those tests check envc's handling, so it is restored here
# whatever launched the suite (an exec'd child gets the default action back, not the ignoring).
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def envc_cli() -> str:
    """The `envc` command of this checkout: the release build scripts/test.sh and the wheel use
    (so this is no rebuild there; a different feature set would rebuild the whole dependency tree)."""
    subprocess.run(
        ["cargo", "build", "-q", "--release", "--locked", "-p", "envc-cli", "--features", "hdf5-static"],
        cwd=ROOT,
        check=True,
    )
    return str(ROOT / "target" / "release" / "envc")


@pytest.fixture
def spawn():
    """`subprocess.Popen`, with every process it started killed at teardown: a test that fails
    part-way (a Ctrl-C that did not land) leaves no collection running for ever."""
    started = []

    def popen(*args, **kwargs):
        p = subprocess.Popen(*args, **kwargs)
        started.append(p)
        return p

    yield popen
    for p in started:
        if p.poll() is None:
            p.kill()
            p.wait()
