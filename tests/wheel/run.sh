#!/usr/bin/env bash
# The wheel outside its checkout (scripts/test.sh runs this): the wheel of scripts/build-wheel.sh,
# installed into a venv of its pinned dependencies, run with the checkout hidden under an empty
# tmpfs (a private mount namespace): tests/wheel/smoke.py against the live reference, then the
# `envc` command of the wheel. (A crate outside the checkout: tests/wheel/crate.sh.)
# Usage: tests/wheel/run.sh [--prebuilt DIST] [--venv-only] WORKDIR
#   --prebuilt DIST: the wheel scripts/build-wheel.sh has just built into DIST, rather than building it;
#   --venv-only: stop once the venv is made (scripts/test.sh makes it while pytest runs).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
USAGE="usage: tests/wheel/run.sh [--prebuilt DIST] [--venv-only] WORKDIR"
PREBUILT=""
VENV_ONLY=0
while [ $# -gt 1 ]; do
  case "$1" in
    --prebuilt) PREBUILT="${2:?$USAGE}"; shift ;;
    --venv-only) VENV_ONLY=1 ;;
    *) echo "$USAGE" >&2; exit 2 ;;
  esac
  shift
done
WORK="${1:?$USAGE}"
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"
case "$WORK" in "$ROOT"/*) echo "wheel test: WORKDIR must be outside the checkout" >&2; exit 1 ;; esac
VERSION="$(sed -n 's/^version = "\(.*\)"/\1/p' "$ROOT/Cargo.toml" | head -1)"

# shellcheck source=tests/wheel/hidden.sh
source "$ROOT/tests/wheel/hidden.sh"

if [ -z "$PREBUILT" ]; then
  "$ROOT/scripts/build-wheel.sh" "$WORK/dist" | tail -1
  PREBUILT="$WORK/dist"
fi
WHEEL="$(ls "$PREBUILT"/envc-*.whl)"
# The wheel and its extras (mazes, PettingZoo, Ray); minari reads the dataset back.
# The reference's pins as constraints (extras dropped: pip refuses them there): the same versions
# as the project venv, and its pip cache.
sed 's/\[[^]]*\]//' "$ROOT/tests/reference/requirements.txt" > "$WORK/constraints.txt"
# The venv outlives a run: its dependencies are a pure function of the pins, the interpreter and
# the wheel's declared requirements, so it is keyed by them and made fresh when any changes (a
# dropped requirement included). The wheel itself is reinstalled every run, then the ordinary
# install must find every requirement satisfied. Installing the dependencies is most of a minute.
KEY="$( { cat "$WORK/constraints.txt"; python3 --version; python3 -c 'import sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
meta = next(n for n in z.namelist() if n.endswith(".dist-info/METADATA"))
print("\n".join(l for l in z.read(meta).decode().splitlines() if l.startswith("Requires-Dist")))' "$WHEEL"; } \
  | sha256sum | cut -c1-16)"
CACHE="${XDG_CACHE_HOME:-$HOME/.cache}/envc-tests"
VENV="$CACHE/wheel-venv-$KEY"
mkdir -p "$CACHE"
find "$CACHE" -maxdepth 1 -name 'wheel-venv-*' ! -name "wheel-venv-$KEY" -exec rm -rf {} +
if [ ! -e "$VENV/.complete" ]; then
  rm -rf "$VENV"
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check -c "$WORK/constraints.txt" \
    "$WHEEL[robotics,ray]" minari h5py pyarrow imageio
  touch "$VENV/.complete"
  [ "$VENV_ONLY" = 0 ] || exit 0
else
  [ "$VENV_ONLY" = 0 ] || exit 0
  "$VENV/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps "$WHEEL"
  "$VENV/bin/pip" install -q --disable-pip-version-check -c "$WORK/constraints.txt" \
    "$WHEEL[robotics,ray]" minari h5py pyarrow imageio
fi
cp "$ROOT/tests/wheel/smoke.py" "$WORK/smoke.py"
hidden "MUJOCO_GL=egl '$VENV/bin/python' '$WORK/smoke.py' '$VERSION' '$WORK'"

# The wheel's `envc` command: every subcommand the judges name, from the hidden checkout's side.
E="$VENV/bin/envc"
hidden "
  set -e
  test \"\$('$E' --version)\" = 'envc $VERSION'
  '$E' list | grep -q '^Ant-v5 '
  '$E' info | grep -q 'installed: $VENV/'
  '$E' info | grep -q 'specs:     $VENV/.*/envc/_bundle/specs (the installed package'
  '$E' run Hopper-v5 --episodes 1 --seed 0 >/dev/null
  '$E' collect Hopper-v5 --dataset-id smoke/cli-v0 --episodes 2 --seed 0 --format hdf5 --root '$WORK/cli-datasets' >/dev/null
  test -d '$WORK/cli-datasets/smoke/cli-v0'
  '$E' render Hopper-v5 --max-steps 2 --size 32x24 --out '$WORK/frames/' >/dev/null
  test -s '$WORK/frames/frame_000001.png'
"
echo "wheel: $(basename "$WHEEL") ($(du -h "$WHEEL" | cut -f1)): smoke suite and the envc command pass with the checkout hidden"
