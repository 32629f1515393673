#!/usr/bin/env bash
# The wheel beside MuJoCo 4.0.1 (scripts/test.sh's MuJoCo 4.0.1 lane): a fresh venv with Gymnasium
# 1.4.0 on MuJoCo 4.0.1, the wheel installed into it, the checkout hidden. MuJoCo must still be
# 4.0.1 afterwards, and envc must compute what Gymnasium computes on it (tests/wheel/mujoco4.py,
# fresh seed, frames included), from Python and from the `envc` command; and beside 4.0.0, which
# envc does not support, `import envc` must say so.
# Usage: tests/wheel/mujoco4.sh DIST WORKDIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DIST="${1:?usage: tests/wheel/mujoco4.sh DIST WORKDIR}"
WORK="${2:?usage: tests/wheel/mujoco4.sh DIST WORKDIR}"
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"
case "$WORK" in "$ROOT"/*) echo "wheel test: WORKDIR must be outside the checkout" >&2; exit 1 ;; esac
WHEEL="$(ls "$DIST"/envc-*.whl)"
# shellcheck source=tests/wheel/hidden.sh
source "$ROOT/tests/wheel/hidden.sh"
REQ="$ROOT/tests/reference/requirements-mujoco-4.0.1.txt"
python3 -m venv "$WORK/venv"
"$WORK/venv/bin/pip" install -q --disable-pip-version-check -r "$REQ"
"$WORK/venv/bin/pip" install -q --disable-pip-version-check "$WHEEL"
cp "$ROOT/tests/wheel/mujoco4.py" "$WORK/mujoco4.py"
hidden "MUJOCO_GL=egl '$WORK/venv/bin/python' '$WORK/mujoco4.py'"
hidden "'$WORK/venv/bin/envc' info | grep -q 'linked:    MuJoCo 4.0.1'"
# A MuJoCo envc does not support (4.0.0, whose sparse Cholesky 4.0.1 fixed): `import envc` names
# the supported versions rather than loading a build for another library.
# Datasets on MuJoCo 4.0.1: the wheel's `envc collect` (arrow and HDF5, overrides, an interrupted
# collection), loaded by the real minari, recovered and replayed in Gymnasium on 4.0.1 bit for bit.
"$WORK/venv/bin/python" "$ROOT/tests/reference/check_minari.py" --envc "$WORK/venv/bin/envc"
"$WORK/venv/bin/pip" install -q --disable-pip-version-check --no-deps mujoco-core==4.0.0
err="$(hidden "'$WORK/venv/bin/python' -c 'import envc'" 2>&1)" && { echo "import envc worked beside MuJoCo 4.0.0" >&2; exit 1; }
grep -q "the installed MuJoCo is 4.0.0; envc supports MuJoCo 3.17.0 and 4.0.1" <<< "$err" ||
  { echo "$err" >&2; echo "import envc beside MuJoCo 4.0.0: not the coded refusal" >&2; exit 1; }
echo "wheel beside MuJoCo 4.0.1: kept, and bit-identical to Gymnasium on it; 4.0.0 refused"
