#!/usr/bin/env bash
# The type stubs of the native core (python/envc/_envc.pyi) checked against the extension the
# venv has installed (scripts/setup.sh builds it), by mypy's stubtest: every class, method,
# property and argument the stub names must exist at run time with that signature, and nothing
# public at run time may be missing from the stub. What stubtest cannot express is listed, with
# why, in scripts/stubtest-allowlist.txt.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-$ROOT/.venv/bin/python}"
cd "$ROOT"
exec "$PY" -m mypy.stubtest envc._envc \
  --allowlist "$ROOT/scripts/stubtest-allowlist.txt"
