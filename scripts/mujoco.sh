#!/usr/bin/env bash
# MuJoCo VERSION beside the default one (scripts/setup.sh's 3.17.0), for building envc against it:
#   third_party/mujoco-VERSION/{lib,include}  MuJoCo's library and headers, from its PyPI wheel
#                                             (`mujoco-core` from 4.0 on, `mujoco` before);
#   third_party/mujoco-rs-VERSION/            mujoco-rs 7.0.0's source, its FFI regenerated from
#                                             those headers by mujoco-rs's own generator (bindgen,
#                                             feature `ffi-regenerate`), and the accessors of
#                                             fields the version removed dropped
#                                             (scripts/mujoco_rs_fields.py).
# Then envc's feature `mujoco-VERSION` builds against it (docs/mujoco-versions.md).
# Idempotent: a version already in place is only checked.
set -euo pipefail
V="${1:?usage: scripts/mujoco.sh VERSION (e.g. 4.0.1)}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="$ROOT/.venv/bin/python"
[ -x "$PY" ] || { echo "scripts/mujoco.sh: run scripts/setup.sh first (it makes .venv)" >&2; exit 1; }
MJ="$ROOT/third_party/mujoco-$V"
RS="$ROOT/third_party/mujoco-rs-$V"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

# The header's version number, e.g. 4000001 for 4.0.1.
IFS=. read -r MAJ MIN PAT <<< "$V"
NUM=$((MAJ * 1000000 + MIN * 1000 + PAT))

if [ ! -e "$MJ/lib/libmujoco.so.$V" ] || [ ! -e "$MJ/include/mujoco/mujoco.h" ]; then
  if [ "$MAJ" -ge 4 ]; then PKG=mujoco-core; else PKG=mujoco; fi
  "$PY" -m pip download -q --disable-pip-version-check --no-deps --only-binary :all: \
    "$PKG==$V" -d "$WORK/wheel"
  "$PY" -m zipfile -e "$WORK"/wheel/*.whl "$WORK/unpacked"
  mkdir -p "$MJ/lib"
  cp "$WORK/unpacked/mujoco/libmujoco.so.$V" "$MJ/lib/.libmujoco.so.$V.new"
  mv -f "$MJ/lib/.libmujoco.so.$V.new" "$MJ/lib/libmujoco.so.$V"
  ln -sf "libmujoco.so.$V" "$MJ/lib/libmujoco.so"
  rm -rf "$MJ/include" && cp -r "$WORK/unpacked/mujoco/include" "$MJ/include"
fi
grep -q "mjVERSION_HEADER $NUM\$" "$MJ/include/mujoco/mujoco.h" ||
  { echo "scripts/mujoco.sh: $MJ/include is not MuJoCo $V's" >&2; exit 1; }

if ! grep -q "mjVERSION_HEADER: u32 = $NUM;" "$RS/src/mujoco_c.rs" 2>/dev/null; then
  # mujoco-rs's source from crates.io, through a throwaway crate that depends on the version the
  # workspace pins (the workspace itself cannot resolve until this bindings crate exists).
  PIN="$(sed -n 's/^mujoco-rs-3-17-0 = .*version = "\([^"]*\)".*/\1/p' "$ROOT/Cargo.toml")"
  mkdir -p "$WORK/probe/src" && touch "$WORK/probe/src/lib.rs"
  printf '[package]\nname = "probe"\nversion = "0.0.0"\nedition = "2024"\n[dependencies]\nmujoco-rs = "%s"\n[workspace]\n' \
    "$PIN" > "$WORK/probe/Cargo.toml"
  SRC="$(cd "$WORK/probe" && cargo metadata -q --format-version 1 | "$PY" -c '
import json, sys, os
pkg = [p for p in json.load(sys.stdin)["packages"] if p["name"] == "mujoco-rs"]
print(os.path.dirname(pkg[0]["manifest_path"]))')"
  # libclang for bindgen, from PyPI (the system's may be absent or lack its C API), and the C
  # compiler's own headers (stddef.h), which that libclang does not ship.
  "$PY" -m pip install -q --disable-pip-version-check --target "$WORK/clang" libclang==18.1.1
  rm -rf "$RS.new" && cp -r "$SRC" "$RS.new"
  mkdir -p "$RS.new/mujoco" && cp -r "$MJ/include" "$RS.new/mujoco/include"
  # The build script regenerates src/mujoco_c.rs before compiling the crate; the crate itself does
  # not compile yet (the removed fields), so only the FFI file is checked.
  (cd "$RS.new" &&
    LIBCLANG_PATH="$WORK/clang/clang/native" \
    BINDGEN_EXTRA_CLANG_ARGS="-I$(cc -print-file-name=include)" \
    MUJOCO_DYNAMIC_LINK_DIR="$MJ/lib" CARGO_TARGET_DIR="$WORK/target" \
    cargo check -q --features ffi-regenerate >"$WORK/regenerate.log" 2>&1) || true
  grep -q "mjVERSION_HEADER: u32 = $NUM;" "$RS.new/src/mujoco_c.rs" ||
    { cat "$WORK/regenerate.log" >&2; echo "scripts/mujoco.sh: bindgen did not regenerate the FFI" >&2; exit 1; }
  "$PY" "$ROOT/scripts/mujoco_rs_fields.py" "$SRC/src/mujoco_c.rs" "$RS.new/src/mujoco_c.rs" "$RS.new"
  rm -rf "$RS.new/mujoco" "$RS.new/target"
  # `cargo fmt --all` also walks path dependencies: this crate is not envc's to format.
  printf 'disable_all_formatting = true\n' > "$RS.new/rustfmt.toml"
  # Its own version, and its own variable for the library's directory (MUJOCO_DYNAMIC_LINK_DIR is
  # 3.17.0's; .cargo/config.toml sets both).
  sed -i "s/^version = \"\(7\.0\.0\)+mj-[0-9.]*\"/version = \"\1+mj-$V\"/" "$RS.new/Cargo.toml"
  VAR="MUJOCO_$(echo "$V" | tr . _)_DYNAMIC_LINK_DIR"
  sed -i "s/\"MUJOCO_DYNAMIC_LINK_DIR\"/\"$VAR\"/" "$RS.new/build.rs"
  grep -q "\"$VAR\"" "$RS.new/build.rs"
  # The library linked by its file name: the 3.17.0 bindings' search path, which a build with
  # both crates also passes, holds a `libmujoco.so` of its own.
  sed -i "s/rustc-link-lib=dylib=mujoco\"/rustc-link-lib=dylib:+verbatim=libmujoco.so.$V\"/" "$RS.new/build.rs"
  grep -q "verbatim=libmujoco.so.$V" "$RS.new/build.rs"
  rm -rf "$RS" && mv "$RS.new" "$RS"
fi
echo "scripts/mujoco.sh: MuJoCo $V in $MJ, its bindings in $RS"
