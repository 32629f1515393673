#!/usr/bin/env bash
# envc outside its checkout (scripts/test.sh runs this):
#  1. the wheel of scripts/build-wheel.sh, installed into a venv of its pinned dependencies, run with the checkout hidden
#     under an empty tmpfs (a private mount namespace): tests/wheel/smoke.py against the live
#     reference, then the `envc` command of the wheel;
#  2. a hand-made crate (`cargo new` plus `envc = { path = ... }`) built with plain `cargo build`,
#     no environment variables and no copied config (MuJoCo through pkg-config, installed by
#     scripts/setup.sh), its binary run from another directory with the checkout hidden.
# Usage: tests/wheel/run.sh WORKDIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WORK="${1:?usage: tests/wheel/run.sh WORKDIR}"
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"
case "$WORK" in "$ROOT"/*) echo "wheel test: WORKDIR must be outside the checkout" >&2; exit 1 ;; esac
VERSION="$(sed -n 's/^version = "\(.*\)"/\1/p' "$ROOT/Cargo.toml" | head -1)"

# Runs a command with the checkout replaced by an empty directory, from WORK, with none of the
# variables that could point back at it.
# Where a private mount namespace cannot be made (no CAP_SYS_ADMIN), a user namespace is tried;
# without either, the checkout stays visible and the run says so.
UNSHARE=(unshare -m --propagation private)
if ! "${UNSHARE[@]}" true 2>/dev/null; then
  UNSHARE=(unshare -rm --propagation private)
  "${UNSHARE[@]}" true 2>/dev/null || UNSHARE=()
fi
hidden() {
  local cmd="cd '$WORK' && $*"
  if [ ${#UNSHARE[@]} -gt 0 ]; then
    cmd="mount -t tmpfs -o size=1m envc-hidden '$ROOT' && $cmd"
  else
    echo "wheel test: cannot make a mount namespace here; the checkout stays visible" >&2
  fi
  env -u MUJOCO_DYNAMIC_LINK_DIR -u MUJOCO_INCLUDE_DIR -u LD_LIBRARY_PATH -u PYTHONPATH \
    -u VIRTUAL_ENV -u ENVC_SPEC_PATH "${UNSHARE[@]}" bash -c "$cmd"
}

"$ROOT/scripts/build-wheel.sh" "$WORK/dist" | tail -1
WHEEL="$(ls "$WORK"/dist/envc-*.whl)"
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
else
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

# A crate of one's own, as a user writes it, outside the checkout.
CRATE="${XDG_CACHE_HOME:-$HOME/.cache}/envc-tests/mybot"
mkdir -p "$CRATE/src"
cat > "$CRATE/Cargo.toml" <<EOF
[package]
name = "mybot"
version = "0.1.0"
edition = "2024"

[dependencies]
envc = { path = "$ROOT/runtime" }
EOF
cat > "$CRATE/src/main.rs" <<'EOF'
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut env = envc::Env::make("Hopper-v5", &[])?;
    env.reset(Some(0));
    let (mut n, mut ret) = (0, 0.0);
    loop {
        let s = env.step(&[0.0; 3])?;
        n += 1;
        ret += s.reward;
        if s.terminated || s.truncated {
            break;
        }
    }
    println!("Hopper-v5: one episode with zero actions, {n} steps, return {ret:.3}");
    Ok(())
}
EOF
# Its dependencies build into the checkout's target/outside/, kept between runs and shared with
# scripts/test.sh's `envc new` crate (whose template optimizes its dependencies: separate builds).
OUTSIDE="$ROOT/target/outside"
(cd "$CRATE" && env -u MUJOCO_DYNAMIC_LINK_DIR -u MUJOCO_INCLUDE_DIR -u PKG_CONFIG_PATH \
  CARGO_TARGET_DIR="$OUTSIDE" cargo build -q)
cp "$OUTSIDE/debug/mybot" "$WORK/mybot-bin"
got="$(hidden "'$WORK/mybot-bin'")"
want="$("$VENV/bin/python" "$ROOT/tests/reference/zero_action_episode.py")"
[ "$got" = "$want" ] || { echo "hand-made crate: got '$got', the reference gives '$want'" >&2; exit 1; }
echo "hand-made crate: plain cargo build, run with the checkout hidden: $got (as the reference)"
