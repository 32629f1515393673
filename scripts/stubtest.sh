#!/usr/bin/env bash
# The type stubs of the native core (python/envc/_envc.pyi) checked against the extension the
# venv has installed (scripts/setup.sh builds it) by mypy's stubtest: every function, class,
# method, property and argument the stub names must exist at run time with that signature, and
# nothing public at run time may be missing from the stub. No allowlist: everything PyO3 builds
# (base classes, final subclasses, `__new__`, read-only properties) is expressible in a stub.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-$ROOT/.venv/bin/python}"
cd "$ROOT"
# mypy's cache stays with the build outputs, out of the source tree.
export MYPY_CACHE_DIR="${MYPY_CACHE_DIR:-$ROOT/target/mypy-cache}"
exec "$PY" -m mypy.stubtest envc._envc
