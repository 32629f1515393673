#!/usr/bin/env bash
# The type stubs of the native core (python/envc/_envc.pyi) checked against the extension the
# venv has installed (scripts/setup.sh builds it) by mypy's stubtest: every function, class,
# method, property and argument the stub names must exist at run time with that signature, and
# nothing public at run time may be missing from the stub. No allowlist: everything PyO3 builds
# (base classes, final subclasses, `__new__`, read-only properties) is expressible in a stub.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-$ROOT/.venv/bin/python}"
# Run from the build outputs, where mypy leaves its cache (.mypy_cache), out of the source tree.
mkdir -p "$ROOT/target/stubtest"
cd "$ROOT/target/stubtest"
exec "$PY" -m mypy.stubtest envc._envc
