#!/usr/bin/env bash
# The Python package linted and type-checked: `ruff check python/envc` (rules in pyproject.toml's
# [tool.ruff]) and `mypy --strict` over python/envc ([tool.mypy]), the native core typed by its
# stub, python/envc/_envc.pyi, so nothing needs building (scripts/stubtest.sh checks that stub
# against the built extension). ruff and mypy are pinned in tests/reference/requirements.txt.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-$ROOT/.venv/bin/python}"
# From the root, where pyproject.toml names the files; the caches go with the build outputs, out of
# the source tree.
cd "$ROOT"
CACHE="$ROOT/target/python-lint"
mkdir -p "$CACHE"
"$PY" -m ruff check --cache-dir "$CACHE/ruff" python/envc
exec "$PY" -m mypy --cache-dir "$CACHE/mypy"
