#!/usr/bin/env bash
# Installs MuJoCo 3.17.0's C library, headers and a pkg-config file under PREFIX (default
# /usr/local), taken from the `mujoco==3.17.0` Python wheel that PYTHON (default: python3) imports.
# After it, any crate that depends on envc builds with a plain `cargo build` (mujoco-rs finds
# MuJoCo through pkg-config) and its binaries run from any directory (the dynamic loader's cache
# knows PREFIX/lib when PREFIX is a system prefix; ldconfig is run).
#
#   scripts/install-mujoco.sh                 # as root: /usr/local
#   scripts/install-mujoco.sh "$HOME/.local"  # without root: prints the two variables to export
#
# Idempotent: files are replaced only when they differ, and by a rename (a library rewritten in
# place crashes every process that has it mapped).
set -euo pipefail
MJ_VERSION=3.17.0
PREFIX="${1:-/usr/local}"
PY="${PYTHON:-python3}"

if ! MJDIR="$("$PY" -c "import mujoco, os; assert mujoco.__version__ == '$MJ_VERSION', mujoco.__version__; print(os.path.dirname(mujoco.__file__))" 2>/dev/null)"; then
  echo "install-mujoco: $PY cannot import mujoco $MJ_VERSION; run: $PY -m pip install mujoco==$MJ_VERSION" >&2
  exit 1
fi

LIB="$PREFIX/lib"
INC="$PREFIX/include"
PC="$LIB/pkgconfig"
mkdir -p "$LIB" "$INC" "$PC"
if ! cmp -s "$MJDIR/libmujoco.so.$MJ_VERSION" "$LIB/libmujoco.so.$MJ_VERSION"; then
  cp "$MJDIR/libmujoco.so.$MJ_VERSION" "$LIB/.libmujoco.so.$MJ_VERSION.new"
  mv -f "$LIB/.libmujoco.so.$MJ_VERSION.new" "$LIB/libmujoco.so.$MJ_VERSION"
fi
ln -sf "libmujoco.so.$MJ_VERSION" "$LIB/libmujoco.so"
rm -rf "$INC/mujoco.new" && cp -r "$MJDIR/include/mujoco" "$INC/mujoco.new"
rm -rf "$INC/mujoco" && mv "$INC/mujoco.new" "$INC/mujoco"
cat > "$PC/.mujoco.pc.new" <<EOF
prefix=$PREFIX
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: mujoco
Description: MuJoCo physics engine (from the mujoco $MJ_VERSION Python wheel)
Version: $MJ_VERSION
Libs: -L\${libdir} -lmujoco
Cflags: -I\${includedir}
EOF
mv -f "$PC/.mujoco.pc.new" "$PC/mujoco.pc"

if [ "$(id -u)" = 0 ] && command -v ldconfig >/dev/null; then
  ldconfig
fi
if pkg-config --exists "mujoco = $MJ_VERSION" 2>/dev/null && ldconfig -p 2>/dev/null | grep -q "libmujoco.so.$MJ_VERSION "; then
  echo "install-mujoco: MuJoCo $MJ_VERSION in $PREFIX (pkg-config and the loader find it)"
else
  echo "install-mujoco: MuJoCo $MJ_VERSION in $PREFIX; PREFIX is not a system prefix, so export:"
  echo "  export PKG_CONFIG_PATH=\"$PC\${PKG_CONFIG_PATH:+:\$PKG_CONFIG_PATH}\""
  echo "  export LD_LIBRARY_PATH=\"$LIB\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}\""
  echo "(or build with MUJOCO_DYNAMIC_LINK_DIR=$LIB, which also gives binaries an rpath)"
fi
