#!/usr/bin/env bash
# Side-by-side throughput: envc vs Gymnasium v5 vs EnvPool, one interleaved run on this machine,
# written to docs/PERFORMANCE.md. Not part of scripts/test.sh (performance is checked here, not by
# timed tests).
#   bash benches/compare.sh [--rounds N] [--seconds S] [--envs Ant Hopper ...]
# Installs its own venv (benches/.venv, gitignored): Gymnasium and MuJoCo at the reference pins,
# plus EnvPool from PyPI (it ships its own MuJoCo build). Needs scripts/setup.sh's MuJoCo library
# for the envc build.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
VENV="$ROOT/benches/.venv"
if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install -q -r tests/reference/requirements.txt
# EnvPool is optional: if pip cannot install it here, compare.py says so in the report.
"$VENV/bin/pip" install -q envpool || echo "compare.sh: envpool could not be installed; measuring without it" >&2
bash scripts/setup.sh >/dev/null
cargo build --release -p envc-cli
# A private copy: the target dir is shared, and a rebuild under a running binary kills it (SIGBUS).
BIN="$(mktemp -d)"
trap 'rm -rf "$BIN"' EXIT
cp target/release/envc "$BIN/envc"
"$VENV/bin/python" benches/compare.py --envc "$BIN/envc" "$@"
