"""``import envc`` warns (``envc.ParityWarning``) when the installed Gymnasium is not the release
envc's bit-for-bit parity is proven against (1.4.0), and says nothing when it is."""

from __future__ import annotations

import subprocess
import sys
import warnings

import pytest

import envc


def test_another_gymnasium_release_warns_naming_both_versions():
    with pytest.warns(envc.ParityWarning, match=r"Gymnasium is 1\.4\.1.*Gymnasium 1\.4\.0") as got:
        envc._parity_warning("1.4.1")
    assert len(got) == 1
    assert issubclass(envc.ParityWarning, UserWarning)


def test_the_proven_release_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        envc._parity_warning("1.4.0")


def _import_envc_with_gymnasium(version: str | None) -> str:
    """The warnings of ``import envc`` in a fresh process whose Gymnasium reports ``version``
    (``None``: the installed one's own)."""
    patch = "" if version is None else f"gymnasium.__version__ = {version!r};"
    code = (
        "import warnings; warnings.simplefilter('always');"
        f"import gymnasium; {patch}"
        "import envc; print('ok')"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"
    return out.stderr


def test_import_warns_once_under_another_release():
    stderr = _import_envc_with_gymnasium("1.4.1")
    assert stderr.count("ParityWarning") == 1, stderr
    assert "1.4.1" in stderr and "1.4.0" in stderr


@pytest.mark.skipif(
    __import__("gymnasium").__version__ != "1.4.0", reason="needs the reference's Gymnasium"
)
def test_import_is_silent_under_the_proven_release():
    assert "ParityWarning" not in _import_envc_with_gymnasium(None)
